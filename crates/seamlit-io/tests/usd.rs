//! OpenUSD in and out (the `usd` feature), with Pixar's USD as the oracle (tests/usd/
//! pxr_check.py, through the `pxr` module of PyPI's usd-core): the stages of
//! assets/models/usd (written by its make.py with pxr) read with the world-space points pxr
//! computes; a head and a body smoothed apart closed to 0.00 degrees as pxr composes the
//! `.usda` layer seamlit writes over them, the layer changing nothing but normals and adding
//! no validation error; authored hard edges and subdivision surfaces left alone; bad stages
//! refused in one line, never a panic.
//!
//! Needs Python 3 with usd-core (`pip install usd-core`; `.ci/run` installs it).
#![cfg(feature = "usd")]

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use glam::Vec3;
use seamlit_io::{Asset, IoError, LoadOptions, SaveOptions, UsdKind, UsdOutput};
use seamlit_mesh::{FixOptions, ReportOptions};
use serde_json::Value;

/// Runs pxr_check.py `command` on `args` and returns the JSON it writes.
fn pxr(command: &str, args: &[&Path]) -> Value {
    common::pxr_check(command, args, &[])
}

fn stage(relative: &str) -> PathBuf {
    common::model(&format!("usd/{relative}"))
}

fn load(path: &Path) -> Asset {
    seamlit_io::load(path, &options_for(path)).unwrap()
}

/// Geometry only; for the car kit, whose entry layer references layers in its siblings'
/// folders, the kit's folder allowed (`--asset-root`).
fn options_for(input: &Path) -> LoadOptions {
    let kit = stage("others/USD_Mini_Car_Kit");
    let asset_roots = if input.starts_with(&kit) { vec![kit] } else { Vec::new() };
    LoadOptions { asset_roots, ..LoadOptions::GEOMETRY }
}

/// Fixes `input` as `seamlit fix` does by default and writes it to `output`; the warnings
/// of loading and saving.
fn fix_to(input: &Path, output: &Path) -> (Asset, Vec<String>) {
    fix_to_with(input, output, &options_for(input))
}

/// [`fix_to`], loading with `options`.
fn fix_to_with(input: &Path, output: &Path, options: &LoadOptions) -> (Asset, Vec<String>) {
    let mut asset = seamlit_io::load(input, options).unwrap();
    let options = asset.fix_options(FixOptions::default(), false);
    seamlit_mesh::fix_in_place(&mut asset.model, &options).unwrap();
    let mut warnings = asset.warnings.clone();
    warnings.extend(seamlit_io::save(&asset, output, &SaveOptions::default()).unwrap().warnings);
    (asset, warnings)
}

/// The largest normal angle across object boundaries, seamlit's own report.
fn seam_degrees(asset: &Asset) -> f32 {
    seamlit_mesh::report(&asset.model, &ReportOptions::default())
        .unwrap()
        .cross_object
        .max_normal_angle_deg
        .unwrap_or(0.0)
}

/// Each object's model-space positions, against pxr's world-space points of its prim (+Y
/// up): every position is a point of the prim and every point a position, within 1e-5 of the
/// coordinates' size.
fn assert_points_match_pxr(path: &Path) {
    assert_points_match_pxr_with(path, &LoadOptions::GEOMETRY);
}

/// [`assert_points_match_pxr`], loading with `options`.
fn assert_points_match_pxr_with(path: &Path, options: &LoadOptions) {
    let asset = seamlit_io::load(path, options).unwrap();
    let expected = pxr("points", &[path]);
    let names: BTreeSet<&str> = asset.model.objects.iter().map(|o| o.name.as_str()).collect();
    let pxr_names: BTreeSet<&str> =
        expected.as_object().unwrap().keys().map(String::as_str).collect();
    assert_eq!(names, pxr_names, "{}: the meshes", path.display());
    for object in &asset.model.objects {
        let m = object.model_transform();
        let ours: Vec<Vec3> = object.positions.iter().map(|p| m.transform_point3(*p)).collect();
        let theirs: Vec<Vec3> = expected[&object.name]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                let v: Vec<f32> = p
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| common::f32_of(x.as_f64().unwrap()))
                    .collect();
                Vec3::new(v[0], v[1], v[2])
            })
            .collect();
        let near = |a: Vec3, set: &[Vec3]| {
            set.iter().any(|b| a.distance(*b) <= 1e-5 * a.abs().max_element().max(1.0))
        };
        for p in &ours {
            assert!(
                near(*p, &theirs),
                "{}: {} position {p} is no point of pxr's",
                path.display(),
                object.name
            );
        }
        for p in &theirs {
            assert!(
                near(*p, &ours),
                "{}: {} pxr's point {p} is no position",
                path.display(),
                object.name
            );
        }
    }
}

#[test]
fn positions_are_pxrs_world_points() {
    for name in [
        "z_up_cm.usda",
        "head_body.usda",
        "head_body.usdc",
        "head_body.usdz",
        "layered/shot.usda",
        "instanced.usda",
        "faceted.usda",
    ] {
        assert_points_match_pxr(&stage(name));
    }
}

