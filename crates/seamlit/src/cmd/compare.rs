//! `seamlit compare`: flat, object and model side by side, labelled (the paper's Figures 9,
//! 11 and 12).

use image::RgbaImage;
use seamlit_mesh::Mode;

use crate::cli::CompareArgs;
use crate::draw::{Gpu, check_png, frame_settings};
use crate::failure::{Classify, Failure};
use crate::picture::{labelled_row, save_png};
use crate::prepare::{FixOverride, Loaded, bounds_of, pick_camera};

/// The three modes with their titles and the paper figure each reproduces.
pub const MODES: [(Mode, &str, &str); 3] = [
    (Mode::Flat, "flat", "face normals (paper Fig. 9)"),
    (Mode::Object, "object", "smooth per object: seams (Fig. 11)"),
    (Mode::Model, "model", "smooth across objects (Fig. 12)"),
];

/// Renders `loaded` in each mode; returns the images in [`MODES`] order. All three models
/// are built (and the camera found) before the GPU is opened, so bad input is reported
/// first.
///
/// # Errors
/// As the fix and the rendering.
pub fn render_modes(
    loaded: &Loaded,
    flags: &crate::cli::FixFlags,
    view: &crate::cli::ViewFlags,
    input: &std::path::Path,
    gpu: Option<Gpu>,
) -> Result<(Vec<RgbaImage>, Gpu), Failure> {
    let size = view.size;
    let aspect = size.0 as f32 / size.1 as f32;
    let settings = frame_settings(view, loaded.lights());
    let mut jobs = Vec::with_capacity(MODES.len());
    for (mode, ..) in MODES {
        let asset = loaded.build(&FixOverride { mode: Some(mode), flags: flags.clone() })?;
        let bounds = bounds_of(&asset);
        let camera = pick_camera(&loaded.cameras(bounds, aspect), view.camera.as_deref(), input)?;
        jobs.push((asset, camera, bounds));
    }
    let mut gpu = match gpu {
        Some(g) => g,
        None => Gpu::open()?,
    };
    let mut images = Vec::with_capacity(MODES.len());
    for (asset, camera, bounds) in &jobs {
        images.push(gpu.render(asset, camera, *bounds, &settings, size)?.1);
    }
    Ok((images, gpu))
}

/// Puts the mode images side by side with their labels.
#[must_use]
pub fn grid(images: Vec<RgbaImage>) -> RgbaImage {
    let panels: Vec<_> = images
        .into_iter()
        .zip(MODES)
        .map(|(img, (_, title, subtitle))| (img, format!("--mode {title}"), subtitle.to_string()))
        .collect();
    labelled_row(&panels)
}

/// Runs `seamlit compare`.
///
/// # Errors
/// Bad input before any GPU work; processing failures after.
pub fn run(args: &CompareArgs) -> Result<(), Failure> {
    check_png(&args.output)?;
    let loaded = args.scene.load()?;
    let (images, _) =
        render_modes(&loaded, &args.scene.fix, &args.scene.view, &args.scene.input, None)?;
    let grid = grid(images);
    save_png(&grid, &args.output).processing()?;
    println!(
        "wrote {} ({}x{}: flat | object | model)",
        args.output.display(),
        grid.width(),
        grid.height()
    );
    Ok(())
}
