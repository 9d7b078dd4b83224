//! The glTF pass-through: a glTF or GLB fixed and saved as glTF or GLB is its input with
//! only NORMAL, TANGENT, split vertices and indices changed.
//!
//! The fixtures are built here (JSON and binary in code). The written files are read back
//! with serde_json and the tests' own accessor reader (common/gltf.rs), never with seamlit's
//! loader, and
//! compared with the input: every JSON subtree seamlit does not own equal, every attribute
//! and morph-target value per triangle corner equal, image bytes equal.

mod common;

use std::collections::BTreeSet;
use std::path::Path;

use common::gltf::{File, read};
use common::{assert_valid, fix_and_save, usize_of};
use serde_json::{Value, json};

use seamlit_io::{LoadOptions, SaveOptions};

// ---------------------------------------------------------------------------------------
// Building fixtures

/// A document under construction: its JSON and its one binary buffer.
struct Builder {
    json: Value,
    bin: Vec<u8>,
}

impl Builder {
    fn new() -> Self {
        let mut json = json!({ "asset": { "version": "2.0", "generator": "pass_through.rs", "copyright": "none" } });
        for key in ["accessors", "bufferViews", "meshes", "nodes"] {
            json[key] = json!([]);
        }
        Self { json, bin: Vec::new() }
    }

    fn push(&mut self, key: &str, value: Value) -> usize {
        let array = self.json[key].as_array_mut().unwrap();
        array.push(value);
        array.len() - 1
    }

    /// A buffer view of `bytes`, 4-byte aligned.
    fn view(&mut self, bytes: &[u8], stride: Option<usize>, target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut view =
            json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        if let Some(stride) = stride {
            view["byteStride"] = json!(stride);
        }
        if let Some(target) = target {
            view["target"] = json!(target);
        }
        self.bin.extend_from_slice(bytes);
        self.push("bufferViews", view)
    }

    /// An accessor of `count` elements of `size` bytes, stored with `stride` (padding
    /// filled with 0xEE, which no reader may see).
    fn accessor(
        &mut self,
        elements: &[Vec<u8>],
        stride: usize,
        component: u32,
        type_: &str,
        target: Option<u32>,
        extra: Value,
    ) -> usize {
        let mut bytes = Vec::new();
        for e in elements {
            bytes.extend_from_slice(e);
            bytes.resize(bytes.len() + stride - e.len(), 0xEE);
        }
        let declared = (stride != elements[0].len()).then_some(stride);
        let view = self.view(&bytes, declared, target);
        let mut accessor = json!({
            "bufferView": view, "componentType": component, "count": elements.len(), "type": type_,
        });
        for (k, v) in extra.as_object().cloned().unwrap_or_default() {
            accessor[k] = v;
        }
        self.push("accessors", accessor)
    }

    /// A float vertex attribute (buffer view target `ARRAY_BUFFER`).
    fn floats<const N: usize>(&mut self, values: &[[f32; N]], type_: &str, bounds: bool) -> usize {
        self.float_data(values, type_, bounds, Some(34962))
    }

    /// Float data (no buffer view target: skins, animations).
    fn float_data<const N: usize>(
        &mut self,
        values: &[[f32; N]],
        type_: &str,
        bounds: bool,
        target: Option<u32>,
    ) -> usize {
        let elements: Vec<Vec<u8>> =
            values.iter().map(|v| v.iter().flat_map(|x| x.to_le_bytes()).collect()).collect();
        let extra = if bounds {
            let min: Vec<f32> =
                (0..N).map(|i| values.iter().map(|v| v[i]).fold(f32::INFINITY, f32::min)).collect();
            let max: Vec<f32> = (0..N)
                .map(|i| values.iter().map(|v| v[i]).fold(f32::NEG_INFINITY, f32::max))
                .collect();
            json!({ "min": min, "max": max })
        } else {
            json!({})
        };
        self.accessor(&elements, 4 * N, 5126, type_, target, extra)
    }

    fn indices(&mut self, triangles: &[[u16; 3]]) -> usize {
        let elements: Vec<Vec<u8>> =
            triangles.as_flattened().iter().map(|i| i.to_le_bytes().to_vec()).collect();
        // Indices are packed (2 bytes each): no stride.
        let bytes: Vec<u8> = elements.concat();
        let view = self.view(&bytes, None, Some(34963));
        self.push(
            "accessors",
            json!({ "bufferView": view, "componentType": 5123, "count": elements.len(), "type": "SCALAR" }),
        )
    }

    /// Writes the document as a GLB (`.glb`) or as a `.gltf` with `NAME.bin` beside it.
    fn write(mut self, path: &Path) {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let glb = path.extension().is_some_and(|e| e == "glb");
        self.json["buffers"] = if glb {
            json!([{ "byteLength": self.bin.len() }])
        } else {
            let name = format!("{}.bin", path.file_stem().unwrap().to_string_lossy());
            std::fs::write(path.with_file_name(&name), &self.bin).unwrap();
            json!([{ "byteLength": self.bin.len(), "uri": name }])
        };
        if glb {
            std::fs::write(path, seamlit_testkit::glb(&self.json, &self.bin)).unwrap();
        } else {
            std::fs::write(path, serde_json::to_vec(&self.json).unwrap()).unwrap();
        }
    }
}

