//! `demo`, `view`, and the rules every command shares for output folders and OS errors.

use super::*;

/// Held while a test runs `xvfb-run -a`: two at once can race for one display number, and
/// under load one of them then failed its own clean-up (exit status 5, "problem while cleaning
/// up temporary directory") after the viewer had exited as it should.
static XVFB: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_xvfb_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    XVFB.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

// --- demo --------------------------------------------------------------------------------

#[test]
fn demo_writes_its_pictures_and_model_and_prints_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let o = seamlit(&[
        "demo",
        "--out",
        &out.display().to_string(),
        "--size",
        "160x120",
        "--tessellation",
        "4",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        listing(&out),
        ["compare.png", "flat.png", "model.png", "object.png", "teapot-fixed.glb"]
    );
    let text = stdout(&o);
    assert!(text.contains("32 objects"));
    assert!(text.contains("normal angle across seams, max"));
    let compare = image::open(out.join("compare.png")).unwrap();
    assert_eq!(compare.width(), 3 * 160 + 8);
    let fixed =
        seamlit_io::load(&out.join("teapot-fixed.glb"), &seamlit_io::LoadOptions::DEFAULT).unwrap();
    assert_eq!(fixed.model.objects.len(), 32);
    // The brick normal map travels with the model.
    assert!(fixed.materials.iter().any(|m| m.normal_texture.is_some()));
}

// --- view --------------------------------------------------------------------------------

#[test]
fn view_refuses_bad_input_before_opening_a_window() {
    assert_bad_input(&seamlit(&["view", "/nonexistent/scene.toml"]), &["/nonexistent/scene.toml"]);
    assert_bad_input(&seamlit(&["view", &teapot(), "--screenshot", "shot.bmp"]), &["shot.bmp"]);
    assert_bad_input(&seamlit(&["view", &example("teapot.toml"), "--camera", "nope"]), &["nope"]);
}

/// The viewer for real: a window under Xvfb (installed by .ci/run), 20 frames, a screenshot of
/// the window, which must show the panel on the left and the teapot on the right.
#[test]
fn view_opens_a_window_under_xvfb_and_its_screenshot_shows_the_teapot() {
    let dir = tempfile::tempdir().unwrap();
    // The folder does not exist yet: view creates it, as every command does.
    let shot = dir.path().join("shots/today/view.png");
    let _xvfb = one_xvfb_at_a_time();
    let o = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24", env!("CARGO_BIN_EXE_seamlit"), "view"])
        .arg(example("teapot.toml"))
        .args([
            "--size",
            "800x600",
            "--tessellation",
            "6",
            "--exit-after-frames",
            "20",
            "--screenshot",
        ])
        .arg(&shot)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("xvfb-run is installed (.ci/run installs the xvfb package)");
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&shot).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (800, 600));
    // Right of the panel (which is under 300 px wide), the teapot covers a good part of the
    // picture; the panel itself has text in it.
    let model = foreground_fraction(&img, 320);
    assert!(model > 0.15, "the teapot covers only {model} of the view");
    let bright_panel_pixels =
        img.enumerate_pixels().filter(|&(x, _, p)| x < 250 && p.0[0] > 180).count();
    assert!(bright_panel_pixels > 200, "the panel shows text ({bright_panel_pixels})");
}

/// One rule for output folders: `fix`, `render` and `compare` create a missing one.
#[test]
fn a_missing_output_folder_is_created_by_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let cornell = models().join("cornell_box/cornell_box.obj").display().to_string();
    let glb = dir.path().join("a/b/fixed.glb");
    let o = seamlit(&["fix", &cornell, "-o", &glb.display().to_string()]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(glb.is_file());
    for (command, name) in [("render", "c/render.png"), ("compare", "d/e/compare.png")] {
        let png = dir.path().join(name);
        let o = seamlit(&[command, &cornell, "-o", &png.display().to_string(), "--size", "64x48"]);
        assert_eq!(o.status.code(), Some(0), "{command}: {}", String::from_utf8_lossy(&o.stderr));
        assert!(png.is_file(), "{command}");
    }
}

/// A folder that cannot be created (a file is in the way) is one line naming it, exit status
/// 1, and nothing is written; `view` says so before it opens a window (no display is needed
/// to see it fail).
#[test]
fn an_output_folder_that_cannot_be_created_is_one_line_and_status_1() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("plain-file");
    std::fs::write(&file, "not a folder").unwrap();
    let cornell = models().join("cornell_box/cornell_box.obj").display().to_string();
    let blocked = |name: &str| file.join(name).display().to_string();
    let runs = [
        vec!["fix", &cornell, "-o"],
        vec!["render", &cornell, "--size", "64x48", "-o"],
        vec!["view", &cornell, "--screenshot"],
    ];
    for (run, name) in runs.into_iter().zip(["x.glb", "x.png", "x.png"]) {
        let target = blocked(name);
        let args: Vec<&str> = run.iter().copied().chain([target.as_str()]).collect();
        let o = Command::new(env!("CARGO_BIN_EXE_seamlit"))
            .args(&args)
            .env("RUST_BACKTRACE", "0")
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
        let errors = errors(&o);
        assert_eq!(errors.len(), 1, "{args:?}: {errors:?}");
        assert!(errors[0].contains("cannot create the output folder"), "{errors:?}");
        assert!(errors[0].contains("plain-file"), "{errors:?}");
    }
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "not a folder");
}

/// An error from the operating system is said once: the library's message already holds it,
/// and the line does not repeat it from the error's source chain.
#[test]
fn an_os_error_is_said_once() {
    let dir = tempfile::tempdir().unwrap();
    // The output name is a folder: the final rename fails with "Is a directory".
    let out = dir.path().join("taken.glb");
    std::fs::create_dir(&out).unwrap();
    let cornell = models().join("cornell_box/cornell_box.obj").display().to_string();
    let o = seamlit(&["fix", &cornell, "-o", &out.display().to_string()]);
    assert_eq!(o.status.code(), Some(1), "{}", String::from_utf8_lossy(&o.stderr));
    let errors = errors(&o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(errors[0].matches("os error").count(), 1, "{errors:?}");
    assert!(out.is_dir());
}

/// `view --screenshot` that cannot write its picture fails the run (exit status 1) with one
/// line, instead of printing the problem and exiting 0.
#[test]
fn a_screenshot_that_cannot_be_written_fails_the_viewer() {
    let dir = tempfile::tempdir().unwrap();
    // The folder exists, but the picture's name is taken by a folder.
    let shot = dir.path().join("taken.png");
    std::fs::create_dir(&shot).unwrap();
    let _xvfb = one_xvfb_at_a_time();
    let o = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 640x480x24", env!("CARGO_BIN_EXE_seamlit"), "view"])
        .arg(models().join("cornell_box/cornell_box.obj"))
        .args(["--size", "320x240", "--exit-after-frames", "3", "--screenshot"])
        .arg(&shot)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("xvfb-run is installed (.ci/run installs the xvfb package)");
    assert_eq!(o.status.code(), Some(1), "{}", String::from_utf8_lossy(&o.stderr));
    let errors = errors(&o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(errors[0].contains("taken.png"), "{errors:?}");
    assert!(shot.is_dir());
}
