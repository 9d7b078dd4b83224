//! OpenUSD through the command line: a stage goes through every command that reads a model
//! (inspect, fix, render, compare, the folder mode), `fix` writes a `.usda` or `.usdc` layer
//! over it or a `.usdz` package, and broken stages are bad input in one line (exit status 2).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn seamlit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the binary runs")
}

fn usd(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/models/usd")
        .join(name)
        .display()
        .to_string()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Exit status 2 and exactly one error line holding every one of `needles`.
fn assert_bad_input(o: &Output, needles: &[&str]) {
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "stdout: {}\nstderr: {stderr}", stdout(o));
    let errors: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("error: ") && !l.contains("XDG_RUNTIME_DIR"))
        .collect();
    assert_eq!(errors.len(), 1, "{errors:?}");
    for n in needles {
        assert!(errors[0].contains(n), "{:?} lacks {n:?}", errors[0]);
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// Pixels that differ clearly from the top-left (background) pixel.
fn foreground_fraction(img: &image::RgbaImage) -> f64 {
    let bg = img.get_pixel(0, 0).0;
    let differs = img
        .pixels()
        .filter(|p| p.0.iter().zip(bg).any(|(&a, b)| (i32::from(a) - i32::from(b)).abs() > 12))
        .count();
    differs as f64 / f64::from(img.width() * img.height())
}

#[test]
fn usd_is_read_by_every_command_and_fixed_as_a_layer() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).display().to_string();
    for stage in ["head_body.usda", "head_body.usdc", "head_body.usdz"] {
        let o = seamlit(&["inspect", &usd(stage), "--json"]);
        assert!(o.status.success(), "{stage}: {}", String::from_utf8_lossy(&o.stderr));
        let report: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
        assert!(report.to_string().contains("/World/"), "{stage}: {report}");
    }
    let layer = out("fixed.usda");
    let o = seamlit(&["fix", &usd("head_body.usdz"), "-o", &layer]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout(&o).starts_with("wrote "), "{}", stdout(&o));
    let text = std::fs::read_to_string(&layer).unwrap();
    assert!(text.contains("subLayers") && text.contains("head_body.usdz@"), "{text}");
    // The layer is itself a stage seamlit reads: it sublayers the input, outside the layer's
    // own folder, which USD resolves; confined to the layer's folder (--asset-root), it is not.
    let o = seamlit(&["inspect", &layer, "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let own = dir.path().display().to_string();
    let o = seamlit(&["inspect", &layer, "--json", "--asset-root", &own]);
    assert_bad_input(&o, &["fixed.usda", "head_body.usdz", "--asset-root"]);
    // A package: the layer first, the input inside; seamlit reads it back.
    let package = out("fixed.usdz");
    let o = seamlit(&["fix", &usd("head_body.usdz"), "-o", &package]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout(&o).starts_with("wrote "), "{}", stdout(&o));
    let bytes = std::fs::read(&package).unwrap();
    assert!(bytes.starts_with(b"PK\x03\x04") && bytes[30..].starts_with(b"fixed.usda"));
    let o = seamlit(&["inspect", &package, "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = seamlit(&["fix", &usd("head_body.usda"), "-o", &out("fixed.glb")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for command in ["render", "compare"] {
        let png = out(&format!("{command}.png"));
        let o = seamlit(&[command, &usd("head_body.usdc"), "-o", &png, "--size", "160x120"]);
        assert!(o.status.success(), "{command}: {}", String::from_utf8_lossy(&o.stderr));
        let img = image::open(&png).unwrap().to_rgba8();
        assert!(foreground_fraction(&img) > 0.01, "{command}: the model is drawn");
    }
}

#[test]
fn usdc_outputs_are_written_and_broken_stages_are_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).display().to_string();
    let o = seamlit(&["fix", &usd("head_body.usda"), "-o", &out("out.usdc")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(std::fs::read(out("out.usdc")).unwrap().starts_with(b"PXR-USDC"));
    // A package whose input names, in a variant not selected (so the stage loads), a layer
    // that cannot be read: one line naming the package and the layer, nothing written.
    for name in ["head_body.usda", "skin.png"] {
        std::fs::copy(usd(name), out(name)).unwrap();
    }
    std::fs::write(out("broken.usdc"), &std::fs::read(usd("head_body.usdc")).unwrap()[..40])
        .unwrap();
    let variants = out("variants.usda");
    std::fs::write(
        &variants,
        "#usda 1.0\n(\n    subLayers = [@./head_body.usda@]\n)\n\ndef Xform \"Extra\" (\n    variants = {\n        string look = \"a\"\n    }\n    prepend variantSets = \"look\"\n)\n{\n    variantSet \"look\" = {\n        \"a\" {\n        }\n        \"b\" (\n            references = @./broken.usdc@\n        ) {\n        }\n    }\n}\n",
    )
    .unwrap();
    let o = seamlit(&["fix", &variants, "-o", &out("never.usdz")]);
    assert_bad_input(&o, &["never.usdz", "package", "broken.usdc"]);
    assert!(!PathBuf::from(out("never.usdz")).exists());
    let bytes = std::fs::read(usd("head_body.usdc")).unwrap();
    let truncated = out("truncated.usdc");
    std::fs::write(&truncated, &bytes[..bytes.len() / 3]).unwrap();
    let o = seamlit(&["inspect", &truncated]);
    assert_bad_input(&o, &["truncated.usdc", "USD"]);
    let missing = out("missing.usda");
    std::fs::write(
        &missing,
        "#usda 1.0\n\ndef Xform \"World\" (\n    references = @./nowhere.usda@\n)\n{\n}\n",
    )
    .unwrap();
    let o = seamlit(&["fix", &missing, "-o", &out("never.usda")]);
    assert_bad_input(&o, &["missing.usda", "nowhere.usda", "/World"]);
    assert!(!PathBuf::from(out("never.usda")).exists());
}

/// The folder mode finds USD stages beside other models.
#[test]
fn the_folder_mode_fixes_usd_stages() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in");
    std::fs::create_dir(&input).unwrap();
    for name in ["head_body.usdc", "faceted.usda"] {
        std::fs::copy(usd(name), input.join(name)).unwrap();
    }
    let output = dir.path().join("out");
    let o = seamlit(&["fix", &input.display().to_string(), "-o", &output.display().to_string()]);
    assert!(o.status.success(), "{}{}", stdout(&o), String::from_utf8_lossy(&o.stderr));
    let mut names: Vec<String> = std::fs::read_dir(&output)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["faceted.glb", "head_body.glb"]);
}

