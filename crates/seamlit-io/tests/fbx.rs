//! FBX in (the `fbx` feature): files written by Blender's own FBX exporter (tests/fbx/
//! blender.py, through the bpy module) read by seamlit and compared with what Blender's own
//! FBX importer reads from the same file: the node names, and per mesh node its triangle
//! count and world-space vertex positions. Then the seam at a neck ring closed by `fix`, the
//! output valid under the Khronos validator, and bad files refused in one line.
//!
//! Needs Python 3 with bpy (Blender 5.0 as a module; `.ci/run` installs it).
#![cfg(feature = "fbx")]

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use glam::{Mat4, Vec3};
use seamlit_io::{Asset, FbxKind, IoError, LoadOptions, SaveOptions};
use seamlit_mesh::{FixOptions, ReportOptions};
use serde_json::Value;

fn python() -> String {
    std::env::var("PYTHON").unwrap_or_else(|_| "python3".to_owned())
}

/// Runs tests/fbx/blender.py with `args`; panics with its output when it fails.
fn blender(args: &[&str]) {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fbx/blender.py");
    let output = Command::new(python())
        .arg(script)
        .args(args)
        .output()
        .expect("python3 with bpy (pip install bpy==5.0.1) is needed for the FBX tests");
    assert!(
        output.status.success(),
        "blender.py {args:?} failed (is bpy installed? pip install bpy==5.0.1):\n{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

/// The scenes of blender.py written once per test run, in one temporary folder.
fn written(scene: &str) -> PathBuf {
    static FOLDER: OnceLock<tempfile::TempDir> = OnceLock::new();
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let folder = FOLDER.get_or_init(|| tempfile::tempdir().unwrap());
    let path = folder.path().join(format!("{scene}.fbx"));
    let _guard = LOCK.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if !path.exists() {
        blender(&["write", scene, path.to_str().unwrap()]);
    }
    path
}

/// What Blender's importer reads from `fbx`: per object name, the object's JSON.
fn blender_reads(fbx: &Path) -> BTreeMap<String, Value> {
    // A file of its own: tests run in parallel.
    let out = tempfile::NamedTempFile::new().unwrap();
    blender(&["read", fbx.to_str().unwrap(), out.path().to_str().unwrap()]);
    let json: Value = serde_json::from_str(&std::fs::read_to_string(out.path()).unwrap()).unwrap();
    json["objects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| (o["name"].as_str().unwrap().to_owned(), o.clone()))
        .collect()
}

fn vec3(value: &Value) -> Vec3 {
    let v: Vec<f32> =
        value.as_array().unwrap().iter().map(|x| common::f32_of(x.as_f64().unwrap())).collect();
    Vec3::new(v[0], v[1], v[2])
}

/// Whether every point of `a` lies within `tolerance` of a point of `b`.
fn covered(a: &[Vec3], b: &[Vec3], tolerance: f32) -> Result<(), String> {
    for p in a {
        let nearest = b.iter().map(|q| q.distance(*p)).fold(f32::INFINITY, f32::min);
        if nearest > tolerance {
            return Err(format!("{p} is {nearest} from the nearest point of the other side"));
        }
    }
    Ok(())
}

/// The world-space positions of the objects a node carries, and their triangle count.
fn node_geometry(asset: &Asset, node: usize) -> (Vec<Vec3>, usize) {
    let mut positions = Vec::new();
    let mut triangles = 0;
    for &o in &asset.nodes[node].objects {
        let object = &asset.model.objects[o];
        let m: Mat4 = object.model_transform();
        positions.extend(object.positions.iter().map(|&p| m.transform_point3(p)));
        triangles += object.triangle_count();
    }
    (positions, triangles)
}

/// Asserts that seamlit reads `fbx` as Blender's importer does: the same node names (every
/// object Blender makes, meshes and empties), the same mesh nodes, and per mesh node the
/// same triangle count and the same world-space positions (each side's within 1e-4 of the
/// other's, relative to the model's size).
fn reads_as_blender(fbx: &Path) -> Asset {
    let asset = seamlit_io::load(fbx, &LoadOptions::GEOMETRY).unwrap();
    let reference = blender_reads(fbx);
    let ours: BTreeSet<&str> = asset.nodes.iter().map(|n| n.name.as_str()).collect();
    let theirs: BTreeSet<&str> = reference.keys().map(String::as_str).collect();
    assert_eq!(ours, theirs, "node names");
    let meshes: BTreeSet<&str> =
        asset.nodes.iter().filter(|n| !n.objects.is_empty()).map(|n| n.name.as_str()).collect();
    let blender_meshes: BTreeSet<&str> =
        reference.iter().filter(|(_, o)| o["type"] == "MESH").map(|(n, _)| n.as_str()).collect();
    assert_eq!(meshes, blender_meshes, "mesh nodes");
    let all: Vec<Vec3> = (0..asset.nodes.len()).flat_map(|n| node_geometry(&asset, n).0).collect();
    let size = all.iter().fold(Vec3::ZERO, |m, p| m.max(p.abs())).max_element();
    for (i, node) in asset.nodes.iter().enumerate() {
        let Some(theirs) = reference.get(&node.name).filter(|o| o["type"] == "MESH") else {
            continue;
        };
        let (positions, triangles) = node_geometry(&asset, i);
        assert_eq!(
            triangles as u64,
            theirs["triangles"].as_u64().unwrap(),
            "{}: triangles",
            node.name
        );
        let blender: Vec<Vec3> = theirs["positions"].as_array().unwrap().iter().map(vec3).collect();
        let tolerance = 1e-4 * size.max(1.0);
        covered(&positions, &blender, tolerance)
            .unwrap_or_else(|e| panic!("{}: ours: {e}", node.name));
        covered(&blender, &positions, tolerance)
            .unwrap_or_else(|e| panic!("{}: Blender's: {e}", node.name));
    }
    asset
}

#[test]
fn a_head_and_a_body_read_as_blender_reads_them() {
    let asset = reads_as_blender(&written("head_body"));
    assert_eq!(asset.model.objects.len(), 2);
    let head = asset.nodes.iter().position(|n| n.name == "Head").unwrap();
    let body = asset.nodes.iter().position(|n| n.name == "Body").unwrap();
    assert_eq!(asset.nodes[head].parent, Some(body), "the head is the body's child");
    for object in &asset.model.objects {
        assert!(object.normals.is_some(), "{}: Blender writes normals", object.name);
    }
}

#[test]
fn cyrillic_names_material_parts_uv_sets_colours_and_tangents_are_read() {
    let asset = reads_as_blender(&written("names"));
    let names: BTreeSet<&str> = asset.model.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, BTreeSet::from(["Тело.0", "Тело.1", "Рука.левая"]), "one object per part");
    let torso: Vec<_> = asset.model.objects.iter().filter(|o| o.name.starts_with("Тело")).collect();
    let materials: BTreeSet<&str> =
        torso.iter().map(|o| asset.materials[o.material.unwrap()].name.as_str()).collect();
    assert_eq!(materials, BTreeSet::from(["Кожа", "Ткань"]));
    let fabric = asset.materials.iter().find(|m| m.name == "Ткань").unwrap();
    for (c, want) in fabric.base_color.iter().zip([0.2, 0.4, 0.9, 1.0]) {
        assert!((c - want).abs() < 1e-3, "Ткань base colour {:?}", fabric.base_color);
    }
    for object in torso {
        assert!(object.uvs.is_some() && object.uvs1.is_some(), "{}: two UV sets", object.name);
        assert!(object.colors.is_some(), "{}: vertex colours", object.name);
        assert!(object.tangents.is_some(), "{}: tangents", object.name);
        // The second set is the first moved by 0.25 in V (blender.py).
        let (uv0, uv1) = (object.uvs.as_ref().unwrap(), object.uvs1.as_ref().unwrap());
        assert!(
            uv0.iter()
                .zip(uv1)
                .all(|(a, b)| (b.y - a.y - 0.25).abs() < 1e-5 && (a.x - b.x).abs() < 1e-6)
        );
    }
    // Written out: both UV sets, the colours and the tangents, valid.
    let mut asset = asset;
    seamlit_mesh::fix_in_place(&mut asset.model, &FixOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("names.glb");
    seamlit_io::save(&asset, &glb, &SaveOptions::default()).unwrap();
    let (errors, line) = common::validate(&glb);
    assert_eq!(errors, 0, "{line}");
    let file = common::gltf::read(&glb);
    let torso = file.json["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == "Тело.0")
        .expect("the torso's first part, by name");
    let attributes = torso["primitives"][0]["attributes"].as_object().unwrap();
    for name in ["TEXCOORD_0", "TEXCOORD_1", "COLOR_0", "TANGENT", "NORMAL"] {
        assert!(attributes.contains_key(name), "{name}: {attributes:?}");
    }
}

#[test]
fn the_neck_seam_is_closed_by_fix_and_the_glb_is_valid() {
    let fbx = written("head_body");
    let mut asset = seamlit_io::load(&fbx, &LoadOptions::GEOMETRY).unwrap();
    let report = |asset: &Asset| {
        let r = seamlit_mesh::report(&asset.model, &ReportOptions::default()).unwrap();
        r.cross_object.max_normal_angle_deg.unwrap()
    };
    let before = report(&asset);
    assert!(before > 1.0, "the file's normals disagree at the neck: {before}");
    seamlit_mesh::fix_in_place(&mut asset.model, &FixOptions::default()).unwrap();
    let after = report(&asset);
    assert!(after < 0.005, "0.00 degrees after fix: {after}");
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("fixed.glb");
    seamlit_io::save(&asset, &glb, &SaveOptions::default()).unwrap();
    let (errors, line) = common::validate(&glb);
    assert_eq!(errors, 0, "{line}");
}

#[test]
fn fbx_output_is_refused_in_one_line_and_nothing_is_written() {
    let asset = seamlit_io::load(&written("head_body"), &LoadOptions::GEOMETRY).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.fbx");
    let err = seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::FbxOutput { .. }), "{err}");
    let line = err.to_string();
    assert!(!line.contains('\n') && line.contains("out.fbx") && line.contains(".glb"), "{line}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing written");
}

#[test]
fn bad_fbx_files_fail_with_one_line_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let whole = std::fs::read(written("head_body")).unwrap();
    let cases: [(&str, Vec<u8>); 3] = [
        ("truncated.fbx", whole[..whole.len() / 2].to_vec()),
        ("garbage.fbx", b"this is not an FBX file at all\n".repeat(20)),
        ("empty.fbx", Vec::new()),
    ];
    for (name, bytes) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let err = seamlit_io::load(&path, &LoadOptions::GEOMETRY).unwrap_err();
        let line = err.to_string();
        assert!(line.starts_with(&path.display().to_string()) && !line.contains('\n'), "{line}");
        match (name, &err) {
            ("truncated.fbx", IoError::Fbx { kind: FbxKind::Truncated { .. }, .. })
            | (_, IoError::Fbx { kind: FbxKind::Refused { .. }, .. }) => {}
            _ => panic!("{name}: {err:?}"),
        }
    }
    let nothing = written("nothing");
    let err = seamlit_io::load(&nothing, &LoadOptions::GEOMETRY).unwrap_err();
    assert!(matches!(err, IoError::NoTriangles { .. }), "{err}");
}

