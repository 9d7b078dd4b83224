//! A real skinned, animated model by others (Khronos sample Fox, assets/models/fox; licence in
//! assets/models/SOURCES.md) through `load` -> `fix` -> `save`: everything skinning and
//! animation need survives, read back with the gltf crate's GLB container and raw accessor
//! bytes (not this crate's reader).

mod common;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use common::gltf::{File, read};
use common::{usize_of, validate};
use serde_json::Value;

use seamlit_io::{LoadOptions, SaveOptions};

fn fox() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models/fox/Fox.glb")
}

/// An accessor index as a document holds it.
fn index_of(value: &Value) -> usize {
    value.as_u64().map(usize_of).unwrap()
}

impl File {
    /// The only primitive's attribute `name`, one element per triangle corner.
    fn per_corner(&self, name: &str) -> Vec<Vec<u8>> {
        let primitive = &self.json["meshes"][0]["primitives"][0];
        let elements = self.elements(index_of(&primitive["attributes"][name]));
        match primitive.get("indices") {
            None => elements,
            Some(indices) => self
                .elements(index_of(indices))
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
fn input_and_output() -> &'static (File, File) {
    static FILES: OnceLock<(File, File)> = OnceLock::new();
    FILES.get_or_init(|| (read(&fox()), read(fixed())))
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
    // Joints are the asset's node indices, each one of the skin's 24 joints.
    let node = asset.nodes.iter().find(|n| n.objects.contains(&0)).unwrap();
    let skin = &asset.skins[node.skin.unwrap()];
    assert_eq!(skin.joints.len(), 24);
    let mut joints = object.skin[0].joints.iter().flatten();
    assert!(joints.all(|&j| skin.joints.contains(&(j as usize))), "joints map through the skin");
    // The file's animations, with their names.
    let names: Vec<&str> = asset.animations.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["Survey", "Walk", "Run"]);
    let (_, output) = input_and_output();
    assert!(output.json["meshes"][0]["primitives"][0]["attributes"].get("NORMAL").is_some());
}

#[test]
fn the_skin_and_its_inverse_bind_matrices_are_unchanged() {
    let (input, output) = input_and_output();
    assert_eq!(input.json["skins"], output.json["skins"]);
    let ibm = &input.json["skins"][0]["inverseBindMatrices"];
    assert_eq!(input.elements(index_of(ibm)).len(), 24);
    assert_eq!(
        input.elements(index_of(ibm)),
        output.elements(index_of(&output.json["skins"][0]["inverseBindMatrices"]))
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
                assert_eq!(
                    input.elements(index_of(&sampler[key])),
                    output.elements(index_of(&sampler[key]))
                );
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
