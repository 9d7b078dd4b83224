//! UsdSkel skin bindings in and out, with Pixar's USD as the oracle (tests/usd/pxr_check.py
//! `skinned`: pxr's `UsdSkelSkinningQuery::ComputeSkinnedPoints` at the bind pose, or at the
//! skeleton's rest pose with a joint turned). The stage, assets/models/usd/skinned_neck.usda
//! (make.py): a head and a body bound to one skeleton, sharing the equator, where the head is
//! all neck and the body 0.6 chest and 0.4 neck. Read: the skinned meshes placed where pxr
//! skins them at the bind pose (`geomBindTransform`, then the skeleton's world matrix; not the
//! meshes' own transforms), their influences named by joint across the meshes' joint orders.
//! Written: matched influences as primvars of the override layer, so that pxr's skinning
//! keeps the neck closed when the neck turns; nothing but normals and those primvars differ.
//!
//! Needs Python 3 with usd-core (`pip install usd-core`; `.ci/run` installs it).
#![cfg(feature = "usd")]

mod common;

use std::path::{Path, PathBuf};

use glam::Vec3;
use seamlit_io::{Asset, LoadOptions, SaveOptions};
use seamlit_mesh::{FixOptions, ReportOptions};
use serde_json::Value;

const HEAD: &str = "/Character/Geom/Head";
const BODY: &str = "/Character/Geom/Body";
/// The joint the posed checks turn, and by how much (degrees about its Z axis).
const NECK: &str = "Hips/Chest/Neck";
const TURN: &str = "40";
/// The equator's points: the head's last ring (points 48 to 63), the body's first (0 to 15).
const HEAD_EQUATOR: usize = 48;
const RING: usize = 16;

/// Runs pxr_check.py `command` on `args` (the output JSON's path goes after the first) and
/// returns the JSON it writes.
fn pxr(command: &str, args: &[&str]) -> Value {
    let (inputs, extra) = args.split_at(if command == "skinned" { 1 } else { args.len() });
    common::pxr_check(command, inputs, extra)
}

fn neck_stage() -> PathBuf {
    common::model("usd/skinned_neck.usda")
}

fn text(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn points_of(json: &Value) -> Vec<Vec3> {
    json.as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let v: Vec<f32> =
                p.as_array().unwrap().iter().map(|x| common::f32_of(x.as_f64().unwrap())).collect();
            Vec3::new(v[0], v[1], v[2])
        })
        .collect()
}

/// The largest distance between the head's and the body's copies of the equator's points as
/// pxr skins `stage` with the neck turned.
fn posed_gap(stage: &Path) -> f32 {
    let posed = pxr("skinned", &[text(stage), NECK, TURN]);
    let head = points_of(&posed["points"][HEAD]);
    let body = points_of(&posed["points"][BODY]);
    (0..RING).map(|i| head[HEAD_EQUATOR + i].distance(body[i])).fold(0.0, f32::max)
}

/// Fixes `input` as `seamlit fix` does (skin seams matched where `matched`, as
/// `--skin-seams match`, the default; else as `--skin-seams keep`), writes it to `output` and
/// returns the warnings of loading and saving.
fn fix_to(input: &Path, output: &Path, matched: bool) -> Vec<String> {
    let mut asset = seamlit_io::load(input, &LoadOptions::GEOMETRY).unwrap();
    let options = asset.fix_options(FixOptions::default(), false);
    let copies = seamlit_mesh::shared_copies(&asset.model, options.weld_tolerance).unwrap();
    seamlit_mesh::fix_in_place(&mut asset.model, &options).unwrap();
    if matched {
        seamlit_io::match_skin_seams(&mut asset, &copies);
    }
    let mut warnings = asset.warnings.clone();
    warnings.extend(seamlit_io::save(&asset, output, &SaveOptions::default()).unwrap().warnings);
    warnings
}

fn object<'a>(asset: &'a Asset, name: &str) -> &'a seamlit_mesh::Object {
    asset.model.objects.iter().find(|o| o.name == name).unwrap()
}

