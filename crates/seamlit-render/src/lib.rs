//! # seamlit-render
//!
//! Per-pixel lighting with normal mapping on wgpu, headless (to an image) or into a window.
//!
//! The lighting equation is that of P. Mileff, "Per-pixel lighting for multi-object models"
//! (2024), section 3: ambient plus, for every light, diffuse and specular, evaluated in one
//! pass over a storage buffer of lights ([`Light`]: directional, point, spot), per pixel
//! (Blinn-Phong, Phong, Lambert) or per vertex (Gouraud), see [`LightingModel`]. For glTF
//! materials, [`LightingModel::Pbr`] is the metallic-roughness model of the glTF 2.0
//! specification's Appendix B in the same pass (base colour, metallic-roughness, occlusion and
//! emissive textures, alpha MASK and BLEND, unlit), tone mapped as [`ToneMapping`] says, with the
//! glTF extensions that add to that BRDF (KHR_materials_ior, _specular, _clearcoat, _sheen,
//! _anisotropy, _transmission, _volume, _iridescence, _dispersion, with their textures:
//! `seamlit_asset::PbrExtensions`) drawn by pipeline variants made on first use, so that a material
//! without them costs what it did. The textures of transmission, volume, iridescence and
//! anisotropy need a device with 21 sampled textures a shader stage (lavapipe and desktop GPUs
//! allow more): on one with fewer their factors are drawn alone
//! ([`GpuContext::draws_all_extension_textures`]). Normal maps
//! are read in the tangent frame built in the vertex shader (section 5.3: Gram-Schmidt,
//! `B = cross(N, T) * w`, times the sign of the transform's determinant). Shaders live in
//! `src/mesh.wgsl`.
//!
//! The pieces:
//! - [`GpuContext`]: the device. [`GpuContext::headless`] picks Vulkan, Metal or DX12 and falls
//!   back to GL (on Linux without a GPU, Mesa's lavapipe: `apt-get install mesa-vulkan-drivers`);
//!   [`GpuContext::for_surface`] for a window, whose device an egui-wgpu renderer can share.
//! - [`GpuScene`]: a model with materials and textures on the GPU (mipmapped, 1x1 defaults for
//!   missing textures; [`TextureOptions`] for mipmaps and anisotropy);
//!   [`GpuScene::replace_model`] swaps the geometry after a re-fix; [`GpuScene::set_pose`]
//!   poses it ([`ObjectPose`]: transform, joint palette, morph weights), skinned and morphed
//!   in the vertex stage (`src/deform.wgsl`), and [`GpuScene::posed_vertices`] reads the
//!   posed vertices back.
//! - [`Renderer`]: pipelines for one target format and MSAA sample count;
//!   [`Renderer::render`] into a view (a window), [`Renderer::render_to_image`] to an image,
//!   [`Renderer::time_frames`] for frame timing, each given a [`FrameDescriptor`] (scene,
//!   camera, settings, size); [`Renderer::for_images`] makes one for images.
//! - [`FrameSettings`]: lights, ambient, lighting model, normal mapping, strength, green flip,
//!   [`DebugView`], TBN lines, exposure, [`ToneMapping`]; [`CameraView`] the camera.
//!
//! ```
//! use glam::{Vec2, Vec3};
//! use seamlit_asset::Asset;
//! use seamlit_mesh::{FixOptions, Model, Object, fix};
//! use seamlit_render::{
//!     CameraDescriptor, CameraView, FrameDescriptor, FrameSettings, GpuContext, GpuScene,
//!     Projection, Renderer,
//! };
//!
//! // A quad facing +Z; fix gives it normals and tangents.
//! let quad = Object::new(
//!     "quad",
//!     vec![Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(-1.0, 1.0, 0.0)],
//!     vec![[0, 1, 2], [0, 2, 3]],
//! )
//! .with_uvs(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]);
//! let model = fix(&Model::new(vec![quad]), &FixOptions::default())?;
//! let asset = Asset { model, ..Asset::default() };
//!
//! let ctx = GpuContext::headless()?;
//! let scene = GpuScene::upload(&ctx, &asset)?;
//! let camera = CameraView::look_at(&CameraDescriptor {
//!     eye: Vec3::new(0.0, 0.0, 3.0),
//!     target: Vec3::ZERO,
//!     up: Vec3::Y,
//!     projection: Projection::Perspective { fov_y_deg: 45.0 },
//!     aspect: 1.0,
//!     near: 0.1,
//!     far: 10.0,
//! });
//! let settings = FrameSettings::default();
//! let frame = FrameDescriptor { scene: &scene, camera: &camera, settings: &settings, size: (64, 64) };
//! let image = Renderer::for_images(&ctx)?.render_to_image(&ctx, &frame)?;
//! assert_eq!(image.dimensions(), (64, 64));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Errors are [`RenderError`]s that name the object, material or texture at fault.
//!
//! For a window: create the instance with [`GpuContext::new_instance`], the surface from it,
//! then [`GpuContext::for_surface`]; make a [`Renderer`] for the surface's format and call
//! [`Renderer::render`] (or [`Renderer::encode`] to share a command encoder with egui) with
//! the surface texture's view every frame.
#![deny(missing_docs)]

mod context;
mod environment;
mod error;
mod light;
mod material;
mod pipeline;
mod pose;
mod readback;
mod renderer;
mod scene;
mod settings;
mod shaders;
mod shadow;
mod sheen;
mod sheen_table;
mod texture;
mod transmission;

pub use context::GpuContext;
pub use environment::{Environment, GpuEnvironment};
pub use error::RenderError;
pub use light::{CameraDescriptor, CameraView, DebugView, Light, LightingModel, Projection};
pub use pose::ObjectPose;
pub use readback::PendingReadback;
pub use readback::PosedVertices;
pub use renderer::{DEFAULT_SAMPLE_COUNT, FrameDescriptor, FrameTimes, IMAGE_FORMAT, Renderer};
pub use scene::GpuScene;
pub use settings::{FrameSettings, ToneMapping};
pub use texture::TextureOptions;
/// The wgpu this crate is built on, for creating surfaces and sharing the device.
pub use wgpu;