/// Every box of the Z-up stage (mirrored, left-handed, under every kind of op) faces out in
/// model space: each triangle's normal points away from its box's centre.
#[test]
fn mirrored_and_left_handed_meshes_face_out() {
    let asset = load(&stage("z_up_cm.usda"));
    assert_eq!(asset.model.objects.len(), 5);
    for object in &asset.model.objects {
        let m = object.model_transform();
        let p: Vec<Vec3> = object.positions.iter().map(|p| m.transform_point3(*p)).collect();
        let centre = p.iter().copied().sum::<Vec3>() / p.len() as f32;
        for t in &object.triangles {
            let [a, b, c] = t.map(|i| p[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(
                n.dot((a + b + c) / 3.0 - centre) > 0.0,
                "{}: triangle {t:?} faces in",
                object.name
            );
        }
    }
}

/// The head and the body, smoothed one by one, meet at 22.5 degrees; fixed and written as a
/// `.usda` over the input (text, binary and package alike), pxr composes a seam of 0.00
/// degrees from the layer, and nothing but normals differs from the input.
#[test]
fn the_neck_is_closed_in_the_layer_pxr_composes() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["head_body.usda", "head_body.usdc", "head_body.usdz"] {
        let input = stage(name);
        let before = pxr("seam", &[&input]);
        assert!(before["largest_degrees"].as_f64().unwrap() > 20.0, "{name}: {before}");
        let loaded = load(&input);
        assert!(seam_degrees(&loaded) > 20.0, "{name}");
        let output = dir.path().join(format!("{}.usda", name.replace('.', "_")));
        let (fixed, warnings) = fix_to(&input, &output);
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        assert!(seam_degrees(&fixed) < 0.005, "{name}: seamlit's report");
        let after = pxr("seam", &[&output]);
        assert_eq!(after["pairs"], before["pairs"], "{name}");
        assert!(after["largest_degrees"].as_f64().unwrap() < 0.005, "{name}: {after}");
        let diff = pxr("compare", &[&input, &output]);
        assert_eq!(diff["differences"], serde_json::json!([]), "{name}: {diff:#}");
        let normals: Vec<&str> =
            diff["normals"].as_array().unwrap().iter().map(|l| l.as_str().unwrap()).collect();
        // The head's indexed primvar, values and indices new; the body's plain `normals`
        // blocked under its new primvar.
        for changed in [
            "/World/HeadPivot/Head primvars:normals: valued -> valued",
            "/World/HeadPivot/Head primvars:normals:indices: valued -> valued",
            "/World/Body primvars:normals: absent -> valued",
            "/World/Body primvars:normals:indices: absent -> valued",
            "/World/Body normals: valued -> blocked",
        ] {
            assert!(normals.contains(&changed), "{name}: {changed} in {normals:#?}");
        }
        assert_eq!(normals.len(), 5, "{name}: {normals:#?}");
        let errors_in = pxr("validate", &[&input]);
        let errors_out = pxr("validate", &[&output]);
        for e in errors_out.as_array().unwrap() {
            assert!(errors_in.as_array().unwrap().contains(e), "{name}: new validation error {e}");
        }
        // The layer sublayers the input and authors only the two meshes' overs.
        let text = std::fs::read_to_string(&output).unwrap();
        assert!(text.starts_with("#usda 1.0\n"), "{text}");
        assert_eq!(text.matches("primvars:normals = ").count(), 2, "{name}");
    }
}

/// A `.usdz` output (from a package, a text and a binary stage, and the formula car's five
/// layers, references, wheel variant set and textures in a sibling folder): pxr opens the
/// package alone in an empty folder (so it is self-contained), its first file is the
/// override layer, every file stored uncompressed with its data 64-byte aligned; it composes
/// to the input with only normals changed, the neck closed to 0.00 degrees, and the
/// validators (usdz ones included) find no error the input lacks.
#[test]
fn usdz_packages_hold_the_layer_and_the_input() {
    let dir = tempfile::tempdir().unwrap();
    for (name, relative, normals_changed) in [
        ("from_usdz", "head_body.usdz", 5),
        ("from_usda", "head_body.usda", 5),
        ("from_usdc", "head_body.usdc", 5),
        (
            "formula",
            "others/USD_Mini_Car_Kit/assets/vehicles/formula/asset/formulaFullAsset.usda",
            0,
        ),
    ] {
        let input = stage(relative);
        let written = dir.path().join(format!("{name}.usdz"));
        let (_, warnings) = fix_to(&input, &written);
        // Alone in a folder of its own: nothing may resolve outside the package.
        let alone = dir.path().join(name);
        std::fs::create_dir(&alone).unwrap();
        let output = alone.join(format!("{name}.usdz"));
        std::fs::rename(&written, &output).unwrap();
        let package = pxr("package", &[&output]);
        let files = package["files"].as_array().unwrap();
        assert_eq!(files[0]["name"], format!("{name}.usda"), "{name}: {package:#}");
        for file in files {
            assert_eq!(file["stored"], true, "{name}: {file}");
            assert_eq!(file["offset"].as_u64().unwrap() % 64, 0, "{name}: {file}");
        }
        let diff = pxr("compare", &[&input, &output]);
        assert_eq!(diff["differences"], serde_json::json!([]), "{name}: {diff:#} {warnings:?}");
        assert_eq!(diff["normals"].as_array().unwrap().len(), normals_changed, "{name}: {diff:#}");
        if normals_changed > 0 {
            let after = pxr("seam", &[&output]);
            assert!(after["largest_degrees"].as_f64().unwrap() < 0.005, "{name}: {after}");
        }
        let errors_in = pxr("validate", &[&input]);
        for e in pxr("validate", &[&output]).as_array().unwrap() {
            assert!(errors_in.as_array().unwrap().contains(e), "{name}: new validation error {e}");
        }
        // seamlit reads its own package back: the same meshes.
        assert_eq!(load(&output).model.objects.len(), load(&input).model.objects.len(), "{name}");
        if name == "formula" {
            // Every layer of the kit and the textures the material layer names beside it.
            let names: Vec<&str> = files.iter().map(|f| f["name"].as_str().unwrap()).collect();
            assert!(names.iter().any(|n| n.ends_with(".jpg") || n.ends_with(".png")), "{names:?}");
            assert!(names.len() >= 6, "{names:?}");
        }
    }
}

/// A package holds only the kinds of file the USDZ specification allows: an asset path to
/// another file (here a text file beside the stage) is left out with a warning naming it.
#[test]
fn usdz_packages_leave_out_files_of_other_kinds() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["head_body.usda", "skin.png"] {
        std::fs::copy(stage(name), dir.path().join(name)).unwrap();
    }
    std::fs::write(dir.path().join("secret.txt"), "not for the package").unwrap();
    let input = dir.path().join("stage.usda");
    std::fs::write(
        &input,
        "#usda 1.0\n(\n    subLayers = [@./head_body.usda@]\n)\n\nover \"World\"\n{\n    asset note = @./secret.txt@\n}\n",
    )
    .unwrap();
    let output = dir.path().join("out.usdz");
    let (_, warnings) = fix_to(&input, &output);
    assert!(warnings.iter().any(|w| w.contains("secret.txt")), "{warnings:?}");
    let package = pxr("package", &[&output]);
    let names: Vec<&str> =
        package["files"].as_array().unwrap().iter().map(|f| f["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["out.usda", "stage.usda", "head_body.usda", "skin.png"]);
}

/// A package holds only files from the stage's folders: an image the stage names in another
/// folder is left out with a warning, unless that folder is allowed (`--asset-root`).
#[test]
fn usdz_packages_leave_out_files_outside_the_stages_folders() {
    let dir = tempfile::tempdir().unwrap();
    let (shot, elsewhere) = (dir.path().join("shot"), dir.path().join("elsewhere"));
    std::fs::create_dir_all(&shot).unwrap();
    std::fs::create_dir_all(&elsewhere).unwrap();
    for name in ["head_body.usda", "skin.png"] {
        std::fs::copy(stage(name), shot.join(name)).unwrap();
    }
    std::fs::copy(stage("skin.png"), elsewhere.join("far.png")).unwrap();
    let input = shot.join("stage.usda");
    std::fs::write(
        &input,
        "#usda 1.0\n(\n    subLayers = [@./head_body.usda@]\n)\n\nover \"World\"\n{\n    asset note = @../elsewhere/far.png@\n}\n",
    )
    .unwrap();
    let names = |output: &Path| -> Vec<String> {
        let package = pxr("package", &[output]);
        package["files"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["name"].as_str().unwrap().to_owned())
            .collect()
    };
    let output = dir.path().join("out.usdz");
    let (_, warnings) = fix_to(&input, &output);
    assert!(
        warnings.iter().any(|w| w.contains("far.png") && w.contains("outside the stage's folder")),
        "{warnings:?}"
    );
    assert_eq!(names(&output), ["out.usda", "stage.usda", "head_body.usda", "skin.png"]);
    let allowed =
        LoadOptions { asset_roots: vec![dir.path().to_path_buf()], ..LoadOptions::GEOMETRY };
    let (_, warnings) = fix_to_with(&input, &output, &allowed);
    assert!(!warnings.iter().any(|w| w.contains("far.png")), "{warnings:?}");
    assert!(
        names(&output).iter().any(|n| n.ends_with("elsewhere/far.png")),
        "{:?}",
        names(&output)
    );
}

/// The blocks with authored hard edges (flat faceVarying normals, one indexed): fixed, the
/// layer overrides nothing, and pxr composes the input.
#[test]
fn authored_hard_edges_are_not_overridden() {
    let dir = tempfile::tempdir().unwrap();
    let input = stage("faceted.usda");
    let output = dir.path().join("faceted.usda");
    let (_, warnings) = fix_to(&input, &output);
    assert!(warnings.is_empty(), "{warnings:?}");
    let text = std::fs::read_to_string(&output).unwrap();
    assert!(!text.contains("over "), "{text}");
    let diff = pxr("compare", &[&input, &output]);
    assert_eq!(diff, serde_json::json!({"differences": [], "normals": []}));
}

/// A subdivision surface (the default scheme, catmullClark) carries normals renderers
/// ignore: it is read without them, reported, and gets no normals in the layer; the
/// polygonal box beside it, which has none, gets seamlit's.
#[test]
fn subdivision_surfaces_get_no_normals() {
    let dir = tempfile::tempdir().unwrap();
    let input = stage("subdivision.usda");
    let asset = load(&input);
    let smooth = asset.model.objects.iter().find(|o| o.name == "/Model/Smooth").unwrap();
    assert!(smooth.normals.is_none());
    assert!(
        asset.warnings.iter().any(|w| w.contains("/Model/Smooth") && w.contains("catmullClark")),
        "{:?}",
        asset.warnings
    );
    let output = dir.path().join("subdivision.usda");
    let (_, warnings) = fix_to(&input, &output);
    assert!(warnings.iter().any(|w| w.contains("no normals are written")), "{warnings:?}");
    let diff = pxr("compare", &[&input, &output]);
    assert_eq!(diff["differences"], serde_json::json!([]), "{diff:#}");
    let normals: Vec<&str> =
        diff["normals"].as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect();
    assert!(normals.iter().all(|l| l.starts_with("/Model/Polygonal ")), "{normals:?}");
    assert!(!normals.is_empty());
}

/// A shot that sublayers its world and references a prop, the prop's box sharing an edge
/// with the world's: both meshes read, fixed, and composed back with only normals new.
#[test]
fn sublayers_and_references_compose() {
    let dir = tempfile::tempdir().unwrap();
    let input = stage("layered/shot.usda");
    let asset = load(&input);
    let names: Vec<&str> = asset.model.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["/World/Ground", "/World/Holder/Geom"]);
    let output = dir.path().join("shot.usda");
    fix_to(&input, &output);
    let diff = pxr("compare", &[&input, &output]);
    assert_eq!(diff["differences"], serde_json::json!([]), "{diff:#}");
}

/// Two instances of one prototype (a box in a `class`, referenced inside the stage) are two
/// objects, drawn where each instance is; their normals are written once, at the
/// prototype's source, and pxr composes them into both instances.
#[test]
fn instances_are_objects_and_their_prototype_is_written_once() {
    let dir = tempfile::tempdir().unwrap();
    let input = stage("instanced.usda");
    assert_points_match_pxr(&input);
    let asset = load(&input);
    let names: Vec<&str> = asset.model.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["/World/One/Geom", "/World/Two/Geom"]);
    let output = dir.path().join("instanced.usda");
    let (_, warnings) = fix_to(&input, &output);
    assert!(warnings.is_empty(), "{warnings:?}");
    let text = std::fs::read_to_string(&output).unwrap();
    assert!(
        text.contains("over \"Prototypes\"\n{\n    over \"Crate\"\n    {\n        over \"Geom\""),
        "{text}"
    );
    assert_eq!(text.matches("primvars:normals = ").count(), 1, "{text}");
    let diff = pxr("compare", &[&input, &output]);
    assert_eq!(diff["differences"], serde_json::json!([]), "{diff:#}");
    let mut normals: Vec<&str> =
        diff["normals"].as_array().unwrap().iter().map(|l| l.as_str().unwrap()).collect();
    normals.sort_unstable();
    let mut expected = Vec::new();
    for prim in ["/Prototypes/Crate/Geom", "/World/One/Geom", "/World/Two/Geom"] {
        expected.push(format!("{prim} primvars:normals: absent -> valued"));
        expected.push(format!("{prim} primvars:normals:indices: absent -> valued"));
    }
    expected.sort_unstable();
    assert_eq!(normals, expected, "{diff:#}");
}