/// Each skinned mesh's positions are where pxr skins its points at the bind pose (every
/// skinning matrix the identity; the rest pose is the bind pose here): `geomBindTransform`
/// (the head's moves it up by 0.5), then the skeleton's world matrix (the SkelRoot's and the
/// skeleton's translations); the Xform above the meshes, which skinning ignores, does not
/// move them.
#[test]
fn skinned_meshes_are_where_pxr_skins_them() {
    let input = neck_stage();
    let asset = seamlit_io::load(&input, &LoadOptions::GEOMETRY).unwrap();
    assert!(asset.warnings.is_empty(), "{:?}", asset.warnings);
    let rest = pxr("skinned", &[text(&input), "bind"]);
    for name in [HEAD, BODY] {
        let object = object(&asset, name);
        let m = object.model_transform();
        let ours: Vec<Vec3> = object.positions.iter().map(|p| m.transform_point3(*p)).collect();
        let theirs = points_of(&rest["points"][name]);
        assert_eq!(ours.len(), theirs.len(), "{name}: one vertex per point");
        let near = |a: &Vec3, set: &[Vec3]| set.iter().any(|b| a.distance(*b) < 1e-5);
        for p in &ours {
            assert!(near(p, &theirs), "{name}: position {p} is no point pxr skins");
        }
        for q in &theirs {
            assert!(near(q, &ours), "{name}: pxr's skinned point {q} is no position");
        }
    }
    // The equator's copies meet there, so the two meshes weld along it.
    let report = seamlit_mesh::report(&asset.model, &ReportOptions::default()).unwrap();
    assert_eq!(report.shared_positions, RING);
}

/// Influences come in per point, in sets of four, naming joints by (skeleton, joint path):
/// the head's own `skel:joints` (the neck alone, constant) and the body's skeleton order name
/// the neck alike. At the equator the head is all neck and the body 0.6 chest and 0.4 neck, so
/// the report counts its 16 positions as skin seams.
#[test]
fn skin_influences_are_read_by_joint() {
    let asset = seamlit_io::load(&neck_stage(), &LoadOptions::GEOMETRY).unwrap();
    let head = object(&asset, HEAD);
    let body = object(&asset, BODY);
    assert_eq!((head.skin.len(), body.skin.len()), (1, 1));
    let neck = head.skin[0].joints[0][0];
    for v in 0..head.positions.len() {
        let lanes: Vec<(u32, f32)> = head.skin[0].of(v).collect();
        assert_eq!(lanes, vec![(neck, 1.0)], "head vertex {v}");
    }
    let equator = body.skin[0].of(0).collect::<Vec<_>>();
    assert_eq!(equator.len(), 2, "{equator:?}");
    assert_eq!(equator[1], (neck, 0.4), "the body's neck is the head's");
    assert_ne!(equator[0].0, neck);
    assert_eq!(equator[0].1, 0.6);
    let report = seamlit_mesh::report(&asset.model, &ReportOptions::default()).unwrap();
    assert_eq!(report.skin_seams.positions, RING);
}

