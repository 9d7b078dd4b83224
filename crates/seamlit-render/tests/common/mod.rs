//! Helpers shared by the rendering tests: a context, hand-built objects, pixel maths and
//! writing images for inspection.
#![allow(dead_code, reason = "each test file uses a different subset of the helpers")]

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};
use image::RgbaImage;
use seamlit_io::{Asset, Material, Texture, TextureRef, TextureSource};
use seamlit_mesh::{Model, Object};
use seamlit_render::{FrameDescriptor, FrameSettings, GpuContext, GpuScene, RenderError, Renderer};

/// The headless context (lavapipe on CI).
pub fn ctx() -> GpuContext {
    match GpuContext::headless() {
        Ok(ctx) => ctx,
        Err(e) => panic!("rendering tests need a GPU or lavapipe: {e}"),
    }
}

/// One frame rendered to an image by a fresh [`Renderer::for_images`].
pub fn render_image(
    ctx: &GpuContext,
    frame: &FrameDescriptor<'_>,
) -> Result<RgbaImage, RenderError> {
    Renderer::for_images(ctx)?.render_to_image(ctx, frame)
}

/// A square orthographic view: [`ortho_camera`]`(half)` onto `size` x `size` pixels.
#[derive(Clone, Copy, Debug)]
pub struct Ortho {
    /// World units shown above, below and to each side of the centre.
    pub half: f32,
    /// Pixels per side.
    pub size: u32,
}

/// One frame of `scene` seen through `view`, rendered by a fresh [`Renderer::for_images`].
pub fn render_ortho(
    ctx: &GpuContext,
    scene: &GpuScene,
    settings: &FrameSettings,
    view: Ortho,
) -> RgbaImage {
    let frame = FrameDescriptor {
        scene,
        camera: &ortho_camera(view.half),
        settings,
        size: (view.size, view.size),
    };
    render_image(ctx, &frame).expect("render")
}

/// A square in the plane z = 0, from -half to +half, facing +Z, with normal +Z, tangent +X
/// (w = +1) and UVs 0..1 (V up).
pub fn plane(half: f32) -> Object {
    let mut o = Object::new(
        "plane",
        vec![
            Vec3::new(-half, -half, 0.0),
            Vec3::new(half, -half, 0.0),
            Vec3::new(half, half, 0.0),
            Vec3::new(-half, half, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .with_uvs(vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(0.0, 1.0),
    ]);
    o.normals = Some(vec![Vec3::Z; 4]);
    o.tangents = Some(vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4]);
    o
}

/// A generated texture.
pub fn texture(name: &str, image: RgbaImage) -> Texture {
    Texture { name: name.into(), source: TextureSource::Generated, image: Some(Arc::new(image)) }
}

/// A texture reference to texture `index`.
pub fn tex_ref(index: usize) -> Option<TextureRef> {
    Some(TextureRef { texture: index, tex_coord: 0, transform: None })
}

/// An asset of one object with material 0.
pub fn asset(mut object: Object, material: Material, textures: Vec<Texture>) -> Asset {
    object.material = Some(0);
    Asset {
        model: Model::new(vec![object]),
        materials: vec![material],
        textures,
        ..Asset::default()
    }
}

/// `v` scaled to unit length.
pub fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

/// The dot product.
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Linear to sRGB, as a byte value (not rounded).
pub fn srgb(linear: f64) -> f64 {
    let l = linear.clamp(0.0, 1.0);
    255.0 * if l <= 0.003_130_8 { l * 12.92 } else { 1.055 * l.powf(1.0 / 2.4) - 0.055 }
}

/// Decodes a normal-map byte as the shader does: `b / 255 * 2 - 1`.
pub fn decode(b: u8) -> f64 {
    f64::from(b) / 255.0 * 2.0 - 1.0
}

/// The world position (on z = 0) of pixel (x, y)'s centre for the orthographic camera of
/// [`ortho_camera`] with an image of `size` x `size`.
pub fn pixel_world(x: u32, y: u32, size: u32, half: f32) -> [f64; 3] {
    let s = f64::from(size);
    let h = f64::from(half);
    [((f64::from(x) + 0.5) / s * 2.0 - 1.0) * h, (1.0 - (f64::from(y) + 0.5) / s * 2.0) * h, 0.0]
}

/// An orthographic camera on the +Z axis looking at the origin, showing +-`half`.
pub fn ortho_camera(half: f32) -> seamlit_render::CameraView {
    seamlit_render::CameraView::look_at(&seamlit_render::CameraDescriptor {
        eye: Vec3::new(0.0, 0.0, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: seamlit_render::Projection::Orthographic { half_height: half },
        aspect: 1.0,
        near: 0.1,
        far: 10.0,
    })
}

/// Where tests write images: target/tmp/seamlit-render/NAME.png. Returns the path.
pub fn save(name: &str, image: &RgbaImage) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("seamlit-render");
    std::fs::create_dir_all(&dir).expect("create the test output folder");
    let path = dir.join(format!("{name}.png"));
    image.save(&path).expect("write a test image");
    path
}

/// Asserts pixel (x, y) matches `expected` (sRGB bytes, unrounded) within `tol` per channel.
pub fn assert_pixel(image: &RgbaImage, x: u32, y: u32, expected: [f64; 3], tol: f64, what: &str) {
    let p = image.get_pixel(x, y).0;
    for c in 0..3 {
        let diff = (f64::from(p[c]) - expected[c]).abs();
        assert!(
            diff <= tol,
            "{what}: pixel ({x}, {y}) is {:?}, expected {expected:?} (channel {c} off by {diff:.2})",
            &p[..3]
        );
    }
}

/// Relative luminance of an sRGB byte pixel in linear light.
pub fn luminance(p: &image::Rgba<u8>) -> f64 {
    let lin = |b: u8| {
        let c = f64::from(b) / 255.0;
        if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
    };
    0.2126 * lin(p[0]) + 0.7152 * lin(p[1]) + 0.0722 * lin(p[2])
}

pub mod shapes;