/// The face corners of `mesh` (pxr's `normals`) at which its normal moved by more than
/// 1e-6 between the stages `before` and `after`, as the points there.
fn moved_points(before: &Value, after: &Value, mesh: &str) -> BTreeSet<u64> {
    let (a, b) = (&before[mesh], &after[mesh]);
    let indices = a["indices"].as_array().unwrap();
    let normal = |v: &Value, c: usize| -> Vec<f64> {
        v["normals"][c].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
    };
    (0..indices.len())
        .filter(|&c| {
            let (n, m) = (normal(a, c), normal(b, c));
            let length = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
            (0..3).any(|k| (n[k] / length(&n) - m[k] / length(&m)).abs() > 1e-6)
        })
        .map(|c| indices[c].as_u64().unwrap())
        .collect()
}

/// The head and body of head_body.usda as one prototype (in a `class`), drawn by three
/// instances referencing it inside the stage, one turned; a cap outside the instances
/// touching the first one's body; two instances of a part referenced from another layer.
/// Each instance is drawn (pxr's points); fixed, the layer authors the head's and the
/// body's normals once, on the class's meshes, and pxr composes them into every instance:
/// the neck of each instance is closed (22.5 degrees before, 0.00 after), and the body's
/// normals moved at the neck and nowhere else, in every instance, although the first
/// instance's lowest ring was fixed against the cap (those corners differ per instance:
/// the input's are kept, one warning says so). The part's prototype, whose opinions come
/// from the other layer only, is not written: one warning per mesh names it. Nothing but
/// normals differs, in `.usda`, `.usdc` and `.usdz`; no new validation error.
#[test]
fn an_instanced_prototype_is_fixed_once_for_all_its_instances() {
    let dir = tempfile::tempdir().unwrap();
    let input = stage("instanced_seams.usda");
    assert_points_match_pxr(&input);
    let before = pxr("seams", &[&input]);
    let necks = ["One", "Two", "Three"].map(|i| format!("/World/{i}/Body /World/{i}/Head"));
    for neck in &necks {
        assert!((before[neck].as_f64().unwrap() - 22.5).abs() < 1e-3, "{before}");
    }
    let normals_before = pxr("normals", &[&input]);
    for extension in ["usda", "usdc", "usdz"] {
        let output = dir.path().join(format!("instanced_seams_out.{extension}"));
        let options =
            LoadOptions { asset_roots: vec![dir.path().to_path_buf()], ..options_for(&input) };
        let (asset, warnings) = fix_to_with(&input, &output, &options);
        assert_eq!(asset.model.objects.len(), 11, "{extension}");
        // Switched off (the first instance's normals written for all), the cap's ring
        // would bend the body of every instance there.
        let kept: Vec<&String> =
            warnings.iter().filter(|w| w.contains("different normals")).collect();
        assert_eq!(kept.len(), 1, "{extension}: {warnings:#?}");
        assert!(
            kept[0].contains("</Prototypes/Character/Body>")
                && kept[0].contains("at 32 face corners"),
            "{kept:?}"
        );
        let external: Vec<&String> = warnings
            .iter()
            .filter(|w| w.contains("outside the stage's root layer stack"))
            .collect();
        assert_eq!(external.len(), 2, "{extension}: {warnings:#?}");
        for (w, mesh) in external.iter().zip(["Lower", "Upper"]) {
            assert!(
                w.contains(&format!("mesh </World/PartA/{mesh}>"))
                    && w.contains("instanced_part.usda"),
                "{w}"
            );
        }
        assert_eq!(warnings.len(), 3, "{extension}: {warnings:#?}");

        let after = pxr("seams", &[&output]);
        for neck in &necks {
            assert!(after[neck].as_f64().unwrap() < 0.005, "{extension}: {neck}: {after}");
        }
        let normals_after = pxr("normals", &[&output]);
        let equator: BTreeSet<u64> = (0..16).collect();
        for i in ["One", "Two", "Three"] {
            let body = format!("/World/{i}/Body");
            assert_eq!(
                moved_points(&normals_before, &normals_after, &body),
                equator,
                "{extension}: {body}"
            );
            let head = format!("/World/{i}/Head");
            assert!(
                !moved_points(&normals_before, &normals_after, &head).is_empty(),
                "{extension}: {head}"
            );
            assert_eq!(normals_after[&head], normals_after["/World/One/Head"], "{extension}");
        }
        for part in ["PartA/Lower", "PartA/Upper", "PartB/Lower", "PartB/Upper"] {
            let mesh = format!("/World/{part}");
            assert_eq!(normals_after[&mesh], normals_before[&mesh], "{extension}: {mesh}");
        }
        let diff = pxr("compare", &[&input, &output]);
        assert_eq!(diff["differences"], serde_json::json!([]), "{extension}: {diff:#}");
        let expected: BTreeSet<String> =
            ["/Prototypes/Character", "/World/One", "/World/Two", "/World/Three"]
                .iter()
                .flat_map(|p| [format!("{p}/Head"), format!("{p}/Body")])
                .chain(["/World/Cap".to_owned()])
                .collect();
        assert_eq!(
            prims_with_new_normals(&diff),
            expected.iter().map(String::as_str).collect(),
            "{extension}: {diff:#}"
        );
        let errors_in = pxr("validate", &[&input]);
        for e in pxr("validate", &[&output]).as_array().unwrap() {
            assert!(
                errors_in.as_array().unwrap().contains(e),
                "{extension}: new validation error {e}"
            );
        }
    }
}

/// A prototype whose source is itself a drawn mesh (instances referencing /World/Original,
/// whose head meets a body outside it): the head's fixed normals are written on it, pxr
/// composes them into both instances too, and one warning says so.
#[test]
fn a_drawn_prototype_source_is_written_and_its_instances_named() {
    let dir = tempfile::tempdir().unwrap();
    let input = stage("instanced_source.usda");
    let output = dir.path().join("instanced_source.usda");
    let (_, warnings) = fix_to(&input, &output);
    assert_eq!(warnings.len(), 1, "{warnings:#?}");
    assert!(
        warnings[0].contains("mesh </World/Original/Head>: its normals, written there, are composed by 2 instances too"),
        "{warnings:?}"
    );
    let seams = pxr("seams", &[&output]);
    assert!(seams["/World/Body /World/Original/Head"].as_f64().unwrap() < 0.005, "{seams}");
    let normals = pxr("normals", &[&output]);
    for instance in ["/World/One/Head", "/World/Two/Head"] {
        assert_eq!(normals[instance], normals["/World/Original/Head"], "{instance}");
    }
    let diff = pxr("compare", &[&input, &output]);
    assert_eq!(diff["differences"], serde_json::json!([]), "{diff:#}");
}

