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
pub(crate) fn run(args: &ViewArgs) -> Result<(), Failure> {
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
    let look = crate::draw::Look::new(&args.scene.view, &loaded);
    let environment = look.read_environment()?;
    let base =
        args.scene.fix.apply(loaded.scene.models.first().map_or(FixOptions::DEFAULT, |m| m.fix));
    let settings = panel::Settings {
        mode: args.mode.map_or(base.mode, Mode::from),
        crease_deg: base.crease_angle_deg,
        weighting: base.weighting,
        lighting: look.lighting,
        tone_mapping: look.tone_mapping,
        exposure: look.exposure,
        ambient: look.ambient,
        normal_mapping: !args.scene.view.no_normal_map,
        debug_view: args.scene.view.view.into(),
        show_tbn: args.scene.view.tbn,
        lights: loaded.lights(),
        camera: 0,
        controller: panel::Controller::Orbit,
        playback: panel::Playback::default(),
        variant: args
            .scene
            .variant
            .clone()
            .or_else(|| loaded.scene.models.iter().find_map(|m| m.variant.clone())),
    };
    let options = app::Options {
        input: args.scene.input.clone(),
        size: args.scene.view.size,
        screenshot: args.screenshot.clone(),
        exit_after_frames: args.exit_after_frames,
        fix: FixOverride { mode: None, flags: args.scene.fix.clone() },
        look,
        environment,
        animation: args.scene.animation.clone(),
    };
    let mut viewer =
        app::Viewer::new(loaded, settings, args.scene.view.camera.as_deref(), options)?;
    let event_loop = EventLoop::new().map_err(|e| {
        Failure::processing(format!(
            "cannot open a window: {} (render and compare draw without one)",
            no_window_reason(&e)
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

/// What winit's error says, without the source location that its `os error at FILE:LINE:`
/// prefix carries (a path inside the user's cargo registry means nothing to them).
fn no_window_reason(error: &winit::error::EventLoopError) -> String {
    without_source_location(&error.to_string()).to_owned()
}

/// `os error at PATH.rs:LINE: REASON` -> `REASON`; any other text unchanged.
fn without_source_location(text: &str) -> &str {
    let Some(rest) = text.strip_prefix("os error at ") else { return text };
    rest.find(".rs:")
        .and_then(|i| rest[i..].find(": ").map(|j| i + j + 2))
        .map_or(text, |start| &rest[start..])
}

#[cfg(test)]
mod tests {
    use super::without_source_location;

    #[test]
    fn a_missing_display_is_said_without_winit_source_paths() {
        let winit = "os error at /root/.cargo/registry/src/x/winit-0.30.13/src/platform_impl/linux/mod.rs:765: neither WAYLAND_DISPLAY nor WAYLAND_SOCKET nor DISPLAY is set.";
        assert_eq!(
            without_source_location(winit),
            "neither WAYLAND_DISPLAY nor WAYLAND_SOCKET nor DISPLAY is set."
        );
        assert_eq!(without_source_location("the X server went away"), "the X server went away");
    }
}
