//! `seamlit-bench render`: files rendered with the normals and tangents they carry (no fix),
//! side by side, so that a reader sees what each tool wrote.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};
use clap::Args;
use glam::Vec3;
use image::{Rgba, RgbaImage, imageops};
use seamlit_io::{Asset, LoadOptions};
use seamlit_render::{
    DebugView, FrameDescriptor, FrameSettings, GpuContext, GpuScene, IMAGE_FORMAT, Renderer,
};
use seamlit_scene::{Camera, demo, lights::three_point_rig};

/// Pixels between pictures.
const GAP: u32 = 4;

/// `seamlit-bench render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The PNG to write: one column per FILE, one row per view.
    #[arg(long, short)]
    output: PathBuf,
    /// The files, left to right.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Each picture's size, WIDTHxHEIGHT.
    #[arg(long, default_value = "480x360", value_parser = parse_size)]
    size: (u32, u32),
    /// Rows, top to bottom: lit (material and normal map), lighting (white, normal map),
    /// plain (white, no normal map: the vertex normals alone), normals (world normals as
    /// colour), tangents (world tangents as colour).
    #[arg(long, value_delimiter = ',', default_value = "lit")]
    views: Vec<String>,
    /// Use the demo teapot's material (brick normal map), lights and camera for every file.
    #[arg(long)]
    demo: bool,
    /// Camera position `x,y,z` (with --target), instead of the default camera.
    #[arg(long, value_parser = parse_vec3, requires = "target")]
    eye: Option<Vec3>,
    /// Camera target `x,y,z` (with --eye).
    #[arg(long, value_parser = parse_vec3, requires = "eye")]
    target: Option<Vec3>,
}

/// Renders the grid and writes it.
///
/// # Errors
/// A file that does not load, no GPU, or a failed write.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let views = args.views.iter().map(|v| parse_view(v)).collect::<anyhow::Result<Vec<_>>>()?;
    let assets =
        args.files.iter().map(|f| load(f, args.demo)).collect::<anyhow::Result<Vec<_>>>()?;
    let ctx = GpuContext::headless()?;
    let samples = if ctx.supported_sample_counts(IMAGE_FORMAT).contains(&4) { 4 } else { 1 };
    let mut renderer = Renderer::new(&ctx, IMAGE_FORMAT, samples)?;
    let (w, h) = args.size;
    let aspect = w as f32 / h as f32;
    let columns = u32::try_from(assets.len()).context("too many files for one picture")?;
    let rows = u32::try_from(views.len()).context("too many views for one picture")?;
    let mut grid = RgbaImage::from_pixel(
        columns * w + (columns - 1) * GAP,
        rows * h + (rows - 1) * GAP,
        Rgba([255, 255, 255, 255]),
    );
    for (col, asset) in (0u32..).zip(&assets) {
        let bounds = asset.model.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
        let camera = match (args.eye, args.target) {
            (Some(eye), Some(target)) => {
                let mut c = Camera::look_at("bench", eye, target);
                c.fov_y_deg = 30.0;
                c
            }
            _ if args.demo => demo::camera(),
            _ => Camera::framing(bounds, aspect),
        };
        let view = camera.view(aspect, Some(bounds));
        let scene = GpuScene::upload(&ctx, asset)?;
        for (row, debug_view) in (0u32..).zip(&views) {
            let (debug_view, normal_mapping) = *debug_view;
            let settings = FrameSettings {
                lights: if args.demo { demo::lights() } else { three_point_rig() },
                debug_view,
                normal_mapping,
                ..FrameSettings::default()
            };
            let image = renderer.render_to_image(
                &ctx,
                &FrameDescriptor {
                    scene: &scene,
                    camera: &view,
                    settings: &settings,
                    size: (w, h),
                },
            )?;
            let x = col * (w + GAP);
            let y = row * (h + GAP);
            imageops::replace(&mut grid, &image, i64::from(x), i64::from(y));
        }
    }
    write_png(&grid, &args.output)?;
    println!(
        "wrote {} ({} x {} pictures on {})",
        args.output.display(),
        columns,
        rows,
        ctx.describe()
    );
    Ok(())
}

/// Loads `path` as it is; with `demo`, every object gets the demo's brick material.
fn load(path: &Path, demo: bool) -> anyhow::Result<Asset> {
    if !demo {
        // As the command line loads a model file: a default material where an object has none.
        let scene = seamlit_scene::Scene::from_model_path(path);
        let [model] = &scene.models[..] else { anyhow::bail!("{}: not one model", path.display()) };
        return Ok(model.load_asset(&LoadOptions::DEFAULT)?);
    }
    let mut asset = seamlit_io::load(path, &LoadOptions::DEFAULT)?;
    asset.materials = vec![demo::material()];
    asset.textures = vec![demo::bricks_texture()];
    for object in &mut asset.model.objects {
        object.material = Some(0);
    }
    Ok(asset)
}

/// Writes to a temporary name beside `path`, then renames.
fn write_png(image: &RgbaImage, path: &Path) -> anyhow::Result<()> {
    let tmp = path.with_extension("png.tmp");
    image
        .save_with_format(&tmp, image::ImageFormat::Png)
        .with_context(|| format!("{}: cannot write", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("{}: cannot write", path.display()))
}

/// A view name: what the shader outputs and whether normal mapping is on.
fn parse_view(name: &str) -> anyhow::Result<(DebugView, bool)> {
    Ok(match name {
        "lit" => (DebugView::Lit, true),
        "lighting" => (DebugView::LightingOnly, true),
        "plain" => (DebugView::LightingOnly, false),
        "normals" => (DebugView::Normals, false),
        "tangents" => (DebugView::Tangents, false),
        other => bail!("unknown view {other:?} (lit, lighting, plain, normals, tangents)"),
    })
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let parse = |t: &str| t.parse::<u32>().ok().filter(|n| (16..=4096).contains(n));
    match s.split_once('x').map(|(w, h)| (parse(w), parse(h))) {
        Some((Some(w), Some(h))) => Ok((w, h)),
        _ => Err(format!("{s:?} is not WIDTHxHEIGHT with sides 16..=4096")),
    }
}

fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s.split(',').filter_map(|t| t.trim().parse().ok()).collect();
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(x, y, z)),
        _ => Err(format!("{s:?} is not x,y,z")),
    }
}