/// `fix` with matched skin seams, as pxr composes its layer: the neck's normals within 0.005
/// degrees at rest (22.5 as authored), and, with the neck turned 40 degrees, pxr's skinning
/// keeps the head's and the body's copies of the equator together (apart by 0.41 in the
/// input); only normals, the skin primvars of the two meshes and the head's `skel:joints`
/// (grown by the chest) differ; no new validation error. `.usdc` and `.usdz` as `.usda`.
/// Without the match the posed gap stays, and nothing but normals is written.
#[test]
fn matched_influences_keep_the_neck_closed_as_pxr_skins_it() {
    let input = neck_stage();
    let before = pxr("skinned", &[text(&input)]);
    assert!(before["seam"]["largest_degrees"].as_f64().unwrap() > 20.0, "{before:#}");
    assert!(posed_gap(&input) > 0.3, "the input opens when posed");
    let errors_in = pxr("validate", &[text(&input)]);
    let dir = tempfile::tempdir().unwrap();
    for name in ["fixed.usda", "fixed.usdc", "fixed.usdz"] {
        let output = dir.path().join(name);
        let warnings = fix_to(&input, &output, true);
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        let after = pxr("skinned", &[text(&output)]);
        assert_eq!(after["seam"]["pairs"], before["seam"]["pairs"], "{name}");
        assert!(after["seam"]["largest_degrees"].as_f64().unwrap() < 0.005, "{name}: {after:#}");
        let gap = posed_gap(&output);
        assert!(gap < 1e-5, "{name}: the neck opens by {gap} when posed");
        let diff = pxr("compare", &[text(&input), text(&output)]);
        let differences: Vec<String> = diff["differences"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l.as_str().unwrap().split(": ").next().unwrap().to_owned())
            .collect();
        assert_eq!(
            differences,
            [
                format!("{BODY} primvars:skel:jointIndices"),
                format!("{BODY} primvars:skel:jointWeights"),
                format!("{HEAD} primvars:skel:jointIndices"),
                format!("{HEAD} primvars:skel:jointWeights"),
                format!("{HEAD} skel:joints"),
            ],
            "{name}: {diff:#}"
        );
        assert_eq!(diff["normals"].as_array().unwrap().len(), 5, "{name}: {diff:#}");
        // By hand: the head's equator (its last 16 points) 0.7 neck (its joint 0) and 0.3
        // chest (1, appended to its joints), the rest all neck; two influences per point.
        let layer = pxr("layer", &[text(&output)]);
        let layer = layer["text"].as_str().unwrap();
        let indices = [vec!["0, 0"; 48], vec!["0, 1"; 16]].concat().join(", ");
        let weights = [vec!["1, 0"; 48], vec!["0.7, 0.3"; 16]].concat().join(", ");
        for expected in [
            r#"uniform token[] skel:joints = ["Hips/Chest/Neck", "Hips/Chest"]"#.to_owned(),
            format!(
                "int[] primvars:skel:jointIndices = [{indices}] (\n                elementSize = 2\n                interpolation = \"vertex\""
            ),
            format!(
                "float[] primvars:skel:jointWeights = [{weights}] (\n                elementSize = 2\n                interpolation = \"vertex\""
            ),
        ] {
            assert!(layer.contains(&expected), "{name}: {expected} in\n{layer}");
        }
        for e in pxr("validate", &[text(&output)]).as_array().unwrap() {
            assert!(errors_in.as_array().unwrap().contains(e), "{name}: new validation error {e}");
        }
    }
    let kept = dir.path().join("kept.usda");
    assert!(fix_to(&input, &kept, false).is_empty());
    assert!(posed_gap(&kept) > 0.3, "--skin-seams keep leaves the gap");
    let diff = pxr("compare", &[text(&input), text(&kept)]);
    assert_eq!(diff["differences"], serde_json::json!([]), "{diff:#}");
}

