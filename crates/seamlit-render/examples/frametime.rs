//! Frame time of the renderer over repeated frames: 1 and 16 lights at about 100k and 1M
//! triangles, normal mapping on, 4x MSAA, offscreen.
//!
//! ```text
//! cargo run --release -p seamlit-render --example frametime -- [--size 1280x720] [--frames 20]
//!     [--samples 4] [--anisotropy 16] [--sides 224,708] [--lights 1,16]
//!     [--lighting blinn-phong|pbr] [--environment none|builtin] [--shadows N]
//! ```
//!
//! `--environment builtin` lights PBR materials with the procedural studio as well (split-sum
//! image-based light) and draws it behind the sphere; `--shadows N` gives the first N
//! directional and spot lights shadow maps (default 0).
//!
//! Each frame is recorded, submitted and waited for (`Renderer::time_frames`); the table gives
//! the median and the fastest of N frames after one warm-up frame.

#[path = "../tests/common/shapes.rs"]
mod shapes;

use std::sync::Arc;

use glam::Vec3;
use seamlit_io::{Asset, Material, Texture, TextureRef, TextureSource};
use seamlit_mesh::Model;
use seamlit_render::{
    CameraDescriptor, CameraView, Environment, FrameDescriptor, FrameSettings, GpuContext,
    GpuEnvironment, GpuScene, IMAGE_FORMAT, Light, LightingModel, Projection, Renderer,
    TextureOptions, ToneMapping,
};

fn arg(name: &str) -> Option<String> {
    let args: Vec<String> = std::env::args().collect();
    args.iter().position(|a| a == name).and_then(|i| args.get(i + 1).cloned())
}

/// `count` lights: one directional, then point and spot lights around the model.
fn lights(count: usize) -> Vec<Light> {
    (0..count)
        .map(|i| {
            let a = i as f32 / count as f32 * std::f32::consts::TAU;
            let position = Vec3::new(a.cos() * 2.5, 1.0 + (i % 3) as f32 * 0.5, a.sin() * 2.5);
            let color = Vec3::new(0.5 + 0.5 * a.cos(), 0.6, 0.5 + 0.5 * a.sin());
            match i % 3 {
                0 => Light::Directional { direction: -position, color, intensity: 0.3 },
                1 => Light::Point { position, color, intensity: 2.0, range: 6.0 },
                _ => Light::Spot {
                    position,
                    direction: -position,
                    color,
                    intensity: 4.0,
                    range: 8.0,
                    inner_cone_deg: 15.0,
                    outer_cone_deg: 30.0,
                },
            }
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let size = arg("--size").unwrap_or_else(|| "1280x720".into());
    let (w, h) = size.split_once('x').ok_or("--size WxH")?;
    let (width, height): (u32, u32) = (w.parse()?, h.parse()?);
    let frames: usize = arg("--frames").map_or(Ok(20), |f| f.parse())?;
    let samples: u32 = arg("--samples").map_or(Ok(4), |f| f.parse())?;
    let anisotropy: u16 = arg("--anisotropy").map_or(Ok(16), |f| f.parse())?;
    // Sphere resolutions: 224 x 224 quads = 100,352 triangles, 708 x 708 = 1,002,528.
    let sides: Vec<u32> = arg("--sides")
        .unwrap_or_else(|| "224,708".into())
        .split(',')
        .map(str::parse)
        .collect::<Result<_, _>>()?;
    let light_counts: Vec<usize> = arg("--lights")
        .unwrap_or_else(|| "1,16".into())
        .split(',')
        .map(str::parse)
        .collect::<Result<_, _>>()?;

    let shadow_maps: usize = arg("--shadows").map_or(Ok(0), |f| f.parse())?;
    let lighting_model = match arg("--lighting").as_deref() {
        None | Some("blinn-phong") => LightingModel::BlinnPhong,
        Some("pbr") => LightingModel::Pbr,
        Some(other) => return Err(format!("--lighting {other}: blinn-phong or pbr").into()),
    };

    let ctx = GpuContext::headless()?;
    println!("adapter: {}", ctx.describe());
    println!(
        "{width}x{height}, {samples}x MSAA, {anisotropy}x anisotropic, normal mapping on, {lighting_model:?}, {shadow_maps} shadow maps, median (min) of {frames} frames\n"
    );
    println!("| triangles | lights | median frame | fastest frame |");
    println!("|---:|---:|---:|---:|");
    let mut renderer = Renderer::new(&ctx, IMAGE_FORMAT, samples)?;
    match arg("--environment").as_deref() {
        None | Some("none") => {}
        Some("builtin") => {
            let started = std::time::Instant::now();
            let environment = GpuEnvironment::new(&ctx, &Environment::Builtin)?;
            ctx.device().poll(wgpu::PollType::wait_indefinitely())?;
            println!(
                "environment prefiltered in {:.0} ms\n",
                started.elapsed().as_secs_f64() * 1e3
            );
            renderer.set_environment(Some(environment));
        }
        Some(other) => return Err(format!("--environment {other}: none or builtin").into()),
    }
    for &side in &sides {
        let mut sphere = shapes::sphere("sphere", 1.0, side, side, 0.0, 1.0);
        sphere.material = Some(0);
        let tex = |name: &str, image| Texture {
            name: name.into(),
            source: TextureSource::Generated,
            image: Some(Arc::new(image)),
        };
        let asset = Asset {
            model: Model::new(vec![sphere]),
            materials: vec![Material {
                base_color_texture: Some(TextureRef { texture: 0, tex_coord: 0, transform: None }),
                normal_texture: Some(TextureRef { texture: 1, tex_coord: 0, transform: None }),
                ..Material::default()
            }],
            textures: vec![
                tex("checker", shapes::checker(512)),
                tex("bricks", shapes::brick_normal_map(512)),
            ],
            ..Asset::default()
        };
        let options = TextureOptions { anisotropy, ..TextureOptions::DEFAULT };
        let scene = GpuScene::upload_parts(
            &ctx,
            &asset.model,
            &asset.materials,
            &asset.textures,
            &options,
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
        for &count in &light_counts {
            let settings = FrameSettings {
                lights: lights(count),
                lighting_model,
                tone_mapping: ToneMapping::default_for(lighting_model),
                shadow_maps,
                ..FrameSettings::default()
            };
            let times = renderer.time_frames(
                &ctx,
                &FrameDescriptor {
                    scene: &scene,
                    camera: &camera,
                    settings: &settings,
                    size: (width, height),
                },
                frames,
            )?;
            println!(
                "| {} | {count} | {:.2} ms | {:.2} ms |",
                scene.triangle_count(),
                times.median().as_secs_f64() * 1e3,
                times.min().as_secs_f64() * 1e3
            );
        }
    }
    Ok(())
}