/// ufbx's own test files (assets/models/ufbx, MIT or public domain), binary FBX 7.4 as
/// Blender 2.7x and 2.9x wrote them: read as Blender's importer reads them.
#[test]
fn files_by_others_read_as_blender_reads_them() {
    for name in [
        "blender_272_cube_7400_binary.fbx",
        "blender_279_unicode_7400_binary.fbx",
        "blender_279_uv_set_tangents_7400_binary.fbx",
        "blender_279_nested_meshes_7400_binary.fbx",
        "blender_293_half_skinned_7400_binary.fbx",
    ] {
        let asset = reads_as_blender(&common::model(&format!("ufbx/{name}")));
        assert!(!asset.model.objects.is_empty(), "{name}");
    }
}

/// ASCII FBX (6.1 and 7.5, Maya), which Blender's importer refuses: Maya's default cube
/// is 1 centimetre, so 0.01 metres a side centred on the origin; the parented cubes keep
/// their names and hierarchy.
#[test]
fn ascii_files_by_others_are_read_in_metres() {
    let cube =
        seamlit_io::load(&common::model("ufbx/maya_cube_6100_ascii.fbx"), &LoadOptions::GEOMETRY)
            .unwrap();
    assert_eq!(cube.nodes.iter().map(|n| n.name.as_str()).collect::<Vec<_>>(), ["pCube1"]);
    let [object] = &cube.model.objects[..] else { panic!("one object") };
    assert_eq!(
        (object.triangle_count(), object.vertex_count()),
        (12, 24),
        "6 quads, 4 corners each"
    );
    let m = object.model_transform();
    for p in &object.positions {
        let p = m.transform_point3(*p);
        assert!(p.abs().abs_diff_eq(Vec3::splat(0.005), 1e-6), "{p}");
    }
    let parented = seamlit_io::load(
        &common::model("ufbx/maya_parented_cubes_7500_ascii.fbx"),
        &LoadOptions::GEOMETRY,
    )
    .unwrap();
    let names: Vec<(&str, Option<usize>)> =
        parented.nodes.iter().map(|n| (n.name.as_str(), n.parent)).collect();
    assert_eq!(names, [("Parent", None), ("Child", Some(0))]);
    assert_eq!(parented.model.triangle_count(), 24);
}

