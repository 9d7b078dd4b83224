//! `seamlit-bench skinned`: a skinned, morphed, animated character of any size, the input of
//! the animation benchmarks (BENCHMARKS.md, "Seams in motion").
//!
//! A tube along +Y (height 2, radius 0.25) of `rings` x `segments` vertices with UVs, split
//! near the top into a body mesh and a head mesh that each keep a copy of the ring they share;
//! a chain of `joints` joints up the tube, each vertex weighted to the two nearest (the
//! head's ring copy to the one above the ring only, so the seam opens in motion); two morph
//! targets on both meshes ("bulge": radial, "lift": up); one animation "sway" of 2 seconds
//! (21 LINEAR keys per joint, each joint swaying about X and Z) and a weights channel per
//! mesh. Written as `.gltf` with its buffer beside it (`NAME.bin`).

use std::f32::consts::TAU;
use std::path::Path;

use anyhow::Context as _;
use glam::{Mat4, Quat, Vec3};
use seamlit_testkit::{ARRAY_BUFFER, Buffer, ELEMENT_ARRAY_BUFFER};
use serde_json::json;

/// The size of the character.
pub(crate) struct Shape {
    pub rings: usize,
    pub segments: usize,
    pub joints: usize,
}

/// Height of the tube and of the joint chain.
const HEIGHT: f32 = 2.0;
const RADIUS: f32 = 0.25;

/// Writes the character to `output` (`.gltf`, with `NAME.bin` beside it).
pub(crate) fn write(shape: &Shape, path: &Path) -> anyhow::Result<()> {
    let Shape { rings, segments, joints } = *shape;
    anyhow::ensure!(rings >= 4 && segments >= 3 && joints >= 2, "too small a character");
    anyhow::ensure!(joints <= 65536, "at most 65536 joints (JOINTS_0 is UNSIGNED_SHORT)");
    let neck = rings * 9 / 10;
    let mut data = Buffer::default();
    let meshes = vec![
        mesh(&mut data, shape, MeshPart { rings: 0..neck + 1, neck, head: false }),
        mesh(&mut data, shape, MeshPart { rings: neck..rings, neck, head: true }),
    ];
    let spacing = spacing(joints);
    // Joints: node 2 + k, each translated `spacing` up from its parent.
    let inverse_bind: Vec<f32> = (0..joints)
        .flat_map(|k| Mat4::from_translation(Vec3::Y * -(k as f32 * spacing)).to_cols_array())
        .collect();
    let ibm = data.floats(&inverse_bind, "MAT4", false, None);
    let (samplers, channels) = sway(&mut data, joints);
    let bin_name = path.with_extension("bin");
    let uri = bin_name.file_name().and_then(|n| n.to_str()).context("a file name")?.to_owned();
    let document = json!({
        "asset": {"version": "2.0", "generator": "seamlit-bench skinned"},
        "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": nodes(joints, spacing),
        "skins": [{"name": "chain", "joints": (2..2 + joints).collect::<Vec<_>>(),
            "inverseBindMatrices": ibm}],
        "animations": [{"name": "sway", "samplers": samplers, "channels": channels}],
        "meshes": meshes,
        "accessors": data.accessors, "bufferViews": data.views,
        "buffers": [{"byteLength": data.bin.len(), "uri": uri}],
    });
    std::fs::write(&bin_name, &data.bin).with_context(|| bin_name.display().to_string())?;
    std::fs::write(path, serde_json::to_vec(&document)?)
        .with_context(|| path.display().to_string())?;
    println!(
        "wrote {} ({} triangles, {joints} joints, 2 morph targets, 1 animation)",
        path.display(),
        2 * (rings - 1) * segments
    );
    Ok(())
}

/// The distance between joints up the chain.
fn spacing(joints: usize) -> f32 {
    HEIGHT / (joints - 1) as f32
}

/// Which rings one mesh holds, and whether it is the head (whose copy of the shared `neck`
/// ring follows the joint above alone).
struct MeshPart {
    rings: std::ops::Range<usize>,
    neck: usize,
    head: bool,
}

/// One mesh's vertex attributes, flat.
#[derive(Default)]
struct Rings {
    positions: Vec<f32>,
    uvs: Vec<f32>,
    joints: Vec<u16>,
    weights: Vec<f32>,
    bulge: Vec<f32>,
    lift: Vec<f32>,
}

/// The mesh of `part`: its vertices, triangles and morph targets written into `data`.
fn mesh(data: &mut Buffer, shape: &Shape, part: MeshPart) -> serde_json::Value {
    let rings = ring_vertices(shape, &part);
    let indices = tube_indices(part.rings.len(), shape.segments);
    let position = data.floats(&rings.positions, "VEC3", true, Some(ARRAY_BUFFER));
    let uv = data.floats(&rings.uvs, "VEC2", false, Some(ARRAY_BUFFER));
    let bytes: Vec<u8> = rings.joints.iter().flat_map(|j| j.to_le_bytes()).collect();
    let vertices = rings.positions.len() / 3;
    let joint_accessor = data.push(
        &bytes,
        json!({"componentType": 5123, "count": vertices, "type": "VEC4"}),
        Some(ARRAY_BUFFER),
    );
    let weight_accessor = data.floats(&rings.weights, "VEC4", false, Some(ARRAY_BUFFER));
    let bulge = data.floats(&rings.bulge, "VEC3", true, Some(ARRAY_BUFFER));
    let lift = data.floats(&rings.lift, "VEC3", true, Some(ARRAY_BUFFER));
    let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
    let index_accessor = data.push(
        &bytes,
        json!({"componentType": 5125, "count": indices.len(), "type": "SCALAR"}),
        Some(ELEMENT_ARRAY_BUFFER),
    );
    json!({
        "name": if part.head { "head" } else { "body" },
        "primitives": [{
            "attributes": {"POSITION": position, "TEXCOORD_0": uv,
                "JOINTS_0": joint_accessor, "WEIGHTS_0": weight_accessor},
            "indices": index_accessor,
            "targets": [{"POSITION": bulge}, {"POSITION": lift}],
        }],
        "weights": [0.0, 0.0],
        "extras": {"targetNames": ["bulge", "lift"]},
    })
}

