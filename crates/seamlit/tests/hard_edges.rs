//! What a user sees: faceted low-poly models made by others (assets/models/lowpoly) render
//! pixel for pixel the same with the default fix and with `--normals keep`; the rule of
//! before (`--normals smooth-shared`) visibly softened their hard edges. `fix` says what it
//! decided at the shared positions. docs/normals.md, "What a shared position is".

use std::path::{Path, PathBuf};
use std::process::Command;

fn lowpoly(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models/lowpoly").join(name)
}

fn seamlit(args: &[&str]) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_seamlit")).args(args).output().expect("runs");
    let text =
        format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "seamlit {args:?}: {text}");
    text
}

/// The pixels of `model` rendered with `--normals policy` (256 x 256, the default camera and
/// lights).
fn render(model: &Path, policy: &str, dir: &Path) -> image::RgbaImage {
    let out = dir.join(format!("{policy}.png"));
    let model = model.to_str().expect("UTF-8");
    let out_s = out.to_str().expect("UTF-8");
    seamlit(&["render", model, "-o", out_s, "--size", "256x256", "--normals", policy]);
    image::open(&out).expect("a PNG").to_rgba8()
}

#[test]
fn faceted_models_by_others_render_as_authored() {
    for name in ["kenney-platformer-cube.glb", "kenney-space-spaceCraft4.fbx"] {
        let dir = tempfile::tempdir().expect("temp dir");
        let model = lowpoly(name);
        let keep = render(&model, "keep", dir.path());
        let auto = render(&model, "auto", dir.path());
        assert!(keep.pixels().any(|p| p.0 != keep.get_pixel(0, 0).0), "{name}: drawn");
        assert!(auto == keep, "{name}: the default changed what the artist authored");
        let old = render(&model, "smooth-shared", dir.path());
        let moved = old.pixels().zip(keep.pixels()).filter(|(a, b)| a != b).count();
        assert!(moved > 500, "{name}: the rule of before softened {moved} pixels only");
    }
}

#[test]
fn fix_says_what_it_decided_at_the_shared_positions() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("cube.glb");
    let model = lowpoly("kenney-platformer-cube.glb");
    let text = seamlit(&["fix", model.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(
        text.contains("of 72 shared positions: 0 seams repaired, 72 kept as authored hard edges, 0 kept as custom, 0 already equal"),
        "{text}"
    );
    let tower = lowpoly("kenney-castle-towerBase.fbx");
    let out = dir.path().join("tower.glb");
    let text = seamlit(&["fix", tower.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(text.contains("within 0.00°"), "{text}");
    assert!(text.contains("24 seams repaired"), "{text}");
    let json = seamlit(&["inspect", model.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    assert_eq!(v["changes"]["model"]["shared"]["hard_edges"], 72, "{json}");
}
