//! glTF sparse accessors: small documents written by the test (JSON with a base64 data URI
//! buffer) whose POSITION accessor is sparse, with and without a base buffer view and with
//! u8, u16 and u32 sparse indices; the loaded positions are compared with values written
//! here by hand. Hostile sparse accessors (an index out of range, indices not strictly
//! increasing, a sparse count above the accessor's or of zero, index or value views too
//! short) get an `IoError` naming the accessor, and no panic.

use std::path::{Path, PathBuf};

use glam::Vec3;
use seamlit_io::{BadAccessor, GltfKind, IoError, LoadOptions};
use serde_json::{Value, json};

/// The four base positions of the quad (when the accessor has a buffer view).
const BASE: [[f32; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];

/// glTF componentType codes for the sparse indices.
const U8: u32 = 5121;
const U16: u32 = 5123;
const U32: u32 = 5125;

/// A quad (4 positions, two u16-indexed triangles) whose POSITION accessor is sparse:
/// `indices` (written as `index_type`) replace the positions with `values`. The sparse
/// count written is `sparse_count` (normally `indices.len()`); `with_base` gives the
/// accessor a buffer view holding [`BASE`], else its base is zeros.
///
/// Buffer layout: [base positions, 48 bytes][triangle indices, 12 bytes]
/// [sparse indices, padded to 4][sparse values, 12 bytes each].
struct Sparse {
    with_base: bool,
    index_type: u32,
    indices: Vec<u32>,
    values: Vec<[f32; 3]>,
    sparse_count: usize,
    accessor_count: usize,
}

impl Sparse {
    fn new(with_base: bool, index_type: u32, indices: &[u32], values: &[[f32; 3]]) -> Self {
        Self {
            with_base,
            index_type,
            indices: indices.to_vec(),
            values: values.to_vec(),
            sparse_count: indices.len(),
            accessor_count: 4,
        }
    }

    fn document(&self) -> Value {
        let mut bytes: Vec<u8> = BASE.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
        bytes.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
        let indices_offset = bytes.len();
        for &i in &self.indices {
            match self.index_type {
                U8 => bytes.push(u8::try_from(i).unwrap()),
                U16 => bytes.extend(u16::try_from(i).unwrap().to_le_bytes()),
                _ => bytes.extend(i.to_le_bytes()),
            }
        }
        let indices_length = bytes.len() - indices_offset;
        while !bytes.len().is_multiple_of(4) {
            bytes.push(0);
        }
        let values_offset = bytes.len();
        bytes.extend(self.values.iter().flatten().flat_map(|x| x.to_le_bytes()));
        let values_length = bytes.len() - values_offset;
        let mut position = json!({
            "componentType": 5126, "count": self.accessor_count, "type": "VEC3",
            "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0],
            "sparse": {
                "count": self.sparse_count,
                "indices": { "bufferView": 2, "componentType": self.index_type },
                "values": { "bufferView": 3 }
            }
        });
        if self.with_base {
            position["bufferView"] = json!(0);
        }
        json!({
            "asset": { "version": "2.0" },
            "scene": 0,
            "scenes": [{ "nodes": [0] }],
            "nodes": [{ "name": "quad", "mesh": 0 }],
            "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
            "accessors": [
                position,
                { "bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR" }
            ],
            "bufferViews": [
                { "buffer": 0, "byteOffset": 0, "byteLength": 48 },
                { "buffer": 0, "byteOffset": 48, "byteLength": 12 },
                { "buffer": 0, "byteOffset": indices_offset, "byteLength": indices_length },
                { "buffer": 0, "byteOffset": values_offset, "byteLength": values_length }
            ],
            "buffers": [{
                "byteLength": bytes.len(),
                "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&bytes))
            }]
        })
    }

    fn write(&self, dir: &Path, name: &str) -> PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_vec(&self.document()).unwrap()).unwrap();
        path
    }

    fn load(&self) -> Result<seamlit_io::Asset, IoError> {
        let dir = tempfile::tempdir().unwrap();
        seamlit_io::load(&self.write(dir.path(), "sparse.gltf"), &LoadOptions::default())
    }

    fn positions(&self) -> Vec<Vec3> {
        let asset = self.load().unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(asset.model.objects.len(), 1);
        let object = &asset.model.objects[0];
        assert_eq!(object.name, "quad");
        assert_eq!(object.triangles, [[0, 1, 2], [0, 2, 3]]);
        object.positions.clone()
    }
}

fn vec3s(values: [[f32; 3]; 4]) -> Vec<Vec3> {
    values.into_iter().map(Vec3::from_array).collect()
}

#[test]
fn sparse_positions_over_a_base_view_with_u8_u16_u32_indices() {
    for index_type in [U8, U16, U32] {
        let sparse = Sparse::new(true, index_type, &[1, 3], &[[5.0, 6.0, 7.0], [-8.0, 9.5, 10.0]]);
        assert_eq!(
            sparse.positions(),
            vec3s([[0.0, 0.0, 0.0], [5.0, 6.0, 7.0], [1.0, 1.0, 0.0], [-8.0, 9.5, 10.0]]),
            "componentType {index_type}"
        );
    }
}