/// The teapot layout confined to its own folder (`--asset-root` naming it) refuses its teapot,
/// a layer outside that folder that 494 arcs reference: the error names the same arc on every
/// run (openusd lists its composition errors in an order that changes from run to run;
/// before, so did the line).
#[test]
fn a_layer_outside_the_folder_is_named_by_the_same_arc_every_time() {
    let input = stage("others/intent-vfx/scenes/teapotScene_layout.usd");
    let scenes = input.parent().unwrap().to_path_buf();
    let strict = LoadOptions { asset_roots: vec![scenes], ..LoadOptions::GEOMETRY };
    let messages: BTreeSet<String> = (0..4)
        .map(|_| match seamlit_io::load(&input, &strict) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("the teapot lies outside the stage's folder"),
        })
        .collect();
    assert_eq!(messages.len(), 1, "{messages:#?}");
    let message = messages.first().unwrap();
    assert!(message.contains("at /Scene/ring000/teapot000:"), "{message}");
}

/// A real stage by others with instancing: usd-wg's teapot layout (`others/intent-vfx`), 494
/// instances of one teapot (an external reference and an inherit of `/_class_/teapot`,
/// which lies in the stage's root layer stack), each drawn. Its teapot is a subdivision
/// surface: one warning for the prototype, naming the class's mesh, nothing written. With
/// the class turned polygonal (teapots_polygonal.usda, ours, over the layout), the normals
/// are written once, on `/_class_/teapot/geo/default/Body`, and pxr composes them into
/// every instance, the stage still of one prototype.
#[test]
fn instanced_teapots_by_others_are_written_once_on_their_class() {
    let dir = tempfile::tempdir().unwrap();
    let folder = stage("others/intent-vfx");
    let input = stage("others/intent-vfx/scenes/teapotScene_layout.usd");
    let options = LoadOptions { asset_roots: vec![folder], ..LoadOptions::GEOMETRY };
    let output = dir.path().join("teapots.usda");
    let (asset, warnings) = fix_to_with(&input, &output, &options);
    assert_eq!(asset.model.objects.len(), 494);
    assert_eq!(warnings.len(), 1, "{warnings:#?}");
    assert!(
        warnings[0]
            .contains("mesh </_class_/teapot/geo/default/Body> (the prototype of 494 instances")
            && warnings[0].contains("is a subdivision surface"),
        "{warnings:?}"
    );
    assert!(!std::fs::read_to_string(&output).unwrap().contains("over"));

    let input = stage("teapots_polygonal.usda");
    let output = dir.path().join("teapots_polygonal.usda");
    let (_, warnings) = fix_to(&input, &output);
    assert!(warnings.is_empty(), "{warnings:#?}");
    let text = std::fs::read_to_string(&output).unwrap();
    assert_eq!(text.matches("primvars:normals = ").count(), 1);
    assert!(text.contains("over \"_class_\"\n{\n    over \"teapot\""), "{}", &text[..400]);
    let bodies = [
        "/Scene/ring000/teapot000/geo/default/Body",
        "/Scene/ring027/teapot500/geo/default/Body",
        "/Scene/ring044/teapot999/geo/default/Body",
        "/Scene/ring038/instancer_teapot038/Prototypes/teapot/geo/default/Body",
    ];
    let mut args: Vec<&Path> = vec![&input];
    args.extend(bodies.iter().map(Path::new));
    let before = pxr("normals", &args);
    args[0] = &output;
    let after = pxr("normals", &args);
    assert_eq!(before["<prototypes>"], 1);
    assert_eq!(after["<prototypes>"], 1);
    for body in bodies {
        assert_eq!(before[body]["normals"], Value::Null, "{body}");
        assert_eq!(after[body]["normals"].as_array().map(Vec::len), Some(4944), "{body}");
        assert_eq!(after[body], after[bodies[0]], "{body}");
    }
}

/// The head's material: UsdPreviewSurface with its diffuse colour from a texture beside the
/// layer (or inside the package); the body's a colour, metallic and roughness.
#[test]
fn preview_surfaces_are_read() {
    for name in ["head_body.usda", "head_body.usdz"] {
        let asset = seamlit_io::load(&stage(name), &LoadOptions::DEFAULT).unwrap();
        assert!(asset.warnings.is_empty(), "{name}: {:?}", asset.warnings);
        let material = |object: &str| {
            let o = asset.model.objects.iter().find(|o| o.name == object).unwrap();
            &asset.materials[o.material.unwrap()]
        };
        let skin = material("/World/HeadPivot/Head");
        let texture = &asset.textures[skin.base_color_texture.as_ref().unwrap().texture];
        let image = texture.image.as_ref().unwrap();
        assert_eq!(image.get_pixel(0, 0).0, [200, 150, 120, 255], "{name}");
        assert_eq!(skin.roughness, 0.6);
        let cloth = material("/World/Body");
        assert_eq!(cloth.base_color, [0.2, 0.3, 0.7, 1.0]);
        assert_eq!((cloth.metallic, cloth.roughness), (0.25, 0.8));
    }
}

/// openusd's crate writer, as patched in vendor/openusd, on a layer of every shape the
/// patches touch: int arrays of 1, 4, 15, 16 and 40 elements (Pixar reads arrays under 16 as
/// uncompressed), prims with children and properties (child-name lists are TokenVectors),
/// sublayers (a StringVector). Pixar's USD exports the `.usdc` to the text of the `.usda`.
#[test]
fn the_patched_crate_writer_writes_what_pxr_reads() {
    let dir = tempfile::tempdir().unwrap();
    let ints = |n: usize| (0..n).map(|i| (i * 7 % 5).to_string()).collect::<Vec<_>>().join(", ");
    let text = format!(
        "#usda 1.0\n(\n    subLayers = [\n        @./a.usda@,\n        @./b.usdc@\n    ]\n)\n\nover \"World\"\n{{\n    int[] one = [{}]\n    int[] four = [{}]\n    int[] fifteen = [{}]\n    int[] sixteen = [{}]\n    int[] forty = [{}]\n\n    over \"Child\"\n    {{\n        normal3f[] normals = None\n    }}\n\n    over \"Other\"\n    {{\n    }}\n}}\n",
        ints(1),
        ints(4),
        ints(15),
        ints(16),
        ints(40)
    );
    let usda = dir.path().join("layer.usda");
    let usdc = dir.path().join("layer.usdc");
    std::fs::write(&usda, &text).unwrap();
    let data = openusd::usda::parse(&text).unwrap();
    let mut bytes = std::io::Cursor::new(Vec::new());
    openusd::usdc::CrateWriter::write(&data, &mut bytes).unwrap();
    std::fs::write(&usdc, bytes.get_ref()).unwrap();
    let (a, b) = (pxr("layer", &[&usda]), pxr("layer", &[&usdc]));
    assert_eq!(a["text"], b["text"], "pxr reads the crate file differently");
}

/// A stage's meshes are read one after another and built side by side, in batches: the error
/// is still the first mesh's. Here the first mesh cannot be built (its world transform is
/// singular, found when its object is made) and the second cannot be read (an index past its
/// points, found when it is read, before the first is built).
#[test]
fn the_first_meshs_error_is_the_one_reported() {
    let dir = tempfile::tempdir().unwrap();
    let triangle = |name: &str, last: u32| {
        format!(
            "def Mesh \"{name}\"\n{{\n    point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]\n    int[] faceVertexCounts = [3]\n    int[] faceVertexIndices = [0, 1, {last}]\n}}\n"
        )
    };
    let text = format!(
        "#usda 1.0\n\ndef Xform \"Flat\"\n{{\n    matrix4d xformOp:transform = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 0, 0), (0, 0, 0, 1))\n    uniform token[] xformOpOrder = [\"xformOp:transform\"]\n\n{}}}\n\n{}",
        triangle("First", 2),
        triangle("Second", 7)
    );
    let path = dir.path().join("two.usda");
    std::fs::write(&path, text).unwrap();
    let error = seamlit_io::load(&path, &LoadOptions::FIX).unwrap_err().to_string();
    assert!(error.contains("</Flat/First>") && error.contains("singular"), "{error}");
    // The second mesh alone: its own error.
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("(0, 0, 0, 0), (0, 0, 0, 1)", "(0, 0, 1, 0), (0, 0, 0, 1)");
    std::fs::write(&path, text).unwrap();
    let error = seamlit_io::load(&path, &LoadOptions::FIX).unwrap_err().to_string();
    assert!(error.contains("</Second>") && error.contains("faceVertexIndices holds 7"), "{error}");
}

