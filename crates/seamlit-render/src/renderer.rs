//! The renderer: records a frame into a target view, headless readback to an image, and
//! repeated frames for timing.

use std::time::{Duration, Instant};

use image::RgbaImage;

use crate::light::LightRaw;
use crate::pipeline::{DEPTH_FORMAT, Features, MeshKey, Pipelines};
use crate::settings::{FrameInputs, FrameRaw};
use crate::shadow::{SHADOW_SIZE, Shadows};
use crate::transmission::Transmission;
use crate::{CameraView, FrameSettings, GpuContext, GpuEnvironment, GpuScene, RenderError};

/// The format [`Renderer::render_to_image`] renders in and reads back.
pub const IMAGE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// The default MSAA sample count.
pub const DEFAULT_SAMPLE_COUNT: u32 = 4;

/// Draws a [`GpuScene`] into a colour target of one format.
///
/// Holds the pipelines, the frame uniforms and light buffer, and the depth and multisampled
/// colour attachments (re-created when the target size changes).
#[derive(Debug)]
pub struct Renderer {
    format: wgpu::TextureFormat,
    sample_count: u32,
    pipelines: Pipelines,
    frame_buffer: wgpu::Buffer,
    light_buffer: wgpu::Buffer,
    light_capacity: usize,
    frame_bind_group: wgpu::BindGroup,
    attachments: Option<Attachments>,
    shadows: Shadows,
    /// Shadow maps in use this frame.
    shadows_used: usize,
    /// The environment's image-based light, and whether it is a real one.
    environment: GpuEnvironment,
    has_environment: bool,
    /// What transmissive materials see through (transmission.rs), made on the first frame
    /// that draws one; `black` stands in for it before.
    transmission: Option<Transmission>,
    black: wgpu::TextureView,
    /// The frame's shadow normal offset, which the transmission pass's uniforms repeat.
    shadow_normal_offset: f32,
}

/// Depth (and, with MSAA, colour) attachments of one size.
#[derive(Debug)]
struct Attachments {
    size: (u32, u32),
    depth: wgpu::TextureView,
    msaa: Option<wgpu::TextureView>,
}

/// One frame to draw: the scene, the camera it is seen through, the frame's settings, and
/// the target's size in pixels (width, height).
#[derive(Clone, Copy, Debug)]
pub struct FrameDescriptor<'a> {
    /// What to draw.
    pub scene: &'a GpuScene,
    /// From where.
    pub camera: &'a CameraView,
    /// Lights, lighting model, debug view, tone mapping.
    pub settings: &'a FrameSettings,
    /// Width and height of the target in pixels.
    pub size: (u32, u32),
}

/// Frame times measured by [`Renderer::time_frames`].
#[derive(Clone, Debug, PartialEq)]
pub struct FrameTimes {
    /// Wall time of each frame, from recording to the GPU having finished it.
    pub frames: Vec<Duration>,
}

impl FrameTimes {
    /// The mean frame time (zero for no frames).
    #[must_use]
    pub fn mean(&self) -> Duration {
        let n = u32::try_from(self.frames.len()).unwrap_or(u32::MAX).max(1);
        self.frames.iter().sum::<Duration>() / n
    }

    /// The median frame time (zero for no frames).
    #[must_use]
    pub fn median(&self) -> Duration {
        let mut sorted = self.frames.clone();
        sorted.sort();
        sorted.get(sorted.len() / 2).copied().unwrap_or_default()
    }

    /// The fastest frame (zero for no frames).
    #[must_use]
    pub fn min(&self) -> Duration {
        self.frames.iter().min().copied().unwrap_or_default()
    }
}