#[test]
fn sparse_positions_without_a_base_view_are_zeros_plus_the_sparse_values() {
    for index_type in [U8, U16, U32] {
        let sparse = Sparse::new(
            false,
            index_type,
            &[0, 2, 3],
            &[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [0.25, -0.5, 0.75]],
        );
        assert_eq!(
            sparse.positions(),
            vec3s([[1.0, 2.0, 3.0], [0.0, 0.0, 0.0], [4.0, 5.0, 6.0], [0.25, -0.5, 0.75]]),
            "componentType {index_type}"
        );
    }
}

#[test]
fn sparse_values_may_replace_every_position() {
    let values = [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [4.0, 0.0, 0.0]];
    let sparse = Sparse::new(true, U16, &[0, 1, 2, 3], &values);
    assert_eq!(sparse.positions(), vec3s(values));
}

/// The error of a hostile sparse POSITION accessor (accessor 0): a `BadAccessor` naming
/// accessor 0 and the file, of kind `expected`.
fn refused(sparse: &Sparse, expected: &BadAccessor) {
    let err = match sparse.load() {
        Ok(asset) => panic!("loaded: {:?}", asset.model.objects[0].positions),
        Err(err) => err,
    };
    let message = err.to_string();
    match &err {
        IoError::Gltf { kind: GltfKind::Accessor { accessor, kind, .. }, .. } => {
            assert_eq!(*accessor, 0, "{message}");
            assert_eq!(&**kind, expected, "{message}");
        }
        other => panic!("expected an accessor error, got {other:?}"),
    }
    assert!(message.contains("sparse.gltf"), "{message}");
}

#[test]
fn a_sparse_index_out_of_range_is_refused() {
    for (with_base, index_type) in [(true, U8), (false, U16), (true, U32)] {
        let sparse = Sparse::new(with_base, index_type, &[1, 4], &[[5.0; 3], [6.0; 3]]);
        refused(&sparse, &BadAccessor::SparseIndexOutOfRange { index: 4, element: 1, count: 4 });
    }
    // Far past any count, with u32 indices.
    refused(
        &Sparse::new(true, U32, &[u32::MAX], &[[5.0; 3]]),
        &BadAccessor::SparseIndexOutOfRange { index: u32::MAX, element: 0, count: 4 },
    );
}

#[test]
fn sparse_indices_must_strictly_increase() {
    // The glTF 2.0 spec: "The indices MUST form a strictly increasing sequence."
    for indices in [[3, 1], [2, 2]] {
        for index_type in [U8, U16, U32] {
            let sparse = Sparse::new(true, index_type, &indices, &[[5.0; 3], [6.0; 3]]);
            let [before, index] = indices;
            refused(&sparse, &BadAccessor::SparseNotIncreasing { element: 1, index, before });
        }
    }
}

#[test]
fn a_sparse_count_above_the_accessor_count_is_refused() {
    let values = [[1.0; 3], [2.0; 3], [3.0; 3], [4.0; 3], [5.0; 3]];
    let sparse = Sparse::new(true, U16, &[0, 1, 2, 3, 4], &values);
    refused(&sparse, &BadAccessor::SparseCountExceeds { sparse: 5, count: 4 });
}

#[test]
fn a_sparse_count_of_zero_is_refused() {
    // glTF requires sparse.count >= 1; gltf 1.4.1's reader computes `count - 1` unchecked.
    let mut sparse = Sparse::new(true, U16, &[1], &[[5.0; 3]]);
    sparse.sparse_count = 0;
    refused(&sparse, &BadAccessor::ZeroSparseCount { attribute: "POSITION".to_owned() });
}

#[test]
fn sparse_index_and_value_views_too_short_are_refused() {
    // Three sparse elements declared, two indices and two values in the views.
    let mut sparse = Sparse::new(true, U32, &[0, 1], &[[5.0; 3], [6.0; 3]]);
    sparse.sparse_count = 3;
    let err = sparse.load().unwrap_err();
    match &err {
        IoError::Gltf {
            kind:
                GltfKind::AccessorOutOfRange { accessor: 0, view: 2, needed: 12, available: 8, .. },
            ..
        } => {}
        other => panic!("expected the indices view to be too short, got {other:?}: {other}"),
    }
    // Enough indices, values for two of three.
    let mut sparse = Sparse::new(true, U8, &[0, 1, 2], &[[5.0; 3], [6.0; 3]]);
    sparse.sparse_count = 3;
    match &sparse.load().unwrap_err() {
        IoError::Gltf {
            kind:
                GltfKind::AccessorOutOfRange { accessor: 0, view: 3, needed: 36, available: 24, .. },
            ..
        } => {}
        other => panic!("expected the values view to be too short, got {other:?}: {other}"),
    }
}

#[test]
fn a_sparse_accessor_larger_than_its_base_view_is_refused() {
    // Count 5 over a base view of 4 positions.
    let mut sparse = Sparse::new(true, U8, &[1], &[[5.0; 3]]);
    sparse.accessor_count = 5;
    match &sparse.load().unwrap_err() {
        IoError::Gltf {
            kind:
                GltfKind::AccessorOutOfRange { accessor: 0, view: 0, needed: 60, available: 48, .. },
            ..
        } => {}
        other => panic!("expected the base view to be too short, got {other:?}: {other}"),
    }
}
