//! Files of other kinds through `fix`: skinned GLB, meshopt and Draco, buffers without data,
//! FBX.

use super::*;

/// A GLB built here: one skinned fold (two quads at a right angle, so fixing splits the two
/// vertices of the hard edge) with JOINTS_0 and WEIGHTS_0, a two-joint skin with inverse
/// bind matrices, and an animation of one joint.
fn skinned_glb(path: &Path) -> serde_json::Value {
    use seamlit_testkit::{ARRAY_BUFFER, Buffer, ELEMENT_ARRAY_BUFFER};
    use serde_json::json;
    let mut glb = Buffer::default();
    let positions =
        [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0];
    let position = glb.floats(&positions, "VEC3", true, Some(ARRAY_BUFFER));
    let indices: Vec<u8> =
        [0u16, 3, 2, 0, 2, 1, 0, 4, 5, 0, 5, 3].iter().flat_map(|i| i.to_le_bytes()).collect();
    let indices = glb.push(
        &indices,
        json!({ "componentType": 5123, "count": 12, "type": "SCALAR" }),
        Some(ELEMENT_ARRAY_BUFFER),
    );
    let joints: Vec<u8> = (0..6u8).flat_map(|v| [v % 2, 1 - v % 2, 0, 0]).collect();
    let joints = glb.push(
        &joints,
        json!({ "componentType": 5121, "count": 6, "type": "VEC4" }),
        Some(ARRAY_BUFFER),
    );
    let weights: Vec<f32> = (0..6)
        .flat_map(|v| {
            let a = 0.125 * (v + 1) as f32;
            [a, 1.0 - a, 0.0, 0.0]
        })
        .collect();
    let weights = glb.floats(&weights, "VEC4", false, Some(ARRAY_BUFFER));
    let mut ibm = [0.0f32; 32];
    for m in 0..2 {
        for d in 0..4 {
            ibm[16 * m + 5 * d] = 1.0;
        }
    }
    ibm[16 + 13] = -1.0;
    let ibm = glb.floats(&ibm, "MAT4", false, None);
    let times = glb.floats(&[0.0, 1.0], "SCALAR", true, None);
    let rotations = glb.floats(&[0.0, 0.0, 0.0, 1.0, 0.6, 0.0, 0.0, 0.8], "VEC4", false, None);
    let bin = glb.bin;
    let document = json!({
        "asset": { "version": "2.0" },
        "buffers": [{ "byteLength": bin.len() }],
        "bufferViews": glb.views,
        "accessors": glb.accessors,
        "meshes": [{ "primitives": [{
            "attributes": { "POSITION": position, "JOINTS_0": joints, "WEIGHTS_0": weights },
            "indices": indices,
        }] }],
        "skins": [{ "joints": [1, 2], "inverseBindMatrices": ibm }],
        "animations": [{
            "samplers": [{ "input": times, "output": rotations }],
            "channels": [{ "sampler": 0, "target": { "node": 2, "path": "rotation" } }],
        }],
        "nodes": [
            { "mesh": 0, "skin": 0 },
            { "name": "root", "children": [2] },
            { "name": "tip", "translation": [0.0, 1.0, 0.0] },
        ],
        "scenes": [{ "nodes": [0, 1] }],
        "scene": 0,
    });
    std::fs::write(path, seamlit_testkit::glb(&document, &bin)).unwrap();
    document
}

/// The JSON chunk of a GLB, read by hand.
fn glb_json(path: &Path) -> serde_json::Value {
    let bytes = std::fs::read(path).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&bytes[20..20 + length]).unwrap()
}

#[test]
fn fix_keeps_the_skin_joints_weights_and_animation_of_a_glb() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("rig.glb");
    let document = skinned_glb(&input);
    let out = dir.path().join("out.glb");
    let o = seamlit(&["fix", &input.display().to_string(), "-o", &out.display().to_string()]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let written = glb_json(&out);
    for key in ["skins", "animations", "nodes", "scenes", "scene"] {
        assert_eq!(written[key], document[key], "{key}");
    }
    let attributes = &written["meshes"][0]["primitives"][0]["attributes"];
    for name in ["POSITION", "NORMAL", "JOINTS_0", "WEIGHTS_0"] {
        assert!(attributes.get(name).is_some(), "{name} missing: {attributes}");
    }
    // The hard edge split its two vertices: every attribute has the new count.
    for name in ["POSITION", "JOINTS_0", "WEIGHTS_0"] {
        let accessor = usize::try_from(attributes[name].as_u64().unwrap()).unwrap();
        assert_eq!(written["accessors"][accessor]["count"], 8, "{name}");
    }
}