impl Renderer {
    /// A renderer for targets of `format` with `sample_count` samples per pixel (1 = no MSAA,
    /// [`DEFAULT_SAMPLE_COUNT`] = 4). An sRGB format is written in linear light and encoded by
    /// the hardware; for other formats the shader encodes to sRGB itself.
    ///
    /// # Errors
    ///
    /// [`RenderError::UnsupportedSampleCount`] when the adapter cannot multisample `format`
    /// (or the depth format) that many times; [`RenderError::Gpu`].
    pub fn new(
        ctx: &GpuContext,
        format: wgpu::TextureFormat,
        sample_count: u32,
    ) -> Result<Self, RenderError> {
        let colour = ctx.supported_sample_counts(format);
        let depth = ctx.supported_sample_counts(DEPTH_FORMAT);
        if !colour.contains(&sample_count) || !depth.contains(&sample_count) {
            let supported = colour.into_iter().filter(|n| depth.contains(n)).collect();
            return Err(RenderError::UnsupportedSampleCount {
                format,
                count: sample_count,
                supported,
            });
        }
        ctx.scoped("creating the renderer", || {
            let device = ctx.device();
            let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("seamlit frame"),
                size: size_of::<FrameRaw>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let light_capacity = 16;
            let light_buffer = light_buffer(ctx, light_capacity);
            let shadows = Shadows::new(ctx);
            let black = black_texture(ctx);
            let frame_bind_group =
                frame_bind_group(ctx, &frame_buffer, &light_buffer, &shadows, &black);
            Ok(Self {
                format,
                sample_count,
                pipelines: Pipelines::new(ctx, format, sample_count),
                frame_buffer,
                light_buffer,
                light_capacity,
                frame_bind_group,
                attachments: None,
                shadows,
                shadows_used: 0,
                environment: GpuEnvironment::none(ctx),
                has_environment: false,
                transmission: None,
                black,
                shadow_normal_offset: 0.0,
            })
        })
    }

    /// A renderer for [`Renderer::render_to_image`]: [`IMAGE_FORMAT`], with
    /// [`DEFAULT_SAMPLE_COUNT`] samples where the adapter supports it, else none.
    ///
    /// # Errors
    ///
    /// As [`Renderer::new`].
    pub fn for_images(ctx: &GpuContext) -> Result<Self, RenderError> {
        let supported = ctx.supported_sample_counts(IMAGE_FORMAT);
        let samples =
            if supported.contains(&DEFAULT_SAMPLE_COUNT) { DEFAULT_SAMPLE_COUNT } else { 1 };
        Self::new(ctx, IMAGE_FORMAT, samples)
    }

    /// Lights PBR materials with `environment` from the next frame on (and, as
    /// [`FrameSettings::environment_background`] says, draws it behind the scene); `None`
    /// removes it.
    pub fn set_environment(&mut self, environment: Option<GpuEnvironment>) {
        self.has_environment = environment.is_some();
        if let Some(environment) = environment {
            self.environment = environment;
        }
    }

    /// The target format this renderer draws into.
    #[must_use]
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// Samples per pixel.
    #[must_use]
    pub fn sample_count(&self) -> u32 {
        self.sample_count
    }

