//! `seamlit fix` and `seamlit inspect` report welded positions whose objects' skin weights
//! differ, in text and JSON; `fix` matches them by default and keeps them with
//! `--skin-seams keep`.

use std::path::Path;
use std::process::Command;

use serde_json::json;

/// Two skinned quads (nodes "arm" and "shoulder", one skin of joints "bone0" and "bone1")
/// meeting at the edge x = 1: at (1, 0) both weigh bone0 0.6; at (1, 1) the arm weighs it 0.7
/// and the shoulder `shoulder_weight`. The buffer is written beside, as `NAME.bin`.
fn two_skinned_quads(path: &Path, shoulder_weight: f32) {
    let mut bin: Vec<u8> = Vec::new();
    let (mut views, mut accessors) = (Vec::new(), Vec::new());
    let mut add = |bytes: Vec<u8>, accessor: serde_json::Value| {
        let at = bin.len();
        bin.extend_from_slice(&bytes);
        views.push(json!({"buffer": 0, "byteOffset": at, "byteLength": bytes.len()}));
        let mut accessor = accessor;
        accessor["bufferView"] = json!(views.len() - 1);
        accessors.push(accessor);
        accessors.len() - 1
    };
    let mut meshes = Vec::new();
    for (x0, weights) in [(0.0f32, [0.2, 0.6, 0.7, 0.2]), (1.0, [0.6, 0.9, 0.1, shoulder_weight])] {
        let positions =
            [[x0, 0.0, 0.0], [x0 + 1.0, 0.0, 0.0], [x0 + 1.0, 1.0, 0.0], [x0, 1.0, 0.0]];
        let bytes = positions.iter().flatten().flat_map(|f: &f32| f.to_le_bytes()).collect();
        let position = add(
            bytes,
            json!({"componentType": 5126, "count": 4, "type": "VEC3",
            "min": [x0, 0.0, 0.0], "max": [x0 + 1.0, 1.0, 0.0]}),
        );
        let joints = add(
            [0u8, 1, 0, 0].repeat(4),
            json!({"componentType": 5121, "count": 4, "type": "VEC4"}),
        );
        let bytes = weights
            .iter()
            .flat_map(|&w: &f32| [w, 1.0 - w, 0.0, 0.0])
            .flat_map(f32::to_le_bytes)
            .collect();
        let weight = add(bytes, json!({"componentType": 5126, "count": 4, "type": "VEC4"}));
        let indices = add(
            [0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()).collect(),
            json!({"componentType": 5123, "count": 6, "type": "SCALAR"}),
        );
        meshes.push(json!({"primitives": [{"indices": indices,
            "attributes": {"POSITION": position, "JOINTS_0": joints, "WEIGHTS_0": weight}}]}));
    }
    std::fs::write(path.with_extension("bin"), &bin).unwrap();
    let uri = path.with_extension("bin").file_name().unwrap().to_str().unwrap().to_owned();
    let document = json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"name": "arm", "mesh": 0, "skin": 0}, {"name": "shoulder", "mesh": 1, "skin": 0},
            {"name": "bone0", "children": [3]}, {"name": "bone1", "translation": [1.0, 0.0, 0.0]},
        ],
        "skins": [{"joints": [2, 3]}],
        "meshes": meshes, "accessors": accessors, "bufferViews": views,
        "buffers": [{"byteLength": bin.len(), "uri": uri}],
    });
    std::fs::write(path, serde_json::to_vec(&document).unwrap()).unwrap();
}

fn seamlit(args: &[&str]) -> (bool, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_seamlit")).args(args).output().unwrap();
    (
        o.status.success(),
        format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr)),
    )
}

#[test]
fn fix_and_inspect_name_the_seam_position_whose_skin_weights_differ() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("quads.gltf");
    let out = dir.path().join("out.glb");
    two_skinned_quads(&input, 0.5);
    let (input, out_s) = (input.to_str().unwrap(), out.to_str().unwrap());
    let (ok, text) = seamlit(&["fix", input, "-o", out_s, "--skin-seams", "keep"]);
    assert!(ok, "{text}");
    assert!(
        text.contains("skins: 1 shared position where objects' skin weights differ")
            && text.contains("(1, 1, 0) between arm and shoulder"),
        "{text}"
    );
    // By default the copies get the same weights, and the report after the fix has none.
    let (ok, text) = seamlit(&["fix", input, "-o", out_s]);
    assert!(ok, "{text}");
    assert!(
        text.contains("skins: gave the copies at 1 shared position the same joints and weights")
            && !text.contains("weights differ"),
        "{text}"
    );
    let input = Path::new(input);
    let (ok, text) = seamlit(&["inspect", input.to_str().unwrap()]);
    assert!(ok, "{text}");
    let row = text.lines().find(|l| l.starts_with("shared positions whose skins differ"));
    assert!(row.is_some_and(|r| r.split_whitespace().any(|w| w == "1")), "{text}");
    let (ok, text) = seamlit(&["inspect", input.to_str().unwrap(), "--json"]);
    assert!(ok, "{text}");
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["as_loaded"]["skin_seams"]["positions"], json!(1), "{text}");
}

#[test]
fn matching_skin_weights_at_the_seam_say_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("quads.gltf");
    two_skinned_quads(&input, 0.7);
    let out = dir.path().join("out.glb");
    let (ok, text) = seamlit(&["fix", input.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(ok, "{text}");
    assert!(!text.contains("skins:"), "{text}");
}
