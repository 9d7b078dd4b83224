//! `--animation` and `--time` (and `[render] animation` and `time`) through the built binary:
//! the Khronos Fox posed by its animations; names and indices it lacks, and times that are
//! not seconds >= 0, refused with exit status 2 and nothing written.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn seamlit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the binary runs")
}

fn fox() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/models/fox/Fox.glb")
        .display()
        .to_string()
}

/// Our error lines (drivers print their own noise, e.g. about XDG_RUNTIME_DIR).
fn errors(o: &Output) -> Vec<String> {
    String::from_utf8_lossy(&o.stderr)
        .lines()
        .filter(|l| l.starts_with("error: ") && !l.contains("XDG_RUNTIME_DIR"))
        .map(str::to_owned)
        .collect()
}

/// Exit status 2 and one error line that contains every one of `needles`.
fn assert_bad_input(o: &Output, needles: &[&str]) {
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "stderr: {stderr}");
    let errors = errors(o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    for n in needles {
        assert!(errors[0].contains(n), "{:?} lacks {n:?}", errors[0]);
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
}

fn render(input: &str, out: &Path, extra: &[&str]) -> image::RgbaImage {
    let o = seamlit(
        &[&["render", input, "-o", &out.display().to_string(), "--size", "96x72"], extra].concat(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    image::open(out).expect("a PNG").to_rgba8()
}

fn differing_pixels(a: &image::RgbaImage, b: &image::RgbaImage) -> usize {
    a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count()
}

#[test]
fn an_animation_by_name_or_index_or_from_the_scene_poses_the_fox() {
    let tmp = tempfile::tempdir().unwrap();
    let at = |name: &str| -> PathBuf { tmp.path().join(name) };
    let rest = render(&fox(), &at("rest.png"), &[]);
    let walk = render(&fox(), &at("walk.png"), &["--animation", "Walk", "--time", "0.35"]);
    let by_index = render(&fox(), &at("one.png"), &["--animation", "1", "--time", "0.35"]);
    assert_eq!(walk, by_index, "Walk is animation 1");
    assert!(differing_pixels(&rest, &walk) > 100, "the walking fox is not in its rest pose");
    let later = render(&fox(), &at("later.png"), &["--animation", "Walk", "--time", "0.6"]);
    assert!(differing_pixels(&walk, &later) > 50, "the fox moves between 0.35 s and 0.6 s");
    let scene = at("fox.toml");
    std::fs::write(
        &scene,
        format!("[[model]]\npath = {:?}\n\n[render]\nanimation = \"Walk\"\ntime = 0.35\n", fox()),
    )
    .unwrap();
    let from_scene = render(&scene.display().to_string(), &at("scene.png"), &[]);
    assert_eq!(from_scene, walk, "the scene's [render] animation and time");
    let overridden = render(&scene.display().to_string(), &at("flags.png"), &["--time", "0.6"]);
    assert_eq!(overridden, later, "a flag overrides the scene's key");
}

#[test]
fn a_model_s_own_animation_poses_that_model_only() {
    let tmp = tempfile::tempdir().unwrap();
    let at = |name: &str| -> PathBuf { tmp.path().join(name) };
    let scene = |keys: &str| {
        let path = at("two.toml");
        std::fs::write(
            &path,
            format!(
                "[[model]]\npath = {fox:?}\ntranslate = [-150, 0, 0]\n{keys}\n\n\
                 [[model]]\npath = {fox:?}\ntranslate = [150, 0, 0]\n\n\
                 [[camera]]\nname = \"both\"\nposition = [0, 150, 700]\ntarget = [0, 40, 0]\n\
                 near = 10\nfar = 2000\n",
                fox = fox()
            ),
        )
        .unwrap();
        path.display().to_string()
    };
    // One camera for both pictures: the default one frames what is drawn, which the walk moves.
    let flags = ["--shadows", "off"];
    let rest = render(&scene(""), &at("rest.png"), &flags);
    let posed = render(&scene("animation = \"Walk\"\ntime = 0.35"), &at("posed.png"), &flags);
    let half = rest.width() / 2;
    let side = |image: &image::RgbaImage, left: bool| {
        let x0 = if left { 0 } else { half };
        image::imageops::crop_imm(image, x0, 0, half, image.height()).to_image()
    };
    assert!(differing_pixels(&side(&rest, true), &side(&posed, true)) > 50, "the left fox walks");
    assert_eq!(side(&rest, false), side(&posed, false), "the right fox stays at rest");
    // The same key on a one-model scene poses it as the flags do.
    let one = at("one.toml");
    std::fs::write(&one, format!("[[model]]\npath = {:?}\nanimation = 1\ntime = 0.35\n", fox()))
        .unwrap();
    let own = render(&one.display().to_string(), &at("own.png"), &[]);
    let flagged = render(&fox(), &at("flagged.png"), &["--animation", "Walk", "--time", "0.35"]);
    assert_eq!(own, flagged, "[[model]] animation = 1 is --animation Walk");
    std::fs::write(&one, format!("[[model]]\npath = {:?}\nanimation = \"Trot\"\n", fox())).unwrap();
    let o =
        seamlit(&["render", &one.display().to_string(), "-o", &at("x.png").display().to_string()]);
    assert_bad_input(&o, &["Fox.glb", "no animation \"Trot\"", "1 \"Walk\""]);
    std::fs::write(&one, format!("[[model]]\npath = {:?}\ntime = -0.5\n", fox())).unwrap();
    let o =
        seamlit(&["render", &one.display().to_string(), "-o", &at("x.png").display().to_string()]);
    assert_bad_input(&o, &["one.toml", "time = -0.5"]);
}

#[test]
fn animations_the_model_lacks_and_bad_times_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out.png");
    let out_s = out.display().to_string();
    let fox = fox();
    let refused = |extra: &[&str], needles: &[&str]| {
        let o = seamlit(&[&["render", fox.as_str(), "-o", &out_s], extra].concat());
        assert_bad_input(&o, needles);
        assert!(!out.exists(), "nothing written for {extra:?}");
    };
    refused(
        &["--animation", "Gallop"],
        &["Fox.glb", "no animation \"Gallop\"", "0 \"Survey\"", "1 \"Walk\"", "2 \"Run\""],
    );
    refused(&["--animation", "3"], &["no animation 3", "2 \"Run\""]);
    for time in ["-1", "nan", "inf", "soon"] {
        refused(&["--time", time], &["--time", time]);
    }
    let scene = tmp.path().join("bad.toml");
    std::fs::write(&scene, format!("[[model]]\npath = {fox:?}\n\n[render]\ntime = -2.0\n"))
        .unwrap();
    let o = seamlit(&["render", &scene.display().to_string(), "-o", &out_s]);
    assert_bad_input(&o, &["bad.toml", "time"]);
    assert!(!out.exists());
    // A model without animations says so.
    let teapot = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/models/newell_teaset/teapot")
        .display()
        .to_string();
    let o = seamlit(&["render", &teapot, "-o", &out_s, "--animation", "0"]);
    assert_bad_input(&o, &["no animation 0", "it has none"]);
}
