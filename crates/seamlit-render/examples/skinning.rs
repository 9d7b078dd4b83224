//! Frame time of a skinned, morphed model against the same model plain: a UV sphere (708 x
//! 708 quads = 1,002,528 triangles by default) with 64 joints (two influences a vertex, bands
//! up the sphere) and two morph targets (a bulge and a shear), posed (every joint turned, the
//! targets at 0.5 and 0.3), against the same sphere uploaded without skin or targets, and
//! against the skinned sphere uploaded but never posed (which must draw at the plain cost).
//! Blinn-Phong, one directional light, no textures, offscreen.
//!
//! ```text
//! cargo run --release -p seamlit-render --example skinning -- [--size 640x360] [--frames 5]
//!     [--sides 708] [--rounds 2] [--samples 1]
//! ```
//!
//! Each configuration is timed `--rounds` times, alternating, with `Renderer::time_frames`
//! (median and fastest of N frames after one warm-up frame).

#![allow(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    reason = "band indices of points on the unit sphere, 0..64"
)]

#[path = "../tests/common/shapes.rs"]
#[allow(dead_code, reason = "the example uses the sphere only")]
mod shapes;

use glam::{Mat4, Vec3};
use seamlit_io::{Asset, Material};
use seamlit_mesh::{Influences, Model, MorphTarget, Object};
use seamlit_render::{
    CameraDescriptor, CameraView, FrameDescriptor, FrameSettings, GpuContext, GpuScene,
    IMAGE_FORMAT, Light, LightingModel, ObjectPose, Projection, Renderer,
};

const JOINTS: u32 = 64;

fn arg(name: &str) -> Option<String> {
    let args: Vec<String> = std::env::args().collect();
    args.iter().position(|a| a == name).and_then(|i| args.get(i + 1).cloned())
}

/// The sphere with 64 joints in bands up Y (each vertex between its two nearest bands) and
/// two morph targets.
fn skinned(mut sphere: Object) -> Object {
    let (joints, weights) = sphere
        .positions
        .iter()
        .map(|p| {
            let f = (p.y + 1.0) * 0.5 * (JOINTS - 1) as f32;
            let lo = (f.floor() as u32).min(JOINTS - 1);
            let hi = (lo + 1).min(JOINTS - 1);
            let t = f - lo as f32;
            ([lo, hi, 0, 0], [1.0 - t, t, 0.0, 0.0])
        })
        .unzip();
    sphere.skin = vec![Influences { joints, weights }];
    let bulge =
        sphere.normals.as_ref().map_or_else(Vec::new, |n| n.iter().map(|n| *n * 0.1).collect());
    let shear = sphere.positions.iter().map(|p| Vec3::new(p.y * 0.2, 0.0, 0.0)).collect();
    sphere.morph_targets = vec![
        MorphTarget { position_deltas: bulge, ..MorphTarget::default() },
        MorphTarget { position_deltas: shear, ..MorphTarget::default() },
    ];
    sphere
}

fn asset(object: Object) -> Asset {
    Asset {
        model: Model::new(vec![Object { material: Some(0), ..object }]),
        materials: vec![Material::default()],
        ..Asset::default()
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let size = arg("--size").unwrap_or_else(|| "640x360".into());
    let (w, h) = size.split_once('x').ok_or("--size WxH")?;
    let (width, height): (u32, u32) = (w.parse()?, h.parse()?);
    let frames: usize = arg("--frames").map_or(Ok(5), |f| f.parse())?;
    let side: u32 = arg("--sides").map_or(Ok(708), |f| f.parse())?;
    let rounds: usize = arg("--rounds").map_or(Ok(2), |f| f.parse())?;
    let samples: u32 = arg("--samples").map_or(Ok(1), |f| f.parse())?;

    let ctx = GpuContext::headless()?;
    let sphere = shapes::sphere("sphere", 1.0, side, side, 0.0, 1.0);
    let plain = GpuScene::upload(&ctx, &asset(sphere.clone()))?;
    let unposed = GpuScene::upload(&ctx, &asset(skinned(sphere.clone())))?;
    let mut posed = GpuScene::upload(&ctx, &asset(skinned(sphere)))?;
    let palette = (0..JOINTS).map(|j| Mat4::from_rotation_y(j as f32 * 0.02)).collect();
    posed.set_pose(
        &ctx,
        &[ObjectPose {
            transform: Mat4::IDENTITY,
            joints: Some(palette),
            morph_weights: vec![0.5, 0.3],
        }],
    )?;
    let camera = CameraView::look_at(&CameraDescriptor {
        eye: Vec3::new(0.0, 0.5, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: Projection::Perspective { fov_y_deg: 45.0 },
        aspect: width as f32 / height as f32,
        near: 0.1,
        far: 20.0,
    });
    let settings = FrameSettings {
        lights: vec![Light::Directional {
            direction: Vec3::new(-0.4, -0.5, -1.0),
            color: Vec3::ONE,
            intensity: 1.0,
        }],
        lighting_model: LightingModel::BlinnPhong,
        ..FrameSettings::default()
    };
    let mut renderer = Renderer::new(&ctx, IMAGE_FORMAT, samples)?;
    println!("adapter: {}", ctx.describe());
    println!(
        "{width}x{height}, {samples}x MSAA, {} triangles, Blinn-Phong, 1 light, median (fastest) of {frames} frames\n",
        plain.triangle_count()
    );
    println!("| round | plain | skinned + 2 targets, posed | ratio | skinned, never posed |");
    println!("|---:|---:|---:|---:|---:|");
    let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
    for round in 1..=rounds {
        let mut time = |scene: &GpuScene| {
            let frame = FrameDescriptor {
                scene,
                camera: &camera,
                settings: &settings,
                size: (width, height),
            };
            renderer.time_frames(&ctx, &frame, frames)
        };
        let a = time(&plain)?;
        let b = time(&posed)?;
        let c = time(&unposed)?;
        println!(
            "| {round} | {:.1} ms ({:.1}) | {:.1} ms ({:.1}) | {:.2}x | {:.1} ms ({:.1}) |",
            ms(a.median()),
            ms(a.min()),
            ms(b.median()),
            ms(b.min()),
            ms(b.median()) / ms(a.median()).max(1e-9),
            ms(c.median()),
            ms(c.min()),
        );
    }
    Ok(())
}
