//! `seamlit demo`: the embedded teapot in the three modes, the seam report before and after,
//! and the fixed model as GLB. Needs no files.

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::Mat4;
use seamlit_io::{Asset, SaveOptions};
use seamlit_mesh::{FixOptions, Mode};
use seamlit_render::LightingModel;
use seamlit_scene::{Scene, SceneModel, demo};

use crate::cli::{DemoArgs, FixFlags, LightingArg, TangentsArg, ViewArg, ViewFlags};
use crate::cmd::compare::{MODES, grid, render_modes};
use crate::cmd::inspect;
use crate::failure::{Classify, Failure};
use crate::picture::save_png;
use crate::prepare::Loaded;

/// What the demo calls the embedded model in messages.
const TEAPOT_NAME: &str = "teapot (embedded Newell patches)";

/// Runs `seamlit demo`.
///
/// # Errors
/// [`Failure::Processing`] when the GPU or a write fails.
pub(crate) fn run(args: &DemoArgs) -> Result<(), Failure> {
    let start = Instant::now();
    let asset = demo::teapot_asset(args.tessellation).processing()?;
    print_seam_report(&asset)?;
    crate::output::prepare_folder(&args.out)?;
    let (mut written, adapter) = write_pictures(args, demo_scene(asset.clone()))?;
    written.push(write_fixed_model(asset, &args.out)?);
    for path in &written {
        println!("wrote {}", path.display());
    }
    println!("({} on {adapter}, {:.1} s)", format_size(args.size), start.elapsed().as_secs_f64());
    Ok(())
}

/// Prints the model's size and the seam report before (`object` mode) and after (`model`).
fn print_seam_report(asset: &Asset) -> Result<(), Failure> {
    println!(
        "The Newell teapot: {} Bezier patches tessellated into {} objects, {} triangles, with a brick normal map made in code.\n",
        asset.model.objects.len(),
        asset.model.objects.len(),
        asset.model.triangle_count()
    );
    let reports = inspect::measure(&asset.model, &FixOptions::DEFAULT, Path::new(TEAPOT_NAME))?;
    println!(
        "Seam report (`seamlit inspect`): before = `object` mode, normals per object as most tools compute them;"
    );
    println!("after = `model` mode, seamlit's default.\n");
    print!("{}", inspect::table(&reports));
    let [_, (_, object, _), (_, model, _)] = &reports.modes;
    let fmt = |a: Option<f32>| a.map_or_else(|| "-".into(), |a| format!("{a:.2}°"));
    println!(
        "\nAcross the {} mesh edges where patches meet, normals differ by up to {} before and {} after.\n",
        object.cross_object.edges,
        fmt(object.cross_object.max_normal_angle_deg),
        fmt(model.cross_object.max_normal_angle_deg)
    );
    Ok(())
}

/// Renders the three modes and writes them, then the grid of all three, into `args.out`.
/// Returns the files written and the adapter that drew them.
fn write_pictures(args: &DemoArgs, loaded: Loaded) -> Result<(Vec<PathBuf>, String), Failure> {
    let view = ViewFlags {
        size: args.size,
        camera: None,
        view: ViewArg::Lit,
        lighting: Some(LightingArg::BlinnPhong),
        tone_mapping: None,
        exposure: None,
        ambient: None,
        environment: None,
        environment_intensity: None,
        environment_rotation: None,
        background: None,
        shadows: Some(crate::cli::Switch::Off),
        no_normal_map: false,
        tbn: false,
    };
    let (images, gpu) = render_modes(
        &loaded,
        &demo_flags(),
        &view,
        &crate::cli::AnimationFlags::default(),
        Path::new(TEAPOT_NAME),
        None,
    )?;
    let mut written: Vec<PathBuf> = Vec::new();
    for (image, (_, name, _)) in images.iter().zip(MODES) {
        let path = args.out.join(format!("{name}.png"));
        save_png(image, &path).processing()?;
        written.push(path);
    }
    let compare = args.out.join("compare.png");
    save_png(&grid(images), &compare).processing()?;
    written.push(compare);
    Ok((written, gpu.ctx.describe()))
}

/// Fixes the teapot in `model` mode and writes it as `teapot-fixed.glb` into `out`.
fn write_fixed_model(asset: Asset, out: &Path) -> Result<PathBuf, Failure> {
    let fixed = seamlit_mesh::fix(&asset.model, &FixOptions::DEFAULT.with_mode(Mode::Model))
        .map_err(|e| Failure::processing(format!("{TEAPOT_NAME}: {e}")))?;
    let glb = out.join("teapot-fixed.glb");
    seamlit_io::save(&Asset { model: fixed, ..asset }, &glb, &SaveOptions::default())
        .processing()?;
    Ok(glb)
}

fn format_size((w, h): (u32, u32)) -> String {
    format!("{w}x{h} per view")
}

/// The demo as a scene: the teapot (already placed), the demo lights and camera.
fn demo_scene(asset: Asset) -> Loaded {
    let model = SceneModel {
        name: "teapot".into(),
        path: PathBuf::from(TEAPOT_NAME),
        transform: Mat4::IDENTITY,
        fix: FixOptions::DEFAULT,
        materials: Vec::new(),
        animation: None,
        time: None,
        variant: None,
    };
    let scene = Scene {
        source: None,
        models: vec![model.clone()],
        lights: demo::lights(),
        cameras: vec![demo::camera()],
        lighting: Some(LightingModel::BlinnPhong),
        render: seamlit_scene::RenderOptions::default(),
    };
    Loaded { scene, parts: vec![(model, asset)] }
}

/// The demo's fix flags: seamlit's own tangents, named, since the brick map is drawn in code
/// in UV space (baked against no tangent generator), so the MikkTSpace default for normal
/// maps without tangents does not apply.
fn demo_flags() -> FixFlags {
    FixFlags { tangents: Some(TangentsArg::Seamlit), ..FixFlags::default() }
}
