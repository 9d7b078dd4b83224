//! Handedness: a quad whose right half mirrors the UVs of its left half (tangent -X, w = -1)
//! carries a normal-mapped bump in each half. Lit from the upper right, the lit side of each
//! bump must be its upper right side in both halves. Ignoring `w` (or the mirrored tangent)
//! would light the lower (or left) side of the mirrored bump.

mod common;

use common::{Ortho, ctx, luminance, render_ortho, save, tex_ref, texture};
use glam::{Vec2, Vec3, Vec4};
use image::RgbaImage;
use seamlit_io::{Asset, Material};
use seamlit_mesh::{Model, Object};
use seamlit_render::{FrameSettings, GpuScene, Light, LightingModel};

const SIZE: u32 = 128;

/// A hemispherical bump of radius 0.35 in the middle of the texture, V up the image.
fn bump_normal_map() -> RgbaImage {
    let n = 64;
    RgbaImage::from_fn(n, n, |i, j| {
        let u = (f64::from(i) + 0.5) / f64::from(n) - 0.5;
        let v = 0.5 - (f64::from(j) + 0.5) / f64::from(n);
        let r2 = 0.35f64 * 0.35;
        let d2 = u * u + v * v;
        let normal = if d2 < r2 * 0.95 {
            let h = (r2 - d2).sqrt();
            let len = (u * u / (h * h) + v * v / (h * h) + 1.0).sqrt();
            [u / h / len, v / h / len, 1.0 / len]
        } else {
            [0.0, 0.0, 1.0]
        };
        #[expect(clippy::cast_possible_truncation, clippy::cast_sign_loss, reason = "in 0..=255")]
        let e = |c: f64| ((c * 0.5 + 0.5) * 255.0).round() as u8;
        image::Rgba([e(normal[0]), e(normal[1]), e(normal[2]), 255])
    })
}

/// Half of the quad: x from x0 to x0 + 1, y from -0.5 to 0.5, U running with +X or mirrored.
fn half(name: &str, x0: f32, mirrored: bool) -> Object {
    let (u0, u1) = if mirrored { (1.0, 0.0) } else { (0.0, 1.0) };
    let mut o = Object::new(
        name,
        vec![
            Vec3::new(x0, -0.5, 0.0),
            Vec3::new(x0 + 1.0, -0.5, 0.0),
            Vec3::new(x0 + 1.0, 0.5, 0.0),
            Vec3::new(x0, 0.5, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .with_uvs(vec![
        Vec2::new(u0, 0.0),
        Vec2::new(u1, 0.0),
        Vec2::new(u1, 1.0),
        Vec2::new(u0, 1.0),
    ]);
    o.normals = Some(vec![Vec3::Z; 4]);
    // T follows increasing U; B = cross(N, T) * w must point up the image (+Y, V up).
    let tangent =
        if mirrored { Vec4::new(-1.0, 0.0, 0.0, -1.0) } else { Vec4::new(1.0, 0.0, 0.0, 1.0) };
    o.tangents = Some(vec![tangent; 4]);
    o.material = Some(0);
    o
}

/// The pixel at world (x, y) for the orthographic camera showing +-1.
fn pixel(x: f32, y: f32) -> (u32, u32) {
    let s = SIZE as f32;
    #[expect(clippy::cast_possible_truncation, clippy::cast_sign_loss, reason = "inside the image")]
    let p = (((x + 1.0) * 0.5 * s) as u32, ((1.0 - y) * 0.5 * s) as u32);
    p
}

#[test]
fn mirrored_uvs_light_the_bump_on_the_same_side() {
    let ctx = ctx();
    let asset = Asset {
        model: Model::new(vec![half("left", -1.0, false), half("right", 0.0, true)]),
        materials: vec![Material {
            base_color: [0.8, 0.8, 0.8, 1.0],
            specular: [0.0; 3],
            normal_texture: tex_ref(0),
            ..Material::default()
        }],
        textures: vec![texture("bump", bump_normal_map())],
        ..Asset::default()
    };
    let scene = GpuScene::upload(&ctx, &asset).expect("upload");
    let settings = FrameSettings {
        lights: vec![Light::Directional {
            direction: Vec3::new(-1.0, -1.0, -0.7),
            color: Vec3::ONE,
            intensity: 1.0,
        }],
        ambient: Vec3::splat(0.05),
        lighting_model: LightingModel::Lambert,
        ..FrameSettings::default()
    };
    let image = render_ortho(&ctx, &scene, &settings, Ortho { half: 1.0, size: SIZE });
    let path = save("handedness_mirrored_bump", &image);
    let lum = |x: f32, y: f32| {
        let (px, py) = pixel(x, y);
        luminance(image.get_pixel(px, py))
    };
    for (name, cx) in [("left (U runs with +X)", -0.5), ("right (mirrored U)", 0.5)] {
        let d = 0.2;
        let (right, left, up, down) = (lum(cx + d, 0.0), lum(cx - d, 0.0), lum(cx, d), lum(cx, -d));
        assert!(
            right > left + 0.1,
            "{name}: the bump's right side ({right:.3}) must be lit more than its left ({left:.3}); see {}",
            path.display()
        );
        assert!(
            up > down + 0.1,
            "{name}: the bump's upper side ({up:.3}) must be lit more than its lower ({down:.3}); see {}",
            path.display()
        );
    }
}