/// A binding that cannot be used is one warning naming the mesh and why; the mesh is read
/// unskinned at its own transform (as USD draws it), and the stage still loads.
#[test]
fn bad_skin_bindings_are_one_warning_each() {
    let original = std::fs::read_to_string(neck_stage()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "out of range",
            "int[] primvars:skel:jointIndices = [0] (",
            "int[] primvars:skel:jointIndices = [3] (",
            HEAD,
            "skel:jointIndices holds 3, for 1 joints",
        ),
        (
            "not per point",
            "elementSize = 2",
            "elementSize = 3",
            BODY,
            "128 joint indices and weights for 64 elements of 3 influences",
        ),
        (
            "wrong count",
            "int[] primvars:skel:jointIndices = [0] (",
            "int[] primvars:skel:jointIndices = [0, 0] (",
            HEAD,
            "2 skel:jointIndices, 1 skel:jointWeights",
        ),
        ("element size 0", "elementSize = 1", "elementSize = 0", HEAD, "elementSize 0"),
        (
            "no skeleton",
            "rel skel:skeleton = </Character/Skeleton>",
            "rel skel:skeleton = </Character/Gone>",
            HEAD,
            "</Character/Gone> is not a Skeleton",
        ),
        ("no SkelRoot", "def SkelRoot \"Character\"", "def Xform \"Character\"", HEAD, "SkelRoot"),
        (
            "no SkelBindingAPI on the SkelRoot",
            "def SkelRoot \"Character\" (\n    prepend apiSchemas = [\"SkelBindingAPI\"]\n)",
            "def SkelRoot \"Character\"",
            BODY,
            "no skel:skeleton is bound to it or an ancestor with SkelBindingAPI",
        ),
        (
            "no SkelBindingAPI",
            "def Mesh \"Head\" (\n            prepend apiSchemas = [\"SkelBindingAPI\"]\n        )",
            "def Mesh \"Head\"",
            HEAD,
            "SkelBindingAPI is not applied to it",
        ),
    ];
    for (what, from, to, mesh, reason) in cases {
        assert!(original.contains(from), "{what}: {from:?}");
        let path = dir.path().join(format!("{}.usda", what.replace(' ', "_")));
        std::fs::write(&path, original.replace(from, to)).unwrap();
        let asset = seamlit_io::load(&path, &LoadOptions::GEOMETRY)
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        let about: Vec<&String> = asset.warnings.iter().filter(|w| w.contains(mesh)).collect();
        assert_eq!(about.len(), 1, "{what}: {:?}", asset.warnings);
        assert!(about[0].contains(reason), "{what}: {about:?} lacks {reason:?}");
        assert!(about[0].contains(text(&path)), "{what}: {about:?} names the layer");
        assert!(object(&asset, mesh).skin.is_empty(), "{what}: read unskinned");
    }
}

/// Skinned stages by others (usd-wg/assets, Khronos glTF samples by Cesium converted by
/// Reality Converter; CC-BY 4.0): every mesh read skinned, without a warning, each vertex's
/// weights adding up to 1 as authored, its positions pxr's skinned points at the bind pose
/// (RiggedSimple's rest pose is not its bind pose: seamlit welds where it was bound); one mesh
/// each, so no seam: `fix` writes no `over` and the output composes to the input unchanged.
#[test]
fn skinned_stages_by_others_are_read_at_pxrs_bind_pose() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["RiggedSimple", "RiggedFigure"] {
        let input = common::model(&format!("usd/others/Rigged/{name}.usdz"));
        let asset = seamlit_io::load(&input, &LoadOptions::GEOMETRY).unwrap();
        assert!(asset.warnings.is_empty(), "{name}: {:?}", asset.warnings);
        let bind = pxr("skinned", &[text(&input), "bind"]);
        assert_eq!(bind["points"].as_object().unwrap().len(), asset.model.objects.len(), "{name}");
        for object in &asset.model.objects {
            assert_eq!(object.skin.len(), 1, "{name}: {} is skinned", object.name);
            for v in 0..object.positions.len() {
                let sum: f32 = object.skin[0].of(v).map(|(_, w)| w).sum();
                assert!((sum - 1.0).abs() < 1e-3, "{name}: vertex {v} weighs {sum}");
            }
            let m = object.model_transform();
            let theirs = points_of(&bind["points"][&object.name]);
            for p in &object.positions {
                let ours = m.transform_point3(*p);
                let nearest = theirs.iter().map(|q| ours.distance(*q)).fold(f32::MAX, f32::min);
                assert!(nearest < 1e-5 * ours.abs().max_element().max(1.0), "{name}: {ours}");
            }
        }
        let output = dir.path().join(format!("{name}.usda"));
        assert!(fix_to(&input, &output, true).is_empty(), "{name}");
        assert!(!std::fs::read_to_string(&output).unwrap().contains("over "), "{name}");
        let diff = pxr("compare", &[text(&input), text(&output)]);
        assert_eq!(diff["differences"], serde_json::json!([]), "{name}: {diff:#}");
        assert_eq!(diff["normals"], serde_json::json!([]), "{name}: {diff:#}");
    }
}