/// A stage whose layers lie in its siblings' folders, as asset libraries lay them out (the
/// car kit's entry layer references `../../../wheels/...`): every command reads it with no
/// flag and `fix` writes the layer. Confined by `--asset-root` to the entry layer's folder
/// (the strict mode), it is bad input in one line naming the layer; the kit's folder allowed,
/// it reads again.
#[test]
fn layers_in_sibling_folders_are_read_and_asset_root_confines() {
    let dir = tempfile::tempdir().unwrap();
    let kit = usd("others/USD_Mini_Car_Kit");
    let car = usd("others/USD_Mini_Car_Kit/assets/vehicles/formula/asset/formulaFullAsset.usda");
    let o = seamlit(&["inspect", &car]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout(&o).contains("wheelRed"), "{}", stdout(&o));
    let own = Path::new(&car).parent().unwrap().display().to_string();
    let o = seamlit(&["inspect", &car, "--asset-root", &own]);
    assert_bad_input(&o, &["formulaFullAsset.usda", "outside the stage's folder", "--asset-root"]);
    let o = seamlit(&["inspect", &car, "--asset-root", &kit]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The output layer beside the input: it sublayers the input by a relative path.
    let out = Path::new(&car).with_file_name("__asset_root_test.usda");
    let o = seamlit(&["fix", &car, "-o", &out.display().to_string()]);
    let written = out.exists();
    let _ = std::fs::remove_file(&out);
    assert!(o.status.success() && written, "{}", String::from_utf8_lossy(&o.stderr));
    let png = dir.path().join("car.png").display().to_string();
    let o = seamlit(&["render", &car, "-o", &png, "--size", "64x48"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// A skinned stage (UsdSkel, `skinned_neck.usda`): `inspect` counts the 16 equator positions
/// whose skins differ, the first at (1, 0, 0) moved by the skeleton's and the SkelRoot's
/// translations to (1.25, 1, 0); `fix` matches them by default, says so and writes both
/// meshes' skin primvars; `--skin-seams keep` writes none.
#[test]
fn skin_seams_of_usd_stages_are_reported_and_matched() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).display().to_string();
    let o = seamlit(&["inspect", &usd("skinned_neck.usda"), "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let seams = &report["as_loaded"]["skin_seams"];
    assert_eq!(seams["positions"], 16, "{seams}");
    assert_eq!(seams["example"]["position"], serde_json::json!([1.25, 1.0, 0.0]), "{seams}");
    assert_eq!(report["model"]["skin_seams"]["positions"], 0, "after fix");
    let o = seamlit(&["fix", &usd("skinned_neck.usda"), "-o", &out("matched.usda")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout(&o).contains("skins: gave the copies at 16 shared positions"), "{}", stdout(&o));
    let text = std::fs::read_to_string(out("matched.usda")).unwrap();
    assert_eq!(text.matches("int[] primvars:skel:jointIndices = ").count(), 2, "{text}");
    assert_eq!(text.matches("float[] primvars:skel:jointWeights = ").count(), 2, "{text}");
    let o = seamlit(&[
        "fix",
        &usd("skinned_neck.usda"),
        "-o",
        &out("kept.usda"),
        "--skin-seams",
        "keep",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out("kept.usda")).unwrap();
    assert!(!text.contains("skel:"), "{text}");
    assert_eq!(text.matches("primvars:normals = ").count(), 2, "{text}");
}

/// `render` draws each `materialBind` GeomSubset with its bound material: the box's left
/// half red and its right half blue, where the mesh's own material is grey; `fix` writes the
/// mesh as one object, as without subsets. Subsets that cannot be used are one warning
/// naming the layer and the mesh, and the stage still renders.
#[test]
fn geom_subsets_are_drawn_with_their_materials() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("subsets.png").display().to_string();
    let o = seamlit(&["render", &usd("subsets.usda"), "-o", &png, "--size", "96x72"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!String::from_utf8_lossy(&o.stderr).contains("warning"));
    let img = image::open(&png).unwrap().to_rgba8();
    let bg = img.get_pixel(0, 0).0;
    let foreground: Vec<(u32, [u8; 4])> = img
        .enumerate_pixels()
        .filter(|(_, _, p)| {
            p.0.iter().zip(bg).any(|(&a, b)| (i32::from(a) - i32::from(b)).abs() > 12)
        })
        .map(|(x, _, p)| (x, p.0))
        .collect();
    let lo = foreground.iter().map(|f| f.0).min().unwrap();
    let hi = foreground.iter().map(|f| f.0).max().unwrap();
    assert!(hi - lo > 48, "the box spans {lo}..{hi}");
    // The outer quarters of the box's columns: the left all red, the right all blue.
    let quarter = (hi - lo) / 4;
    let side = |keep: &dyn Fn(u32) -> bool| -> Vec<[u8; 4]> {
        foreground.iter().filter(|f| keep(f.0)).map(|f| f.1).collect()
    };
    let (left, right) = (side(&|x| x < lo + quarter), side(&|x| x > hi - quarter));
    let dominant = |p: &[u8; 4], c: usize| (0..3).all(|k| k == c || p[c] > p[k].saturating_add(40));
    assert!(left.len() > 100 && right.len() > 100, "{} and {}", left.len(), right.len());
    let red = left.iter().filter(|p| dominant(p, 0)).count();
    let blue = right.iter().filter(|p| dominant(p, 2)).count();
    assert!(red * 100 >= left.len() * 95, "{red} of {} left pixels red", left.len());
    assert!(blue * 100 >= right.len() * 95, "{blue} of {} right pixels blue", right.len());

    let out = dir.path().join("subsets_fixed.usda").display().to_string();
    let o = seamlit(&["fix", &usd("subsets.usda"), "-o", &out]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    let o = seamlit(&["render", &usd("subsets_bad.usda"), "-o", &png, "--size", "32x24"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.starts_with("warning: ")).collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    for needle in ["subsets_bad.usda", "</Model/Box>", "GeomSubsets"] {
        assert!(warnings[0].contains(needle), "{:?} lacks {needle:?}", warnings[0]);
    }
}