/// The vertices of `part`'s rings: `segments + 1` a ring (the last column repeats the first,
/// with other UVs), each weighted to the two joints around its height.
fn ring_vertices(shape: &Shape, part: &MeshPart) -> Rings {
    let Shape { rings, segments, joints } = *shape;
    let spacing = spacing(joints);
    let mut out = Rings::default();
    for j in part.rings.clone() {
        let y = HEIGHT * j as f32 / (rings - 1) as f32;
        // The two joints around y, weighted linearly; the head's copy of the shared ring
        // follows the upper one alone.
        let at = (y / spacing).min((joints - 1) as f32 - 1e-3);
        // Between 0 and joints - 2 (at is clamped above): fits.
        #[expect(clippy::cast_possible_truncation, clippy::cast_sign_loss, reason = "0..joints")]
        let lower = at.floor() as usize;
        let joint = |k: usize| u16::try_from(k).expect("at most 65536 joints");
        let t = if part.head && j == part.neck { 1.0 } else { at - lower as f32 };
        for i in 0..=segments {
            let theta = TAU * (i % segments) as f32 / segments as f32;
            let (sin, cos) = theta.sin_cos();
            out.positions.extend([RADIUS * cos, y, RADIUS * sin]);
            out.uvs.extend([i as f32 / segments as f32, 1.0 - y / HEIGHT]);
            let upper = if t > 0.0 { joint(lower + 1) } else { 0 };
            let first = if t < 1.0 { joint(lower) } else { 0 };
            out.joints.extend([first, upper, 0, 0]);
            out.weights.extend([1.0 - t, t, 0.0, 0.0]);
            let swell = 0.1 * (std::f32::consts::PI * y / HEIGHT).sin();
            out.bulge.extend([swell * cos, 0.0, swell * sin]);
            out.lift.extend([0.0, 0.05 * y, 0.0]);
        }
    }
    out
}

/// Two triangles per quad of a tube of `count` rings of `segments + 1` vertices.
fn tube_indices(count: usize, segments: usize) -> Vec<u32> {
    let width = segments + 1;
    let mut indices: Vec<u32> = Vec::with_capacity((count - 1) * segments * 6);
    for j in 0..count - 1 {
        for i in 0..segments {
            let at = |j: usize, i: usize| u32::try_from(j * width + i).expect("fits u32");
            let (a, b, c, d) = (at(j, i), at(j, i + 1), at(j + 1, i + 1), at(j + 1, i));
            indices.extend([a, d, c, a, c, b]);
        }
    }
    indices
}

/// The animation "sway": 21 LINEAR keys over 2 seconds, a rotation channel per joint and a
/// weights channel per mesh node; its samplers and channels.
fn sway(data: &mut Buffer, joints: usize) -> (Vec<serde_json::Value>, Vec<serde_json::Value>) {
    let keys = 21;
    let times: Vec<f32> = (0..keys).map(|k| 2.0 * k as f32 / (keys - 1) as f32).collect();
    let input = data.floats(&times, "SCALAR", true, None);
    let (mut samplers, mut channels) = (Vec::new(), Vec::new());
    for k in 0..joints {
        let rotations: Vec<f32> = times
            .iter()
            .flat_map(|&t| {
                let phase = TAU * t / 2.0 + k as f32 * 0.3;
                Quat::from_euler(glam::EulerRot::XYZ, 0.05 * phase.sin(), 0.0, 0.04 * phase.cos())
                    .to_array()
            })
            .collect();
        let output = data.floats(&rotations, "VEC4", false, None);
        samplers.push(json!({"input": input, "output": output, "interpolation": "LINEAR"}));
        channels.push(json!({"sampler": samplers.len() - 1,
            "target": {"node": 2 + k, "path": "rotation"}}));
    }
    let morph: Vec<f32> =
        times.iter().flat_map(|&t| [0.5 - 0.5 * (TAU * t / 2.0).cos(), 0.5 * t / 2.0]).collect();
    let output = data.floats(&morph, "SCALAR", false, None);
    samplers.push(json!({"input": input, "output": output, "interpolation": "LINEAR"}));
    for node in [0, 1] {
        channels.push(json!({"sampler": samplers.len() - 1,
            "target": {"node": node, "path": "weights"}}));
    }
    (samplers, channels)
}

/// The two mesh nodes and the chain of joints, node 2 + k, each `spacing` above its parent.
fn nodes(joints: usize, spacing: f32) -> Vec<serde_json::Value> {
    let mut nodes = vec![
        json!({"name": "body", "mesh": 0, "skin": 0}),
        json!({"name": "head", "mesh": 1, "skin": 0}),
    ];
    for k in 0..joints {
        let mut node = json!({"name": format!("joint{k}")});
        if k > 0 {
            node["translation"] = json!([0.0, spacing, 0.0]);
        }
        if k + 1 < joints {
            node["children"] = json!([3 + k]);
        }
        nodes.push(node);
    }
    nodes
}
