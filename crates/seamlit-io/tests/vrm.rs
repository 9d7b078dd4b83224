//! VRM avatars (`.vrm`: a GLB with VRM's extensions) read and written as the GLB they are:
//! every VRM extension (VRM 0.x's `VRM`; VRM 1.0's `VRMC_vrm`, `VRMC_springBone`,
//! `VRMC_node_constraint`, `VRMC_materials_mtoon`) kept by the pass-through, the references
//! inside them (nodes, meshes, morph targets, materials) still pointing where they did, and
//! the seams of a many-object model closed.

mod common;

use std::path::Path;

use seamlit_io::{IoError, LoadOptions, SaveOptions};
use seamlit_mesh::FixOptions;
use serde_json::{Value, json};

/// The test character (body and head meshes, skinned, the body with a morph target) with a
/// material on both meshes and `extend` applied to its document, as a `.vrm` at `path`.
fn avatar(path: &Path, extend: impl FnOnce(&mut Value)) {
    let (mut document, bin) = seamlit_testkit::character::document(true);
    document["materials"] =
        json!([{"name": "skin", "pbrMetallicRoughness": {"roughnessFactor": 0.8}}]);
    for mesh in document["meshes"].as_array_mut().unwrap() {
        mesh["primitives"][0]["material"] = json!(0);
    }
    extend(&mut document);
    std::fs::write(path, seamlit_testkit::glb(&document, &bin)).unwrap();
}

/// VRM 1.0: the humanoid on the joints, an expression binding the body's morph target, a
/// spring on the neck, a rotation constraint on a node, MToon on the material.
fn vrm1(document: &mut Value) {
    document["extensionsUsed"] =
        json!(["VRMC_vrm", "VRMC_springBone", "VRMC_node_constraint", "VRMC_materials_mtoon"]);
    document["extensions"] = json!({
        "VRMC_vrm": {
            "specVersion": "1.0",
            "meta": {"name": "seamlit test avatar", "version": "1", "authors": ["seamlit"],
                "licenseUrl": "https://vrm.dev/licenses/1.0/", "avatarPermission": "onlyAuthor",
                "commercialUsage": "personalNonProfit", "allowRedistribution": false},
            "humanoid": {"humanBones": {"hips": {"node": 2}, "chest": {"node": 3}, "neck": {"node": 4},
                "head": {"node": 4}}},
            "expressions": {"preset": {"happy": {"morphTargetBinds": [{"node": 0, "index": 0, "weight": 1.0}],
                "isBinary": false}}},
            "lookAt": {"type": "bone", "offsetFromHeadBone": [0.0, 0.06, 0.0]}
        },
        "VRMC_springBone": {"specVersion": "1.0",
            "springs": [{"name": "neck", "joints": [{"node": 3, "stiffness": 1.0}, {"node": 4}]}]}
    });
    // A value the JSON parser must read exactly to write it back (Blender's exporters write
    // f32s as 17 digits): serde_json's default parser is one ULP off on it.
    document["nodes"][3]["translation"] = json!([0.0, 0.10000002384185791, 0.0]);
    document["nodes"][3]["extensions"] = json!({"VRMC_node_constraint": {"specVersion": "1.0",
        "constraint": {"rotation": {"source": 2, "weight": 0.5}}}});
    document["materials"][0]["extensions"] = json!({"VRMC_materials_mtoon": {"specVersion": "1.0",
        "shadeColorFactor": [0.8, 0.6, 0.5], "outlineWidthMode": "worldCoordinates",
        "outlineWidthFactor": 0.002}});
}

