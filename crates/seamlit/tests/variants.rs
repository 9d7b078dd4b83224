//! KHR_materials_variants on the command line: `--variant NAME` on `render`, `compare` and
//! `view`, the scene file's `variant` key (which the flag overrides), and an unknown name
//! refused in one line that lists the variants, exit status 2. (The pictures of each variant
//! against the Sample Viewer's: sample_viewer.rs.)

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn seamlit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("the binary runs")
}

/// bench/sample-viewer/models.mjs's `variants`: body, trim and plain spheres; "ruby" and
/// "sapphire".
fn model() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/sample-viewer/variants.glb")
}

#[test]
fn an_unknown_variant_is_one_line_listing_the_variants_and_status_2() {
    let dir = tempfile::tempdir().unwrap();
    let model = model().display().to_string();
    let out = dir.path().join("x.png").display().to_string();
    for command in ["render", "compare", "view"] {
        let flag = if command == "view" { "--screenshot" } else { "-o" };
        let o = seamlit(&[command, &model, flag, &out, "--variant", "emerald"]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{command}: {stderr}");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
        assert_eq!(errors.len(), 1, "{command}: {stderr}");
        for needle in ["variants.glb", "\"emerald\"", "\"ruby\", \"sapphire\""] {
            assert!(errors[0].contains(needle), "{command}: {:?} lacks {needle}", errors[0]);
        }
        assert!(!Path::new(&out).exists(), "{command} wrote nothing");
    }
}

/// Renders `scene` at 96 x 72 with `flags`; the picture's bytes.
fn render(scene: &Path, flags: &[&str], out: &Path) -> Vec<u8> {
    let (scene, png) = (scene.display().to_string(), out.display().to_string());
    let mut args = vec!["render", &scene, "-o", &png, "--size", "96x72", "--shadows", "off"];
    args.extend_from_slice(flags);
    let o = seamlit(&args);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    image::open(out).unwrap().to_rgb8().into_raw()
}

#[test]
fn the_scene_file_s_variant_key_draws_the_variant_and_the_flag_overrides_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("ruby.toml");
    let model = model().display().to_string().replace('\\', "/");
    std::fs::write(&scene, format!("[[model]]\npath = \"{model}\"\nvariant = \"ruby\"\n")).unwrap();
    let plain = dir.path().join("plain.toml");
    std::fs::write(&plain, format!("[[model]]\npath = \"{model}\"\n")).unwrap();
    let keyed = render(&scene, &[], &dir.path().join("keyed.png"));
    let flagged = render(&plain, &["--variant", "ruby"], &dir.path().join("flagged.png"));
    let default = render(&plain, &[], &dir.path().join("default.png"));
    assert_eq!(keyed, flagged, "the key draws what the flag draws");
    assert_ne!(keyed, default, "the variant is not the default");
    let overridden = render(&scene, &["--variant", "sapphire"], &dir.path().join("overridden.png"));
    let sapphire = render(&plain, &["--variant", "sapphire"], &dir.path().join("sapphire.png"));
    assert_eq!(overridden, sapphire, "the flag overrides the key");
    // A key the model lacks is refused like the flag.
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, format!("[[model]]\npath = \"{model}\"\nvariant = \"opal\"\n")).unwrap();
    let out = dir.path().join("bad.png").display().to_string();
    let o = seamlit(&["render", &bad.display().to_string(), "-o", &out]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("\"opal\""));
}

/// The viewer starts with the variant asked for (its panel lists the variants and switches
/// them): under Xvfb, `view --variant ruby`'s screenshot shows the red body and no white one,
/// `view`'s the white one.
#[test]
fn view_draws_the_variant_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    let reddish = |flags: &[&str], name: &str| {
        let shot = dir.path().join(name);
        let o = Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1024x768x24", env!("CARGO_BIN_EXE_seamlit"), "view"])
            .arg(model())
            .args(["--size", "800x600", "--exit-after-frames", "10", "--screenshot"])
            .arg(&shot)
            .args(flags)
            .env("RUST_BACKTRACE", "0")
            .output()
            .expect("xvfb-run is installed (.ci/run installs the xvfb package)");
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        let img = image::open(&shot).unwrap().to_rgb8();
        // Right of the panel: pixels clearly red (the ruby body) and clearly white-grey
        // (the default body).
        let count = |f: &dyn Fn([u8; 3]) -> bool| {
            img.enumerate_pixels().filter(|&(x, _, p)| x > 320 && f(p.0)).count()
        };
        let red = count(&|[r, g, b]| r > 120 && u16::from(g) + u16::from(b) < u16::from(r) / 2);
        let white = count(&|[r, g, b]| r > 140 && g > 140 && b > 140);
        (red, white)
    };
    let (red, white) = reddish(&["--variant", "ruby"], "ruby.png");
    assert!(red > 300, "ruby: {red} red pixels");
    let (plain_red, plain_white) = reddish(&[], "default.png");
    assert!(plain_red < red / 10, "default: {plain_red} red pixels against {red}");
    assert!(plain_white > white, "default: {plain_white} white pixels against {white}");
}