    /// Renders one frame into `target` (a view of a texture of this renderer's format and of
    /// `frame.size` pixels, e.g. a window's surface texture) and submits it. The target is
    /// cleared to [`FrameSettings::clear_color`] first.
    ///
    /// # Errors
    ///
    /// [`RenderError::BadSize`], [`RenderError::Gpu`].
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        frame: &FrameDescriptor<'_>,
        target: &wgpu::TextureView,
    ) -> Result<(), RenderError> {
        ctx.scoped("rendering", || {
            let mut encoder =
                ctx.device().create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("seamlit frame"),
                });
            self.encode(ctx, &mut encoder, frame, target)?;
            ctx.queue().submit([encoder.finish()]);
            Ok(())
        })
    }

    /// Records one frame into `encoder` without submitting it, for callers that draw more
    /// (an egui overlay) in the same command buffer. Uniforms are written through the queue,
    /// so submit before the next call.
    ///
    /// # Errors
    ///
    /// [`RenderError::BadSize`].
    pub fn encode(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameDescriptor<'_>,
        target: &wgpu::TextureView,
    ) -> Result<(), RenderError> {
        let FrameDescriptor { scene, camera, settings, size } = *frame;
        check_size(ctx, size.0, size.1)?;
        self.prepare(ctx, frame);
        let sky = self.has_environment && settings.environment_background;
        prepare_pipelines(&mut self.pipelines, ctx.device(), scene, sky, false);
        if settings.show_tbn {
            self.pipelines.prepare_tbn(ctx.device());
        }
        self.shadows.encode(encoder, scene, self.shadows_used);
        if scene.meshes.iter().any(|m| scene.materials[m.material].transmission) {
            self.encode_transmission(ctx, encoder, frame);
        }
        let Some(attachments) = &self.attachments else { return Ok(()) };
        let (view, resolve) = match &attachments.msaa {
            Some(msaa) => (msaa, Some(target)),
            None => (target, None),
        };
        // The clear colour is linear; a target that is not sRGB gets it encoded, as the
        // shader encodes what it draws there.
        let clear = if self.format.is_srgb() {
            settings.clear_color
        } else {
            let [r, g, b, a] = settings.clear_color;
            [linear_to_srgb(r), linear_to_srgb(g), linear_to_srgb(b), a]
        };
        let colour = PassColour { view, resolve, clear };
        let mut pass = begin_pass(encoder, "seamlit scene", colour, &attachments.depth);
        pass.set_bind_group(0, &self.frame_bind_group, &[]);
        pass.set_bind_group(3, &self.environment.bind_group, &[]);
        if sky {
            self.draw_sky(&mut pass, scene);
        }
        self.draw_meshes(&mut pass, &self.pipelines, scene, camera.eye, false);
        if settings.show_tbn {
            self.draw_tbn(&mut pass, scene);
        }
        Ok(())
    }

    /// KHR_materials_transmission's target: the scene without its transmissive objects, in
    /// linear light (no exposure, no tone mapping, as the Sample Viewer's), the sky where the
    /// frame shows it, then its mips; the scene pass's frame bind group reads it.
    fn encode_transmission(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameDescriptor<'_>,
    ) {
        let FrameDescriptor { scene, camera, settings, .. } = *frame;
        if self.transmission.is_none() {
            self.transmission = Some(Transmission::new(ctx, size_of::<FrameRaw>() as u64));
            self.frame_bind_group = self.scene_frame_bind_group(ctx);
        }
        let Some(transmission) = &mut self.transmission else { return };
        let sky = self.has_environment && settings.environment_background;
        prepare_pipelines(&mut transmission.pipelines, ctx.device(), scene, sky, true);
        let frame_group = self.transmission_frame_group(ctx, frame);
        let Some(transmission) = &self.transmission else { return };
        {
            let colour = PassColour {
                view: transmission.target(),
                resolve: None,
                clear: settings.clear_color,
            };
            let label = "seamlit transmission";
            let mut pass = begin_pass(encoder, label, colour, &transmission.depth);
            pass.set_bind_group(0, &frame_group, &[]);
            pass.set_bind_group(3, &self.environment.bind_group, &[]);
            if sky {
                self.draw_sky_with(&mut pass, &transmission.pipelines, scene);
            }
            self.draw_meshes(&mut pass, &transmission.pipelines, scene, camera.eye, true);
        }
        transmission.encode_mips(encoder);
    }

    /// The transmission pass's frame bind group: the frame's uniforms in linear light (no
    /// exposure, no tone mapping), written to the transmission target's own buffer, with the
    /// scene pass's lights and shadow maps and a black texel for the target it draws into.
    fn transmission_frame_group(
        &self,
        ctx: &GpuContext,
        frame: &FrameDescriptor<'_>,
    ) -> wgpu::BindGroup {
        let FrameDescriptor { scene, camera, settings, .. } = *frame;
        let transmission = self.transmission.as_ref().expect("made before its frame group");
        let mut raw = settings.to_raw(&FrameInputs {
            camera,
            default_tbn_length: scene.default_tbn_length(),
            encode_srgb: false,
            environment: self.has_environment,
            shadow_normal_offset: (self.shadows_used > 0).then_some(self.shadow_normal_offset),
        });
        raw.exposure = 1.0;
        raw.tone_mapping = 0;
        ctx.queue().write_buffer(&transmission.frame_buffer, 0, bytemuck::bytes_of(&raw));
        frame_bind_group(
            ctx,
            &transmission.frame_buffer,
            &self.light_buffer,
            &self.shadows,
            &self.black,
        )
    }

    /// The scene pass's frame bind group: the frame uniforms, lights, shadow maps and the
    /// transmission target (a black texel before there is one).
    fn scene_frame_bind_group(&self, ctx: &GpuContext) -> wgpu::BindGroup {
        let target = self.transmission.as_ref().map_or(&self.black, |t| &t.view);
        frame_bind_group(ctx, &self.frame_buffer, &self.light_buffer, &self.shadows, target)
    }

    /// Draws every mesh, in [`draw_order`] from `eye`, with its variant of the mesh pipeline
    /// of `pipelines`; with `opaque_only`, not the transmissive ones.
    fn draw_meshes(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipelines: &Pipelines,
        scene: &GpuScene,
        eye: glam::Vec3,
        opaque_only: bool,
    ) {
        for mesh in draw_order(scene, eye) {
            let material = &scene.materials[mesh.material];
            if opaque_only && material.transmission {
                continue;
            }
            pass.set_pipeline(pipelines.mesh(mesh_key(scene, mesh)));
            pass.set_bind_group(1, &material.bind_group, &[]);
            pass.set_bind_group(2, &mesh.bind_group, &[]);
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.index_count, 0, 0..1);
        }
    }

    /// Draws each mesh's tangent, bitangent and normal lines (six vertices per vertex).
    fn draw_tbn(&self, pass: &mut wgpu::RenderPass<'_>, scene: &GpuScene) {
        pass.set_pipeline(self.pipelines.tbn());
        for mesh in &scene.meshes {
            pass.set_bind_group(1, &scene.materials[mesh.material].bind_group, &[]);
            pass.set_bind_group(2, &mesh.bind_group, &[]);
            pass.draw(0..mesh.tbn_vertex_count * 6, 0..1);
        }
    }

    /// Draws the environment behind everything. The sky reads only groups 0 and 3, but the
    /// pipeline layout has all four set: any material and object will do (a scene without
    /// objects has no sky).
    fn draw_sky(&self, pass: &mut wgpu::RenderPass<'_>, scene: &GpuScene) {
        self.draw_sky_with(pass, &self.pipelines, scene);
    }

    /// As [`Renderer::draw_sky`], with the sky pipeline of `pipelines`.
    fn draw_sky_with(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        pipelines: &Pipelines,
        scene: &GpuScene,
    ) {
        let (Some(material), Some(mesh)) = (scene.materials.last(), scene.meshes.first()) else {
            return;
        };
        pass.set_pipeline(pipelines.sky());
        pass.set_bind_group(1, &material.bind_group, &[]);
        pass.set_bind_group(2, &mesh.bind_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Writes the uniforms and lights, and makes the attachments fit `size`.
    fn prepare(&mut self, ctx: &GpuContext, frame: &FrameDescriptor<'_>) {
        let FrameDescriptor { scene, camera, settings, size } = *frame;
        let (shadow_layers, used) =
            self.shadows.prepare(ctx, &settings.lights, settings.shadow_maps, scene.bounds());
        self.shadows_used = used;
        // Two shadow-map texels of the directional maps, which span the scene's bounds.
        let normal_offset = (used > 0).then(|| {
            scene.bounds().map_or(0.0, |(lo, hi)| (hi - lo).length() / SHADOW_SIZE as f32 * 2.0)
        });
        let raw = settings.to_raw(&FrameInputs {
            camera,
            default_tbn_length: scene.default_tbn_length(),
            encode_srgb: !self.format.is_srgb(),
            environment: self.has_environment,
            shadow_normal_offset: normal_offset,
        });
        self.shadow_normal_offset = raw.shadow_normal_offset;
        ctx.queue().write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&raw));
        if settings.lights.len() > self.light_capacity {
            self.light_capacity = settings.lights.len().next_power_of_two();
            self.light_buffer = light_buffer(ctx, self.light_capacity);
            self.frame_bind_group = self.scene_frame_bind_group(ctx);
        }
        if !settings.lights.is_empty() {
            let lights: Vec<LightRaw> = settings
                .lights
                .iter()
                .zip(shadow_layers)
                .map(|(light, shadow)| LightRaw { shadow, ..light.to_raw() })
                .collect();
            ctx.queue().write_buffer(&self.light_buffer, 0, bytemuck::cast_slice(&lights));
        }
        if self.attachments.as_ref().is_none_or(|a| a.size != size) {
            self.attachments = Some(self.create_attachments(ctx, size));
        }
    }

    fn create_attachments(&self, ctx: &GpuContext, size: (u32, u32)) -> Attachments {
        let texture = |label, format| {
            ctx.device()
                .create_texture(&wgpu::TextureDescriptor {
                    sample_count: self.sample_count,
                    ..target_descriptor(label, size, format)
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        Attachments {
            size,
            depth: texture("seamlit depth", DEPTH_FORMAT),
            msaa: (self.sample_count > 1).then(|| texture("seamlit msaa colour", self.format)),
        }
    }

    /// Renders one frame offscreen at `frame.size` and reads it back as an sRGB RGBA image. The renderer's format must be [`IMAGE_FORMAT`] (the hardware encodes sRGB) or
    /// `Rgba8Unorm` (the shader encodes, as for a window surface without an sRGB format).
    ///
    /// # Errors
    ///
    /// [`RenderError::BadSize`], [`RenderError::Gpu`] (also for another format),
    /// [`RenderError::Poll`], [`RenderError::Map`].
    pub fn render_to_image(
        &mut self,
        ctx: &GpuContext,
        frame: &FrameDescriptor<'_>,
    ) -> Result<RgbaImage, RenderError> {
        let (width, height) = frame.size;
        check_size(ctx, width, height)?;
        if !matches!(self.format, IMAGE_FORMAT | wgpu::TextureFormat::Rgba8Unorm) {
            return Err(RenderError::Gpu {
                during: "rendering to an image",
                message: format!(
                    "the renderer draws {:?}, images need {IMAGE_FORMAT:?} or Rgba8Unorm",
                    self.format
                ),
            });
        }
        ctx.scoped("rendering to an image", || {
            let target = ctx.device().create_texture(&wgpu::TextureDescriptor {
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                ..target_descriptor("seamlit image", frame.size, self.format)
            });
            let view = target.create_view(&wgpu::TextureViewDescriptor::default());
            let mut encoder =
                ctx.device().create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("seamlit image"),
                });
            self.encode(ctx, &mut encoder, frame, &view)?;
            crate::readback::read_texture(ctx, encoder, &target, width, height)
        })
    }

    /// Renders `frames` frames offscreen at `frame.size` (after one unmeasured warm-up
    /// frame) and measures each from recording to the GPU having finished it (submit, then
    /// wait). This is what `seamlit render --frames N` reports.
    ///
    /// # Errors
    ///
    /// As [`Renderer::render`], and [`RenderError::Poll`].
    pub fn time_frames(
        &mut self,
        ctx: &GpuContext,
        frame: &FrameDescriptor<'_>,
        frames: usize,
    ) -> Result<FrameTimes, RenderError> {
        let (width, height) = frame.size;
        check_size(ctx, width, height)?;
        let target = ctx.device().create_texture(&target_descriptor(
            "seamlit timing target",
            frame.size,
            self.format,
        ));
        let view = target.create_view(&wgpu::TextureViewDescriptor::default());
        let mut times = Vec::with_capacity(frames);
        for i in 0..=frames {
            let start = Instant::now();
            self.render(ctx, frame, &view)?;
            ctx.device().poll(wgpu::PollType::wait_indefinitely())?;
            if i > 0 {
                times.push(start.elapsed());
            }
        }
        Ok(FrameTimes { frames: times })
    }
}