/// Every prefix of two of ufbx's test files (binary and ASCII) at 97 lengths, and 3000
/// copies of each with four bytes overwritten (a fixed pseudo-random sequence), either loads
/// or fails with an error: no panic, no abort. The fuzz target `fbx` (fuzz/) does the same at random.
#[test]
fn cut_and_corrupted_fbx_files_fail_cleanly_or_load() {
    let mut next = seamlit_testkit::xorshift(0x2545_f491_4f6c_dd1d);
    let path = Path::new("/nonexistent-seamlit-test/model.fbx");
    let options = LoadOptions::GEOMETRY;
    for name in ["blender_272_cube_7400_binary.fbx", "maya_cube_6100_ascii.fbx"] {
        let bytes = std::fs::read(common::model(&format!("ufbx/{name}"))).unwrap();
        let (mut loaded, mut refused) = (0, 0);
        for k in 0..97 {
            match seamlit_io::fbx::parse(&bytes[..bytes.len() * k / 97], path, &options) {
                Ok(_) => loaded += 1,
                Err(e) => {
                    assert!(!e.to_string().contains('\n'), "{e}");
                    refused += 1;
                }
            }
        }
        // ufbx reads ASCII leniently (a prefix that holds the geometry loads); a binary
        // prefix is a truncated file.
        if name.contains("binary") {
            assert!(refused > 90, "{name}: prefixes are truncated files ({loaded} loaded)");
        }
        for _ in 0..3000 {
            let mut corrupted = bytes.clone();
            for _ in 0..4 {
                let at = usize::try_from(next() % bytes.len() as u64).unwrap();
                corrupted[at] = next().to_le_bytes()[0];
            }
            if let Ok(asset) = seamlit_io::fbx::parse(&corrupted, path, &options) {
                let _ = seamlit_mesh::report(&asset.model, &ReportOptions::default());
            }
        }
    }
}