/// The crate writer's int arrays are coded as Pixar's are: deltas, the most common one
/// (ties to the smallest) left out. The file is, byte for byte, `tests/usd/int_codings.usdc`,
/// written by openusd before its most common delta was counted apart near zero
/// (vendor/openusd/PATCHES.md): deltas far from zero, near it, tied across its edge.
#[test]
fn the_crate_writers_int_coding_is_unchanged() {
    let arrays: [(&str, Vec<i64>); 5] = [
        ("far", (0..40).map(|i| i * 5000 + i64::from(i % 7 == 0)).collect()),
        ("near", (0..40).map(|i| i + (i % 5) * 3).collect()),
        ("tied", (0..40).map(|i| if i % 2 == 0 { i * 1000 } else { i * 1000 + 3 }).collect()),
        ("edges", [0, -1025, -1, 1023, 1022, -3, 1021, -4, 1020].repeat(5)),
        ("wide", (0..40).map(|i: i64| i.pow(5) % 2_000_000_000 - 1_000_000_000).collect()),
    ];
    let mut text = String::from("#usda 1.0\n\nover \"World\"\n{\n");
    for (name, values) in &arrays {
        let values: Vec<String> = values.iter().map(i64::to_string).collect();
        text.push_str(&format!("    int[] {name} = [{}]\n", values.join(", ")));
    }
    text.push_str("}\n");
    let data = openusd::usda::parse(&text).unwrap();
    let mut bytes = std::io::Cursor::new(Vec::new());
    openusd::usdc::CrateWriter::write(&data, &mut bytes).unwrap();
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/usd/int_codings.usdc");
    let expected = std::fs::read(golden);
    assert!(bytes.get_ref() == &expected.unwrap(), "the crate writer's bytes changed");
}

/// A `.usdc` output is, byte for byte, the `.usda` output's text parsed by openusd and
/// written by its crate writer (the writer puts the arrays in as values instead of
/// formatting and parsing them): meshes with changed normals, polygons, instanced
/// prototypes, a layer with nothing to override, and skinned meshes whose matched
/// influences are written (the joint indices and weights, the head's grown `skel:joints`).
#[test]
fn usdc_layers_are_the_usda_text_as_openusd_writes_it() {
    let dir = tempfile::tempdir().unwrap();
    // The car overrides nothing (its normals are authored and agree): a layer of metadata.
    for (relative, overrides) in [
        ("head_body.usdz", true),
        ("teapots_polygonal.usda", true),
        ("instanced_seams.usda", true),
        ("skinned_neck.usda", true),
        ("others/USD_Mini_Car_Kit/assets/vehicles/formula/asset/formulaFullAsset.usda", false),
    ] {
        let input = stage(relative);
        let mut asset = load(&input);
        let options = asset.fix_options(FixOptions::default(), false);
        let copies = seamlit_mesh::shared_copies(&asset.model, options.weld_tolerance).unwrap();
        seamlit_mesh::fix_in_place(&mut asset.model, &options).unwrap();
        seamlit_io::match_skin_seams(&mut asset, &copies);
        // One stem in one folder: both layers sublayer the input by the same path.
        let (text, binary) = (dir.path().join("layer.usda"), dir.path().join("layer.usdc"));
        for output in [&text, &binary] {
            seamlit_io::save(&asset, output, &SaveOptions::default()).unwrap();
        }
        let text = std::fs::read_to_string(&text).unwrap();
        assert_eq!(text.contains("primvars:normals = [("), overrides, "{relative}: {text}");
        if relative == "skinned_neck.usda" {
            assert!(!text.contains("jointWeights = []"), "{relative}: {text}");
            assert!(text.contains("jointWeights = ["), "{relative}: no influences written");
        }
        let mut data = openusd::usda::parse(&text).unwrap();
        // As the writer does (`element_sizes_as_ints`): Pixar reads `elementSize` as an int.
        let paths: Vec<openusd::sdf::Path> = data.iter().map(|(path, _)| path.clone()).collect();
        for path in paths {
            if let Some(size) = data.spec_mut(&path).and_then(|spec| spec.get_mut("elementSize"))
                && let openusd::sdf::Value::Int64(n) = *size
            {
                *size = openusd::sdf::Value::Int(i32::try_from(n).unwrap());
            }
        }
        let mut expected = std::io::Cursor::new(Vec::new());
        openusd::usdc::CrateWriter::write(&data, &mut expected).unwrap();
        assert!(
            std::fs::read(&binary).unwrap() == expected.into_inner(),
            "{relative}: the .usdc is not the .usda's text as openusd writes it"
        );
    }
}

/// A `.usdc` output is the `.usda` layer in binary: Pixar's USD reads the two layers to the
/// same text (`Sdf.Layer.ExportToString`), for the head and body (arrays of 4 to 15 ints, which
/// unpatched openusd compressed where Pixar reads them uncompressed; child-name lists, which
/// it wrote as token arrays) and the formula car; the stage composes as the `.usda` one does.
#[test]
fn usdc_layers_read_as_the_usda_ones_and_other_formats_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (name, relative) in [
        ("head_body", "head_body.usdz"),
        ("faceted", "faceted.usda"),
        ("formula", "others/USD_Mini_Car_Kit/assets/vehicles/formula/asset/formulaFullAsset.usda"),
    ] {
        let input = stage(relative);
        let text = dir.path().join(format!("{name}.usda"));
        let binary = dir.path().join(format!("{name}.usdc"));
        fix_to(&input, &text);
        fix_to(&input, &binary);
        assert!(std::fs::read(&binary).unwrap().starts_with(b"PXR-USDC"), "{name}");
        let (a, b) = (pxr("layer", &[&text]), pxr("layer", &[&binary]));
        assert_eq!(a["text"], b["text"], "{name}: pxr reads the layers differently");
        let diff = pxr("compare", &[&text, &binary]);
        assert_eq!(diff, serde_json::json!({"differences": [], "normals": []}), "{name}");
        let errors_in = pxr("validate", &[&input]);
        for e in pxr("validate", &[&binary]).as_array().unwrap() {
            assert!(errors_in.as_array().unwrap().contains(e), "{name}: new validation error {e}");
        }
    }
    let obj = load(&common::model("cornell_box/cornell_box.obj"));
    let path = dir.path().join("box.usda");
    let err = seamlit_io::save(&obj, &path, &SaveOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::UsdOutput { kind: UsdOutput::NotFromUsd, .. }), "{err}");
    // A USD input goes to glTF through the generic writer.
    let asset = load(&stage("head_body.usda"));
    let glb = dir.path().join("head_body.glb");
    seamlit_io::save(&asset, &glb, &SaveOptions::default()).unwrap();
    assert_eq!(load(&glb).model.triangle_count(), asset.model.triangle_count());
}

