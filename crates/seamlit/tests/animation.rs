//! Seams in motion through the binary: `fix` matches the skin influences of a two-object
//! character at its neck and says how far the seam opened in its animation before and after;
//! `--skin-seams keep` leaves the weights as authored; `inspect --animation` measures.

use std::path::Path;
use std::process::Command;

use seamlit_io::LoadOptions;
use seamlit_mesh::WeldTolerance;
use seamlit_testkit::character;

fn seamlit(args: &[&str]) -> (i32, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_seamlit")).args(args).output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr)),
    )
}

/// The largest gap across the neck over 41 times of the nod, as a fraction of the bounds,
/// and the largest normal angle, for the model in `file` as the loader reads it.
fn motion(file: &Path) -> (f32, Option<f32>) {
    let asset = seamlit_io::load(file, &LoadOptions::DEFAULT).unwrap();
    let copies = seamlit_mesh::shared_copies(&asset.model, WeldTolerance::default()).unwrap();
    // Every copy counts as a seam side (the character's normals are computed, or smooth).
    let seams: Vec<Vec<bool>> = copies.iter().map(|g| vec![true; g.len()]).collect();
    let m = seamlit_io::motion::seam_motion(&asset, 0, 41, &copies, &seams, 30.0);
    (m.max_gap_fraction, m.max_normal_angle_deg)
}

#[test]
fn fix_closes_the_neck_in_every_pose_and_keep_leaves_the_weights() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("character.gltf");
    character::write(&input);
    let (gap, _) = motion(&input);
    assert!(gap > 0.01, "the ring opens as the neck turns: {gap}");

    let fixed = dir.path().join("fixed.glb");
    let (code, text) = seamlit(&["fix", input.to_str().unwrap(), "-o", fixed.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("skins: gave the copies at 12 shared positions the same joints and weights")
            && text.contains("in motion, \"nod\" (2.00 s, 30 samples): gap")
            && text.contains("after: gap 0.000e0 (0.00% of the bounds)"),
        "{text}"
    );
    let (gap, angle) = motion(&fixed);
    assert!(gap < 1e-6, "the gap after fix: {gap}");
    assert!(angle.unwrap() < 0.01, "the normal angle across the neck after fix: {angle:?}");

    // keep: the influences are the input's, bit for bit, and the seam opens in motion.
    let kept = dir.path().join("kept.glb");
    let (code, text) = seamlit(&[
        "fix",
        input.to_str().unwrap(),
        "-o",
        kept.to_str().unwrap(),
        "--skin-seams",
        "keep",
    ]);
    assert_eq!(code, 0, "{text}");
    assert!(!text.contains("gave the copies"), "{text}");
    let load = |p: &Path| seamlit_io::load(p, &LoadOptions::DEFAULT).unwrap();
    let (a, b) = (load(&input), load(&kept));
    for (x, y) in a.model.objects.iter().zip(&b.model.objects) {
        assert_eq!(x.skin, y.skin, "{}", x.name);
    }
    assert_eq!(a.skins, b.skins);
    let (gap, angle) = motion(&kept);
    assert!(gap > 0.01, "kept weights open the seam: {gap}");
    assert!(angle.unwrap() > 1.0, "and part the normals: {angle:?}");
}

#[test]
fn inspect_measures_each_animation_as_loaded_and_fixed() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("character.gltf");
    character::write(&input);
    let file = input.to_str().unwrap();
    let (code, text) = seamlit(&["inspect", file, "--animation", "all", "--samples", "9"]);
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains("Seams in motion (the copies of each shared position posed at 9 times"),
        "{text}"
    );
    let row = text.lines().find(|l| l.trim_start().starts_with("nod")).expect("a row for the nod");
    assert!(row.contains("2.00s"), "{row}");

    let (code, text) =
        seamlit(&["inspect", file, "--animation", "nod", "--samples", "21", "--json"]);
    assert_eq!(code, 0, "{text}");
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let motion = &json["motion"];
    assert_eq!(motion["matched_positions"], 12, "{motion}");
    let loaded = motion["as_loaded"][0]["max_gap_fraction"].as_f64().unwrap();
    let fixed = motion["fixed"][0]["max_gap_fraction"].as_f64().unwrap();
    assert!(loaded > 0.01 && fixed < 1e-6, "{motion}");
    // The neck is furthest from the body half way through the nod, at 60 degrees.
    assert_eq!(motion["as_loaded"][0]["max_gap_time"], 1.0, "{motion}");
    assert!(motion["fixed"][0]["max_normal_angle_deg"].as_f64().unwrap() < 0.01, "{motion}");

    let (code, text) = seamlit(&["inspect", file, "--animation", "walk"]);
    assert_eq!(code, 2, "{text}");
    assert!(text.contains("no animation \"walk\"; its animations: 0 \"nod\""), "{text}");
    assert_eq!(text.trim().lines().count(), 1, "{text}");
}

#[test]
fn fix_names_a_morph_target_that_opens_the_seam() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("swell.gltf");
    character::write_with(&input, true);
    let out = dir.path().join("out.glb");
    let (code, text) = seamlit(&["fix", input.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    assert!(
        text.contains(
            "morph targets whose deltas differ across the seam (it opens while they are active): \"swell\" at 12 shared positions"
        ),
        "{text}"
    );
    // Without the target nothing is said.
    let plain = dir.path().join("plain.gltf");
    character::write(&plain);
    let (code, text) = seamlit(&["fix", plain.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{text}");
    assert!(!text.contains("morph targets"), "{text}");
}
