//! Skins and morph targets through the glTF pass: loaded into the model, their normal deltas
//! computed and written, read back with the gltf crate (an independent reader).

mod common;

use std::path::Path;

use common::validate;
use glam::Vec3;
use seamlit_io::{LoadOptions, SaveOptions};
use seamlit_mesh::{FixOptions, Model, fix, fix_in_place};
use seamlit_testkit::Buffer;
use serde_json::{Value, json};

/// A bump centred on the seam x = 2, y = 1.
fn bulge(p: Vec3) -> Vec3 {
    let d2 = (p.x - 2.0).powi(2) + (p.y - 1.0).powi(2);
    Vec3::new(0.0, 0.0, 0.6 * (-d2).exp())
}

/// The document around `meshes` and `nodes`, `data`'s buffer in a `data:` URI.
fn document(data: Buffer, meshes: Vec<Value>, nodes: Vec<Value>, extra: Value) -> Value {
    let uri = format!("data:application/octet-stream;base64,{}", base64::encode(&data.bin));
    let mut document = json!({
        "asset": {"version": "2.0"}, "scene": 0,
        "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes, "meshes": meshes, "accessors": data.accessors,
        "bufferViews": data.views, "buffers": [{"byteLength": data.bin.len(), "uri": uri}],
    });
    for (key, value) in extra.as_object().into_iter().flatten() {
        document[key] = value.clone();
    }
    document
}

/// The triangles of a grid of `n` x `n` vertices.
fn grid_indices(n: u16) -> Vec<u16> {
    let mut indices = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let v = j * n + i;
            indices.extend([v, v + 1, v + n + 1, v, v + n + 1, v + n]);
        }
    }
    indices
}

/// The vertices of a 5 x 5 grid over `[x0, x0 + 2] x [0, 2]`, gently curved.
fn sheet_positions(x0: f32) -> Vec<Vec3> {
    (0..25u16)
        .map(|v| {
            let x = x0 + 0.5 * f32::from(v % 5);
            Vec3::new(x, 0.5 * f32::from(v / 5), 0.05 * x * x)
        })
        .collect()
}

/// Two 4 x 4 sheets of quads meeting at x = 2, each a mesh of its own node with one morph
/// target ([`bulge`]) and no normals, as a `.gltf` with its buffer in a `data:` URI.
fn two_sheets(path: &Path) {
    let mut data = Buffer::default();
    let (mut meshes, mut nodes) = (Vec::new(), Vec::new());
    for (m, x0) in [0.0f32, 2.0].into_iter().enumerate() {
        let positions = sheet_positions(x0);
        let deltas: Vec<Vec3> = positions.iter().map(|&p| bulge(p)).collect();
        let (position, delta) = (data.vec3(&positions), data.vec3(&deltas));
        let indices = data.indices(&grid_indices(5));
        meshes.push(json!({"primitives": [{
            "attributes": {"POSITION": position}, "indices": indices,
            "targets": [{"POSITION": delta}]}], "weights": [0.0]}));
        nodes.push(json!({"mesh": m, "name": format!("sheet{m}")}));
    }
    let document = document(data, meshes, nodes, json!({}));
    std::fs::write(path, serde_json::to_vec_pretty(&document).unwrap()).unwrap();
}

/// Per node (in node order): positions, normals, and target 0's position and normal deltas,
/// as the gltf crate reads them.
fn read_back(path: &Path) -> Vec<[Vec<Vec3>; 4]> {
    let (document, buffers, _) = gltf::import(path).unwrap();
    let mut out = Vec::new();
    for node in document.nodes() {
        let primitive = node.mesh().unwrap().primitives().next().unwrap();
        let reader = primitive.reader(|b| Some(&buffers[b.index()]));
        let v3 = |it: &mut dyn Iterator<Item = [f32; 3]>| it.map(Vec3::from_array).collect();
        let (dp, dn, _) = reader.read_morph_targets().next().unwrap();
        out.push([
            v3(&mut reader.read_positions().unwrap()),
            v3(&mut reader.read_normals().unwrap()),
            v3(&mut dp.unwrap()),
            dn.map(|mut it| v3(&mut it)).unwrap_or_default(),
        ]);
    }
    out
}

#[test]
fn computed_morph_normals_are_written_and_agree_across_the_seam() {
    let dir = tempfile::tempdir().unwrap();
    let (input, output) = (dir.path().join("in.gltf"), dir.path().join("out.glb"));
    two_sheets(&input);
    let mut asset = seamlit_io::load(&input, &LoadOptions::GEOMETRY).unwrap();
    // The loader carries the target's position deltas.
    let deltas = &asset.model.objects[1].morph_targets[0].position_deltas;
    assert_eq!(deltas[12], bulge(Vec3::new(3.0, 1.0, 0.45)));
    // The displaced model, fixed from scratch: what the file's morphed normals must be.
    let mut displaced: Model = asset.model.clone();
    for o in &mut displaced.objects {
        for (p, d) in o.positions.iter_mut().zip(o.morph_targets.remove(0).position_deltas) {
            *p += d;
        }
    }
    let scratch = fix(&displaced, &FixOptions::default()).unwrap();
    fix_in_place(&mut asset.model, &FixOptions::default()).unwrap();
    seamlit_io::save(&asset, &output, &SaveOptions::default()).unwrap();
    let (errors, report) = validate(&output);
    assert_eq!(errors, 0, "{report}");

    let written = read_back(&output);
    let mut seam = 0;
    for (o, [positions, normals, _, normal_deltas]) in written.iter().enumerate() {
        assert_eq!(normal_deltas.len(), positions.len(), "node {o}: target 0 has NORMAL deltas");
        let expected = scratch.objects[o].normals.as_ref().unwrap();
        for v in 0..positions.len() {
            let morphed = normals[v] + normal_deltas[v];
            assert!(morphed.abs_diff_eq(expected[v], 1e-5), "node {o} v{v}: {morphed}");
        }
    }
    let [(p0, n0, d0), (p1, n1, d1)] =
        [0, 1].map(|o| (&written[o][0], &written[o][1], &written[o][3]));
    for (a, pa) in p0.iter().enumerate() {
        for (b, _) in p1.iter().enumerate().filter(|(_, pb)| *pb == pa) {
            assert!((n0[a] + d0[a]).abs_diff_eq(n1[b] + d1[b], 1e-5), "seam at {pa}");
            seam += 1;
        }
    }
    assert_eq!(seam, 5);
}

/// The validator's view of the input, as a control: the fixture is valid glTF.
#[test]
fn the_two_sheets_are_valid_gltf() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.gltf");
    two_sheets(&input);
    let (errors, report) = validate(&input);
    assert_eq!(errors, 0, "{report}");
    let json: Value = serde_json::from_slice(&std::fs::read(&input).unwrap()).unwrap();
    assert_eq!(json["meshes"].as_array().unwrap().len(), 2);
}
