//! Usage (help, bad arguments) and `inspect`.

use super::*;

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
