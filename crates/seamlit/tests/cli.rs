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
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models")
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
    // The options are spelled as the flags that set them.
    let first = text.lines().next().unwrap();
    assert!(first.contains("--crease 60 --weld-tolerance rel:1e-6 --weighting angle"), "{first}");
    let o = seamlit(&[
        "inspect",
        &path.display().to_string(),
        "--weld-tolerance",
        "exact",
        "--weighting",
        "angle-area",
    ]);
    let first = stdout(&o).lines().next().unwrap().to_owned();
    assert!(first.contains("--weld-tolerance exact --weighting angle-area"), "{first}");
}

/// Counts read as English: "1 object", not "1 objects".
#[test]
fn one_object_is_said_in_the_singular() {
    let dir = tempfile::tempdir().unwrap();
    let one = write(dir.path(), "one.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let out = dir.path().join("one.glb").display().to_string();
    let o = seamlit(&["fix", &one, "-o", &out]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let line = stdout(&o);
    assert!(line.contains(": 1 object, 1 triangle, 0 positions shared"), "{line}");
}

/// Without a display, `view` says so in one line that names no source file of winit's.
#[test]
fn view_without_a_display_says_so_plainly() {
    let o = Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .args(["view", &teapot(), "--tessellation", "2"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", String::from_utf8_lossy(&o.stderr));
    let errors = errors(&o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(errors[0].contains("cannot open a window"), "{errors:?}");
    assert!(!errors[0].contains(".rs:") && !errors[0].contains("registry"), "{errors:?}");
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

/// A library error whose kind keeps a foreign error as its source (serde_json's here) prints
/// on one line with that error's text once: neither lost nor repeated by the chain.
#[test]
fn a_library_error_prints_its_source_once() {
    let dir = tempfile::tempdir().unwrap();
    let broken = write(
        dir.path(),
        "broken.gltf",
        "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"nodes\": [,]\n}",
    );
    let o = seamlit(&["inspect", &broken]);
    assert_bad_input(&o, &[&format!("{broken}: glTF JSON line 3 column 13: expected value")]);
    assert_eq!(errors(&o)[0].matches("expected value").count(), 1, "{:?}", errors(&o));
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
    // Each side carries its own face's normal: an authored hard edge, which the default
    // keeps and says so (issue 31); `smooth-shared` (the rule before) averages it.
    let auto = run(None);
    assert_eq!(run(Some("auto")), auto);
    assert!(
        auto.contains(
            "normals (auto): kept in every object; changed at 0 of 8 vertices; 0 vertices split"
        ),
        "{auto}"
    );
    assert!(auto.contains("0 seams repaired, 2 kept as authored hard edges"), "{auto}");
    assert!(auto.contains("within 11.31° (kept ones included)"), "{auto}");
    let shared = run(Some("smooth-shared"));
    assert!(shared.contains("normals across seams within 0.00°"), "{shared}");
    assert!(
        shared
            .contains("normals (smooth-shared): kept in every object; changed at 4 of 8 vertices"),
        "{shared}"
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
    // object, normals, tangents, vertices, normals changed, split: flat sides, kept.
    assert_eq!(row("a "), ["a", "kept", "computed", "4", "0", "0"], "{text}");
    assert_eq!(row("b "), ["b", "kept", "computed", "4", "0", "0"], "{text}");
    assert!(text.contains("2 kept as authored hard edges"), "{text}");

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
    assert_bad_input(&seamlit(&["fix", &good, "-o", &good]), &["good.obj", "--overwrite-input"]);
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

/// A VRM avatar stays a `.vrm` (file and folder mode); a GLB that is no avatar is refused as
/// one, in one line, before anything is written.
#[test]
fn fix_writes_a_vrm_as_a_vrm_and_refuses_one_from_a_plain_glb() {
    let dir = tempfile::tempdir().unwrap();
    let (mut document, bin) = seamlit_testkit::character::document(false);
    let plain = dir.path().join("plain.glb");
    std::fs::write(&plain, seamlit_testkit::glb(&document, &bin)).unwrap();
    document["extensionsUsed"] = serde_json::json!(["VRMC_vrm"]);
    document["extensions"] = serde_json::json!({"VRMC_vrm": {"specVersion": "1.0",
        "meta": {"name": "tube"}, "humanoid": {"humanBones": {"hips": {"node": 2}}}}});
    let models = dir.path().join("models");
    std::fs::create_dir(&models).unwrap();
    std::fs::write(models.join("avatar.vrm"), seamlit_testkit::glb(&document, &bin)).unwrap();

    let fixed = dir.path().join("avatar-fixed.vrm");
    let o = seamlit(&[
        "fix",
        &models.join("avatar.vrm").display().to_string(),
        "-o",
        &fixed.display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(&std::fs::read(&fixed).unwrap()[..4], b"glTF");

    let out_dir = dir.path().join("fixed");
    let o = seamlit(&["fix", &models.display().to_string(), "-o", &out_dir.display().to_string()]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(listing(&out_dir), ["avatar.vrm"]);

    let refused = dir.path().join("plain.vrm");
    let o = seamlit(&["fix", &plain.display().to_string(), "-o", &refused.display().to_string()]);
    assert_bad_input(&o, &["plain.vrm", "VRM input", "write .glb"]);
    assert!(!refused.exists());
}

/// Every file under `dir`, relative, sorted.
fn tree(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p.strip_prefix(dir).unwrap().display().to_string());
            }
        }
    }
    out.sort();
    out
}

/// A folder run descends into subfolders and mirrors the tree, each model's texture beside
/// it; hidden folders and the output folder inside the input are not read; `--no-recurse`
/// keeps to the top folder.
#[test]
fn fix_a_folder_tree_mirrors_it_with_textures_beside_each_model() {
    let input = tempfile::tempdir().unwrap();
    let quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
    write(input.path(), "a.obj", &format!("{quad}f 1/1 2/2 3/3 4/4\n"));
    let hero = input.path().join("chars/hero");
    std::fs::create_dir_all(&hero).unwrap();
    write(&hero, "head.mtl", "newmtl skin\nmap_Kd skin.png\n");
    image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 150, 120, 255]))
        .save(hero.join("skin.png"))
        .unwrap();
    write(&hero, "head.obj", &format!("mtllib head.mtl\nusemtl skin\n{quad}f 1/1 2/2 3/3 4/4\n"));
    std::fs::create_dir_all(input.path().join("props")).unwrap();
    write(&input.path().join("props"), "chair.obj", &format!("{quad}f 1/1 2/2 3/3\n"));
    std::fs::create_dir_all(input.path().join(".git")).unwrap();
    write(&input.path().join(".git"), "hidden.obj", &format!("{quad}f 1/1 2/2 3/3\n"));

    // The output folder lies inside the input: the second run must not fix the first's output.
    let out = input.path().join("fixed");
    let out_arg = out.display().to_string();
    let in_arg = input.path().display().to_string();
    for _ in 0..2 {
        let o = seamlit(&["fix", &in_arg, "-o", &out_arg, "--format", "gltf"]);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(stdout(&o).contains("fixed 3 of 3 models"), "{}", stdout(&o));
    }
    let files = tree(&out);
    for expected in ["a.gltf", "chars/hero/head.gltf", "props/chair.gltf"] {
        assert!(files.iter().any(|f| f == expected), "{expected} not in {files:?}");
    }
    assert!(
        files.iter().any(|f| f.starts_with("chars/hero/") && f.ends_with(".png")),
        "the hero's texture is not beside it: {files:?}"
    );
    assert!(!files.iter().any(|f| f.contains("hidden") || f.starts_with("fixed")), "{files:?}");

    let top = tempfile::tempdir().unwrap();
    let o = seamlit(&["fix", &in_arg, "-o", &top.path().display().to_string(), "--no-recurse"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(tree(top.path()), ["a.glb"]);
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
    // Two rows of three 120 px panels with 4 px gaps, each under a 44 px label band: the modes,
    // then the window where object and model differ most, enlarged 5 times.
    assert_eq!(img.dimensions(), (3 * 120 + 2 * 4, 2 * (90 + 44) + 4));
    // The label bands have light text in them above each panel.
    for (panel, band) in (0..3).flat_map(|p| [(p, 0), (p, 90 + 44 + 4)]) {
        let x0 = panel * 124;
        let ink = (x0..x0 + 120)
            .flat_map(|x| (band..band + 44).map(move |y| (x, y)))
            .filter(|&(x, y)| img.get_pixel(x, y).0[0] > 150)
            .count();
        assert!(ink > 20, "panel {panel} has no label at row {band}");
    }
    // The window is framed in yellow in each panel; each inset is that window, every pixel a
    // 5 x 5 block of the panel's pixel (nothing smoothed); object's and model's insets differ.
    let framed: Vec<(u32, u32)> = (0..120)
        .flat_map(|x| (44..44 + 90).map(move |y| (x, y)))
        .filter(|&(x, y)| img.get_pixel(x + 124, y).0 == [255, 210, 60, 255])
        .collect();
    // The frame runs from window - 2 to window + size + 1 (span size + 3), clipped to the panel:
    // where it is clipped on the low side, count from the high side.
    let (lo, hi) = framed.iter().fold(((u32::MAX, u32::MAX), (0, 0)), |(lo, hi), &(x, y)| {
        ((lo.0.min(x), lo.1.min(y)), (hi.0.max(x), hi.1.max(y)))
    });
    let start = |lo: u32, hi: u32, size: u32| if lo == 0 { hi - size - 1 } else { lo + 2 };
    let (wx, wy) = (start(lo.0, hi.0, 24), start(lo.1 - 44, hi.1 - 44, 18));
    let inset_top = 2 * 44 + 90 + 4;
    let mut differ = 0;
    for panel in 0..3 {
        for y in 0..90 {
            for x in 0..120 {
                let zoomed = img.get_pixel(panel * 124 + x, inset_top + y);
                let source = img.get_pixel(panel * 124 + wx + x / 5, 44 + wy + y / 5);
                assert_eq!(zoomed, source, "panel {panel} inset pixel {x},{y}");
                if panel == 1 && zoomed != img.get_pixel(2 * 124 + x, inset_top + y) {
                    differ += 1;
                }
            }
        }
    }
    assert!(differ > 0, "object and model look the same in the inset");
}

/// A model of one object has no seam: object and model agree, and no inset row is drawn.
#[test]
fn compare_draws_no_inset_where_object_and_model_agree() {
    let dir = tempfile::tempdir().unwrap();
    let one = write(
        dir.path(),
        "one.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 0.3\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n",
    );
    let out = dir.path().join("grid.png");
    let o = seamlit(&["compare", &one, "-o", &out.display().to_string(), "--size", "120x90"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(image::open(&out).unwrap().to_rgba8().dimensions(), (3 * 120 + 2 * 4, 90 + 44));
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

/// A GLB built here: one skinned fold (two quads at a right angle, so fixing splits the two
/// vertices of the hard edge) with JOINTS_0 and WEIGHTS_0, a two-joint skin with inverse
/// bind matrices, and an animation of one joint.
fn skinned_glb(path: &Path) -> serde_json::Value {
    use seamlit_testkit::{ARRAY_BUFFER, Buffer, ELEMENT_ARRAY_BUFFER};
    use serde_json::json;
    let mut glb = Buffer::default();
    let positions =
        [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0];
    let position = glb.floats(&positions, "VEC3", true, Some(ARRAY_BUFFER));
    let indices: Vec<u8> =
        [0u16, 3, 2, 0, 2, 1, 0, 4, 5, 0, 5, 3].iter().flat_map(|i| i.to_le_bytes()).collect();
    let indices = glb.push(
        &indices,
        json!({ "componentType": 5123, "count": 12, "type": "SCALAR" }),
        Some(ELEMENT_ARRAY_BUFFER),
    );
    let joints: Vec<u8> = (0..6u8).flat_map(|v| [v % 2, 1 - v % 2, 0, 0]).collect();
    let joints = glb.push(
        &joints,
        json!({ "componentType": 5121, "count": 6, "type": "VEC4" }),
        Some(ARRAY_BUFFER),
    );
    let weights: Vec<f32> = (0..6)
        .flat_map(|v| {
            let a = 0.125 * (v + 1) as f32;
            [a, 1.0 - a, 0.0, 0.0]
        })
        .collect();
    let weights = glb.floats(&weights, "VEC4", false, Some(ARRAY_BUFFER));
    let mut ibm = [0.0f32; 32];
    for m in 0..2 {
        for d in 0..4 {
            ibm[16 * m + 5 * d] = 1.0;
        }
    }
    ibm[16 + 13] = -1.0;
    let ibm = glb.floats(&ibm, "MAT4", false, None);
    let times = glb.floats(&[0.0, 1.0], "SCALAR", true, None);
    let rotations = glb.floats(&[0.0, 0.0, 0.0, 1.0, 0.6, 0.0, 0.0, 0.8], "VEC4", false, None);
    let bin = glb.bin;
    let document = json!({
        "asset": { "version": "2.0" },
        "buffers": [{ "byteLength": bin.len() }],
        "bufferViews": glb.views,
        "accessors": glb.accessors,
        "meshes": [{ "primitives": [{
            "attributes": { "POSITION": position, "JOINTS_0": joints, "WEIGHTS_0": weights },
            "indices": indices,
        }] }],
        "skins": [{ "joints": [1, 2], "inverseBindMatrices": ibm }],
        "animations": [{
            "samplers": [{ "input": times, "output": rotations }],
            "channels": [{ "sampler": 0, "target": { "node": 2, "path": "rotation" } }],
        }],
        "nodes": [
            { "mesh": 0, "skin": 0 },
            { "name": "root", "children": [2] },
            { "name": "tip", "translation": [0.0, 1.0, 0.0] },
        ],
        "scenes": [{ "nodes": [0, 1] }],
        "scene": 0,
    });
    std::fs::write(path, seamlit_testkit::glb(&document, &bin)).unwrap();
    document
}

/// The JSON chunk of a GLB, read by hand.
fn glb_json(path: &Path) -> serde_json::Value {
    let bytes = std::fs::read(path).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&bytes[20..20 + length]).unwrap()
}

#[test]
fn fix_keeps_the_skin_joints_weights_and_animation_of_a_glb() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("rig.glb");
    let document = skinned_glb(&input);
    let out = dir.path().join("out.glb");
    let o = seamlit(&["fix", &input.display().to_string(), "-o", &out.display().to_string()]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let written = glb_json(&out);
    for key in ["skins", "animations", "nodes", "scenes", "scene"] {
        assert_eq!(written[key], document[key], "{key}");
    }
    let attributes = &written["meshes"][0]["primitives"][0]["attributes"];
    for name in ["POSITION", "NORMAL", "JOINTS_0", "WEIGHTS_0"] {
        assert!(attributes.get(name).is_some(), "{name} missing: {attributes}");
    }
    // The hard edge split its two vertices: every attribute has the new count.
    for name in ["POSITION", "JOINTS_0", "WEIGHTS_0"] {
        let accessor = usize::try_from(attributes[name].as_u64().unwrap()).unwrap();
        assert_eq!(written["accessors"][accessor]["count"], 8, "{name}");
    }
}

/// A bare model is framed tightly and centred, as glTF viewers frame one: Spot's silhouette
/// spans most of the picture one way and sits in its middle.
#[test]
fn a_bare_model_fills_the_frame_and_sits_in_its_middle() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("spot.png");
    let spot = models().join("spot/spot_triangulated.obj").display().to_string();
    let o = seamlit(&["render", &spot, "-o", &out.display().to_string(), "--size", "200x150"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgba8();
    let bg = img.get_pixel(0, 0).0;
    let (mut lo, mut hi) = ((u32::MAX, u32::MAX), (0, 0));
    for (x, y, p) in img.enumerate_pixels() {
        let d: i32 = (0..3).map(|k| (i32::from(p.0[k]) - i32::from(bg[k])).abs()).sum();
        if d > 30 {
            (lo, hi) = ((lo.0.min(x), lo.1.min(y)), (hi.0.max(x), hi.1.max(y)));
        }
    }
    let (w, h) = (f64::from(hi.0 - lo.0 + 1) / 200.0, f64::from(hi.1 - lo.1 + 1) / 150.0);
    assert!(w.max(h) > 0.7, "the model spans only {w:.2} x {h:.2} of the picture");
    let centre = (f64::from(lo.0 + hi.0) / 400.0, f64::from(lo.1 + hi.1) / 300.0);
    assert!((centre.0 - 0.5).abs() < 0.1 && (centre.1 - 0.5).abs() < 0.1, "centre {centre:?}");
}

/// `--camera side` on a bare model (which has only the framing camera) names the cameras there
/// are, in one line, exit status 2.
#[test]
fn an_unknown_camera_on_a_bare_model_lists_the_cameras_there_are() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png").display().to_string();
    let spot = models().join("spot/spot_triangulated.obj").display().to_string();
    let o = seamlit(&["render", &spot, "-o", &out, "--camera", "side"]);
    assert_bad_input(&o, &["spot_triangulated.obj", "\"side\"", "there are: default"]);
    assert!(!Path::new(&out).exists());
}

#[test]
fn fix_reads_meshopt_and_draco_and_writes_them_uncompressed_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let compressed = models().join("compressed");
    let input = compressed.join("teapot_mo.glb").display().to_string();
    let out = dir.path().join("out.glb").display().to_string();
    let o = seamlit(&["fix", &input, "-o", &out]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.lines().any(|l| l.starts_with("warning: ")
            && l.contains("teapot_mo.glb")
            && l.contains("EXT_meshopt_compression")
            && l.contains("uncompressed")),
        "{stderr}"
    );
    assert!(stdout(&o).contains("32 objects"), "{}", stdout(&o));
    let o = seamlit(&["inspect", &out]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    // Draco (the default `draco` feature of seamlit-io): decoded, written uncompressed.
    let draco = compressed.join("teapot_draco.glb").display().to_string();
    let out = dir.path().join("draco.glb").display().to_string();
    let o = seamlit(&["fix", &draco, "-o", &out]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.lines().any(|l| l.starts_with("warning: ")
            && l.contains("teapot_draco.glb")
            && l.contains("32 primitives compressed with KHR_draco_mesh_compression")
            && l.contains("uncompressed")),
        "{stderr}"
    );
    let written = std::fs::read(&out).unwrap();
    assert!(!String::from_utf8_lossy(&written).contains("draco"));
}

#[test]
fn render_and_compare_refuse_a_missing_or_malformed_environment_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let model = models().join("NormalTangentTest.glb").display().to_string();
    let bad = write(dir.path(), "bad.hdr", "#?RADIANCE\nFORMAT=nonsense\n");
    let missing = dir.path().join("missing.hdr").display().to_string();
    for command in ["render", "compare"] {
        let png = dir.path().join("out.png").display().to_string();
        for (hdr, name) in [(&bad, "bad.hdr"), (&missing, "missing.hdr")] {
            let o =
                seamlit(&[command, &model, "-o", &png, "--size", "32x24", "--environment", hdr]);
            assert_bad_input(&o, &[name, "environment"]);
        }
    }
    assert_eq!(listing(dir.path()), ["bad.hdr"]);
    // Every flag of the look is read, and a value out of range is refused by name.
    let png = dir.path().join("ok.png").display().to_string();
    let o = seamlit(&[
        "render",
        &model,
        "-o",
        &png,
        "--size",
        "32x24",
        "--environment",
        "builtin",
        "--environment-intensity",
        "0.5",
        "--environment-rotation",
        "-90",
        "--background",
        "1,1,1",
        "--tone-mapping",
        "aces",
        "--exposure",
        "1.5",
        "--ambient",
        "0",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let image = image::open(&png).unwrap().to_rgba8();
    assert_eq!(image.get_pixel(0, 0).0, [255, 255, 255, 255], "the background is white");
    let o = seamlit(&["render", &model, "-o", &png, "--background", "1,2,3"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("1,2,3"));
}

#[test]
fn fix_keep_compression_keeps_meshopt_and_refuses_draco_and_obj() {
    let dir = tempfile::tempdir().unwrap();
    let compressed = models().join("compressed");
    let input = compressed.join("teapot_mo.glb").display().to_string();
    let out = dir.path().join("out.glb");
    let o = seamlit(&["fix", &input, "-o", &out.display().to_string(), "--keep-compression"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.lines().any(|l| l.starts_with("warning: ")
            && l.contains("teapot_mo.glb")
            && l.contains("kept compressed")
            && l.contains("EXT_meshopt_compression")),
        "{stderr}"
    );
    let written = String::from_utf8_lossy(&std::fs::read(&out).unwrap()).into_owned();
    assert!(written.contains(
        "\"extensionsRequired\":[\"KHR_mesh_quantization\",\"EXT_meshopt_compression\"]"
    ));

    // Draco: no encoder; refused, one line, exit 2, nothing written.
    let draco = compressed.join("teapot_draco.glb").display().to_string();
    let out = dir.path().join("draco.glb").display().to_string();
    let o = seamlit(&["fix", &draco, "-o", &out, "--keep-compression"]);
    assert_bad_input(&o, &["teapot_draco.glb", "no Draco encoder", "gltf-transform"]);
    assert!(!Path::new(&out).exists());

    // OBJ output: nothing to keep the compression in.
    let out = dir.path().join("out.obj").display().to_string();
    let o = seamlit(&["fix", &input, "-o", &out, "--keep-compression"]);
    assert_bad_input(&o, &["out.obj", "--keep-compression", "glTF or GLB"]);
    assert!(!Path::new(&out).exists());
}

/// A .gltf whose buffer 0 has no data of its own (valid glTF: "MAY be provided by other
/// means") and whose triangle lies in buffer 1: the new normals cannot be appended to buffer
/// 0, in a GLB or a .gltf. The user's file, not the machine: exit 2, one line naming buffer 0,
/// nothing written.
#[test]
fn new_normals_cannot_be_appended_to_a_buffer_without_data() {
    let dir = tempfile::tempdir().unwrap();
    let mut bin = Vec::new();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for c in v {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    std::fs::write(dir.path().join("triangle.bin"), &bin).unwrap();
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 4}, {"byteLength": 36, "uri": "triangle.bin"}],
        "bufferViews": [{"buffer": 1, "byteLength": 36}],
        "accessors": [{
            "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
            "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]
        }],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}]
    });
    let input = dir.path().join("no_data.gltf");
    std::fs::write(&input, gltf.to_string()).unwrap();
    for name in ["out.glb", "out.gltf"] {
        let out = dir.path().join(name);
        let o = seamlit(&["fix", &input.display().to_string(), "-o", &out.display().to_string()]);
        assert_bad_input(&o, &[name, "buffer 0", "cannot be appended"]);
        assert!(!out.exists());
    }
}

/// An FBX (ufbx's test file of nested Blender meshes) goes through every command that reads
/// a model; an .fbx output and a truncated FBX are bad input in one line.
#[test]
fn fbx_is_read_by_every_command_and_refused_as_output() {
    let fbx = models().join("ufbx/blender_279_nested_meshes_7400_binary.fbx").display().to_string();
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).display().to_string();
    let o = seamlit(&["inspect", &fbx, "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = seamlit(&["fix", &fbx, "-o", &out("fixed.glb")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout(&o).starts_with("wrote "), "{}", stdout(&o));
    for command in ["render", "compare"] {
        let png = out(&format!("{command}.png"));
        let o = seamlit(&[command, &fbx, "-o", &png, "--size", "160x120"]);
        assert!(o.status.success(), "{command}: {}", String::from_utf8_lossy(&o.stderr));
        let img = image::open(&png).unwrap().to_rgba8();
        assert!(foreground_fraction(&img, 0) > 0.01, "{command}: the model is drawn");
    }
    let o = seamlit(&["fix", &fbx, "-o", &out("out.fbx")]);
    assert_bad_input(&o, &["out.fbx", "cannot write FBX", ".glb"]);
    let bytes = std::fs::read(&fbx).unwrap();
    let truncated = out("truncated.fbx");
    std::fs::write(&truncated, &bytes[..bytes.len() / 3]).unwrap();
    let o = seamlit(&["inspect", &truncated]);
    assert_bad_input(&o, &["truncated.fbx", "FBX", "truncated"]);
    assert_eq!(listing(dir.path()), ["compare.png", "fixed.glb", "render.png", "truncated.fbx"]);
}