/// VRM 0.x: one root extension, `VRM`, that binds the body's morph target by mesh index.
fn vrm0(document: &mut Value) {
    document["extensionsUsed"] = json!(["VRM"]);
    document["extensions"] = json!({"VRM": {
        "exporterVersion": "seamlit tests", "specVersion": "0.0",
        "meta": {"title": "seamlit test avatar", "version": "1", "author": "seamlit",
            "allowedUserName": "OnlyAuthor", "licenseName": "Other"},
        "humanoid": {"humanBones": [{"bone": "hips", "node": 2}, {"bone": "chest", "node": 3},
            {"bone": "neck", "node": 4}, {"bone": "head", "node": 4}]},
        "blendShapeMaster": {"blendShapeGroups": [{"name": "Joy", "presetName": "joy",
            "binds": [{"mesh": 0, "index": 0, "weight": 100}]}]},
        "secondaryAnimation": {"boneGroups": [{"bones": [4], "stiffiness": 1.0}]},
        "materialProperties": [{"name": "skin", "shader": "VRM/MToon", "floatProperties": {"_Cutoff": 0.5}}]
    }});
}

/// The JSON chunk of a GLB, as text.
fn json_text(path: &Path) -> String {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..4], b"glTF", "{} is a GLB", path.display());
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    String::from_utf8(bytes[20..20 + length].to_vec()).unwrap()
}

/// The JSON chunk of a GLB.
fn json_of(path: &Path) -> Value {
    serde_json::from_str(&json_text(path)).unwrap()
}

/// The largest angle between the normals of coincident corners of different objects across
/// a smooth edge.
fn seam_angle(path: &Path) -> f32 {
    let asset = seamlit_io::load(path, &LoadOptions::DEFAULT).unwrap();
    let report =
        seamlit_mesh::report(&asset.model, &seamlit_mesh::ReportOptions::default()).unwrap();
    report.cross_object.max_normal_angle_deg.expect("smooth cross-object edges")
}

fn fix_file(input: &Path, output: &Path) -> Result<Vec<String>, IoError> {
    let mut asset = seamlit_io::load(input, &LoadOptions::DEFAULT)?;
    seamlit_mesh::fix_in_place(&mut asset.model, &FixOptions::default()).unwrap();
    seamlit_io::save(&asset, output, &SaveOptions::default()).map(|r| r.warnings)
}

#[test]
fn vrm_1_and_0_avatars_round_trip_with_every_extension() {
    let dir = tempfile::tempdir().unwrap();
    for (name, extend) in [("vrm1", vrm1 as fn(&mut Value)), ("vrm0", vrm0)] {
        let input = dir.path().join(format!("{name}.vrm"));
        let output = dir.path().join(format!("{name}-fixed.vrm"));
        avatar(&input, extend);
        fix_file(&input, &output).unwrap();

        let (a, b) = (json_of(&input), json_of(&output));
        assert_eq!(a["extensions"], b["extensions"], "{name}: root extensions");
        assert_eq!(a["extensionsUsed"], b["extensionsUsed"], "{name}: extensionsUsed");
        assert_eq!(a["materials"], b["materials"], "{name}: materials and MToon");
        // The nodes, skins and meshes the extensions index keep their places and their
        // morph targets (the pass-through adds NORMAL and TANGENT attributes only).
        assert_eq!(a["nodes"], b["nodes"], "{name}: nodes and constraints");
        // Numbers as written, not one ULP off (compared as text: the parser is the suspect).
        for text in [json_text(&input), json_text(&output)] {
            assert_eq!(text.contains("0.10000002384185791"), name == "vrm1", "{name}");
        }
        assert_eq!(a["skins"], b["skins"], "{name}: skins");
        assert_eq!(a["meshes"].as_array().unwrap().len(), b["meshes"].as_array().unwrap().len());
        assert_eq!(
            a["meshes"][0]["primitives"][0]["targets"].as_array().map(Vec::len),
            b["meshes"][0]["primitives"][0]["targets"].as_array().map(Vec::len),
            "{name}: the expression's morph target is still there"
        );
        assert!(b["meshes"][0]["primitives"][0]["attributes"]["NORMAL"].is_u64());
        let (errors, report) = common::validate(&output);
        assert_eq!(errors, 0, "{name}: {report}");
    }
}