/// `fbx::load` streams a file on disk to ufbx; `fbx::parse` gives it the bytes. Both read the same
/// asset from whole files (binary and ASCII, one skinned, one naming a texture), and the
/// same asset or the same error, word for word, from 12 prefixes of each and 100 copies with
/// four bytes overwritten (ufbx reads a stream in its own buffer, a path the fuzz target,
/// which gives bytes, does not take).
#[test]
fn a_streamed_file_reads_as_its_bytes_do() {
    let dir = tempfile::tempdir().unwrap();
    let options = LoadOptions::default();
    let mut next = seamlit_testkit::xorshift(0x9e37_79b9_7f4a_7c15);
    for name in [
        "blender_272_cube_7400_binary.fbx",
        "blender_293_half_skinned_7400_binary.fbx",
        "max2009_cube_texture_5800_binary.fbx",
        "maya_cube_6100_ascii.fbx",
    ] {
        let whole = std::fs::read(common::model(&format!("ufbx/{name}"))).unwrap();
        let path = dir.path().join(name);
        let prefixes =
            (1..=13).rev().map(|k| (format!("{k}/13"), whole[..whole.len() * k / 13].to_vec()));
        let corrupted = (0..100).map(|i| {
            let mut bytes = whole.clone();
            for _ in 0..4 {
                let at = usize::try_from(next() % whole.len() as u64).unwrap();
                bytes[at] = next().to_le_bytes()[0];
            }
            (format!("corrupted copy {i}"), bytes)
        });
        for (case, bytes) in prefixes.chain(corrupted) {
            std::fs::write(&path, &bytes).unwrap();
            let streamed = seamlit_io::fbx::load(&path, &options);
            let given = seamlit_io::fbx::parse(&bytes, &path, &options);
            match (&streamed, &given) {
                (Ok(a), Ok(b)) => assert_eq!(format!("{a:?}"), format!("{b:?}"), "{name} {case}"),
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{name} {case}"),
                _ => panic!("{name} {case}: streamed {streamed:?}, given {given:?}"),
            }
            assert!(case != "13/13" || streamed.is_ok(), "{name}: the whole file loads");
        }
    }
}

