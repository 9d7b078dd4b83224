//! End-to-end tests of every subcommand through the built binary: success, bad arguments and
//! bad files (exit status 2, one line naming the file and the problem, no output left).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn seamlit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the binary runs")
}

fn models() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/models")
}

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(name).display().to_string()
}

fn teapot() -> String {
    models().join("newell_teaset/teapot").display().to_string()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The lines of stderr that are ours (drivers print their own noise, e.g. about
/// XDG_RUNTIME_DIR).
fn errors(o: &Output) -> Vec<String> {
    String::from_utf8_lossy(&o.stderr)
        .lines()
        .filter(|l| l.starts_with("error: ") && !l.contains("XDG_RUNTIME_DIR"))
        .map(str::to_owned)
        .collect()
}

/// Exit status 2, exactly one error line, and that line contains every one of `needles`.
fn assert_bad_input(o: &Output, needles: &[&str]) {
    assert_eq!(
        o.status.code(),
        Some(2),
        "stdout: {}\nstderr: {}",
        stdout(o),
        String::from_utf8_lossy(&o.stderr)
    );
    let errors = errors(o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    for n in needles {
        assert!(errors[0].contains(n), "{:?} lacks {n:?}", errors[0]);
    }
    assert!(!String::from_utf8_lossy(&o.stderr).contains("panicked"));
}

/// Files in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

/// Pixels that differ clearly from the top-left (background) pixel.
fn foreground_fraction(img: &image::RgbaImage, x0: u32) -> f64 {
    let bg = img.get_pixel(img.width() - 1, img.height() - 1).0;
    let mut count = 0u64;
    let mut total = 0u64;
    for (x, _, p) in img.enumerate_pixels() {
        if x < x0 {
            continue;
        }
        total += 1;
        let d: i32 = (0..3).map(|k| (i32::from(p.0[k]) - i32::from(bg[k])).abs()).sum();
        if d > 30 {
            count += 1;
        }
    }
    count as f64 / total.max(1) as f64
}

// --- usage -------------------------------------------------------------------------------

#[test]
fn help_explains_every_subcommand_and_option() {
    let o = seamlit(&["--help"]);
    assert_eq!(o.status.code(), Some(0));
    for sub in ["demo", "fix", "inspect", "render", "compare", "view"] {
        assert!(stdout(&o).contains(sub), "{sub}");
    }
    let o = seamlit(&["fix", "--help"]);
    let text = stdout(&o);
    for flag in [
        "--mode",
        "--crease",
        "--weld-tolerance",
        "--weighting",
        "--tangents",
        "--normals",
        "--output",
        "--format",
    ] {
        assert!(text.contains(flag), "fix --help lacks {flag}");
    }
    assert!(text.contains("angle-area") && text.contains("mikktspace"));
    let text = stdout(&seamlit(&["render", "--help"]));
    for flag in
        ["--size", "--camera", "--mode", "--view", "--frames", "--lighting", "--no-normal-map"]
    {
        assert!(text.contains(flag), "render --help lacks {flag}");
    }
    assert!(stdout(&seamlit(&["view", "--help"])).contains("--exit-after-frames"));
}

#[test]
fn usage_errors_exit_with_2() {
    for args in [
        &["frobnicate"][..],
        &["inspect"],
        &["fix", "a.obj"],
        &["render", "a.obj", "-o", "x.png", "--size", "big"],
        &["fix", "a.obj", "-o", "b.glb", "--mode", "smooth"],
        &["fix", "a.obj", "-o", "b.glb", "--crease", "500"],
        &["fix", "a.obj", "-o", "b.glb", "--weld-tolerance", "-1"],
    ] {
        let o = seamlit(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
    }
}

// --- inspect -----------------------------------------------------------------------------

#[test]
fn inspect_json_reports_each_mode_and_model_mode_closes_the_teapot_seams() {
    let o = seamlit(&["inspect", &teapot(), "--json", "--tessellation", "6"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    // 32 patches of 6 x 6 quads.
    assert_eq!(v["as_loaded"]["objects"], 32);
    assert_eq!(v["model"]["triangles"], 32 * 2 * 36);
    let angle = |mode: &str| v[mode]["cross_object"]["max_normal_angle_deg"].as_f64().unwrap();
    assert!(angle("object") > 5.0, "object mode leaves seams: {}", angle("object"));
    assert!(angle("model") < 0.01, "model mode closes them: {}", angle("model"));
    // As loaded, the patches have no normals to compare.
    assert!(v["as_loaded"]["cross_object"]["max_normal_angle_deg"].is_null());
}

#[test]
fn inspect_prints_a_table_by_default() {
    let path = models().join("cornell_box/cornell_box.obj");
    let o = seamlit(&["inspect", &path.display().to_string()]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let text = stdout(&o);
    let header = text.lines().find(|l| l.contains("as loaded")).unwrap();
    assert!(header.contains("flat") && header.contains("object") && header.contains("model"));
    let objects = text.lines().find(|l| l.starts_with("objects ")).unwrap();
    // The Cornell box file has 8 `o` objects... as the models' SOURCES.md says.
    assert!(objects.split_whitespace().skip(1).all(|c| c == "8"), "{objects}");
}

#[test]
fn inspect_names_a_missing_or_malformed_file() {
    assert_bad_input(
        &seamlit(&["inspect", "/nonexistent/model.obj"]),
        &["/nonexistent/model.obj", "no such file"],
    );
    let dir = tempfile::tempdir().unwrap();
    let bad = write(dir.path(), "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    assert_bad_input(&seamlit(&["inspect", &bad]), &["bad.obj"]);
    let nan = write(dir.path(), "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_bad_input(&seamlit(&["inspect", &nan]), &["nan.obj"]);
    let patches = write(dir.path(), "broken.bpt", "1\n1,2,3\n");
    assert_bad_input(&seamlit(&["inspect", &patches]), &["broken.bpt", "patches"]);
}

// --- fix ---------------------------------------------------------------------------------

#[test]
fn fix_writes_a_model_with_normals_and_tangents() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("teapot.glb");
    let o = seamlit(&[
        "fix",
        &teapot(),
        "-o",
        &out.display().to_string(),
        "--tessellation",
        "4",
        "--crease",
        "45",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout(&o).contains("wrote"));
    let asset = seamlit_io::load(&out, &seamlit_io::LoadOptions::DEFAULT).unwrap();
    assert_eq!(asset.model.objects.len(), 32);
    assert!(asset.model.objects.iter().all(|o| o.normals.is_some() && o.tangents.is_some()));
    assert_eq!(listing(dir.path()), ["teapot.glb"]);
}

/// Two objects sharing the edge x = 1, each with its own face normal authored: they disagree
/// there by about 11.3 degrees.
const SEAM_OBJ: &str = "o a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
    vn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n\
    o b\nv 1 0 0\nv 2 0 -0.2\nv 2 1 -0.2\nv 1 1 0\nvn 0.19611613 0 0.98058068\n\
    f 5/1/2 6/2/2 7/3/2\nf 5/1/2 7/3/2 8/4/2\n";

#[test]
fn fix_keeps_authored_normals_repairs_the_seam_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "seam.obj", SEAM_OBJ);
    let out = dir.path().join("out.glb").display().to_string();
    let run = |policy: Option<&str>| {
        let mut args = vec!["fix", input.as_str(), "-o", out.as_str()];
        args.extend(policy.map(|p| ["--normals", p]).into_iter().flatten());
        let o = seamlit(&args);
        assert_eq!(o.status.code(), Some(0), "{policy:?}: {}", String::from_utf8_lossy(&o.stderr));
        stdout(&o)
    };
    let auto = run(None);
    assert_eq!(run(Some("auto")), auto);
    assert!(auto.contains("normals across seams within 0.00°"), "{auto}");
    assert!(
        auto.contains(
            "normals (auto): kept in every object; changed at 4 of 8 vertices; 0 vertices split"
        ),
        "{auto}"
    );
    let keep = run(Some("keep"));
    assert!(keep.contains("normals across seams within 11.31°"), "{keep}");
    assert!(
        keep.contains("normals (keep): kept in every object; changed at 0 of 8 vertices"),
        "{keep}"
    );
    let recompute = run(Some("recompute"));
    assert!(recompute.contains("normals across seams within 0.00°"), "{recompute}");
    assert!(recompute.contains("normals (recompute): computed in every object"), "{recompute}");
}

#[test]
fn a_normal_map_without_tangents_gets_mikktspace_unless_asked_otherwise() {
    let dir = tempfile::tempdir().unwrap();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([128, 128, 255, 255]))
        .save(dir.path().join("n.png"))
        .unwrap();
    write(dir.path(), "seam.mtl", "newmtl mapped\nnorm n.png\n");
    let mapped = format!("mtllib seam.mtl\nusemtl mapped\n{SEAM_OBJ}");
    let input = write(dir.path(), "mapped.obj", &mapped);
    let plain = write(dir.path(), "plain.obj", SEAM_OBJ);
    let out = dir.path().join("out.glb").display().to_string();
    let run = |args: &[&str]| {
        let o = seamlit(&[&["fix", "-o", out.as_str()][..], args].concat());
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
        stdout(&o)
    };
    assert!(run(&[&input]).contains("; tangents: mikktspace"), "{}", run(&[&input]));
    assert!(run(&[&input, "--tangents", "seamlit"]).contains("; tangents: seamlit"));
    assert!(run(&[&plain]).contains("; tangents: seamlit"), "no normal map");
}

#[test]
fn inspect_says_what_fix_keeps_in_text_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "seam.obj", SEAM_OBJ);
    let o = seamlit(&["inspect", &input]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let text = stdout(&o);
    assert!(text.contains("What `fix` changes (model mode): normals (auto): kept in every object"));
    let row = |name: &str| {
        let line = text.lines().find(|l| l.starts_with(name)).unwrap_or_default();
        line.split_whitespace().map(str::to_owned).collect::<Vec<_>>()
    };
    // object, normals, tangents, vertices, normals changed, split
    assert_eq!(row("a "), ["a", "kept", "computed", "4", "2", "0"], "{text}");
    assert_eq!(row("b "), ["b", "kept", "computed", "4", "2", "0"], "{text}");

    let o = seamlit(&["inspect", &input, "--json", "--normals", "recompute"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["options"]["normals"], "recompute");
    let model = &v["changes"]["model"]["objects"];
    assert_eq!(model[0]["kept_normals"], false);
    assert_eq!(model[1]["name"], "b");
    let o = seamlit(&["inspect", &input, "--json", "--normals", "keep"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["changes"]["model"]["objects"][0]["kept_normals"], true);
    assert_eq!(v["changes"]["model"]["objects"][0]["normals_changed"], 0);
    let seam = v["model"]["cross_object"]["max_normal_angle_deg"].as_f64().unwrap();
    assert!(seam > 11.0, "keep leaves the seam: {seam}");
}

#[test]
fn every_command_takes_normals_and_refuses_a_bad_policy() {
    for command in ["fix", "inspect", "render", "compare", "view"] {
        let help = stdout(&seamlit(&[command, "--help"]));
        assert!(help.contains("--normals") && help.contains("recompute"), "{command} --help");
        // clap checks the value as it reads it, before missing arguments.
        let o = seamlit(&[command, "--normals", "sometimes", "a.obj"]);
        assert_eq!(o.status.code(), Some(2), "{command}: {}", String::from_utf8_lossy(&o.stderr));
        assert!(String::from_utf8_lossy(&o.stderr).contains("sometimes"), "{command}");
    }
    // render and compare run with it (fix and inspect: the tests above).
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "seam.obj", SEAM_OBJ);
    for command in ["render", "compare"] {
        let png = dir.path().join(format!("{command}.png")).display().to_string();
        let o = seamlit(&[command, &input, "-o", &png, "--size", "64x48", "--normals", "keep"]);
        assert_eq!(o.status.code(), Some(0), "{command}: {}", String::from_utf8_lossy(&o.stderr));
        assert!(Path::new(&png).is_file(), "{command}");
    }
}

#[test]
fn fix_refuses_bad_input_and_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let bad = write(dir.path(), "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    let out = dir.path().join("out.glb").display().to_string();
    assert_bad_input(&seamlit(&["fix", &bad, "-o", &out]), &["bad.obj"]);
    let missing = dir.path().join("missing.obj").display().to_string();
    assert_bad_input(&seamlit(&["fix", &missing, "-o", &out]), &["missing.obj", "no such file"]);
    let txt = dir.path().join("out.txt").display().to_string();
    assert_bad_input(&seamlit(&["fix", &teapot(), "-o", &txt]), &["out.txt", "output format"]);
    assert_eq!(listing(dir.path()), ["bad.obj"]);
    // The output may not be the input itself.
    let good = write(dir.path(), "good.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_bad_input(&seamlit(&["fix", &good, "-o", &good]), &["good.obj", "overwrite"]);
    assert_eq!(std::fs::read_to_string(&good).unwrap(), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
}

#[test]
fn fix_a_folder_goes_on_past_a_bad_file_and_says_so() {
    let input = tempfile::tempdir().unwrap();
    let output = tempfile::tempdir().unwrap();
    write(
        input.path(),
        "a.obj",
        "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no b\nv 1 0 0\nv 0 1 0\nv 1 1 -0.2\nf 1 3 2\n",
    );
    write(input.path(), "b.obj", "v 0 0 0\nf 1 2 3\n");
    write(input.path(), "notes.txt", "not a model");
    let out_dir = output.path().join("fixed");
    let o = seamlit(&[
        "fix",
        &input.path().display().to_string(),
        "-o",
        &out_dir.display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    let errors = errors(&o);
    assert!(errors.iter().any(|e| e.contains("b.obj")), "{errors:?}");
    assert!(errors.last().unwrap().contains("1 of 2 models failed"), "{errors:?}");
    assert_eq!(listing(&out_dir), ["a.glb"]);
    assert!(stdout(&o).contains("fixed 1 of 2 models"));
}

// --- render and compare ------------------------------------------------------------------

#[test]
fn render_draws_the_example_scene_through_a_named_camera_and_times_frames() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("side.png");
    let o = seamlit(&[
        "render",
        &example("teapot.toml"),
        "-o",
        &out.display().to_string(),
        "--size",
        "160x120",
        "--camera",
        "side",
        "--tessellation",
        "4",
        "--frames",
        "3",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (160, 120));
    let f = foreground_fraction(&img, 0);
    assert!(f > 0.1 && f < 0.9, "the teapot covers {f} of the picture");
    assert!(stdout(&o).contains("3 frames at 160x120"), "{}", stdout(&o));
}

#[test]
fn render_debug_views_and_a_bare_model_with_the_default_camera() {
    let dir = tempfile::tempdir().unwrap();
    let path = models().join("spot/spot_triangulated.obj").display().to_string();
    for view in ["normals", "objects", "uv"] {
        let out = dir.path().join(format!("{view}.png"));
        let o = seamlit(&[
            "render",
            &path,
            "-o",
            &out.display().to_string(),
            "--size",
            "96x96",
            "--view",
            view,
        ]);
        assert_eq!(o.status.code(), Some(0), "{view}: {}", String::from_utf8_lossy(&o.stderr));
        let f = foreground_fraction(&image::open(&out).unwrap().to_rgba8(), 0);
        assert!(f > 0.1, "{view}: the default camera frames the cow ({f})");
    }
}

#[test]
fn render_a_scene_of_two_placed_models_with_their_own_options() {
    // examples/spot.toml: the cow twice, the second scaled, turned, moved, processed per
    // object with MikkTSpace tangents; no lights (the default rig). Seen from above, both
    // cows show: ink on the left and on the right half of the picture.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("top.png");
    let o = seamlit(&[
        "render",
        &example("spot.toml"),
        "-o",
        &out.display().to_string(),
        "--size",
        "160x120",
        "--camera",
        "top",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout(&o).contains("camera \"top\""), "{}", stdout(&o));
    let img = image::open(&out).unwrap().to_rgba8();
    let left = image::imageops::crop_imm(&img, 0, 0, 80, 120).to_image();
    let right = image::imageops::crop_imm(&img, 80, 0, 80, 120).to_image();
    let (l, r) = (foreground_fraction(&left, 0), foreground_fraction(&right, 0));
    assert!(l > 0.05 && r > 0.02, "left {l}, right {r}");
}

#[test]
fn render_refuses_bad_scenes_cameras_and_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.png").display().to_string();
    let o = seamlit(&["render", &example("teapot.toml"), "-o", &out, "--camera", "top"]);
    assert_bad_input(&o, &["teapot.toml", "no camera named \"top\"", "front, side"]);
    let scene = write(
        dir.path(),
        "bad.toml",
        &format!(
            "[[model]]\npath = {:?}\n\n[[light]]\ntype = \"point\"\nposition = [0, 1, 0]\ncolour = [1, 0, 0]\n",
            teapot()
        ),
    );
    assert_bad_input(&seamlit(&["render", &scene, "-o", &out]), &["bad.toml", "line 7", "colour"]);
    let missing_model = write(dir.path(), "missing.toml", "[[model]]\npath = \"nope.obj\"\n");
    assert_bad_input(&seamlit(&["render", &missing_model, "-o", &out]), &["nope.obj"]);
    assert_bad_input(
        &seamlit(&["render", &teapot(), "-o", "picture.jpg"]),
        &["picture.jpg", ".png"],
    );
    assert_eq!(listing(dir.path()), ["bad.toml", "missing.toml"]);
}

#[test]
fn compare_puts_the_three_modes_side_by_side_with_labels() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("grid.png");
    let o = seamlit(&[
        "compare",
        &teapot(),
        "-o",
        &out.display().to_string(),
        "--size",
        "120x90",
        "--tessellation",
        "4",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgba8();
    // Three 120 px panels with 4 px gaps, under a 44 px label band.
    assert_eq!(img.dimensions(), (3 * 120 + 2 * 4, 90 + 44));
    // The label band has light text in it above each panel.
    for panel in 0..3 {
        let x0 = panel * 124;
        let ink = (x0..x0 + 120)
            .flat_map(|x| (0..44).map(move |y| (x, y)))
            .filter(|&(x, y)| img.get_pixel(x, y).0[0] > 150)
            .count();
        assert!(ink > 20, "panel {panel} has no label");
    }
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
    let shot = dir.path().join("view.png");
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
