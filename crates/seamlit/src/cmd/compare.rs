//! `seamlit compare`: flat, object and model side by side, labelled (the paper's Figures 9,
//! 11 and 12).

use image::RgbaImage;
use seamlit_mesh::Mode;

use crate::cli::CompareArgs;
use crate::draw::{Gpu, Look, check_png, frame_settings};
use crate::failure::{Classify, Failure};
use crate::picture::{frame, labelled_row, most_different_window, save_png, stack, zoom};
use crate::prepare::{FixOverride, Loaded, drawn_bounds, pick_camera};

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
pub(crate) fn render_modes(
    loaded: &Loaded,
    flags: &crate::cli::FixFlags,
    view: &crate::cli::ViewFlags,
    animation: &crate::cli::AnimationFlags,
    input: &std::path::Path,
    gpu: Option<Gpu>,
) -> Result<(Vec<RgbaImage>, Gpu), Failure> {
    let size = view.size;
    let aspect = size.0 as f32 / size.1 as f32;
    let settings = frame_settings(view, loaded);
    let environment = Look::new(view, loaded).read_environment()?;
    let mut jobs = Vec::with_capacity(MODES.len());
    for (mode, ..) in MODES {
        let asset = loaded.build(&FixOverride { mode: Some(mode), flags: flags.clone() })?;
        let moment = crate::animate::moment(animation, loaded, &asset, input)?;
        let own = crate::animate::own_moments(animation, loaded, &asset, input)?;
        let poses = crate::animate::poses(&asset, moment, &own);
        let bounds = drawn_bounds(&asset, poses.as_deref());
        let camera = pick_camera(&loaded.cameras(bounds, aspect), view.camera.as_deref(), input)?;
        jobs.push((asset, poses, camera, bounds));
    }
    let mut gpu = match gpu {
        Some(g) => g,
        None => Gpu::open()?,
    };
    gpu.set_environment(environment.as_ref())?;
    let mut images = Vec::with_capacity(MODES.len());
    for (asset, poses, camera, bounds) in &jobs {
        images.push(gpu.render(asset, poses.as_deref(), camera, *bounds, &settings, size)?.1);
    }
    Ok((images, gpu))
}

/// Puts the mode images side by side with their labels.
///
/// Under them, when `object` and `model` differ, a second row enlarges the same window of each
/// panel [`ZOOM`] times: the window where the two differ in the most pixels, that is, where a
/// seam between objects shows most (at 640x480 a seam of the demo teapot covers a few thousand
/// pixels of 307,200, invisible at full size). The window is framed in the panels above.
#[must_use]
pub(crate) fn grid(mut images: Vec<RgbaImage>) -> RgbaImage {
    let window = match images.as_slice() {
        [_, object, model] => {
            let size = (object.width() / ZOOM, object.height() / ZOOM);
            most_different_window(object, model, size, SEAM_THRESHOLD)
        }
        _ => None,
    };
    let insets: Vec<_> =
        window.map(|w| images.iter().map(|img| zoom(img, w, ZOOM)).collect()).unwrap_or_default();
    if let Some(w) = window {
        images.iter_mut().for_each(|img| frame(img, w, FRAME_COLOUR));
    }
    let panels: Vec<_> = images
        .into_iter()
        .zip(MODES)
        .map(|(img, (_, title, subtitle))| (img, format!("--mode {title}"), subtitle.to_string()))
        .collect();
    let top = labelled_row(&panels);
    if insets.is_empty() {
        return top;
    }
    let titles = MODES.map(|(_, title, _)| title);
    let zoomed: Vec<_> = insets
        .into_iter()
        .zip(titles)
        .map(|(img, title)| {
            let subtitle = "pixels enlarged, not smoothed: where object and model differ most";
            (img, format!("{title}, x{ZOOM} at the framed square"), subtitle.to_owned())
        })
        .collect();
    stack(&top, &labelled_row(&zoomed), 4)
}

/// How many times the inset enlarges the window (which is a fifth of the panel each way).
pub const ZOOM: u32 = 5;

/// Channel difference (of 255) above which object and model count as different in a pixel.
const SEAM_THRESHOLD: u8 = 8;

/// The frame around the enlarged window: a yellow that stands out on the dark background.
const FRAME_COLOUR: [u8; 3] = [255, 210, 60];

/// Runs `seamlit compare`.
///
/// # Errors
/// Bad input before any GPU work; processing failures after.
pub(crate) fn run(args: &CompareArgs) -> Result<(), Failure> {
    check_png(&args.output)?;
    let loaded = args.scene.load()?;
    let (images, _) = render_modes(
        &loaded,
        &args.scene.fix,
        &args.scene.view,
        &args.scene.animation,
        &args.scene.input,
        None,
    )?;
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