/// The meshes in drawing order: opaque (and masked) ones as they come, then the blended ones
/// from the farthest to the nearest, by the distance from `eye` to the centre of their bounds.
fn draw_order(scene: &GpuScene, eye: glam::Vec3) -> Vec<&crate::scene::GpuMesh> {
    let blended = |m: &crate::scene::GpuMesh| scene.materials[m.material].blend;
    let mut order: Vec<_> = scene.meshes.iter().filter(|m| !blended(m)).collect();
    let mut back_to_front: Vec<_> = scene.meshes.iter().filter(|m| blended(m)).collect();
    back_to_front
        .sort_by(|a, b| eye.distance_squared(b.center).total_cmp(&eye.distance_squared(a.center)));
    order.extend(back_to_front);
    order
}

/// A pass's colour attachment: drawn into `view` (resolved into `resolve` when `view` is
/// multisampled), cleared to `clear`.
struct PassColour<'a> {
    view: &'a wgpu::TextureView,
    resolve: Option<&'a wgpu::TextureView>,
    clear: [f32; 4],
}

/// Begins a pass that draws meshes (the scene's, the transmission target's): colour cleared
/// (and kept only where it is not resolved elsewhere), depth `depth` cleared to 1 and not
/// kept.
fn begin_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    colour: PassColour<'_>,
    depth: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    let [r, g, b, a] = colour.clear.map(f64::from);
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: colour.view,
            depth_slice: None,
            resolve_target: colour.resolve,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                store: if colour.resolve.is_some() {
                    wgpu::StoreOp::Discard
                } else {
                    wgpu::StoreOp::Store
                },
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Discard,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// The descriptor of a render target of `size` pixels: 2D, one mip level, one sample, usable
/// as a render attachment only. Callers change what differs with struct update syntax.
fn target_descriptor(
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
) -> wgpu::TextureDescriptor<'_> {
    wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    }
}

