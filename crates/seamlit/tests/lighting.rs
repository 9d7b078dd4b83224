//! Which lighting model a picture gets: PBR for glTF models, Blinn-Phong for the rest, a
//! scene's `[render] lighting` over that, `--lighting` over both.

use std::path::{Path, PathBuf};
use std::process::Command;

fn models() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models")
}

/// Renders `input` at 48x48 with `extra` arguments into `dir/name.png` and reads it back.
fn render(dir: &Path, name: &str, input: &Path, extra: &[&str]) -> image::RgbaImage {
    let out = dir.join(format!("{name}.png"));
    let status = Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .arg("render")
        .arg(input)
        .arg("-o")
        .arg(&out)
        .args(["--size", "48x48"])
        .args(extra)
        .output()
        .expect("the binary runs");
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    image::open(&out).expect("a PNG").to_rgba8()
}

#[test]
fn gltf_gets_pbr_obj_gets_blinn_phong_and_the_scene_or_the_flag_can_say_otherwise() {
    // Images are compared whole with `==` (assert_eq! would print every pixel).
    let dir = tempfile::tempdir().unwrap();
    let glb = models().join("NormalTangentTest.glb");
    let default = render(dir.path(), "default", &glb, &[]);
    let pbr = render(dir.path(), "pbr", &glb, &["--lighting", "pbr"]);
    let blinn = render(dir.path(), "blinn", &glb, &["--lighting", "blinn-phong"]);
    assert!(default == pbr, "a glTF model is drawn with PBR by default");
    assert!(pbr != blinn, "the two models draw different pictures");

    let scene = dir.path().join("scene.toml");
    let text = format!("[[model]]\npath = {glb:?}\n\n[render]\nlighting = \"blinn-phong\"\n");
    std::fs::write(&scene, text).unwrap();
    let from_scene = render(dir.path(), "scene", &scene, &[]);
    assert!(from_scene == blinn, "[render] lighting is obeyed");
    let flagged = render(dir.path(), "scene_pbr", &scene, &["--lighting", "pbr"]);
    assert!(flagged == pbr, "--lighting overrides the scene");

    // A model that is not glTF (the Newell teapot patches) keeps Blinn-Phong.
    let teapot = models().join("newell_teaset/teapot");
    let obj_default = render(dir.path(), "teapot", &teapot, &[]);
    let obj_blinn = render(dir.path(), "teapot_blinn", &teapot, &["--lighting", "blinn-phong"]);
    assert!(obj_default == obj_blinn, "a non-glTF model is drawn with Blinn-Phong by default");
}