#[test]
fn fix_reads_meshopt_and_draco_and_writes_them_uncompressed_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let compressed = models().join("compressed");
    let input = compressed.join("teapot_mo.glb").display().to_string();
    let out = dir.path().join("out.glb").display().to_string();
    let o = seamlit(&["fix", &input, "-o", &out]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.lines().any(|l| l.starts_with("warning: ")
            && l.contains("teapot_mo.glb")
            && l.contains("EXT_meshopt_compression")
            && l.contains("uncompressed")),
        "{stderr}"
    );
    assert!(stdout(&o).contains("32 objects"), "{}", stdout(&o));
    let o = seamlit(&["inspect", &out]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    // Draco (the default `draco` feature of seamlit-io): decoded, written uncompressed.
    let draco = compressed.join("teapot_draco.glb").display().to_string();
    let out = dir.path().join("draco.glb").display().to_string();
    let o = seamlit(&["fix", &draco, "-o", &out]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.lines().any(|l| l.starts_with("warning: ")
            && l.contains("teapot_draco.glb")
            && l.contains("32 primitives compressed with KHR_draco_mesh_compression")
            && l.contains("uncompressed")),
        "{stderr}"
    );
    let written = std::fs::read(&out).unwrap();
    assert!(!String::from_utf8_lossy(&written).contains("draco"));
}

#[test]
fn fix_keep_compression_keeps_meshopt_and_refuses_draco_and_obj() {
    let dir = tempfile::tempdir().unwrap();
    let compressed = models().join("compressed");
    let input = compressed.join("teapot_mo.glb").display().to_string();
    let out = dir.path().join("out.glb");
    let o = seamlit(&["fix", &input, "-o", &out.display().to_string(), "--keep-compression"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.lines().any(|l| l.starts_with("warning: ")
            && l.contains("teapot_mo.glb")
            && l.contains("kept compressed")
            && l.contains("EXT_meshopt_compression")),
        "{stderr}"
    );
    let written = String::from_utf8_lossy(&std::fs::read(&out).unwrap()).into_owned();
    assert!(written.contains(
        "\"extensionsRequired\":[\"KHR_mesh_quantization\",\"EXT_meshopt_compression\"]"
    ));

    // Draco: no encoder; refused, one line, exit 2, nothing written.
    let draco = compressed.join("teapot_draco.glb").display().to_string();
    let out = dir.path().join("draco.glb").display().to_string();
    let o = seamlit(&["fix", &draco, "-o", &out, "--keep-compression"]);
    assert_bad_input(&o, &["teapot_draco.glb", "no Draco encoder", "gltf-transform"]);
    assert!(!Path::new(&out).exists());

    // OBJ output: nothing to keep the compression in.
    let out = dir.path().join("out.obj").display().to_string();
    let o = seamlit(&["fix", &input, "-o", &out, "--keep-compression"]);
    assert_bad_input(&o, &["out.obj", "--keep-compression", "glTF or GLB"]);
    assert!(!Path::new(&out).exists());
}

/// A .gltf whose buffer 0 has no data of its own (valid glTF: "MAY be provided by other
/// means") and whose triangle lies in buffer 1: the new normals cannot be appended to buffer
/// 0, in a GLB or a .gltf. The user's file, not the machine: exit 2, one line naming buffer 0,
/// nothing written.
#[test]
fn new_normals_cannot_be_appended_to_a_buffer_without_data() {
    let dir = tempfile::tempdir().unwrap();
    let mut bin = Vec::new();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for c in v {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    std::fs::write(dir.path().join("triangle.bin"), &bin).unwrap();
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 4}, {"byteLength": 36, "uri": "triangle.bin"}],
        "bufferViews": [{"buffer": 1, "byteLength": 36}],
        "accessors": [{
            "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
            "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]
        }],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}]
    });
    let input = dir.path().join("no_data.gltf");
    std::fs::write(&input, gltf.to_string()).unwrap();
    for name in ["out.glb", "out.gltf"] {
        let out = dir.path().join(name);
        let o = seamlit(&["fix", &input.display().to_string(), "-o", &out.display().to_string()]);
        assert_bad_input(&o, &[name, "buffer 0", "cannot be appended"]);
        assert!(!out.exists());
    }
}

/// An FBX (ufbx's test file of nested Blender meshes) goes through every command that reads
/// a model; an .fbx output and a truncated FBX are bad input in one line.
#[test]
fn fbx_is_read_by_every_command_and_refused_as_output() {
    let fbx = models().join("ufbx/blender_279_nested_meshes_7400_binary.fbx").display().to_string();
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).display().to_string();
    let o = seamlit(&["inspect", &fbx, "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = seamlit(&["fix", &fbx, "-o", &out("fixed.glb")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout(&o).starts_with("wrote "), "{}", stdout(&o));
    for command in ["render", "compare"] {
        let png = out(&format!("{command}.png"));
        let o = seamlit(&[command, &fbx, "-o", &png, "--size", "160x120"]);
        assert!(o.status.success(), "{command}: {}", String::from_utf8_lossy(&o.stderr));
        let img = image::open(&png).unwrap().to_rgba8();
        assert!(foreground_fraction(&img, 0) > 0.01, "{command}: the model is drawn");
    }
    let o = seamlit(&["fix", &fbx, "-o", &out("out.fbx")]);
    assert_bad_input(&o, &["out.fbx", "cannot write FBX", ".glb"]);
    let bytes = std::fs::read(&fbx).unwrap();
    let truncated = out("truncated.fbx");
    std::fs::write(&truncated, &bytes[..bytes.len() / 3]).unwrap();
    let o = seamlit(&["inspect", &truncated]);
    assert_bad_input(&o, &["truncated.fbx", "FBX", "truncated"]);
    assert_eq!(listing(dir.path()), ["compare.png", "fixed.glb", "render.png", "truncated.fbx"]);
}