/// Blend shapes (Blender shape keys written as FBX blend shapes) become morph targets: per
/// target, the displaced world positions equal those of Blender's own import of the shape
/// key; the animated weight poses the mesh as Blender poses it at three frames; and the fixed
/// model is written as a valid GLB with its targets, their names and weights, and a
/// `weights` channel.
#[test]
fn blend_shapes_become_morph_targets_as_blender_reads_them() {
    let fbx = written("shapes");
    let asset = reads_as_blender(&fbx);
    let reference = blender_reads(&fbx);
    let [object] = &asset.model.objects[..] else { panic!("one object") };
    let keys = reference["Лицо"]["shape_keys"].as_array().unwrap();
    assert_eq!(object.morph_targets.len(), keys.len(), "one target per shape key");
    let m = object.model_transform();
    for (target, key) in object.morph_targets.iter().zip(keys) {
        let name = key["name"].as_str().unwrap();
        let ours: Vec<Vec3> = object
            .positions
            .iter()
            .zip(&target.position_deltas)
            .map(|(&p, &d)| m.transform_point3(p + d))
            .collect();
        let theirs: Vec<Vec3> = key["positions"].as_array().unwrap().iter().map(vec3).collect();
        covered(&ours, &theirs, 1e-4).unwrap_or_else(|e| panic!("{name}: ours: {e}"));
        covered(&theirs, &ours, 1e-4).unwrap_or_else(|e| panic!("{name}: Blender's: {e}"));
        let moved = target.position_deltas.iter().map(|&d| m.transform_vector3(d).length());
        assert!(moved.fold(0.0, f32::max) > 0.15, "{name} moves");
    }
    // The smile's animation: posed at frames 0, 5 and 10 as Blender poses it.
    assert_eq!(asset.animations.len(), 1);
    let frames = [0, 5, 10];
    for (frame, (time, meshes)) in frames.iter().zip(blender_poses(&fbx, &frames)) {
        let pose = seamlit_io::pose::Pose::at(&asset, 0, time);
        let ours = seamlit_io::pose::posed_object(&asset, &pose, 0).positions;
        let theirs = &meshes["Лицо"];
        covered(&ours, theirs, 1e-4).unwrap_or_else(|e| panic!("frame {frame}: ours: {e}"));
        covered(theirs, &ours, 1e-4).unwrap_or_else(|e| panic!("frame {frame}: Blender's: {e}"));
    }
    let mut asset = asset;
    seamlit_mesh::fix_in_place(&mut asset.model, &FixOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("shapes.glb");
    seamlit_io::save(&asset, &glb, &SaveOptions::default()).unwrap();
    let (errors, line) = common::validate(&glb);
    assert_eq!(errors, 0, "{line}");
    let file = common::gltf::read(&glb);
    let mesh = &file.json["meshes"][0];
    assert_eq!(mesh["primitives"][0]["targets"].as_array().unwrap().len(), 2, "{line}");
    assert_eq!(mesh["extras"]["targetNames"], serde_json::json!(["Улыбка", "Frown"]));
    let weights: Vec<f64> =
        mesh["weights"].as_array().unwrap().iter().map(|w| w.as_f64().unwrap()).collect();
    assert!((weights[0] - 0.25).abs() < 1e-6, "Улыбка at 0.25 as Blender set it: {weights:?}");
    let channels = file.json["animations"][0]["channels"].as_array().unwrap();
    assert!(channels.iter().any(|c| c["target"]["path"] == "weights"), "{channels:?}");
}

/// What Blender's importer poses from `fbx` at each frame: per frame, its time in seconds
/// and per mesh object its evaluated (skinned, animated) world positions.
fn blender_poses(fbx: &Path, frames: &[u32]) -> Vec<(f32, BTreeMap<String, Vec<Vec3>>)> {
    let out = tempfile::NamedTempFile::new().unwrap();
    let frames: Vec<String> = frames.iter().map(u32::to_string).collect();
    let mut args = vec!["pose", fbx.to_str().unwrap(), out.path().to_str().unwrap()];
    args.extend(frames.iter().map(String::as_str));
    blender(&args);
    let json: Value = serde_json::from_str(&std::fs::read_to_string(out.path()).unwrap()).unwrap();
    json["poses"]
        .as_array()
        .unwrap()
        .iter()
        .map(|pose| {
            let meshes = pose["meshes"]
                .as_object()
                .unwrap()
                .iter()
                .map(|(name, v)| (name.clone(), v.as_array().unwrap().iter().map(vec3).collect()))
                .collect();
            (common::f32_of(pose["time"].as_f64().unwrap()), meshes)
        })
        .collect()
}

/// The box around points.
fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    points.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)))
}