#[test]
fn a_vrm_written_as_glb_keeps_its_extensions_and_a_glb_is_no_vrm() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("avatar.vrm");
    avatar(&input, vrm1);
    let glb = dir.path().join("avatar.glb");
    fix_file(&input, &glb).unwrap();
    assert_eq!(json_of(&glb)["extensions"], json_of(&input)["extensions"]);

    // A GLB without VRM's extensions is no avatar: refused as .vrm, one line, nothing written.
    let plain = dir.path().join("plain.glb");
    avatar(&plain, |_| {});
    let out = dir.path().join("plain.vrm");
    let err = fix_file(&plain, &out).unwrap_err();
    assert!(matches!(err, IoError::VrmOutput { .. }), "{err}");
    let line = err.to_string();
    assert!(line.contains("plain.vrm") && line.contains("write .glb instead"), "{line}");
    assert!(!line.contains('\n'), "{line}");
    assert!(!out.exists());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 3, "no temporary file left");
}

#[test]
fn a_vrm_whose_objects_changed_is_refused_rather_than_written_without_its_extensions() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("avatar.vrm");
    avatar(&input, vrm0);
    let mut asset = seamlit_io::load(&input, &LoadOptions::DEFAULT).unwrap();
    asset.model.objects.pop();
    let out = dir.path().join("out.vrm");
    let err = seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::VrmOutput { .. }), "{err}");
    assert!(!out.exists());
    // The same asset as .glb goes through the generic writer, with a warning.
    let glb = dir.path().join("out.glb");
    let report = seamlit_io::save(&asset, &glb, &SaveOptions::default()).unwrap();
    assert!(report.warnings.iter().any(|w| w.contains("generic glTF writer")), "{report:?}");
}

/// The 32-patch teapot, each patch smoothed on its own (open seams, as an exporter that
/// smooths object by object writes it), made an "avatar" by VRM 1.0's extension: fixed as a
/// `.vrm`, its seams close and the extension stays.
#[test]
fn a_vrm_of_many_objects_has_its_seams_closed() {
    let dir = tempfile::tempdir().unwrap();
    let apart = dir.path().join("apart.glb");
    let mut asset =
        seamlit_io::load(&common::model("compressed/teapot_noq.glb"), &LoadOptions::DEFAULT)
            .unwrap();
    let per_object = FixOptions::DEFAULT
        .with_mode(seamlit_mesh::Mode::Object)
        .with_normals(seamlit_mesh::NormalPolicy::Recompute);
    asset.model = seamlit_mesh::fix(&asset.model, &per_object).unwrap();
    seamlit_io::save(&asset, &apart, &SaveOptions::default()).unwrap();
    let teapot = std::fs::read(&apart).unwrap();
    let length = u32::from_le_bytes(teapot[12..16].try_into().unwrap()) as usize;
    let mut document: Value = serde_json::from_slice(&teapot[20..20 + length]).unwrap();
    let bin = &teapot[20 + length + 8..];
    document["extensionsUsed"] = json!(["VRMC_vrm"]);
    document["extensions"] = json!({"VRMC_vrm": {"specVersion": "1.0",
        "meta": {"name": "teapot", "authors": ["Martin Newell"], "licenseUrl": "https://vrm.dev/licenses/1.0/"},
        "humanoid": {"humanBones": {"hips": {"node": 0}, "spine": {"node": 1}, "head": {"node": 2}}},
        "expressions": {"preset": {"angry": {"materialColorBinds":
            [{"material": 0, "type": "color", "targetValue": [1.0, 0.0, 0.0, 1.0]}]}}}}});
    let input = dir.path().join("teapot.vrm");
    std::fs::write(&input, seamlit_testkit::glb(&document, bin)).unwrap();
    let before = seam_angle(&input);
    assert!(before > 1.0, "the patches are smoothed apart: {before} degrees");

    let output = dir.path().join("teapot-fixed.vrm");
    fix_file(&input, &output).unwrap();
    let after = seam_angle(&output);
    assert!(after < 0.01, "{before} degrees before, {after} after");
    assert_eq!(json_of(&output)["extensions"], document["extensions"]);
    common::assert_valid(&output);
}