/// A fold: two unit quads meeting at a right angle along the edge from vertex 0 to vertex 3,
/// a hard edge (beyond the 60 degree crease) where fixing splits vertices 0 and 3.
const FOLD: [[f32; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 0.0, 1.0],
    [0.0, 0.0, 1.0],
    [0.0, 1.0, 0.0],
    [0.0, 1.0, 1.0],
];
const FOLD_TRIANGLES: [[u16; 3]; 4] = [[0, 3, 2], [0, 2, 1], [0, 4, 5], [0, 5, 3]];
const FOLD_UVS: [[f32; 2]; 6] =
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.25, 0.5], [0.75, 0.5]];

fn shifted(by: [f32; 3]) -> Vec<[f32; 3]> {
    FOLD.iter().map(|p| [p[0] + by[0], p[1] + by[1], p[2] + by[2]]).collect()
}

/// A fold primitive with POSITION, NORMAL (to be replaced), TEXCOORD_0 and indices.
fn fold_attributes(b: &mut Builder, positions: &[[f32; 3]]) -> (Value, usize) {
    let position = b.floats(positions, "VEC3", true);
    let normal = b.floats(&[[0.0, 1.0, 0.0]; 6], "VEC3", false);
    let uv = b.floats(&FOLD_UVS, "VEC2", false);
    let indices = b.indices(&FOLD_TRIANGLES);
    (json!({ "POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv }), indices)
}

/// A 1 x 1 PNG.
fn png() -> Vec<u8> {
    let mut bytes = Vec::new();
    image::RgbaImage::from_pixel(1, 1, image::Rgba([200, 100, 50, 255]))
        .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .unwrap();
    bytes
}

/// Bytes that start like a KTX2 file: they are passed through, never decoded.
const KTX2: &[u8] = b"\xABKTX 20\xBB\r\n\x1A\nnot a real texture, kept byte for byte";

/// The everything fixture: a skinned, animated two-primitive mesh; a morphed mesh with
/// TEXCOORD_1, COLOR_0 and `_ID` and a rich material; a mesh instanced by two nodes; a
/// camera, a light, KTX2 and PNG images, TRS and matrix nodes, extras and an unknown
/// extension.
fn everything(path: &Path) {
    everything_with(path, true);
}

/// [`everything`] without its unknown extension (`VENDOR_materials_unknown`): every index in
/// it is one the writer knows, so the data only replaced normals used may be pruned.
fn everything_known(path: &Path) {
    everything_with(path, false);
}

fn everything_with(path: &Path, unknown_extension: bool) {
    let mut b = Builder::new();
    // Mesh 0, skinned: two folds, with JOINTS_0 (u8, 4 bytes) and WEIGHTS_0.
    let mut primitives = Vec::new();
    for k in 0..2 {
        let (mut attributes, indices) =
            fold_attributes(&mut b, &shifted([0.0, 0.0, 2.0 * f32::from(k)]));
        let joints: Vec<Vec<u8>> =
            (0..6u8).map(|v| vec![(v + k) % 2, (v + k + 1) % 2, 0, 0]).collect();
        attributes["JOINTS_0"] =
            json!(b.accessor(&joints, 4, 5121, "VEC4", Some(34962), json!({})));
        let weights: Vec<[f32; 4]> = (0..6)
            .map(|v| {
                let a = 0.125 * (v + 1) as f32;
                [a, 1.0 - a, 0.0, 0.0]
            })
            .collect();
        attributes["WEIGHTS_0"] = json!(b.floats(&weights, "VEC4", false));
        primitives
            .push(json!({ "attributes": attributes, "indices": indices, "extras": { "part": k } }));
    }
    b.push("meshes", json!({ "name": "body", "primitives": primitives }));

    // Mesh 1, morphed: TEXCOORD_1 (u16 normalised), COLOR_0 (u8 normalised VEC3, stride 4),
    // `_ID` (u16, stride 4), two targets (POSITION + NORMAL; the second POSITION sparse).
    let (mut attributes, indices) = fold_attributes(&mut b, &shifted([3.0, 0.0, 0.0]));
    let uv1: Vec<Vec<u8>> = (0..6u16)
        .map(|v| [v * 1000, 65535 - v * 1000].iter().flat_map(|x| x.to_le_bytes()).collect())
        .collect();
    attributes["TEXCOORD_1"] =
        json!(b.accessor(&uv1, 4, 5123, "VEC2", Some(34962), json!({ "normalized": true })));
    let colours: Vec<Vec<u8>> = (0..6u8).map(|v| vec![v * 40, 255 - v * 40, 7]).collect();
    attributes["COLOR_0"] =
        json!(b.accessor(&colours, 4, 5121, "VEC3", Some(34962), json!({ "normalized": true })));
    let ids: Vec<Vec<u8>> = (0..6u16).map(|v| (v * 3 + 1).to_le_bytes().to_vec()).collect();
    attributes["_ID"] = json!(b.accessor(&ids, 4, 5123, "SCALAR", Some(34962), json!({})));
    let d0: Vec<[f32; 3]> = (0..6).map(|v| [0.125 * v as f32, 0.0, 0.0]).collect();
    let n0: Vec<[f32; 3]> = (0..6).map(|v| [0.0, 0.0, 0.0625 * v as f32]).collect();
    let n1: Vec<[f32; 3]> = (0..6).map(|v| [0.0625 * v as f32, 0.0, 0.0]).collect();
    let target0 =
        json!({ "POSITION": b.floats(&d0, "VEC3", true), "NORMAL": b.floats(&n0, "VEC3", false) });
    let sparse_indices = b.view(&[1u8, 4], None, None);
    let sparse_values: Vec<u8> = [[0.0f32, 0.5, 0.0], [0.25, 0.0, -0.5]]
        .as_flattened()
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let sparse_values = b.view(&sparse_values, None, None);
    let sparse = b.push(
        "accessors",
        json!({
            "componentType": 5126, "count": 6, "type": "VEC3",
            "min": [0.0, 0.0, -0.5], "max": [0.25, 0.5, 0.0],
            "sparse": {
                "count": 2,
                "indices": { "bufferView": sparse_indices, "componentType": 5121 },
                "values": { "bufferView": sparse_values },
            },
        }),
    );
    let target1 = json!({ "POSITION": sparse, "NORMAL": b.floats(&n1, "VEC3", false) });
    b.push(
        "meshes",
        json!({
            "name": "face",
            "weights": [0.5, 0.25],
            "extras": { "targetNames": ["smile", "frown"] },
            "primitives": [{
                "attributes": attributes, "indices": indices, "material": 0, "mode": 4,
                "targets": [target0, target1],
            }],
        }),
    );

    // Mesh 2, instanced by two nodes far apart.
    let (attributes, indices) = fold_attributes(&mut b, &FOLD);
    b.push("meshes", json!({ "name": "wheel", "primitives": [{ "attributes": attributes, "indices": indices }] }));

    // Skin: joints 1 and 2, inverse bind matrices.
    let ibm: Vec<[f32; 16]> = [[0.0f32, 0.0, 0.0], [0.0, -1.0, 0.0]]
        .iter()
        .map(|t| {
            let mut m = [0.0; 16];
            m[0] = 1.0;
            m[5] = 1.0;
            m[10] = 1.0;
            m[15] = 1.0;
            m[12..15].copy_from_slice(t);
            m
        })
        .collect();
    let ibm = b.float_data(&ibm, "MAT4", false, None);
    b.json["skins"] =
        json!([{ "name": "rig", "joints": [1, 2], "inverseBindMatrices": ibm, "skeleton": 1 }]);

    // Animation: node 1's rotation, two keys.
    let times = b.float_data(&[[0.0], [1.5]], "SCALAR", true, None);
    let rotations = b.float_data(
        &[[0.0, 0.0, 0.0, 1.0], [0.0, 0.707_106_77, 0.0, 0.707_106_77]],
        "VEC4",
        false,
        None,
    );
    b.json["animations"] = json!([{
        "name": "wave",
        "samplers": [{ "input": times, "output": rotations, "interpolation": "LINEAR" }],
        "channels": [{ "sampler": 0, "target": { "node": 1, "path": "rotation" } }],
    }]);

    // Images: a PNG, and KTX2 bytes for KHR_texture_basisu.
    let png = png();
    let png_view = b.view(&png, None, None);
    let ktx2_view = b.view(KTX2, None, None);
    b.json["images"] = json!([
        { "bufferView": png_view, "mimeType": "image/png", "name": "fallback" },
        { "bufferView": ktx2_view, "mimeType": "image/ktx2", "name": "basis" },
    ]);
    b.json["samplers"] =
        json!([{ "magFilter": 9729, "minFilter": 9987, "wrapS": 33648, "wrapT": 33071 }]);
    // Texture 1 has no `source`: only its extension names an image (valid glTF).
    b.json["textures"] = json!([
        { "source": 0, "sampler": 0, "extensions": { "KHR_texture_basisu": { "source": 1 } } },
        { "sampler": 0, "extensions": { "KHR_texture_basisu": { "source": 1 } } },
    ]);
    let transform = json!({ "KHR_texture_transform": { "offset": [0.25, 0.5], "rotation": 0.125, "scale": [2.0, 3.0], "texCoord": 1 } });
    b.json["materials"] = json!([{
        "name": "skin",
        "alphaMode": "BLEND",
        "doubleSided": true,
        "pbrMetallicRoughness": {
            "baseColorFactor": [0.9, 0.8, 0.7, 0.5],
            "baseColorTexture": { "index": 0, "texCoord": 1, "extensions": transform },
            "metallicFactor": 0.25,
            "roughnessFactor": 0.75,
            "metallicRoughnessTexture": { "index": 0 },
        },
        "normalTexture": { "index": 0, "scale": 0.8 },
        "occlusionTexture": { "index": 0, "strength": 0.6 },
        "emissiveTexture": { "index": 0 },
        "emissiveFactor": [0.1, 0.2, 0.3],
        "extensions": {
            "KHR_materials_clearcoat": { "clearcoatFactor": 0.5, "clearcoatTexture": { "index": 1 } },
            "KHR_materials_sheen": { "sheenColorFactor": [0.1, 0.2, 0.3], "sheenRoughnessFactor": 0.4 },
            "KHR_materials_transmission": { "transmissionFactor": 0.3 },
            "KHR_materials_ior": { "ior": 1.4 },
            "KHR_materials_emissive_strength": { "emissiveStrength": 2.5 },
            "KHR_materials_anisotropy": { "anisotropyStrength": 0.6, "anisotropyRotation": 1.0 },
            "VENDOR_materials_unknown": { "anything": [1, "two", { "three": 3.0 }] },
        },
        "extras": { "author": "pass_through.rs", "tags": ["a", "b"] },
    }]);

    b.json["cameras"] = json!([{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.01, "aspectRatio": 1.5 } }]);
    b.json["extensions"] = json!({
        "KHR_lights_punctual": { "lights": [{ "type": "spot", "color": [1.0, 0.9, 0.8], "intensity": 3.0, "spot": { "outerConeAngle": 0.7 } }] },
    });
    // Nodes: 0 the skinned mesh (its translation ignored by glTF); 1, 2 the joints (TRS,
    // matrix); 3, 4 the wheel's instances; 5 the face; 6 the camera with the light.
    b.json["nodes"] = json!([
        { "name": "body", "mesh": 0, "skin": 0, "translation": [0.0, 0.0, 7.0] },
        { "name": "hip", "translation": [0.0, 0.5, 0.0], "rotation": [0.0, 0.0, 0.0, 1.0], "scale": [1.0, 1.0, 1.0], "children": [2] },
        { "name": "knee", "matrix": [2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.1, 0.5, 0.3, 1.0] },
        { "mesh": 2, "translation": [10.0, 0.0, 0.0] },
        { "mesh": 2, "translation": [-10.0, 0.0, 0.0], "rotation": [0.0, 0.382_683_43, 0.0, 0.923_879_5] },
        { "name": "face", "mesh": 1, "weights": [0.1, 0.9], "extras": { "note": 1 } },
        { "camera": 0, "translation": [0.0, 1.0, 5.0], "extensions": { "KHR_lights_punctual": { "light": 0 } } },
    ]);
    // A scene without nodes is valid glTF (gltf-json requires the member: the loader adds it).
    b.json["scenes"] = json!([
        { "name": "main", "nodes": [0, 1, 3, 4, 5, 6], "extras": { "level": 3 } },
        { "name": "empty" },
    ]);
    b.json["scene"] = json!(0);
    b.json["extensionsUsed"] = json!([
        "KHR_texture_basisu",
        "KHR_texture_transform",
        "KHR_lights_punctual",
        "KHR_materials_clearcoat",
        "KHR_materials_sheen",
        "KHR_materials_transmission",
        "KHR_materials_ior",
        "KHR_materials_emissive_strength",
        "KHR_materials_anisotropy",
        "VENDOR_materials_unknown",
    ]);
    b.json["extensionsRequired"] = json!(["KHR_lights_punctual"]);
    if !unknown_extension {
        b.json["materials"][0]["extensions"]
            .as_object_mut()
            .unwrap()
            .remove("VENDOR_materials_unknown");
        b.json["extensionsUsed"]
            .as_array_mut()
            .unwrap()
            .retain(|e| e != "VENDOR_materials_unknown");
    }
    b.json["extras"] = json!({ "pipeline": { "stage": 2 } });
    b.write(path);
}

// ---------------------------------------------------------------------------------------
// Reading written files, independently of seamlit

impl File {
    /// A primitive's corners: its indices, or 0, 1, 2, ... without.
    fn corners(&self, primitive: &Value) -> Vec<usize> {
        match primitive["indices"].as_u64() {
            Some(a) => self
                .elements(usize_of(a))
                .iter()
                .map(|e| {
                    let mut word = [0u8; 4];
                    word[..e.len()].copy_from_slice(e);
                    u32::from_le_bytes(word) as usize
                })
                .collect(),
            None => {
                let position = primitive["attributes"]["POSITION"].as_u64().map(usize_of).unwrap();
                (0..self.json["accessors"][position]["count"].as_u64().map(usize_of).unwrap())
                    .collect()
            }
        }
    }

    /// Image `i`'s bytes, from its buffer view or its file.
    fn image(&self, i: usize) -> Vec<u8> {
        let image = &self.json["images"][i];
        match image["bufferView"].as_u64() {
            Some(view) => self.view(usize_of(view)).to_vec(),
            None => std::fs::read(self.folder.join(image["uri"].as_str().unwrap())).unwrap(),
        }
    }
}

// ---------------------------------------------------------------------------------------
// Comparing

/// Attributes seamlit owns: written new, not compared with the input.
const OWNED: [&str; 2] = ["NORMAL", "TANGENT"];

/// The document members the pass-through may change; everything else must be equal.
const CHANGED: [&str; 5] = ["accessors", "bufferViews", "buffers", "meshes", "images"];

/// Compares a written file with its input as the module docs say; returns how many vertices
/// the output has more than the input (split copies), so callers can check that the
/// fixture really split.
fn compare(input: &File, output: &File, what: &str, pruning: Pruning) -> usize {
    // Every member but those the pass-through may change, equal.
    let members = |f: &File| f.json.as_object().unwrap().keys().cloned().collect::<BTreeSet<_>>();
    assert_eq!(members(input), members(output), "{what}: top-level members");
    for key in members(input) {
        if !CHANGED.contains(&key.as_str()) {
            assert_eq!(input.json[&key], output.json[&key], "{what}: {key}");
        }
    }
    let (a, b) =
        (input.json["buffers"].as_array().unwrap(), output.json["buffers"].as_array().unwrap());
    assert_eq!(a.len(), b.len(), "{what}: buffers");
    match pruning {
        Pruning::Off => {
            // Existing accessors and buffer views: never renumbered, never changed; buffer 0
            // starts with the input's bytes.
            for key in ["accessors", "bufferViews"] {
                let (a, b) =
                    (input.json[key].as_array().unwrap(), output.json[key].as_array().unwrap());
                assert!(b.len() >= a.len(), "{what}: {key} lost entries");
                assert_eq!(&b[..a.len()], &a[..], "{what}: existing {key}");
            }
            let kept = a[0]["byteLength"].as_u64().map(usize_of).unwrap();
            assert_eq!(
                &output.buffers[0][..kept],
                &input.buffers[0][..kept],
                "{what}: buffer 0 bytes"
            );
        }
        Pruning::On => {
            // What the output uses besides its meshes (skins, animations) and what the input
            // left unused: the same index, the same JSON, the same bytes.
            let (used_in, used_out) = (References::of(&input.json), References::of(&output.json));
            let unused_in = used_in.unused(&input.json);
            let accessors: BTreeSet<usize> =
                used_in.outside_meshes.union(&unused_in.0).copied().collect();
            for &i in &accessors {
                assert_eq!(
                    input.json["accessors"][i], output.json["accessors"][i],
                    "{what}: accessor {i}"
                );
                assert_eq!(input.elements(i), output.elements(i), "{what}: accessor {i} elements");
            }
            let mut views: BTreeSet<usize> = unused_in.1.clone();
            views.extend(used_in.images.iter().copied());
            for &i in &accessors {
                views.extend(References::views_of(&input.json["accessors"][i]));
            }
            for &v in &views {
                let strip = |f: &File| {
                    let mut view = f.json["bufferViews"][v].as_object().unwrap().clone();
                    view.remove("byteOffset");
                    view
                };
                assert_eq!(strip(input), strip(output), "{what}: buffer view {v}");
                assert_eq!(input.view(v), output.view(v), "{what}: buffer view {v} bytes");
            }
            // Nothing unused but what the input left unused.
            let unused_out = used_out.unused(&output.json);
            assert!(
                unused_out.0.is_subset(&unused_in.0),
                "{what}: unused accessors {unused_out:?}, the input's {unused_in:?}"
            );
            assert!(
                unused_out.1.is_subset(&unused_in.1),
                "{what}: unused buffer views {unused_out:?}, the input's {unused_in:?}"
            );
        }
    }
    // Images: the same entries, the same bytes.
    let images = input.json["images"].as_array().map_or(0, Vec::len);
    assert_eq!(output.json["images"].as_array().map_or(0, Vec::len), images, "{what}: images");
    for i in 0..images {
        assert_eq!(input.image(i), output.image(i), "{what}: image {i} bytes");
        for key in ["name", "mimeType", "extras", "extensions"] {
            if input.json["images"][i].get(key).is_some() {
                assert_eq!(
                    input.json["images"][i][key], output.json["images"][i][key],
                    "{what}: image {i} {key}"
                );
            }
        }
    }
    // Meshes: same members but primitives; primitives the same but attributes, indices and
    // targets; every attribute and target value per corner the same.
    let meshes = input.json["meshes"].as_array().unwrap();
    let mut added = 0;
    for (m, mesh) in meshes.iter().enumerate() {
        let out_mesh = &output.json["meshes"][m];
        let strip = |v: &Value, keys: &[&str]| {
            let mut v = v.as_object().unwrap().clone();
            for k in keys {
                v.remove(*k);
            }
            v
        };
        assert_eq!(
            strip(mesh, &["primitives"]),
            strip(out_mesh, &["primitives"]),
            "{what}: mesh {m}"
        );
        let primitives = mesh["primitives"].as_array().unwrap();
        assert_eq!(primitives.len(), out_mesh["primitives"].as_array().unwrap().len());
        for (p, primitive) in primitives.iter().enumerate() {
            let out_primitive = &out_mesh["primitives"][p];
            let place = format!("{what}: mesh {m} primitive {p}");
            let changing = ["attributes", "indices", "targets"];
            assert_eq!(strip(primitive, &changing), strip(out_primitive, &changing), "{place}");
            let names = |v: &Value| v.as_object().unwrap().keys().cloned().collect::<BTreeSet<_>>();
            let mut expected = names(&primitive["attributes"]);
            // NORMAL always; TANGENT where there are texture coordinates to derive it from.
            expected.insert("NORMAL".to_owned());
            if primitive["attributes"].get("TEXCOORD_0").is_some() {
                expected.insert("TANGENT".to_owned());
            }
            assert_eq!(names(&out_primitive["attributes"]), expected, "{place}: attributes");
            let (ci, co) = (input.corners(primitive), output.corners(out_primitive));
            assert_eq!(ci.len(), co.len(), "{place}: corners");
            let count = |f: &File, p: &Value| {
                f.json["accessors"][p["attributes"]["POSITION"].as_u64().map(usize_of).unwrap()]["count"]
                    .as_u64()
                    .map(usize_of)
                    .unwrap()
            };
            added += count(output, out_primitive) - count(input, primitive);
            let same_per_corner = |a: &Value, b: &Value, name: &str| {
                let (x, y) = (
                    input.elements(a.as_u64().map(usize_of).unwrap()),
                    output.elements(b.as_u64().map(usize_of).unwrap()),
                );
                assert_eq!(y.len(), count(output, out_primitive), "{place}: {name} count");
                let used = co.iter().max().map_or(0, |&o| o + 1);
                assert!(
                    used <= y.len(),
                    "{place}: {name} has {} elements, the indices use {used}",
                    y.len()
                );
                for (k, (&i, &o)) in ci.iter().zip(&co).enumerate() {
                    assert_eq!(x[i], y[o], "{place}: {name} at corner {k} (vertex {i} -> {o})");
                }
            };
            for (name, accessor) in primitive["attributes"].as_object().unwrap() {
                if !OWNED.contains(&name.as_str()) {
                    same_per_corner(accessor, &out_primitive["attributes"][name], name);
                }
            }
            let targets = primitive["targets"].as_array().map_or(&[][..], Vec::as_slice);
            let out_targets = out_primitive["targets"].as_array().map_or(&[][..], Vec::as_slice);
            assert_eq!(targets.len(), out_targets.len(), "{place}: targets");
            for (t, (target, out_target)) in targets.iter().zip(out_targets).enumerate() {
                assert_eq!(names(target), names(out_target), "{place}: target {t} attributes");
                for (name, accessor) in target.as_object().unwrap() {
                    same_per_corner(accessor, &out_target[name], &format!("target {t} {name}"));
                }
            }
        }
    }
    added
}

/// Whether the writer may prune the input's replaced data (no unknown extension in it).
#[derive(Clone, Copy, Debug)]
enum Pruning {
    On,
    Off,
}

/// Where a document uses accessors and buffer views, read here from the specification's
/// list of places (not with the writer's code).
#[derive(Debug, Default)]
struct References {
    /// Accessors named by mesh primitives (attributes, indices, morph targets).
    meshes: BTreeSet<usize>,
    /// Accessors named elsewhere: skins, animation samplers, EXT_mesh_gpu_instancing.
    outside_meshes: BTreeSet<usize>,
    /// Buffer views named by accessors (sparse included).
    accessor_views: BTreeSet<usize>,
    /// Buffer views named by images.
    images: BTreeSet<usize>,
}

impl References {
    fn of(json: &Value) -> Self {
        let mut r = Self::default();
        let ids = |v: &Value| {
            v.as_object()
                .into_iter()
                .flatten()
                .filter_map(|(_, i)| i.as_u64())
                .map(usize_of)
                .collect::<Vec<_>>()
        };
        for mesh in json["meshes"].as_array().into_iter().flatten() {
            for p in mesh["primitives"].as_array().into_iter().flatten() {
                r.meshes.extend(ids(&p["attributes"]));
                r.meshes.extend(p["indices"].as_u64().map(usize_of));
                for t in p["targets"].as_array().into_iter().flatten() {
                    r.meshes.extend(ids(t));
                }
            }
        }
        for skin in json["skins"].as_array().into_iter().flatten() {
            r.outside_meshes.extend(skin["inverseBindMatrices"].as_u64().map(usize_of));
        }
        for animation in json["animations"].as_array().into_iter().flatten() {
            for sampler in animation["samplers"].as_array().into_iter().flatten() {
                for key in ["input", "output"] {
                    r.outside_meshes.extend(sampler[key].as_u64().map(usize_of));
                }
            }
        }
        for node in json["nodes"].as_array().into_iter().flatten() {
            r.outside_meshes
                .extend(ids(&node["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]));
        }
        for accessor in json["accessors"].as_array().into_iter().flatten() {
            r.accessor_views.extend(Self::views_of(accessor));
        }
        for image in json["images"].as_array().into_iter().flatten() {
            r.images.extend(image["bufferView"].as_u64().map(usize_of));
        }
        r
    }

    /// The buffer views an accessor reads.
    fn views_of(accessor: &Value) -> Vec<usize> {
        [
            &accessor["bufferView"],
            &accessor["sparse"]["indices"]["bufferView"],
            &accessor["sparse"]["values"]["bufferView"],
        ]
        .into_iter()
        .filter_map(Value::as_u64)
        .map(usize_of)
        .collect()
    }

    /// The accessors and buffer views nothing uses.
    fn unused(&self, json: &Value) -> (BTreeSet<usize>, BTreeSet<usize>) {
        let count = |key: &str| json[key].as_array().map_or(0, Vec::len);
        let accessors = (0..count("accessors"))
            .filter(|i| !self.meshes.contains(i) && !self.outside_meshes.contains(i))
            .collect();
        let views = (0..count("bufferViews"))
            .filter(|i| !self.accessor_views.contains(i) && !self.images.contains(i))
            .collect();
        (accessors, views)
    }
}

// ---------------------------------------------------------------------------------------
// Tests

#[test]
fn the_fixture_itself_is_valid_gltf() {
    // A control: the comparisons below mean something only if the input is valid.
    let dir = tempfile::tempdir().unwrap();
    for name in ["in.glb", "in.gltf"] {
        everything(&dir.path().join(name));
        assert_valid(&dir.path().join(name));
    }
}

/// Builds the fixture with `build` as GLB and as .gltf, fixes and saves each as GLB and as
/// .gltf, and compares every output with its input ([`compare`], `pruning`); at least the
/// fixture's 8 crease vertices must have been split, and every output must be valid. Returns
/// each (input, output) pair read back, for further checks.
fn round_trips(build: fn(&Path), pruning: Pruning) -> Vec<(File, File)> {
    let dir = tempfile::tempdir().unwrap();
    let mut pairs = Vec::new();
    for input in ["in.glb", "in.gltf"] {
        let source = dir.path().join(input);
        build(&source);
        assert_valid(&source);
        for output in ["out.glb", "out.gltf"] {
            let folder = dir.path().join(format!("{input}-{output}"));
            std::fs::create_dir(&folder).unwrap();
            let out = folder.join(output);
            let warnings = fix_and_save(&source, &out);
            assert!(warnings.is_empty(), "{warnings:?}");
            let (a, b) = (read(&source), read(&out));
            let added = compare(&a, &b, &format!("{input} -> {output}"), pruning);
            // Each fold splits its two crease vertices: 4 primitives, at least 8 copies.
            assert!(added >= 8, "{input} -> {output}: only {added} vertices were split");
            assert_valid(&out);
            pairs.push((a, b));
        }
    }
    pairs
}

#[test]
fn a_fixed_gltf_keeps_everything_seamlit_does_not_own() {
    round_trips(everything, Pruning::Off);
}

#[test]
fn the_data_only_replaced_normals_used_leaves_the_file_and_nothing_else_moves() {
    for (a, b) in round_trips(everything_known, Pruning::On) {
        // The fixture's input holds no unused data, and neither may the output.
        assert_eq!(References::of(&a.json).unused(&a.json), Default::default());
        // Buffer 0 holds no more than the input's bytes plus what the splits added: every
        // attribute of a split primitive was rewritten, so at most the input's size again
        // (with padding).
        let length = |f: &File| f.json["buffers"][0]["byteLength"].as_u64().unwrap();
        assert!(length(&b) < 2 * length(&a), "{} -> {}", length(&a), length(&b));
    }
}

#[test]
fn a_mesh_used_by_two_nodes_stays_one_mesh_when_both_got_the_same_result() {
    let dir = tempfile::tempdir().unwrap();
    let source = dir.path().join("in.glb");
    everything(&source);
    let out = dir.path().join("out.glb");
    fix_and_save(&source, &out);
    let (a, b) = (read(&source), read(&out));
    assert_eq!(
        a.json["meshes"].as_array().unwrap().len(),
        b.json["meshes"].as_array().unwrap().len()
    );
    assert_eq!(b.json["nodes"][3]["mesh"], 2);
    assert_eq!(b.json["nodes"][4]["mesh"], 2);
}

#[test]
fn a_skinned_mesh_is_welded_in_its_bind_pose_and_placed_nodes_by_their_transforms() {
    let dir = tempfile::tempdir().unwrap();
    let source = dir.path().join("in.gltf");
    everything(&source);
    let asset = seamlit_io::load(&source, &LoadOptions::GEOMETRY).unwrap();
    let named = |name: &str| asset.model.objects.iter().find(|o| o.name == name).unwrap();
    // Node 0 ("body") carries a skin: glTF ignores its translation, so its objects have no
    // transform.
    assert_eq!(named("body.0").transform, None);
    assert_eq!(named("body.1").transform, None);
    // The wheel's two instances are placed by their nodes.
    let wheels: Vec<_> = asset.model.objects.iter().filter(|o| o.name == "wheel").collect();
    assert_eq!(wheels.len(), 2);
    assert!(wheels.iter().all(|o| o.transform.is_some()));
}

/// A plain flat quad mesh used by two nodes, and beside the second a quad tilted by 30
/// degrees sharing its edge: welding smooths the second instance's edge normals, so the two
/// instances differ.
fn instances_that_differ(path: &Path) {
    let mut b = Builder::new();
    let quad = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 1.0], [0.0, 0.0, 1.0f32]];
    let position = b.floats(&quad, "VEC3", true);
    let indices = b.indices(&[[0, 3, 2], [0, 2, 1]]);
    b.push("meshes", json!({ "name": "tile", "primitives": [{ "attributes": { "POSITION": position }, "indices": indices }] }));
    let (s, c) = (0.5f32, 0.866_025_4f32);
    let tilted = [[1.0, 0.0, 0.0], [1.0 + c, s, 0.0], [1.0 + c, s, 1.0], [1.0, 0.0, 1.0f32]];
    let position = b.floats(&tilted, "VEC3", true);
    let indices = b.indices(&[[0, 3, 2], [0, 2, 1]]);
    b.push("meshes", json!({ "name": "ramp", "primitives": [{ "attributes": { "POSITION": position }, "indices": indices }] }));
    b.json["nodes"] = json!([
        { "mesh": 0, "translation": [-5.0, 0.0, 0.0] },
        { "mesh": 0 },
        { "mesh": 1 },
    ]);
    b.json["scenes"] = json!([{ "nodes": [0, 1, 2] }]);
    b.write(path);
}

#[test]
fn instances_that_got_different_normals_become_a_clone_and_the_save_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let source = dir.path().join("in.glb");
    instances_that_differ(&source);
    let out = dir.path().join("out.glb");
    let warnings = fix_and_save(&source, &out);
    assert_valid(&out);
    let (a, b) = (read(&source), read(&out));
    assert_eq!(b.json["meshes"].as_array().unwrap().len(), 3);
    assert_eq!(b.json["nodes"][0]["mesh"], 0);
    assert_eq!(b.json["nodes"][1]["mesh"], 2);
    assert_eq!(b.json["meshes"][2]["name"], "tile");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("mesh 0") && warnings[0].contains("[1]"), "{warnings:?}");
    // The two tiles' normals differ (else the clone would be pointless), and the nodes are
    // otherwise untouched.
    let normals = |mesh: usize| {
        b.elements(
            b.json["meshes"][mesh]["primitives"][0]["attributes"]["NORMAL"]
                .as_u64()
                .map(usize_of)
                .unwrap(),
        )
    };
    assert_ne!(normals(0), normals(2));
    for n in 0..3 {
        let mut node = b.json["nodes"][n].clone();
        node["mesh"] = a.json["nodes"][n]["mesh"].clone();
        assert_eq!(node, a.json["nodes"][n]);
    }
}

/// Bytes of a second buffer, kept in a file of its own.
const EXTRA: &[u8] = b"extra buffer, 32 bytes long!!!!!";

#[test]
fn the_pass_through_copies_side_files_beside_a_gltf_and_embeds_images_in_a_glb() {
    let dir = tempfile::tempdir().unwrap();
    let source = dir.path().join("in.gltf");
    everything(&source);
    // Image 1 (KTX2) moves out to a file in a subfolder; a second buffer lives in its own
    // file, with a view into it (extensions may use such views).
    let mut json: Value = serde_json::from_slice(&std::fs::read(&source).unwrap()).unwrap();
    std::fs::create_dir(dir.path().join("tex")).unwrap();
    std::fs::write(dir.path().join("tex/basis file.ktx2"), KTX2).unwrap();
    json["images"][1] =
        json!({ "uri": "tex/basis%20file.ktx2", "mimeType": "image/ktx2", "name": "basis" });
    std::fs::write(dir.path().join("extra.bin"), EXTRA).unwrap();
    json["buffers"].as_array_mut().unwrap().push(json!({ "uri": "extra.bin", "byteLength": 32 }));
    json["bufferViews"].as_array_mut().unwrap().push(json!({ "buffer": 1, "byteLength": 32 }));
    std::fs::write(&source, serde_json::to_vec(&json).unwrap()).unwrap();

    for output in ["out.gltf", "out.glb"] {
        let folder = dir.path().join(format!("{output}-folder"));
        std::fs::create_dir(&folder).unwrap();
        let out = folder.join(output);
        fix_and_save(&source, &out);
        let written = read(&out);
        assert_eq!(written.json["buffers"][1], json["buffers"][1], "{output}");
        assert_eq!(written.buffers[1], EXTRA, "{output}");
        if output.ends_with(".gltf") {
            assert_eq!(written.json["images"][1], json["images"][1]);
            assert_eq!(std::fs::read(folder.join("tex/basis file.ktx2")).unwrap(), KTX2);
        } else {
            let image = &written.json["images"][1];
            assert!(image.get("uri").is_none(), "{image}");
            assert_eq!(image["mimeType"], "image/ktx2");
            assert_eq!(image["name"], "basis");
            assert_eq!(written.image(1), KTX2);
        }
        assert_valid(&out);
    }
}

/// A long fold: a ridge of `r` vertices shared by two planes at a right angle (`3 r`
/// vertices, indices of `component` type 5121 or 5123), where fixing splits every ridge
/// vertex; and a non-indexed flat quad beside it.
fn long_fold(path: &Path, r: u16, component: u32) {
    let mut b = Builder::new();
    let mut positions = Vec::new();
    for row in 0..3 {
        for i in 0..r {
            let x = f32::from(i);
            positions.push(match row {
                0 => [x, 0.0, 0.0],
                1 => [x, 0.0, 1.0],
                _ => [x, 1.0, 0.0],
            });
        }
    }
    let mut corners: Vec<u16> = Vec::new();
    for i in 0..r - 1 {
        let (ridge, a, b) = (i, r + i, 2 * r + i);
        corners.extend([ridge, a, a + 1, ridge, a + 1, ridge + 1]);
        corners.extend([ridge, ridge + 1, b + 1, ridge, b + 1, b]);
    }
    let position = b.floats(&positions, "VEC3", true);
    let elements: Vec<Vec<u8>> = corners
        .iter()
        .map(|&c| {
            if component == 5121 {
                vec![u8::try_from(c).unwrap()]
            } else {
                c.to_le_bytes().to_vec()
            }
        })
        .collect();
    let view = b.view(&elements.concat(), None, Some(34963));
    let indices = b.push(
        "accessors",
        json!({ "bufferView": view, "componentType": component, "count": corners.len(), "type": "SCALAR" }),
    );
    b.push(
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": position }, "indices": indices }] }),
    );
    let quad = [
        [0.0, 5.0, 0.0],
        [0.0, 5.0, 1.0],
        [1.0, 5.0, 1.0],
        [0.0, 5.0, 0.0],
        [1.0, 5.0, 1.0],
        [1.0, 5.0, 0.0f32],
    ];
    let position = b.floats(&quad, "VEC3", true);
    b.push("meshes", json!({ "primitives": [{ "attributes": { "POSITION": position } }] }));
    b.json["nodes"] = json!([{ "mesh": 0 }, { "mesh": 1 }]);
    b.json["scenes"] = json!([{ "nodes": [0, 1] }]);
    b.write(path);
}

#[test]
fn indices_keep_their_type_where_the_split_vertices_fit_and_widen_to_u32_where_not() {
    let dir = tempfile::tempdir().unwrap();
    // 85 ridge vertices: 255 vertices in, 340 out.
    for (component, expected) in [(5121, 5125), (5123, 5123)] {
        let source = dir.path().join(format!("fold{component}.glb"));
        long_fold(&source, 85, component);
        assert_valid(&source);
        let out = dir.path().join(format!("out{component}.glb"));
        fix_and_save(&source, &out);
        let (a, b) = (read(&source), read(&out));
        let indices =
            b.json["meshes"][0]["primitives"][0]["indices"].as_u64().map(usize_of).unwrap();
        assert_eq!(b.json["accessors"][indices]["componentType"], expected, "{component}");
        assert_eq!(compare(&a, &b, &format!("u{component}"), Pruning::On), 85);
        assert_valid(&out);
        // The non-indexed quad has nothing to split and stays non-indexed.
        assert!(b.json["meshes"][1]["primitives"][0].get("indices").is_none());
    }
}

#[test]
fn a_model_that_no_longer_matches_its_source_goes_to_the_generic_writer_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let source = dir.path().join("in.glb");
    everything(&source);
    let mut asset = seamlit_io::load(&source, &LoadOptions::GEOMETRY).unwrap();
    asset.model.objects.pop();
    let out = dir.path().join("out.glb");
    let report = seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap();
    assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
    assert!(report.warnings[0].contains("generic"), "{:?}", report.warnings);
    // The generic writer's layout: one mesh per object, no skin.
    let written = read(&out);
    assert_eq!(written.json["meshes"].as_array().unwrap().len(), asset.model.objects.len());
    assert!(written.json.get("skins").is_none());
    assert_valid(&out);
}
