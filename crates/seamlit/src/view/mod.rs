//! `seamlit view`: a winit window with a wgpu surface and an egui panel: mode, crease angle
//! (re-running the fix live), weighting, lighting model, normal mapping, lights, cameras
//! (orbit and FPS controllers), debug views, the frame time, and screenshots (F12).

mod app;
mod capture;
mod input;
mod panel;

use seamlit_mesh::{FixOptions, Mode};
use winit::event_loop::EventLoop;

use crate::cli::ViewArgs;
use crate::failure::Failure;
use crate::prepare::FixOverride;

/// Runs `seamlit view`.
///
/// # Errors
/// Bad input before the window opens; processing failures (no display, no GPU) after.
pub fn run(args: &ViewArgs) -> Result<(), Failure> {
    if let Some(shot) = &args.screenshot
        && !shot.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return Err(Failure::input(format!(
            "{}: the screenshot must be a .png file",
            shot.display()
        )));
    }
    if let Some(shot) = &args.screenshot {
        crate::output::prepare_folder_of(shot)?;
    }
    let loaded = args.scene.load()?;
    let base =
        args.scene.fix.apply(loaded.scene.models.first().map_or(FixOptions::DEFAULT, |m| m.fix));
    let settings = panel::Settings {
        mode: args.mode.map_or(base.mode, Mode::from),
        crease_deg: base.crease_angle_deg,
        weighting: base.weighting,
        lighting: args.scene.view.lighting.into(),
        normal_mapping: !args.scene.view.no_normal_map,
        debug_view: args.scene.view.view.into(),
        show_tbn: args.scene.view.tbn,
        lights: loaded.lights(),
        camera: 0,
        controller: panel::Controller::Orbit,
    };
    let options = app::Options {
        input: args.scene.input.clone(),
        size: args.scene.view.size,
        screenshot: args.screenshot.clone(),
        exit_after_frames: args.exit_after_frames,
        fix: FixOverride { mode: None, flags: args.scene.fix.clone() },
    };
    let mut viewer =
        app::Viewer::new(loaded, settings, args.scene.view.camera.as_deref(), options)?;
    let event_loop = EventLoop::new().map_err(|e| {
        Failure::processing(format!(
            "cannot open a window (is there a display? DISPLAY or WAYLAND_DISPLAY): {e}"
        ))
    })?;
    event_loop
        .run_app(&mut viewer)
        .map_err(|e| Failure::processing(format!("the window's event loop failed: {e}")))?;
    match viewer.failure.take() {
        Some(f) => Err(f),
        None => Ok(()),
    }
}