/// Stages that do not compose, each written by the test: one line naming the stage, the
/// layer and the prim, as [`UsdKind::Composition`] or [`UsdKind::Layer`]; a missing payload
/// is a warning.
#[test]
fn stages_that_do_not_compose_fail_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let box_mesh = std::fs::read_to_string(stage("layered/prop.usda")).unwrap();
    write("prop.usda", &box_mesh);
    let header = "#usda 1.0\n(\n    defaultPrim = \"World\"\n)\n\n";
    let cases = [
        (
            "missing_reference.usda",
            "def Xform \"World\"\n{\n    def \"Holder\" (\n        references = @./gone.usda@\n    )\n    {\n    }\n}\n",
            "gone.usda",
            "/World/Holder",
        ),
        (
            "cycle_a.usda",
            "def Xform \"World\" (\n    references = @./cycle_b.usda@\n)\n{\n}\n",
            "cycle",
            "/World",
        ),
    ];
    write(
        "cycle_b.usda",
        &format!("{header}def Xform \"World\" (\n    references = @./cycle_a.usda@\n)\n{{\n}}\n"),
    );
    for (name, body, layer, prim) in cases {
        let path = write(name, &format!("{header}{body}"));
        let err = seamlit_io::load(&path, &LoadOptions::GEOMETRY).unwrap_err();
        let line = err.to_string();
        assert!(
            matches!(err, IoError::Usd { kind: UsdKind::Composition { .. }, .. }),
            "{name}: {err:?}"
        );
        assert!(line.starts_with(&path.display().to_string()) && !line.contains('\n'), "{line}");
        assert!(line.contains(layer) && line.contains(prim), "{name}: {line}");
    }
    let path =
        write("missing_sublayer.usda", "#usda 1.0\n(\n    subLayers = [@./gone_layer.usda@]\n)\n");
    let err = seamlit_io::load(&path, &LoadOptions::GEOMETRY).unwrap_err();
    assert!(matches!(err, IoError::Usd { .. }), "{err:?}");
    assert!(
        err.to_string().contains("gone_layer.usda") && !err.to_string().contains('\n'),
        "{err}"
    );
    let path = write("missing_root.usda", "");
    std::fs::remove_file(&path).unwrap();
    assert!(seamlit_io::load(&path, &LoadOptions::GEOMETRY).is_err());
    // A missing payload: the stage composes without it, with a warning; the prop still loads.
    let path = write(
        "payload.usda",
        &format!(
            "{header}def Xform \"World\"\n{{\n    def \"Lazy\" (\n        payload = @./gone_payload.usda@\n    )\n    {{\n    }}\n    def \"Prop\" (\n        references = @./prop.usda@\n    )\n    {{\n    }}\n}}\n"
        ),
    );
    let asset = load(&path);
    assert_eq!(asset.model.objects.len(), 1);
    assert!(asset.warnings.iter().any(|w| w.contains("gone_payload.usda")), "{:?}", asset.warnings);
}

/// A layer a stage names outside its folder (`../`, an absolute path) is read as USD resolves
/// it, as asset libraries lay their layers out. With `asset_roots` (`--asset-root`, the
/// strict mode) a layer outside the stage's folder and those folders is not opened: one line
/// naming the arc's layer and prim, exit status 2 at the command line. A device is never
/// opened. Every layer, not only the root one, is held to the size limit and the text
/// nesting limit.
#[test]
fn layers_outside_the_stages_folder_are_read_unless_confined_and_limits_hold() {
    let dir = tempfile::tempdir().unwrap();
    let (inner, outer) = (dir.path().join("shot"), dir.path().join("elsewhere"));
    std::fs::create_dir_all(&inner).unwrap();
    std::fs::create_dir_all(&outer).unwrap();
    let prop = std::fs::read_to_string(stage("layered/prop.usda")).unwrap();
    std::fs::write(outer.join("prop.usda"), &prop).unwrap();
    std::fs::write(inner.join("prop.usda"), &prop).unwrap();
    let header = "#usda 1.0\n(\n    defaultPrim = \"World\"\n)\n\n";
    let referencing = |name: &str, asset: &str| {
        let path = inner.join(name);
        let body = format!(
            "{header}def Xform \"World\"\n{{\n    def \"Prop\" (\n        references = @{asset}@\n    )\n    {{\n    }}\n}}\n"
        );
        std::fs::write(&path, body).unwrap();
        path
    };
    let absolute = outer.join("prop.usda").display().to_string();
    // Strict: only the stage's own folder (and so nothing outside it).
    let strict = LoadOptions { asset_roots: vec![inner.clone()], ..LoadOptions::GEOMETRY };
    for (name, asset) in [("up.usda", "../elsewhere/prop.usda"), ("absolute.usda", &absolute)] {
        let path = referencing(name, asset);
        assert_eq!(load(&path).model.objects.len(), 1, "{name}: read as USD resolves it");
        let err = seamlit_io::load(&path, &strict).unwrap_err();
        assert!(matches!(err, IoError::Usd { kind: UsdKind::Outside { .. }, .. }), "{err:?}");
        let line = err.to_string();
        assert!(!line.contains('\n'), "{line}");
        for needle in ["prop.usda", "/World/Prop", "outside the stage's folder", "--asset-root"] {
            assert!(line.contains(needle), "{name}: {needle:?} in {line}");
        }
        let allowed = LoadOptions { asset_roots: vec![outer.clone()], ..LoadOptions::GEOMETRY };
        assert_eq!(seamlit_io::load(&path, &allowed).unwrap().model.objects.len(), 1, "{name}");
    }
    // A sublayer outside: the stage would compose without it; refused all the same.
    let path = inner.join("sub.usda");
    std::fs::write(&path, "#usda 1.0\n(\n    subLayers = [@../elsewhere/prop.usda@]\n)\n").unwrap();
    assert_eq!(load(&path).model.objects.len(), 1);
    let err = seamlit_io::load(&path, &strict).unwrap_err();
    assert!(matches!(err, IoError::Usd { kind: UsdKind::Outside { .. }, .. }), "{err:?}");
    // A device or a pipe is no layer, even named like one (reading it would never end): one
    // line naming it, nothing read from it.
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/dev/zero", outer.join("zero.usda")).unwrap();
        let path = referencing("device.usda", "../elsewhere/zero.usda");
        let err = seamlit_io::load(&path, &LoadOptions::GEOMETRY).unwrap_err().to_string();
        assert!(err.contains("/dev/zero") && !err.contains('\n'), "{err}");
        let fifo = outer.join("pipe.usda");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(made.success());
        let path = referencing("pipe.usda", "../elsewhere/pipe.usda");
        let err = seamlit_io::load(&path, &LoadOptions::GEOMETRY).unwrap_err().to_string();
        assert!(err.contains("pipe.usda") && err.contains("not a regular file"), "{err}");
        assert!(!err.contains('\n'), "{err}");
    }

    // Inside the folder, each layer a stage references is checked as the root one is.
    let path = referencing("inside.usda", "./prop.usda");
    assert_eq!(load(&path).model.objects.len(), 1);
    // The referenced layer grows past a limit the root layer is within.
    let limit = std::fs::metadata(&path).unwrap().len() + 100;
    let padded = format!("{prop}\n# {}\n", "x".repeat(usize::try_from(limit).unwrap()));
    std::fs::write(inner.join("prop.usda"), padded).unwrap();
    assert_eq!(load(&path).model.objects.len(), 1);
    let small = LoadOptions { max_file_bytes: limit, ..LoadOptions::GEOMETRY };
    let err = seamlit_io::load(&path, &small).unwrap_err().to_string();
    assert!(err.contains("prop.usda") && err.contains("more than the limit"), "{err}");
    let deep = format!("{header}{}{}", "def \"A\" {\n".repeat(300), "}\n".repeat(300));
    std::fs::write(inner.join("prop.usda"), deep).unwrap();
    let err = seamlit_io::load(&path, &LoadOptions::GEOMETRY).unwrap_err().to_string();
    assert!(err.contains("prop.usda") && err.contains("nested 300 levels"), "{err}");
}

/// Points with time samples and no default (an animated mesh) are read at the earliest
/// sample, with a warning that the normals hold for that shape only.
#[test]
fn time_sampled_points_are_read_at_the_earliest_sample() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("animated.usda");
    let samples = |dy: f32| {
        format!("[(0, {dy}, 0), (1, {dy}, 0), (1, {y1}, 0), (0, {y1}, 0)]", y1 = dy + 1.0)
    };
    std::fs::write(
        &path,
        format!(
            "#usda 1.0\n\ndef Mesh \"Quad\"\n{{\n    int[] faceVertexCounts = [4]\n    int[] faceVertexIndices = [0, 1, 2, 3]\n    point3f[] points.timeSamples = {{\n        2: {},\n        1: {},\n    }}\n    uniform token subdivisionScheme = \"none\"\n}}\n",
            samples(5.0),
            samples(-3.0)
        ),
    )
    .unwrap();
    let asset = load(&path);
    let [quad] = &asset.model.objects[..] else { panic!("one object") };
    let lowest = quad.positions.iter().map(|p| p.y).fold(f32::INFINITY, f32::min);
    assert_eq!(lowest, -3.0, "the sample at time 1");
    assert!(
        asset.warnings.iter().any(|w| w.contains("</Quad>") && w.contains("time-sampled")),
        "{:?}",
        asset.warnings
    );
}