fn check_size(ctx: &GpuContext, width: u32, height: u32) -> Result<(), RenderError> {
    let max = ctx.device().limits().max_texture_dimension_2d;
    if width == 0 || height == 0 || width > max || height > max {
        return Err(RenderError::BadSize { width, height, max });
    }
    Ok(())
}

fn light_buffer(ctx: &GpuContext, capacity: usize) -> wgpu::Buffer {
    ctx.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some("seamlit lights"),
        size: (capacity.max(1) * size_of::<LightRaw>()) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A 1 x 1 black texture, for a binding with nothing to read yet.
fn black_texture(ctx: &GpuContext) -> wgpu::TextureView {
    ctx.device()
        .create_texture(&wgpu::TextureDescriptor {
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            ..target_descriptor("seamlit black", (1, 1), crate::transmission::FORMAT)
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

fn frame_bind_group(
    ctx: &GpuContext,
    frame: &wgpu::Buffer,
    lights: &wgpu::Buffer,
    shadows: &Shadows,
    transmission: &wgpu::TextureView,
) -> wgpu::BindGroup {
    ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("seamlit frame"),
        layout: &ctx.layouts.frame,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: frame.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: lights.as_entire_binding() },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&shadows.view),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::Sampler(&shadows.sampler),
            },
            wgpu::BindGroupEntry { binding: 4, resource: shadows.matrices.as_entire_binding() },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(transmission),
            },
        ],
    })
}

