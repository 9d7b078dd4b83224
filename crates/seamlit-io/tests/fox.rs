//! A real skinned, animated model by others (Khronos sample Fox, assets/models/fox; licence in
//! assets/models/SOURCES.md) through `load` -> `fix` -> `save`: everything skinning and
//! animation need survives, read back with the gltf crate's GLB container and raw accessor
//! bytes (not this crate's reader).

mod common;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use common::{usize_of, validate};
use serde_json::Value;

use seamlit_io::{LoadOptions, SaveOptions};

fn fox() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models/fox/Fox.glb")
}

/// A GLB's JSON document and BIN chunk.
struct Glb {
    json: Value,
    bin: Vec<u8>,
}

impl Glb {
    fn read(path: &Path) -> Self {
        let bytes = std::fs::read(path).unwrap();
        let glb = gltf::Glb::from_slice(&bytes).unwrap();
        Self {
            json: serde_json::from_slice(&glb.json).unwrap(),
            bin: glb.bin.expect("a BIN chunk").into_owned(),
        }
    }

    /// Accessor `index`'s elements as stored, one byte string per element (no sparse: Fox
    /// has none).
    fn elements(&self, index: &Value) -> Vec<Vec<u8>> {
        let a = &self.json["accessors"][index.as_u64().map(usize_of).unwrap()];
        let components = match a["type"].as_str().unwrap() {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" | "MAT2" => 4,
            "MAT3" => 9,
            "MAT4" => 16,
            other => panic!("type {other}"),
        };
        let component = match a["componentType"].as_u64().unwrap() {
            5120 | 5121 => 1,
            5122 | 5123 => 2,
            _ => 4,
        };
        let size = components * component;
        let view = &self.json["bufferViews"][a["bufferView"].as_u64().map(usize_of).unwrap()];
        assert_eq!(view["buffer"], 0);
        let start =
            view["byteOffset"].as_u64().unwrap_or(0) + a["byteOffset"].as_u64().unwrap_or(0);
        let stride = view["byteStride"].as_u64().map_or(size, usize_of);
        (0..a["count"].as_u64().map(usize_of).unwrap())
            .map(|i| {
                let at = usize_of(start) + i * stride;
                self.bin[at..at + size].to_vec()
            })
            .collect()
    }

    /// The only primitive's attribute `name`, one element per triangle corner.
    fn per_corner(&self, name: &str) -> Vec<Vec<u8>> {
        let primitive = &self.json["meshes"][0]["primitives"][0];
        let elements = self.elements(&primitive["attributes"][name]);
        match primitive.get("indices") {
            None => elements,
            Some(indices) => self
                .elements(indices)
                .iter()
                .map(|i| {
                    let mut word = [0u8; 4];
                    word[..i.len()].copy_from_slice(i);
                    elements[u32::from_le_bytes(word) as usize].clone()
                })
                .collect(),
        }
    }
}

/// The fixed copy's path (in a folder kept for the process).
fn fixed() -> &'static Path {
    static FILE: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();
    let (_, out) = FILE.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("fox.glb");
        let mut asset = seamlit_io::load(&fox(), &LoadOptions::default()).unwrap();
        seamlit_mesh::fix_in_place(&mut asset.model, &seamlit_mesh::FixOptions::default()).unwrap();
        let saved = seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap();
        assert!(saved.warnings.is_empty(), "{:?}", saved.warnings);
        (dir, out)
    });
    out
}

/// The input and its fixed copy (written once, shared by the tests).
fn input_and_output() -> &'static (Glb, Glb) {
    static FILES: OnceLock<(Glb, Glb)> = OnceLock::new();
    FILES.get_or_init(|| (Glb::read(&fox()), Glb::read(fixed())))
}

#[test]
fn the_fixed_fox_passes_the_validator() {
    let (errors, report) = validate(fixed());
    assert_eq!(errors, 0, "{report}");
}

#[test]
fn the_fox_is_loaded_with_its_skin_and_gets_normals() {
    let asset = seamlit_io::load(&fox(), &LoadOptions::GEOMETRY).unwrap();
    let object = &asset.model.objects[0];
    assert_eq!(object.triangle_count(), 576);
    assert_eq!(object.skin.len(), 1);
    // Joints are node indices: the skin's joints are nodes 2 to 25.
    let joints = object.skin[0].joints.iter().flatten();
    assert!(joints.clone().all(|&j| (2..=25).contains(&j)), "joints map through the skin");
    let (_, output) = input_and_output();
    assert!(output.json["meshes"][0]["primitives"][0]["attributes"].get("NORMAL").is_some());
}

#[test]
fn the_skin_and_its_inverse_bind_matrices_are_unchanged() {
    let (input, output) = input_and_output();
    assert_eq!(input.json["skins"], output.json["skins"]);
    let ibm = &input.json["skins"][0]["inverseBindMatrices"];
    assert_eq!(input.elements(ibm).len(), 24);
    assert_eq!(
        input.elements(ibm),
        output.elements(&output.json["skins"][0]["inverseBindMatrices"])
    );
}

#[test]
fn joints_and_weights_are_unchanged_at_every_triangle_corner() {
    let (input, output) = input_and_output();
    for name in ["JOINTS_0", "WEIGHTS_0", "TEXCOORD_0", "POSITION"] {
        let (a, b) = (input.per_corner(name), output.per_corner(name));
        assert_eq!(a.len(), 576 * 3, "{name}");
        assert!(
            a == b,
            "{name}: corners differ, first at {:?}",
            a.iter().zip(&b).position(|(x, y)| x != y)
        );
    }
}

#[test]
fn the_three_animations_are_unchanged_channel_by_channel_and_byte_by_byte() {
    let (input, output) = input_and_output();
    let animations = input.json["animations"].as_array().unwrap();
    assert_eq!(animations.len(), 3);
    assert_eq!(&input.json["animations"], &output.json["animations"]);
    let mut samplers = 0;
    for animation in animations {
        assert_eq!(animation["channels"].as_array().unwrap().len(), 21);
        for sampler in animation["samplers"].as_array().unwrap() {
            for key in ["input", "output"] {
                assert_eq!(input.elements(&sampler[key]), output.elements(&sampler[key]));
            }
            samplers += 1;
        }
    }
    assert_eq!(samplers, 63);
}

#[test]
fn the_node_tree_and_names_are_unchanged() {
    let (input, output) = input_and_output();
    assert_eq!(input.json["nodes"].as_array().unwrap().len(), 26);
    assert_eq!(input.json["nodes"], output.json["nodes"]);
    assert_eq!(input.json["scenes"], output.json["scenes"]);
}