/// Time samples (time_sampled.usda): two heads and bodies smoothed apart, the first body's
/// points time-sampled, the second head's normals. A value the layer writes would hold for
/// every frame (USD takes the strongest layer's opinion, samples or default), so those two
/// meshes get no normals written, one warning each naming the layer and the mesh, and pxr
/// composes their normals (the second head's samples) as the input's; their static partners
/// are written.
#[test]
fn time_sampled_points_or_normals_are_not_overridden() {
    let dir = tempfile::tempdir().unwrap();
    let input = stage("time_sampled.usda");
    let output = dir.path().join("time_sampled.usda");
    let (_, warnings) = fix_to(&input, &output);
    let refused: Vec<&String> =
        warnings.iter().filter(|w| w.contains("its normals are not written")).collect();
    assert_eq!(refused.len(), 2, "{warnings:#?}");
    let layer = output.display().to_string();
    assert!(
        refused[0].starts_with(&layer)
            && refused[0].contains("mesh </World/Body1>: its `points` is time-sampled, and normals fixed for one shape would hold for every frame"),
        "{refused:?}"
    );
    assert!(
        refused[1].starts_with(&layer)
            && refused[1].contains("mesh </World/Head2>: its `primvars:normals` is time-sampled, and one value would replace its normals at every frame"),
        "{refused:?}"
    );
    let diff = pxr("compare", &[&input, &output]);
    assert_eq!(diff["differences"], serde_json::json!([]), "{diff:#}");
    assert_eq!(
        prims_with_new_normals(&diff),
        BTreeSet::from(["/World/Body2", "/World/Head1"]),
        "{diff:#}"
    );
}

/// Every prefix of the committed stages (binary, package, text) at 61 lengths, and 400
/// copies of each with four bytes overwritten (a fixed pseudo-random sequence; 2,000 copies
/// of the `.usdc`, with one to four bytes overwritten, half of them inside its structural
/// sections at the end), either loads or fails with one line: never a panic inside openusd
/// (which the reader would report as [`UsdKind::Panicked`]) and never an abort. Unpatched
/// openusd 0.6 sized buffers by the counts a corrupted `.usdc` gives and aborted the whole
/// process on the failed allocation; the fork in vendor/openusd bounds them by the file
/// (vendor/openusd/PATCHES.md).
#[test]
fn cut_and_corrupted_stages_fail_cleanly_or_load() {
    let mut next = seamlit_testkit::xorshift(0x2545_f491_4f6c_dd1d);
    let dir = tempfile::tempdir().unwrap();
    let mut panics = BTreeMap::new();
    for name in ["head_body.usdc", "head_body.usdz", "faceted.usda"] {
        let bytes = std::fs::read(stage(name)).unwrap();
        let path = dir.path().join(name);
        let mut check = |bytes: &[u8], what: String| {
            std::fs::write(&path, bytes).unwrap();
            match seamlit_io::load(&path, &LoadOptions::GEOMETRY) {
                Ok(asset) => {
                    let _ = seamlit_mesh::report(&asset.model, &ReportOptions::default());
                }
                Err(e) => {
                    assert!(!e.to_string().contains('\n'), "{what}: {e}");
                    if let IoError::Usd { kind: UsdKind::Panicked { message }, .. } = &e {
                        panics.insert(what, message.clone());
                    }
                }
            }
        };
        for k in 0..61 {
            check(&bytes[..bytes.len() * k / 61], format!("{name} cut at {k}/61"));
        }
        let binary = name.ends_with(".usdc");
        for i in 0..if binary { 2000 } else { 400 } {
            let mut corrupted = bytes.clone();
            let (flips, from) = match (binary, i % 2) {
                // The crate file's tables of contents, tokens, fields, paths and specs are
                // in its last quarter (its values before them).
                (true, 0) => (1 + next() % 4, bytes.len() * 3 / 4),
                (true, _) => (1 + next() % 4, 0),
                (false, _) => (4, 0),
            };
            for _ in 0..flips {
                let span = (bytes.len() - from) as u64;
                let at = from + usize::try_from(next() % span).unwrap();
                corrupted[at] = next().to_le_bytes()[0];
            }
            check(&corrupted, format!("{name} corrupted #{i}"));
        }
    }
    assert!(panics.is_empty(), "openusd panicked on {} files: {panics:#?}", panics.len());
}

/// The `usd` fuzz target's first finding (fuzz/README.md): a `.usdc` whose header gives a
/// count past the end of the file. Unpatched openusd 0.6 allocated it (848 TB) before reading
/// and the process aborted; the fork refuses it as a layer it cannot read, in one line.
#[test]
fn a_usdc_count_past_the_file_is_refused_in_one_line() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/regressions/usd_usdc_count_past_the_file.usdc");
    let err = seamlit_io::load(&path, &LoadOptions::GEOMETRY).unwrap_err();
    let line = err.to_string();
    assert!(
        matches!(&err, IoError::Usd { kind: UsdKind::Layer { .. } | UsdKind::Prim { .. }, .. }),
        "{err:?}"
    );
    assert!(line.contains("usd_usdc_count_past_the_file.usdc") && !line.contains('\n'), "{line}");
}

/// The `usd` fuzz target's fourth run: a corrupted `.usdc` whose child-name list holds a
/// name that is not an identifier; openusd's traversal walked the stage for ever (a hang).
/// The fork skips children that are not named by identifiers: the stage loads, its two
/// meshes read, within seconds.
#[test]
fn a_usdc_child_that_is_not_a_name_does_not_hang_the_traversal() {
    assert_eq!(load_within_60_s("usd_usdc_prim_child_not_a_name.usdc"), Ok(2));
}

/// The `usd` fuzz target's fifth run: a text layer whose metadata holds arrays nested 48
/// deep; openusd's parser formatted each level's array into the one outside it with `{:?}`,
/// doubling the escapes each level (2^48 bytes: gigabytes, then a hang). The fork refuses an
/// array of arrays as a metadata value: one line, at once.
#[test]
fn metadata_arrays_of_arrays_are_refused_at_once() {
    let result = load_within_60_s("usd_metadata_arrays_nested_48_deep.usda");
    assert!(result.as_ref().is_err_and(|e| e.contains("an array of arrays")), "{result:?}");
}

/// The prims whose normals `pxr_check.py compare` found changed (each line of its `normals`
/// starts with the prim's path).
fn prims_with_new_normals(diff: &Value) -> BTreeSet<&str> {
    let lines = diff["normals"].as_array().expect("compare lists the normals");
    lines.iter().map(|l| l.as_str().unwrap().split(' ').next().unwrap()).collect()
}

/// Loads a regression input on a thread: the number of objects, or the error's line; the
/// test fails if the load takes over 60 s (the inputs that hung openusd).
fn load_within_60_s(name: &str) -> Result<usize, String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/regressions").join(name);
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let objects =
            seamlit_io::load(&path, &LoadOptions::GEOMETRY).map(|a| a.model.objects.len());
        let _ = send.send(objects.map_err(|e| e.to_string()));
    });
    receive.recv_timeout(std::time::Duration::from_secs(60)).expect("the load took over 60 s")
}

/// Stages by others (the ASWF USD Assets working group's repository, Apache 2.0): RYStorm's
/// formula car, a stage of layers, references and a variant set, exported by 3ds Max with
/// flat normals everywhere; and three instanced, payloaded, spinning subdivision pyramids.
/// Read with pxr's world-space points; fixed, the layer seamlit writes composes back to the
/// input, with no normal changed (all hard edges; subdivision surfaces inside instances) and
/// no new validation error.
#[test]
fn stages_by_others_compose_back_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    // The car's entry layer references layers in sibling folders of the kit.
    let kit = stage("others/USD_Mini_Car_Kit");
    for (name, relative, meshes, roots) in [
        (
            "formula",
            "others/USD_Mini_Car_Kit/assets/vehicles/formula/asset/formulaFullAsset.usda",
            5,
            vec![kit],
        ),
        ("pyramids", "others/SubdivisionSurfaces/Creases_SpinningPyramids.usda", 3, vec![]),
    ] {
        let input = stage(relative);
        let options = LoadOptions { asset_roots: roots, ..LoadOptions::GEOMETRY };
        assert_points_match_pxr_with(&input, &options);
        let output = dir.path().join(format!("{name}.usda"));
        let (asset, warnings) = fix_to_with(&input, &output, &options);
        assert_eq!(asset.model.objects.len(), meshes, "{name}");
        let diff = pxr("compare", &[&input, &output]);
        assert_eq!(
            diff,
            serde_json::json!({"differences": [], "normals": []}),
            "{name}: {warnings:?}"
        );
        let errors_in = pxr("validate", &[&input]);
        for e in pxr("validate", &[&output]).as_array().unwrap() {
            assert!(errors_in.as_array().unwrap().contains(e), "{name}: new validation error {e}");
        }
    }
}