/// The pipeline `mesh` draws with: a posed object's skins and morphs in the vertex stage, its
/// material's PBR extensions in the fragment stage, its facing, culling and blending.
fn mesh_key(scene: &GpuScene, mesh: &crate::scene::GpuMesh) -> MeshKey {
    let material = &scene.materials[mesh.material];
    MeshKey {
        features: Features { deform: mesh.posed, layers: material.layers },
        mirrored: mesh.mirrored,
        double_sided: material.double_sided,
        blend: material.blend,
    }
}

/// Makes the pipelines a pass over `scene` draws with: each mesh's (with `opaque_only`, each
/// not transmissive one's, as [`Renderer::draw_meshes`] skips the rest) and, with `sky`, the
/// sky's.
fn prepare_pipelines(
    pipelines: &mut Pipelines,
    device: &wgpu::Device,
    scene: &GpuScene,
    sky: bool,
    opaque_only: bool,
) {
    for mesh in &scene.meshes {
        if !(opaque_only && scene.materials[mesh.material].transmission) {
            pipelines.prepare_mesh(device, mesh_key(scene, mesh));
        }
    }
    if sky {
        pipelines.prepare_sky(device);
    }
}

/// The sRGB transfer function (IEC 61966-2-1) of one linear channel, for the clear colour of a
/// target that is not sRGB.
fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec3};
    use seamlit_asset::{Asset, Material};
    use seamlit_mesh::{Model, Object};

    use super::*;
    use crate::{CameraDescriptor, Projection};

    /// A square of two triangles facing +Z, with normals, in `material`.
    fn square(name: &str, material: usize) -> Object {
        let corners = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::X - Vec3::Y,
            Vec3::ONE - Vec3::Z,
            -Vec3::X + Vec3::Y,
        ];
        let mut o = Object::new(name, corners.to_vec(), vec![[0, 1, 2], [0, 2, 3]]);
        o.normals = Some(vec![Vec3::Z; 4]);
        o.material = Some(material);
        o
    }

    fn frame_of(renderer: &mut Renderer, ctx: &GpuContext, asset: &Asset, show_tbn: bool) {
        let scene = GpuScene::upload(ctx, asset).expect("upload");
        let camera = CameraView::look_at(&CameraDescriptor {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            projection: Projection::Orthographic { half_height: 2.0 },
            aspect: 1.0,
            near: 0.1,
            far: 10.0,
        });
        let settings = FrameSettings { show_tbn, ..FrameSettings::default() };
        let frame =
            FrameDescriptor { scene: &scene, camera: &camera, settings: &settings, size: (8, 8) };
        renderer.render_to_image(ctx, &frame).expect("a frame");
    }

    /// A frame makes the pipelines it draws with and no others (each costs a shader compile):
    /// one for a plain opaque square; a mirrored copy and a double-sided, blended material add
    /// theirs; TBN lines theirs when shown.
    #[test]
    fn a_frame_makes_only_the_pipelines_it_draws_with() {
        let ctx = GpuContext::headless().expect("rendering tests need a GPU or lavapipe");
        let mut renderer = Renderer::new(&ctx, IMAGE_FORMAT, 1).expect("a renderer");
        let made = |r: &Renderer| (r.pipelines.made(), r.pipelines.made_tbn());
        assert_eq!(made(&renderer), (0, false));

        let mut asset = Asset {
            model: Model::new(vec![square("a", 0)]),
            materials: vec![Material::default()],
            ..Asset::default()
        };
        frame_of(&mut renderer, &ctx, &asset, false);
        assert_eq!(made(&renderer), (1, false));
        frame_of(&mut renderer, &ctx, &asset, false);
        assert_eq!(made(&renderer), (1, false), "made again");

        let mut mirrored = square("mirrored", 0);
        mirrored.transform = Some(Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
        asset.model.objects.push(mirrored);
        asset.model.objects.push(square("glass", 1));
        asset.materials.push(Material {
            double_sided: true,
            alpha_mode: seamlit_asset::AlphaMode::Blend,
            ..Material::default()
        });
        frame_of(&mut renderer, &ctx, &asset, true);
        assert_eq!(made(&renderer), (3, true));
    }
}
