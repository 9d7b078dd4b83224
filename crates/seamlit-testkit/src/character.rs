//! A two-object character built in code: a tube split at the neck into a body mesh and a
//! head mesh that share the neck ring (each with its own copy of its 12 vertices), three
//! joints (root, chest, neck) and one animation, "nod", turning the neck 60 degrees about X
//! and back over 2 seconds. The ring's copies are weighted differently: the body's half
//! chest, half neck; the head's all neck. The head's skin has the neck joint only, so a fix
//! that gives its ring the chest too must add that joint to its skin.

use std::f32::consts::TAU;
use std::path::Path;

use crate::Buffer;
use glam::{Mat4, Quat, Vec3};
use serde_json::{Value, json};

/// Segments around the tube.
pub const SEGMENTS: usize = 12;
/// The tube's radius.
pub const RADIUS: f32 = 0.25;
/// Where the body ends and the head begins.
pub const NECK_Y: f32 = 1.5;

/// The rings of the body and of the head: (height, weights of root, chest, neck).
const BODY: [(f32, [f32; 3]); 5] = [
    (0.0, [1.0, 0.0, 0.0]),
    (0.375, [0.5, 0.5, 0.0]),
    (0.75, [0.0, 1.0, 0.0]),
    (1.125, [0.0, 1.0, 0.0]),
    (NECK_Y, [0.0, 0.5, 0.5]),
];
const HEAD: [(f32, [f32; 3]); 3] =
    [(NECK_Y, [0.0, 0.0, 1.0]), (1.75, [0.0, 0.0, 1.0]), (2.0, [0.0, 0.0, 1.0])];

/// The joints' places in the bind pose (root at the origin, chest at 0.75, neck at 1.5), as
/// each is translated from its parent.
const JOINT_Y: [f32; 3] = [0.0, 0.75, NECK_Y];

/// The nod's keys: (time, angle about X in degrees).
pub const NOD: [(f32, f32); 3] = [(0.0, 0.0), (1.0, 60.0), (2.0, 0.0)];

/// One mesh of the tube: its rings, with joints given as indices into its skin's joints
/// (`slots`: root, chest, neck -> skin slot).
fn tube(data: &mut Buffer, rings: &[(f32, [f32; 3])], slots: [u8; 3]) -> Value {
    let (mut positions, mut joints, mut weights) = (Vec::new(), Vec::new(), Vec::new());
    for &(y, w) in rings {
        for i in 0..SEGMENTS {
            let theta = TAU * i as f32 / SEGMENTS as f32;
            positions.extend([RADIUS * theta.cos(), y, RADIUS * theta.sin()]);
            // The two largest influences, in joint order.
            let mut lanes: Vec<(u8, f32)> =
                (0..3).filter(|&j| w[j] > 0.0).map(|j| (slots[j], w[j])).collect();
            lanes.resize(4, (0, 0.0));
            joints.extend(lanes.iter().map(|l| l.0));
            weights.extend(lanes.iter().map(|l| l.1));
        }
    }
    let mut indices: Vec<u16> = Vec::new();
    for j in 0..rings.len() - 1 {
        for i in 0..SEGMENTS {
            let at = |j: usize, i: usize| u16::try_from(j * SEGMENTS + i % SEGMENTS).unwrap();
            let (a, b, c, d) = (at(j, i), at(j, i + 1), at(j + 1, i + 1), at(j + 1, i));
            indices.extend([a, d, c, a, c, b]);
        }
    }
    let count = positions.len() / 3;
    let position = data.floats(&positions, "VEC3", true, None);
    let joints =
        data.push(&joints, json!({"componentType": 5121, "count": count, "type": "VEC4"}), None);
    let weights = data.floats(&weights, "VEC4", false, None);
    let indices = data.indices(&indices);
    json!({"primitives": [{"indices": indices,
        "attributes": {"POSITION": position, "JOINTS_0": joints, "WEIGHTS_0": weights}}]})
}

/// Writes the character as a `.gltf` with its buffer in a `data:` URI.
pub fn write(path: &Path) {
    write_with(path, false);
}

/// [`write`], and with `swell` the body (only) gets a morph target named "swell" that pushes
/// every vertex out by a tenth of the radius: a seam that opens at the neck while it is active.
pub fn write_with(path: &Path, swell: bool) {
    let (mut document, bin) = document(swell);
    let uri = format!("data:application/octet-stream;base64,{}", base64::encode(&bin));
    document["buffers"][0]["uri"] = json!(uri);
    std::fs::write(path, serde_json::to_vec_pretty(&document).unwrap()).unwrap();
}

/// The character's document (see [`write_with`]) and its one buffer's bytes; the buffer has
/// no `uri` (a GLB's BIN chunk: [`crate::glb`]).
pub fn document(swell: bool) -> (Value, Vec<u8>) {
    let mut data = Buffer::default();
    // Skin 0 (body): root, chest, neck. Skin 1 (head): neck only.
    let mut body = tube(&mut data, &BODY, [0, 1, 2]);
    if swell {
        let deltas: Vec<f32> = BODY
            .iter()
            .flat_map(|_| {
                (0..SEGMENTS).flat_map(|i| {
                    let theta = TAU * i as f32 / SEGMENTS as f32;
                    [0.1 * RADIUS * theta.cos(), 0.0, 0.1 * RADIUS * theta.sin()]
                })
            })
            .collect();
        let target = data.floats(&deltas, "VEC3", true, None);
        body["primitives"][0]["targets"] = json!([{"POSITION": target}]);
        body["weights"] = json!([0.0]);
        body["extras"] = json!({"targetNames": ["swell"]});
    }
    let head = tube(&mut data, &HEAD, [0, 0, 0]);
    let inverse_bind = |y: f32| Mat4::from_translation(Vec3::new(0.0, -y, 0.0)).to_cols_array();
    let body_ibm: Vec<f32> = JOINT_Y.iter().flat_map(|&y| inverse_bind(y)).collect();
    let body_ibm = data.floats(&body_ibm, "MAT4", false, None);
    let head_ibm = data.floats(&inverse_bind(NECK_Y), "MAT4", false, None);
    let times: Vec<f32> = NOD.iter().map(|k| k.0).collect();
    let times = data.floats(&times, "SCALAR", true, None);
    let rotations: Vec<f32> =
        NOD.iter().flat_map(|k| Quat::from_rotation_x(k.1.to_radians()).to_array()).collect();
    let rotations = data.floats(&rotations, "VEC4", false, None);
    let document = json!({
        "asset": {"version": "2.0", "generator": "seamlit tests (character.rs)"},
        "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"name": "body", "mesh": 0, "skin": 0},
            {"name": "head", "mesh": 1, "skin": 1},
            {"name": "root", "children": [3]},
            {"name": "chest", "translation": [0.0, JOINT_Y[1] - JOINT_Y[0], 0.0], "children": [4]},
            {"name": "neck", "translation": [0.0, JOINT_Y[2] - JOINT_Y[1], 0.0]},
        ],
        "skins": [
            {"name": "body", "joints": [2, 3, 4], "inverseBindMatrices": body_ibm},
            {"name": "head", "joints": [4], "inverseBindMatrices": head_ibm},
        ],
        "animations": [{"name": "nod",
            "samplers": [{"input": times, "output": rotations, "interpolation": "LINEAR"}],
            "channels": [{"sampler": 0, "target": {"node": 4, "path": "rotation"}}]}],
        "meshes": [body, head],
        "accessors": data.accessors, "bufferViews": data.views,
        "buffers": [{"byteLength": data.bin.len()}],
    });
    (document, data.bin)
}