/// The materials of `materialBind` GeomSubsets are read only when asked for (for drawing):
/// the box's left half has the red material, its right half the blue, the mesh its own grey.
/// Cut after the fix, each half is an object of its own whose every triangle corner keeps the
/// position and normal the whole mesh was given there, so the cut makes no seam; by default
/// (`fix`) the mesh is one object and nothing is read of its subsets.
#[test]
fn subset_materials_are_read_for_drawing_and_cut_after_the_fix() {
    let input = stage("subsets.usda");
    let plain = seamlit_io::load(&input, &LoadOptions::GEOMETRY).unwrap();
    assert!(plain.triangle_materials.is_empty());
    let names = |a: &Asset| a.materials.iter().map(|m| m.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&plain), ["Grey"]);

    let options = LoadOptions::GEOMETRY.with_subset_materials();
    let mut asset = seamlit_io::load(&input, &options).unwrap();
    assert!(asset.warnings.is_empty(), "{:?}", asset.warnings);
    assert_eq!(asset.model.objects.len(), 1);
    assert_eq!(asset.split_object_count(), 2);
    let fix = asset.fix_options(FixOptions::default(), false);
    seamlit_mesh::fix_in_place(&mut asset.model, &fix).unwrap();
    let whole = asset.model.objects[0].clone();
    let by_name = |n: &str| asset.materials.iter().position(|m| m.name == n);
    let [red, blue] = [by_name("Red"), by_name("Blue")];
    assert!(red.is_some() && blue.is_some(), "{:?}", names(&asset));
    let per_triangle = asset.triangle_materials[0].materials.clone();
    assert_eq!(per_triangle.iter().filter(|m| **m == red).count(), 10);
    assert_eq!(per_triangle.iter().filter(|m| **m == blue).count(), 10);

    asset.split_triangle_materials();
    assert!(asset.triangle_materials.is_empty());
    let parts = &asset.model.objects;
    assert_eq!(parts.iter().map(|o| o.material).collect::<Vec<_>>(), [red, blue]);
    let normals = |o: &seamlit_mesh::Object| o.normals.clone().unwrap();
    for part in parts {
        // The whole mesh's triangles of this part's material, in order.
        let mut of_part = (0..whole.triangles.len()).filter(|&t| per_triangle[t] == part.material);
        assert_eq!(part.triangles.len(), 10);
        for t in &part.triangles {
            let w = whole.triangles[of_part.next().unwrap()];
            for (&v, &wv) in t.iter().zip(&w) {
                assert_eq!(part.positions[v as usize], whole.positions[wv as usize]);
                assert_eq!(normals(part)[v as usize], normals(&whole)[wv as usize]);
            }
        }
    }
}

/// Subsets that cannot be used (indices past the faces, a face in two subsets, a subset of
/// points, a binding on a subset of another family) are one warning naming the layer and the
/// mesh; the usable faces keep their subsets' materials.
#[test]
fn unusable_subsets_are_one_warning() {
    let input = stage("subsets_bad.usda");
    let options = LoadOptions::GEOMETRY.with_subset_materials();
    let asset = seamlit_io::load(&input, &options).unwrap();
    assert_eq!(asset.warnings.len(), 1, "{:?}", asset.warnings);
    let w = &asset.warnings[0];
    for needle in [
        "subsets_bad.usda",
        "</Model/Box>",
        "Left has 2 indices outside the mesh's 10 faces",
        "Right has 1 face that an earlier subset holds",
        "Points has elementType \"point\"",
        "Other binds a material but its family is \"parts\"",
    ] {
        assert!(w.contains(needle), "{w:?} lacks {needle:?}");
    }
    let red = asset.materials.iter().position(|m| m.name == "Red");
    let blue = asset.materials.iter().position(|m| m.name == "Blue");
    let per_triangle = &asset.triangle_materials[0].materials;
    assert_eq!(per_triangle.iter().filter(|m| **m == red).count(), 10);
    // Face 8 is Left's (red), though Right lists it too; Other's binding is not used.
    assert_eq!(per_triangle.iter().filter(|m| **m == blue).count(), 10);
    assert_eq!(per_triangle[16..18], [red, red]);
}

/// A layer in a format openusd has no reader for (MaterialX's `.mtlx`, which Pixar's USD
/// reads only through its MaterialX plugin) is one warning, as in Pixar's USD without the
/// plugin, and the rest of the stage composes: the same model as without the reference.
#[test]
fn a_materialx_layer_is_one_warning_and_the_rest_composes() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(stage("head_body.usda")).unwrap();
    let looks = "def \"Looks\"\n    {";
    let library = "\n        def \"Library\" (\n            references = @./looks.mtlx@</MaterialX>\n        )\n        {\n        }\n";
    let with = text.replacen(looks, &format!("{looks}{library}"), 1);
    assert_ne!(with, text, "head_body.usda has its Looks");
    let path = dir.path().join("head_body.usda");
    std::fs::write(&path, with).unwrap();
    std::fs::write(
        dir.path().join("looks.mtlx"),
        "<?xml version=\"1.0\"?>\n<materialx version=\"1.38\">\n  <surfacematerial name=\"M\" type=\"material\" />\n</materialx>\n",
    )
    .unwrap();
    let asset = seamlit_io::load(&path, &LoadOptions::GEOMETRY).unwrap();
    let plain = seamlit_io::load(&stage("head_body.usda"), &LoadOptions::GEOMETRY).unwrap();
    assert_eq!(asset.model.objects.len(), plain.model.objects.len());
    assert_eq!(asset.model.triangle_count(), plain.model.triangle_count());
    let lines: Vec<&String> = asset.warnings.iter().filter(|w| w.contains("looks.mtlx")).collect();
    assert_eq!(lines.len(), 1, "{:?}", asset.warnings);
    assert!(lines[0].contains("openusd reads no .mtlx layers") && !lines[0].contains('\n'));
}

/// The seam check by pxr joins corners at one position as seamlit's weld does (within 1e-6
/// of the model's diagonal), not by rounding to a grid: two meshes that share two vertices
/// (normals equal) and have, 32 micrometres apart, two distinct vertices whose normals face
/// opposite ways have no seam. Rounded to 1e-4 those two vertices were one position and a
/// 180-degree "seam", as BrainStem.usdz's five were (BENCHMARKS.md).
#[test]
fn the_pxr_seam_check_joins_positions_as_the_weld_does() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = |name: &str, side: f32, indices: &str, near: &str| {
        format!(
            "def Mesh \"{name}\" {{\n    int[] faceVertexCounts = [3, 3]\n    \
             int[] faceVertexIndices = [{indices}]\n    \
             point3f[] points = [(0, 0, 0), (0, 1, 0), ({side}, 0.5, 0), ({near}, 0.5, 0)]\n    \
             normal3f[] primvars:normals = [(0, 0, 1), ({side}, 0, 0)] (interpolation = \"vertex\")\n    \
             int[] primvars:normals:indices = [0, 0, 0, 1]\n}}\n"
        )
    };
    let text = format!(
        "#usda 1.0\n(\n    upAxis = \"Y\"\n)\n{}{}",
        mesh("A", -1.0, "0, 3, 2, 3, 1, 2", "-0.000016"),
        mesh("B", 1.0, "0, 2, 3, 3, 2, 1", "0.000016")
    );
    let path = dir.path().join("near.usda");
    std::fs::write(&path, text).unwrap();
    let seam = pxr("seam", &[&path]);
    // Corners of A and B at (0, 0, 0) and at (0, 1, 0): one pair each, normals equal.
    assert_eq!(seam["pairs"], 2, "{seam}");
    assert!(seam["largest_degrees"].as_f64().unwrap() < 1e-3, "{seam}");
    // seamlit's weld sees the same two shared positions.
    let report = seamlit_mesh::report(&load(&path).model, &ReportOptions::default()).unwrap();
    assert_eq!(report.shared_positions, 2, "{report:?}");
}