/// A skinned, animated arm (two bones, weights blended over the elbow, 24 frames): one skin
/// whose joints are the two bones, one animation, and at three times the posed arm
/// (`seamlit_io::pose`) equal to Blender's own import posed at the same frame: its bounds
/// within 1e-4 of their size, and every vertex within that of one of Blender's.
#[test]
fn a_skinned_animated_arm_poses_as_blender_poses_it() {
    let fbx = written("arm");
    let asset = reads_as_blender(&fbx);
    let [skin] = &asset.skins[..] else { panic!("one skin: {:?}", asset.skins) };
    let joints: BTreeSet<&str> =
        skin.joints.iter().map(|&j| asset.nodes[j].name.as_str()).collect();
    assert_eq!(joints, BTreeSet::from(["Плечо", "Предплечье"]));
    assert_eq!(
        asset.animations.len(),
        1,
        "{:?}",
        asset.animations.iter().map(|a| &a.name).collect::<Vec<_>>()
    );
    let arm = asset.model.objects.iter().position(|o| o.name == "Рука").unwrap();
    assert!(asset.model.objects[arm].transform.is_none(), "placed by its joints");
    assert!(!asset.model.objects[arm].skin.is_empty(), "influences");
    let frames = [0, 7, 18];
    let reference = blender_poses(&fbx, &frames);
    let mut moved = 0.0f32;
    for (frame, (time, meshes)) in frames.iter().zip(&reference) {
        let pose = seamlit_io::pose::Pose::at(&asset, 0, *time);
        let ours = seamlit_io::pose::posed_object(&asset, &pose, arm).positions;
        let theirs = &meshes["Рука"];
        let (lo, hi) = bounds(theirs);
        let tolerance = 1e-4 * (hi - lo).max_element();
        let (our_lo, our_hi) = bounds(&ours);
        assert!(
            our_lo.abs_diff_eq(lo, tolerance) && our_hi.abs_diff_eq(hi, tolerance),
            "frame {frame} (t = {time}): bounds {our_lo} {our_hi}, Blender's {lo} {hi}"
        );
        covered(&ours, theirs, tolerance).unwrap_or_else(|e| panic!("frame {frame}: ours: {e}"));
        covered(theirs, &ours, tolerance)
            .unwrap_or_else(|e| panic!("frame {frame}: Blender's: {e}"));
        moved = moved.max((hi.x - 2.0).abs());
    }
    assert!(moved > 0.5, "the arm bends over the frames compared ({moved})");

    // Fixed and written as GLB: valid, with the skin, the animation and the influences, and
    // read back it poses as Blender does.
    let mut fixed = asset.clone();
    seamlit_mesh::fix_in_place(&mut fixed.model, &FixOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("arm.glb");
    seamlit_io::save(&fixed, &glb, &SaveOptions::default()).unwrap();
    let (errors, line) = common::validate(&glb);
    assert_eq!(errors, 0, "{line}");
    let file = common::gltf::read(&glb);
    assert_eq!(file.json["skins"].as_array().map(Vec::len), Some(1), "{}", file.json);
    assert_eq!(file.json["animations"].as_array().map(Vec::len), Some(1));
    let back = seamlit_io::load(&glb, &LoadOptions::GEOMETRY).unwrap();
    let arm = back.model.objects.iter().position(|o| o.name == "Рука").unwrap();
    assert!(!back.model.objects[arm].skin.is_empty(), "JOINTS_0 and WEIGHTS_0 read back");
    for (frame, (time, meshes)) in frames.iter().zip(&reference) {
        let pose = seamlit_io::pose::Pose::at(&back, 0, *time);
        let ours = seamlit_io::pose::posed_object(&back, &pose, arm).positions;
        let theirs = &meshes["Рука"];
        let (lo, hi) = bounds(theirs);
        let tolerance = 1e-4 * (hi - lo).max_element();
        covered(&ours, theirs, tolerance).unwrap_or_else(|e| panic!("GLB, frame {frame}: {e}"));
        covered(theirs, &ours, tolerance).unwrap_or_else(|e| panic!("GLB, frame {frame}: {e}"));
    }
}

/// ufbx's half-skinned mesh (Blender 2.93: some vertices weighted to no bone) and Maya's
/// blend-shape cube (ASCII 6.1): a skin whose unweighted vertices follow the mesh's own node
/// (weights summing to 1 everywhere, as glTF requires), posed as the file poses it equal to
/// Blender's evaluated import; a morph target with its name; both written as GLB without a
/// validator error (the half-skinned one's joints under a common root).
#[test]
fn skins_and_blend_shapes_of_files_by_others_are_read_and_written_valid() {
    let dir = tempfile::tempdir().unwrap();
    let skinned = seamlit_io::load(
        &common::model("ufbx/blender_293_half_skinned_7400_binary.fbx"),
        &LoadOptions::GEOMETRY,
    )
    .unwrap();
    assert_eq!(skinned.skins.len(), 1);
    // As the file poses it (no animation): Blender's evaluated mesh, the armature applied.
    let half = common::model("ufbx/blender_293_half_skinned_7400_binary.fbx");
    let copy = dir.path().join("half_skinned.fbx");
    std::fs::copy(&half, &copy).unwrap();
    let (_, meshes) = &blender_poses(&copy, &[0])[0];
    let pose = seamlit_io::pose::Pose::rest(&skinned);
    for (o, object) in skinned.model.objects.iter().enumerate() {
        let ours = seamlit_io::pose::posed_object(&skinned, &pose, o).positions;
        let theirs = &meshes[&object.name];
        let (lo, hi) = bounds(theirs);
        let tolerance = 1e-4 * (hi - lo).max_element();
        covered(&ours, theirs, tolerance).unwrap_or_else(|e| panic!("{}: ours: {e}", object.name));
        covered(theirs, &ours, tolerance)
            .unwrap_or_else(|e| panic!("{}: Blender's: {e}", object.name));
    }
    for object in &skinned.model.objects {
        for v in 0..object.vertex_count() {
            let total: f32 = object.skin.iter().map(|set| set.weights[v].iter().sum::<f32>()).sum();
            assert!((total - 1.0).abs() < 1e-5, "{}: vertex {v} weighs {total}", object.name);
        }
    }
    let shapes = seamlit_io::load(
        &common::model("ufbx/maya_blend_shape_cube_6100_ascii.fbx"),
        &LoadOptions::GEOMETRY,
    )
    .unwrap();
    let targets: Vec<&str> = shapes
        .model
        .objects
        .iter()
        .flat_map(|o| o.morph_targets.iter().map(|t| t.name.as_str()))
        .collect();
    assert!(!targets.is_empty() && targets.iter().all(|n| !n.is_empty()), "{targets:?}");
    for (name, mut asset) in [("skinned", skinned), ("shapes", shapes)] {
        seamlit_mesh::fix_in_place(&mut asset.model, &FixOptions::default()).unwrap();
        let glb = dir.path().join(format!("{name}.glb"));
        seamlit_io::save(&asset, &glb, &SaveOptions::default()).unwrap();
        let (errors, line) = common::validate(&glb);
        assert_eq!(errors, 0, "{name}: {line}");
    }
}

/// A material's base colour texture, named by a relative path (the PNG beside the FBX) and
/// embedded in the file (the FBX alone in its folder): found, decoded (4 x 4, one colour per
/// row as Blender's script painted them), and carried into a valid GLB.
#[test]
fn textures_are_read_by_path_and_embedded() {
    for scene in ["textured", "embedded"] {
        let fbx = written(scene);
        let dir = tempfile::tempdir().unwrap();
        let copy = dir.path().join(format!("{scene}.fbx"));
        std::fs::copy(&fbx, &copy).unwrap();
        if scene == "textured" {
            std::fs::copy(fbx.with_file_name("texture.png"), dir.path().join("texture.png"))
                .unwrap();
        }
        let asset = seamlit_io::load(&copy, &LoadOptions::DEFAULT).unwrap();
        assert!(asset.warnings.is_empty(), "{scene}: {:?}", asset.warnings);
        let material = asset.materials.iter().find(|m| m.name == "Картинка").unwrap();
        let texture = &asset.textures[material.base_color_texture.as_ref().expect(scene).texture];
        match (scene, &texture.source) {
            ("textured", seamlit_io::TextureSource::File(_))
            | ("embedded", seamlit_io::TextureSource::Embedded { .. }) => {}
            _ => panic!("{scene}: {:?}", texture.source),
        }
        let image = texture.image.as_ref().unwrap_or_else(|| panic!("{scene}: decoded"));
        assert_eq!(image.dimensions(), (4, 4));
        let rows: BTreeSet<[u8; 4]> = (0..4).map(|y| image.get_pixel(0, y).0).collect();
        let painted = [[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], [255, 255, 255, 255]];
        assert_eq!(rows, BTreeSet::from(painted), "{scene}");
        let glb = dir.path().join(format!("{scene}.glb"));
        seamlit_io::save(&asset, &glb, &SaveOptions::default()).unwrap();
        let (errors, line) = common::validate(&glb);
        assert_eq!(errors, 0, "{line}");
        assert_eq!(common::gltf::read(&glb).json["images"].as_array().map(Vec::len), Some(1));
    }
}
