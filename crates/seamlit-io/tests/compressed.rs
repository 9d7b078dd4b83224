//! Quantised and compressed glTF geometry (issue 11): KHR_mesh_quantization and
//! EXT_meshopt_compression are read, and so is KHR_draco_mesh_compression with the `draco`
//! feature; the pass-through writes them back readable by a viewer without a meshopt or
//! Draco decoder.
//!
//! The inputs are the Newell teapot (32 objects) made by gltfpack three ways from one
//! textured GLB (assets/models/SOURCES.md): `teapot_noq.glb` uncompressed (floats),
//! `teapot_q.glb` quantised, `teapot_mo.glb` quantised and meshopt-compressed; and
//! `teapot_draco.glb`, the uncompressed one through glTF-Transform's `draco`. This file reads
//! glTF with its own small accessor reader (serde_json and byte slices), never with the
//! loader under test, except where the loader's result is what is checked.

mod common;

use std::path::{Path, PathBuf};

use common::gltf::{File, component_size, read};
use common::{assert_valid, f32_of, fix_and_save, usize_of};
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
#[cfg(feature = "draco")]
use seamlit_io::Draco;
use seamlit_io::{GltfKind, IoError, KeepCompression, LoadOptions, Meshopt};
use seamlit_mesh::FixOptions;
use serde_json::Value;

fn model(name: &str) -> PathBuf {
    common::model(&format!("compressed/{name}"))
}

// ---------------------------------------------------------------------------------------
// An independent reader: the document, its buffers, and per-corner attribute values.

/// A component of an accessor element: (raw bits for exact comparison, value as the glTF
/// specification converts it).
fn component(bytes: &[u8], component_type: u64, normalized: bool) -> (u32, f32) {
    let n = normalized;
    match component_type {
        5120 => {
            let c = bytes[0] as i8;
            (c as u32, if n { (f32::from(c) / 127.0).max(-1.0) } else { f32::from(c) })
        }
        5121 => (u32::from(bytes[0]), f32::from(bytes[0]) / if n { 255.0 } else { 1.0 }),
        5122 => {
            let c = i16::from_le_bytes([bytes[0], bytes[1]]);
            (c as u32, if n { (f32::from(c) / 32767.0).max(-1.0) } else { f32::from(c) })
        }
        5123 => {
            let c = u16::from_le_bytes([bytes[0], bytes[1]]);
            (u32::from(c), f32::from(c) / if n { 65535.0 } else { 1.0 })
        }
        5125 => {
            let c = u32::from_le_bytes(bytes[..4].try_into().unwrap());
            (c, c as f32)
        }
        5126 => {
            let c = f32::from_le_bytes(bytes[..4].try_into().unwrap());
            (c.to_bits(), c)
        }
        other => panic!("componentType {other}"),
    }
}

/// An accessor's elements: per element, its components (raw bits, value). Refuses what this
/// reader does not implement (sparse storage, compressed views), so that a test never
/// compares zeros.
fn elements(file: &File, index: u64) -> Elements {
    let accessor = &file.json["accessors"][usize_of(index)];
    assert!(accessor.get("sparse").is_none(), "accessor {index} is sparse");
    let view = &file.json["bufferViews"][accessor["bufferView"].as_u64().map(usize_of).unwrap()];
    assert!(view.get("extensions").is_none(), "accessor {index}: its view has extensions");
    let component_type = accessor["componentType"].as_u64().unwrap();
    let size = component_size(component_type);
    let n = match accessor["type"].as_str().unwrap() {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        other => panic!("type {other}"),
    };
    let normalized = accessor["normalized"].as_bool().unwrap_or(false);
    let stride = view["byteStride"].as_u64().map_or(n * size, usize_of);
    let buffer = &file.buffers[view["buffer"].as_u64().map(usize_of).unwrap()];
    let start = view["byteOffset"].as_u64().map_or(0, usize_of)
        + accessor["byteOffset"].as_u64().map_or(0, usize_of);
    (0..accessor["count"].as_u64().map(usize_of).unwrap())
        .map(|k| {
            (0..n)
                .map(|c| {
                    let at = start + k * stride + c * size;
                    component(&buffer[at..at + size], component_type, normalized)
                })
                .collect()
        })
        .collect()
}

/// Per element, its components (raw bits, value).
type Elements = Vec<Vec<(u32, f32)>>;

/// A node's local matrix (TRS or matrix).
fn local(node: &Value) -> Mat4 {
    let floats = |key: &str| -> Option<Vec<f32>> {
        Some(node.get(key)?.as_array()?.iter().map(|v| f32_of(v.as_f64().unwrap())).collect())
    };
    if let Some(m) = floats("matrix") {
        return Mat4::from_cols_slice(&m);
    }
    let t = floats("translation").map_or(Vec3::ZERO, |t| Vec3::from_slice(&t));
    let r = floats("rotation").map_or(Quat::IDENTITY, |r| Quat::from_slice(&r));
    let s = floats("scale").map_or(Vec3::ONE, |s| Vec3::from_slice(&s));
    Mat4::from_scale_rotation_translation(s, r, t)
}

/// One corner of a triangle: the raw components and values of each attribute it has.
#[derive(Debug)]
struct Corner {
    /// Model-space position.
    position: Vec3,
    /// Per attribute name: (raw bits, values).
    attributes: Vec<(String, Vec<(u32, f32)>)>,
}

impl Corner {
    fn raw(&self, name: &str) -> Vec<u32> {
        self.get(name).iter().map(|c| c.0).collect()
    }
    fn values(&self, name: &str) -> Vec<f32> {
        self.get(name).iter().map(|c| c.1).collect()
    }
    fn get(&self, name: &str) -> &[(u32, f32)] {
        let found = self.attributes.iter().find(|(n, _)| n == name);
        found.map_or(&[], |(_, v)| v.as_slice())
    }
}

/// Every corner of every triangle of every mesh instance of the scene, in scene order (depth
/// first), with its position in model space.
fn corners(file: &File) -> Vec<Corner> {
    let json = &file.json;
    let mut out = Vec::new();
    let scene = &json["scenes"][json["scene"].as_u64().map_or(0, usize_of)];
    let mut stack: Vec<(u64, Mat4)> = scene["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .rev()
        .map(|n| (n.as_u64().unwrap(), Mat4::IDENTITY))
        .collect();
    while let Some((index, parent)) = stack.pop() {
        let node = &json["nodes"][usize_of(index)];
        let global = parent * local(node);
        if let Some(mesh) = node["mesh"].as_u64() {
            for primitive in json["meshes"][usize_of(mesh)]["primitives"].as_array().unwrap() {
                let attributes: Vec<(String, Elements)> = primitive["attributes"]
                    .as_object()
                    .unwrap()
                    .iter()
                    .map(|(name, a)| (name.clone(), elements(file, a.as_u64().unwrap())))
                    .collect();
                let count = attributes[0].1.len();
                let indices: Vec<usize> = match primitive["indices"].as_u64() {
                    Some(a) => elements(file, a).iter().map(|e| e[0].0 as usize).collect(),
                    None => (0..count).collect(),
                };
                for i in indices {
                    let position = attributes.iter().find(|(n, _)| n == "POSITION").unwrap();
                    let p = &position.1[i];
                    let position = global.transform_point3(Vec3::new(p[0].1, p[1].1, p[2].1));
                    let attributes =
                        attributes.iter().map(|(n, e)| (n.clone(), e[i].clone())).collect();
                    out.push(Corner { position, attributes });
                }
            }
        }
        let children = node["children"].as_array().into_iter().flatten().rev();
        stack.extend(children.map(|c| (c.as_u64().unwrap(), global)));
    }
    out
}

/// The KHR_texture_transform of material 0's base colour texture: (offset, scale), the
/// identity when there is none.
fn uv_transform(file: &File) -> (Vec2, Vec2) {
    let t = &file.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"];
    let pair = |key: &str, default: f32| {
        t.get(key).map_or(Vec2::splat(default), |v| {
            Vec2::new(f32_of(v[0].as_f64().unwrap()), f32_of(v[1].as_f64().unwrap()))
        })
    };
    (pair("offset", 0.0), pair("scale", 1.0))
}

/// The quantisation step of the positions of `teapot_q.glb`: the scale gltfpack puts on
/// every mesh node (one integer unit in model space).
fn position_step(file: &File) -> f32 {
    let step = f32_of(file.json["nodes"][0]["scale"][0].as_f64().unwrap());
    assert!(step > 0.0 && step < 1e-3, "step {step}");
    step
}

/// One UV step of gltfpack's default 12-bit texture coordinates.
const UV_STEP: f32 = 1.0 / 4095.0;

/// A corner as the tolerant comparison sees it: model-space position, texture coordinates
/// (texture transform applied), normal.
#[derive(Clone, Copy, Debug)]
struct Point {
    position: Vec3,
    uv: Vec2,
    normal: Vec3,
}

/// The points of a file's corners, its texture transform applied to the UVs.
fn points(file: &File) -> Vec<Point> {
    let (offset, scale) = if file.json.get("materials").is_some() {
        uv_transform(file)
    } else {
        (Vec2::ZERO, Vec2::ONE)
    };
    corners(file)
        .iter()
        .map(|c| Point {
            position: c.position,
            uv: offset + scale * Vec2::from_slice(&c.values("TEXCOORD_0")),
            normal: Vec3::from_slice(&c.values("NORMAL")),
        })
        .collect()
}

/// Pairs each triangle of `actual` with a triangle of `expected` (each used once) whose
/// corners, in some rotation, lie within `step` in position and [`UV_STEP`] in UV; returns
/// the pairs of corners. gltfpack orders triangles and vertices its own way (meshopt
/// compression reorders them again), so triangles are matched, not indexed.
fn match_triangles(actual: &[Point], expected: &[Point], step: f32) -> Vec<(Point, Point)> {
    match_within(actual, expected, step, UV_STEP)
}

/// [`match_triangles`] within `uv_step` in UV.
fn match_within(
    actual: &[Point],
    expected: &[Point],
    step: f32,
    uv_step: f32,
) -> Vec<(Point, Point)> {
    assert_eq!(actual.len(), expected.len(), "corner counts");
    let close = |a: &Point, b: &Point| {
        (a.position - b.position).abs().max_element() <= step
            && (a.uv - b.uv).abs().max_element() <= uv_step
    };
    let mut used = vec![false; expected.len() / 3];
    let mut pairs = Vec::with_capacity(actual.len());
    for (t, a) in actual.as_chunks::<3>().0.iter().enumerate() {
        let found = expected.as_chunks::<3>().0.iter().enumerate().find_map(|(u, e)| {
            let rotation = (0..3).find(|r| (0..3).all(|i| close(&a[i], &e[(i + r) % 3])))?;
            (!used[u]).then_some((u, rotation))
        });
        let Some((u, r)) = found else {
            panic!("triangle {t} {a:?} has no match within {step}");
        };
        used[u] = true;
        let e = &expected[3 * u..3 * u + 3];
        pairs.extend((0..3).map(|i| (a[i], e[(i + r) % 3])));
    }
    pairs
}

// ---------------------------------------------------------------------------------------
// Tests

#[test]
fn the_inputs_are_valid_and_the_quantised_one_is_the_original_within_its_steps() {
    // Controls: the comparisons below mean something only if the inputs are valid and the
    // quantised file holds the original's triangles within its steps.
    let names = ["teapot_noq.glb", "teapot_q.glb", "teapot_mo.glb", "teapot_mo_filters.glb"];
    for name in names.into_iter().chain(["teapot_mo_khr.glb"]) {
        assert_valid(&model(name));
    }
    let original = read(&model("teapot_noq.glb"));
    let quantised = read(&model("teapot_q.glb"));
    assert!(quantised.json["extensionsRequired"].to_string().contains("KHR_mesh_quantization"));
    assert_eq!(points(&original).len(), 3072);
    match_triangles(&points(&quantised), &points(&original), position_step(&quantised));
}

#[test]
fn quantised_and_meshopt_geometry_loads_as_the_original_within_its_steps() {
    let original = points(&read(&model("teapot_noq.glb")));
    let step = position_step(&read(&model("teapot_q.glb")));
    // teapot_mo_filters.glb: float positions and UVs through the EXPONENTIAL filter,
    // normals and tangents through OCTAHEDRAL; teapot_mo_khr.glb: KHR_meshopt_compression.
    let names = ["teapot_q.glb", "teapot_mo.glb", "teapot_mo_filters.glb", "teapot_mo_khr.glb"];
    for name in names {
        let (offset, scale) = uv_transform(&read(&model(name)));
        let asset = seamlit_io::load(&model(name), &LoadOptions::GEOMETRY).unwrap();
        assert_eq!(asset.model.objects.len(), 32, "{name}");
        let mut loaded = Vec::new();
        for object in &asset.model.objects {
            let m = object.model_transform();
            let (uvs, normals) = (object.uvs.as_ref().unwrap(), object.normals.as_ref().unwrap());
            for &v in object.triangles.as_flattened() {
                let v = v as usize;
                loaded.push(Point {
                    position: m.transform_point3(object.positions[v]),
                    uv: offset + scale * uvs[v],
                    normal: normals[v],
                });
            }
        }
        for (a, e) in match_triangles(&loaded, &original, step) {
            // 8-bit normals, read as unit vectors: within a degree or so of the original's.
            assert!((a.normal.length() - 1.0).abs() < 1e-5, "{name}: {a:?}");
            assert!(a.normal.dot(e.normal) > 0.999, "{name}: {a:?} {e:?}");
        }
    }
}

#[test]
fn a_fixed_quantised_file_keeps_its_integers_and_gets_float_frames() {
    let dir = tempfile::tempdir().unwrap();
    let source = model("teapot_q.glb");
    let input = read(&source);
    let before = corners(&input);
    for output in ["out.glb", "out.gltf"] {
        let out = dir.path().join(output);
        let warnings = fix_and_save(&source, &out);
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_valid(&out);
        let written = read(&out);
        for key in ["extensionsUsed", "extensionsRequired", "materials", "nodes", "scenes"] {
            assert_eq!(input.json[key], written.json[key], "{output}: {key}");
        }
        let after = corners(&written);
        assert_eq!(before.len(), after.len());
        for (k, (a, b)) in before.iter().zip(&after).enumerate() {
            // Quantised POSITION and TEXCOORD_0: the same integers, per corner.
            for name in ["POSITION", "TEXCOORD_0"] {
                assert_eq!(a.raw(name), b.raw(name), "{output} corner {k} {name}");
            }
            let n = Vec3::from_slice(&b.values("NORMAL"));
            let t = Vec4::from_slice(&b.values("TANGENT"));
            assert!((n.length() - 1.0).abs() < 1e-5, "{output} corner {k}: normal {n}");
            assert!((t.truncate().length() - 1.0).abs() < 1e-5, "{output} corner {k}: {t}");
            assert!(t.w.abs() == 1.0, "{output} corner {k}: {t}");
        }
        // New frames are floats (KHR_mesh_quantization allows both).
        let primitive = &written.json["meshes"][0]["primitives"][0]["attributes"];
        for name in ["NORMAL", "TANGENT"] {
            let accessor =
                &written.json["accessors"][primitive[name].as_u64().map(usize_of).unwrap()];
            assert_eq!(accessor["componentType"], 5126, "{output} {name}");
        }
    }
}

#[test]
fn a_meshopt_file_is_written_uncompressed_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let quantised = dir.path().join("q.glb");
    fix_and_save(&model("teapot_q.glb"), &quantised);
    let reference = points(&read(&quantised));
    let inputs = [
        ("teapot_mo.glb", "EXT_meshopt_compression"),
        ("teapot_mo_khr.glb", "KHR_meshopt_compression"),
    ];
    for ((input, extension), output) in
        inputs.iter().flat_map(|i| ["out.glb", "out.gltf"].map(|o| (i, o)))
    {
        let out = dir.path().join(output);
        let warnings = fix_and_save(&model(input), &out);
        assert!(
            warnings.len() == 1
                && warnings[0].contains(input)
                && warnings[0].contains(extension)
                && warnings[0].contains("uncompressed"),
            "{warnings:?}"
        );
        assert_valid(&out);
        let written = read(&out);
        let text = written.json.to_string();
        assert!(!text.contains("meshopt"), "{input} -> {output}: {text}");
        assert!(text.contains("KHR_mesh_quantization"), "{output}");
        // The fallback buffer (no data of its own) is gone: one buffer holds every view.
        assert_eq!(written.json["buffers"].as_array().unwrap().len(), 1, "{output}");
        // The same model as the fix of its uncompressed twin: every triangle there, with
        // the same quantised values (exactly) and normals (up to summation order).
        let after = points(&written);
        for (a, e) in match_triangles(&after, &reference, 0.0) {
            assert!(a.normal.dot(e.normal) > 1.0 - 1e-6, "{output}: {a:?} {e:?}");
        }
    }
}

/// `teapot_mo.glb` with its JSON changed by `edit`, written to `dir`.
fn edited_meshopt(dir: &Path, edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> PathBuf {
    edited_glb(&model("teapot_mo.glb"), &dir.join("edited.glb"), edit)
}

/// The GLB `source` with its JSON and BIN chunk changed by `edit`, written to `path`.
fn edited_glb(source: &Path, path: &Path, edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> PathBuf {
    let bytes = std::fs::read(source).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let mut json: Value = serde_json::from_slice(&bytes[20..20 + length]).unwrap();
    let mut bin = bytes[20 + length + 8..].to_vec();
    edit(&mut json, &mut bin);
    std::fs::write(path, seamlit_testkit::glb(&json, &bin)).unwrap();
    path.to_path_buf()
}

/// The EXT_meshopt_compression object of buffer view 1 (view 0 is the texture).
fn view_1(json: &mut Value) -> &mut Value {
    &mut json["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]
}

/// Whether an error's kind is the one a case expects.
type Expected<Kind> = fn(&Kind) -> bool;

#[test]
fn malformed_meshopt_views_are_refused_naming_the_view() {
    let dir = tempfile::tempdir().unwrap();
    let refused = |what: &str, path: PathBuf, expected: Expected<Meshopt>| match seamlit_io::load(
        &path,
        &LoadOptions::GEOMETRY,
    ) {
        Err(IoError::Gltf { path: p, place, kind: GltfKind::Meshopt(kind) }) => {
            let at = "bufferViews[1].extensions.EXT_meshopt_compression";
            assert_eq!((p, place.as_str()), (path, at), "{what}: {kind}");
            assert!(expected(&kind), "{what}: {kind:?}");
        }
        other => panic!("{what}: {other:?}"),
    };
    let edits: [(&str, &str, Value, Expected<Meshopt>); 4] = [
        (
            "an unknown mode",
            "mode",
            "FAN".into(),
            |kind| matches!(kind, Meshopt::UnknownMode { found: Some(mode) } if mode == "FAN"),
        ),
        (
            "a stride ATTRIBUTES does not allow",
            "byteStride",
            6.into(),
            |kind| matches!(kind, Meshopt::StrideNotAllowed { stride: 6, mode, .. } if mode == "ATTRIBUTES"),
        ),
        ("bytes outside the buffer", "byteLength", 1_000_000.into(), |kind| {
            matches!(kind, Meshopt::CompressedOutside { buffer: 0, .. })
        }),
        // Refused before the decoder allocates a trillion elements.
        ("more elements than the view holds", "count", 1_000_000_000_000_u64.into(), |kind| {
            matches!(kind, Meshopt::LengthMismatch { count: 1_000_000_000_000, .. })
        }),
    ];
    for (what, key, value, expected) in edits {
        refused(what, edited_meshopt(dir.path(), |json, _| view_1(json)[key] = value), expected);
    }
    // The vertex codec's header byte (0xa0 | version) made unknown.
    let garbage = edited_meshopt(dir.path(), |json, bin| {
        let at = view_1(json)["byteOffset"].as_u64().unwrap();
        bin[usize_of(at)] = 0x00;
    });
    refused("a corrupt header", garbage, |kind| matches!(kind, Meshopt::Refused { .. }));
}

#[cfg(not(feature = "draco"))]
#[test]
fn without_the_draco_feature_draco_geometry_is_refused_naming_the_primitive_and_a_way_out() {
    let path = model("teapot_draco.glb");
    let error = seamlit_io::load(&path, &LoadOptions::GEOMETRY).unwrap_err();
    assert_eq!(error.to_string().lines().count(), 1, "{error}");
    let IoError::Gltf { path: p, place, kind: GltfKind::NoDracoDecoder { file } } = &error else {
        panic!("{error:?}")
    };
    assert_eq!((p, file), (&path, &path));
    assert_eq!(place, "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression");
    assert!(error.to_string().contains("gltf-transform/cli copy"), "{error}");
}

/// The Draco teapot's tolerances, from what glTF-Transform's `draco` command quantises by
/// default: positions to 14 bits over each primitive's largest extent (the POSITION
/// accessors' `min` and `max`, written from the original data), texture coordinates to 12
/// bits over theirs (at most 1 in the original file: measured here). One step each, twice
/// the rounding error.
#[cfg(feature = "draco")]
fn draco_steps(original: &[Point]) -> (f32, f32) {
    let draco = read(&model("teapot_draco.glb"));
    let mut extent = 0.0f32;
    for accessor in draco.json["accessors"].as_array().unwrap() {
        if let (Some(min), Some(max)) = (accessor["min"].as_array(), accessor["max"].as_array()) {
            for (a, b) in min.iter().zip(max) {
                extent = extent.max(f32_of(b.as_f64().unwrap() - a.as_f64().unwrap()));
            }
        }
    }
    let uvs = original.iter().map(|p| p.uv);
    let (low, high) = uvs.fold((Vec2::MAX, Vec2::MIN), |(l, h), uv| (l.min(uv), h.max(uv)));
    assert!(extent > 1.0 && (high - low).max_element() <= 1.0, "{extent} {low} {high}");
    (extent / 16383.0, (high - low).max_element() / 4095.0)
}

#[cfg(feature = "draco")]
#[test]
fn draco_geometry_loads_as_the_original_within_its_steps() {
    let original = without_degenerate(points(&read(&model("teapot_noq.glb"))));
    // The 32 patches' poles: one degenerate triangle each.
    assert_eq!(original.len(), 3072 - 32 * 3);
    let (step, uv_step) = draco_steps(&original);
    let asset = seamlit_io::load(&model("teapot_draco.glb"), &LoadOptions::GEOMETRY).unwrap();
    assert_eq!(asset.model.objects.len(), 32);
    let mut loaded = Vec::new();
    for object in &asset.model.objects {
        let (uvs, normals) = (object.uvs.as_ref().unwrap(), object.normals.as_ref().unwrap());
        for &v in object.triangles.as_flattened() {
            let v = v as usize;
            let position = object.model_transform().transform_point3(object.positions[v]);
            loaded.push(Point { position, uv: uvs[v], normal: normals[v] });
        }
    }
    // Every triangle of the original, corner by corner, once: the indices too.
    for (a, e) in match_within(&loaded, &original, step, uv_step) {
        // 10-bit octahedral normals: within a few tenths of a degree.
        assert!(a.normal.dot(e.normal) > 0.9999, "{a:?} {e:?}");
    }
}

#[cfg(feature = "draco")]
#[test]
fn a_draco_file_is_written_uncompressed_valid_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let input = model("teapot_draco.glb");
    let original = without_degenerate(points(&read(&model("teapot_noq.glb"))));
    let (step, uv_step) = draco_steps(&original);
    for output in ["out.glb", "out.gltf"] {
        let out = dir.path().join(output);
        let warnings = fix_and_save(&input, &out);
        assert!(
            warnings.len() == 1
                && warnings[0].contains("teapot_draco.glb")
                && warnings[0].contains("32 primitives compressed with KHR_draco_mesh_compression")
                && warnings[0].contains("uncompressed"),
            "{warnings:?}"
        );
        assert_valid(&out);
        let written = read(&out);
        let text = written.json.to_string().to_lowercase();
        assert!(!text.contains("draco"), "{output}: {text}");
        // The compressed streams' views and the decoded data the fix replaced are given to
        // the new data (pruning): every view is used, and the buffer holds the views' bytes
        // and their padding only (the streams' bytes are gone).
        let json = &written.json;
        let views = json["bufferViews"].as_array().unwrap();
        let used: std::collections::BTreeSet<u64> = json["accessors"]
            .as_array()
            .unwrap()
            .iter()
            .chain(json["images"].as_array().unwrap())
            .filter_map(|item| item["bufferView"].as_u64())
            .collect();
        assert_eq!(used, (0..views.len() as u64).collect(), "{output}: a view nothing uses");
        let held: u64 =
            views.iter().map(|v| v["byteLength"].as_u64().unwrap().next_multiple_of(4)).sum();
        let buffer = json["buffers"][0]["byteLength"].as_u64().unwrap();
        assert!(buffer <= held, "{output}: {buffer} bytes for views of {held}");
        // The written corners are the original's, within the quantisation steps.
        let after = points(&written);
        for (a, e) in match_within(&after, &original, step, uv_step) {
            assert!((a.normal.length() - 1.0).abs() < 1e-5, "{output}: {a:?}");
            assert!(a.normal.dot(e.normal) > 0.99, "{output}: {a:?} {e:?}");
        }
    }
}

/// The points of the triangles of `points` that are not degenerate (no two corners at one
/// position): Draco's encoder drops the degenerate ones.
#[cfg(feature = "draco")]
fn without_degenerate(points: Vec<Point>) -> Vec<Point> {
    let kept = points.as_chunks::<3>().0.iter().filter(|t| {
        t[0].position != t[1].position
            && t[1].position != t[2].position
            && t[2].position != t[0].position
    });
    kept.flatten().copied().collect()
}

/// `teapot_draco.glb` with its GLB rebuilt after `edit` changed its JSON and BIN chunk.
#[cfg(feature = "draco")]
fn edited_draco(dir: &Path, name: &str, edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> PathBuf {
    edited_glb(&model("teapot_draco.glb"), &dir.join(name), edit)
}

#[cfg(feature = "draco")]
#[test]
fn corrupt_draco_streams_fail_with_an_error_naming_the_primitive_never_a_panic() {
    // Truncated streams (the view cut short) and streams with one byte flipped: each file
    // must load or give an error naming its primitive, never panic (a panic in the decoder
    // is caught: `gltf/decode/draco.rs`). A smoke test beside the checks, not a guard of one
    // of them.
    let dir = tempfile::tempdir().unwrap();
    let json = read(&model("teapot_draco.glb")).json;
    let place = "meshes[3].primitives[0].extensions.KHR_draco_mesh_compression";
    let view =
        json["meshes"][3]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"]
            .as_u64()
            .map(usize_of)
            .unwrap();
    let start = json["bufferViews"][view]["byteOffset"].as_u64().map(usize_of).unwrap();
    let length = json["bufferViews"][view]["byteLength"].as_u64().map(usize_of).unwrap();
    let (mut loaded, mut refused) = (0, 0);
    let mut outcome = |path: PathBuf| match seamlit_io::load(&path, &LoadOptions::GEOMETRY) {
        Ok(_) => loaded += 1,
        Err(error @ IoError::Gltf { kind: GltfKind::Draco(_), .. }) => {
            let IoError::Gltf { place: p, .. } = &error else { unreachable!() };
            assert_eq!(p, place, "{error}");
            assert_eq!(error.to_string().lines().count(), 1, "{error}");
            refused += 1;
        }
        Err(other) => panic!("{other}"),
    };
    for cut in (0..length).step_by(7) {
        outcome(edited_draco(dir.path(), "cut.glb", |json, _| {
            json["bufferViews"][view]["byteLength"] = cut.into();
        }));
    }
    for at in (start..start + length).step_by(3) {
        for flip in [0xff, 0x01] {
            outcome(edited_draco(dir.path(), "flipped.glb", |_, bin| bin[at] ^= flip));
        }
    }
    assert!(refused >= length / 7, "{loaded} loaded, {refused} refused");
    assert!(loaded + refused > 400, "{loaded} loaded, {refused} refused");
}

/// A change to a document.
#[cfg(feature = "draco")]
type Edit = Box<dyn Fn(&mut Value)>;

/// The KHR_draco_mesh_compression object of mesh 0's primitive.
#[cfg(feature = "draco")]
fn draco_of_0(json: &mut Value) -> &mut Value {
    &mut json["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]
}

#[cfg(feature = "draco")]
#[test]
fn a_draco_stream_that_does_not_hold_what_its_accessors_declare_is_refused() {
    let dir = tempfile::tempdir().unwrap();

    let edits: [(&str, Edit, Expected<Draco>); 5] = [
        ("more points", Box::new(|json| json["accessors"][1]["count"] = 31.into()), |kind| {
            matches!(kind, Draco::AttributeMismatch { count: 30, accessor: 1, declared: 31, .. })
        }),
        ("another type", Box::new(|json| json["accessors"][4]["type"] = "VEC3".into()), |kind| {
            matches!(
                kind,
                Draco::AttributeMismatch { name, components: 2, declared_components: 3, .. }
                    if name == "TEXCOORD_0"
            )
        }),
        (
            "integers",
            Box::new(|json| json["accessors"][2]["componentType"] = 5122.into()),
            |kind| {
                matches!(
                    kind,
                    Draco::AttributeMismatch { name, component_type: 5122, .. } if name == "NORMAL"
                )
            },
        ),
        ("more corners", Box::new(|json| json["accessors"][0]["count"] = 99.into()), |kind| {
            matches!(kind, Draco::CornerCount { corners: 96, accessor: 0, declared: 99 })
        }),
        (
            "an unknown id",
            Box::new(|json| draco_of_0(json)["attributes"]["NORMAL"] = 9.into()),
            |kind| matches!(kind, Draco::NoSuchId { name, id: 9 } if name == "NORMAL"),
        ),
    ];
    for (what, edit, expected) in edits {
        let path = edited_draco(dir.path(), "edited.glb", |json, _| edit(json));
        let error = seamlit_io::load(&path, &LoadOptions::GEOMETRY).unwrap_err();
        let IoError::Gltf { place, kind: GltfKind::Draco(kind), .. } = &error else {
            panic!("{what}: {error:?}")
        };
        assert_eq!(
            place, "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression",
            "{what}"
        );
        assert!(expected(kind), "{what}: {kind:?}");
    }
}

#[test]
fn a_fallback_buffer_that_cannot_be_removed_gets_its_bytes() {
    // A buffer after the fallback one: removing the fallback would renumber it.
    let dir = tempfile::tempdir().unwrap();
    let input = edited_meshopt(dir.path(), |json, _| {
        let buffers = json["buffers"].as_array_mut().unwrap();
        buffers.push(serde_json::json!({ "byteLength": 4, "uri": "data:application/octet-stream;base64,AAAAAA==" }));
    });
    let out = dir.path().join("out.glb");
    fix_and_save(&input, &out);
    assert_valid(&out);
    let written = read(&out);
    let buffers = written.json["buffers"].as_array().unwrap();
    assert_eq!(buffers.len(), 3);
    assert!(buffers[1]["uri"].as_str().unwrap().starts_with("data:"), "{}", buffers[1]);
    assert_eq!(written.buffers[1].len(), 25164);
    assert!(!written.json.to_string().contains("EXT_meshopt_compression"));
}

#[test]
fn corrupt_meshopt_data_loads_or_fails_cleanly() {
    // Every 31st byte of the compressed data, one at a time, set to 0xff: each file must load
    // or fail with an error (garbage indices and values are caught by the loader's checks),
    // never panic. A smoke test beside the fuzz targets, not a guard of one check.
    let dir = tempfile::tempdir().unwrap();
    for name in ["teapot_mo.glb", "teapot_mo_filters.glb"] {
        let bytes = std::fs::read(model(name)).unwrap();
        let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let json: Value = serde_json::from_slice(&bytes[20..20 + length]).unwrap();
        let views = json["bufferViews"].as_array().unwrap();
        let (mut loaded, mut refused) = (0, 0);
        for extension in views.iter().filter_map(|v| v["extensions"].get("EXT_meshopt_compression"))
        {
            let start = 20 + length + 8 + extension["byteOffset"].as_u64().map(usize_of).unwrap();
            let end = start + extension["byteLength"].as_u64().map(usize_of).unwrap();
            for at in (start..end).step_by(31) {
                let mut corrupt = bytes.clone();
                corrupt[at] = 0xff;
                let path = dir.path().join("corrupt.glb");
                std::fs::write(&path, corrupt).unwrap();
                match seamlit_io::load(&path, &LoadOptions::GEOMETRY) {
                    Ok(_) => loaded += 1,
                    Err(_) => refused += 1,
                }
            }
        }
        assert!(loaded + refused > 250, "{name}: {loaded} + {refused}");
    }
}

// ---------------------------------------------------------------------------------------
// Keeping meshopt compression (`SaveOptions::keep_compression`).

/// Loads `input`, fixes it with the default options, saves it as `output` keeping the
/// compression; returns the save's warnings.
fn fix_and_keep(input: &Path, output: &Path) -> Result<Vec<String>, IoError> {
    fix_with(input, output, &FixOptions::default(), true)
}

/// Loads `input`, fixes it with `options`, saves it as `output`, keeping the compression
/// or not; returns the save's warnings.
fn fix_with(
    input: &Path,
    output: &Path,
    options: &FixOptions,
    keep_compression: bool,
) -> Result<Vec<String>, IoError> {
    let mut asset = seamlit_io::load(input, &LoadOptions::GEOMETRY).unwrap();
    seamlit_mesh::fix_in_place(&mut asset.model, options).unwrap();
    let save = seamlit_io::SaveOptions { keep_compression, ..Default::default() };
    seamlit_io::save(&asset, output, &save).map(|report| report.warnings)
}

/// The default fix, and one that splits vertices (flat normals computed anew: 2097 of the
/// teapot's vertices are split), so that every attribute gets a new view.
fn fixes() -> [(&'static str, FixOptions); 2] {
    let split = FixOptions {
        normals: seamlit_mesh::NormalPolicy::Recompute,
        ..FixOptions::default().with_mode(seamlit_mesh::Mode::Flat)
    };
    [("default", FixOptions::default()), ("flat", split)]
}

/// The meshopt extension object of a buffer or buffer view, with its name.
fn meshopt_of(item: &Value) -> Option<(&str, &Value)> {
    item["extensions"]
        .as_object()?
        .iter()
        .find(|(name, _)| name.ends_with("_meshopt_compression"))
        .map(|(name, e)| (name.as_str(), e))
}

/// `file` with every meshopt-compressed view decoded into the bytes the view names (filters
/// applied) and its extension removed, so that [`elements`] reads it: this test's own
/// decoder, on the `meshopt` crate, apart from the loader's.
fn decoded(mut file: File) -> File {
    let views = file.json["bufferViews"].as_array().unwrap().clone();
    for (index, view) in views.iter().enumerate() {
        let Some((_, e)) = meshopt_of(view) else { continue };
        let field = |key: &str| usize_of(e[key].as_u64().unwrap());
        let start = usize_of(e["byteOffset"].as_u64().unwrap_or(0));
        let data = &file.buffers[field("buffer")][start..start + field("byteLength")];
        let (count, stride) = (field("count"), field("byteStride"));
        let plain = decode_view(data, count, stride, e["mode"].as_str().unwrap(), &e["filter"]);
        assert_eq!(plain.len(), usize_of(view["byteLength"].as_u64().unwrap()), "view {index}");
        let target = &mut file.buffers[usize_of(view["buffer"].as_u64().unwrap())];
        let at = usize_of(view["byteOffset"].as_u64().unwrap_or(0));
        if target.len() < at + plain.len() {
            target.resize(at + plain.len(), 0);
        }
        target[at..at + plain.len()].copy_from_slice(&plain);
        file.json["bufferViews"][index].as_object_mut().unwrap().remove("extensions");
    }
    file
}

/// One compressed view's plain bytes (the modes and filters the test files use).
fn decode_view(data: &[u8], count: usize, stride: usize, mode: &str, filter: &Value) -> Vec<u8> {
    let words = |v: Vec<u32>, size: usize| -> Vec<u8> {
        v.into_iter().flat_map(|i| i.to_le_bytes().into_iter().take(size)).collect()
    };
    match mode {
        "TRIANGLES" => words(meshopt::decode_index_buffer::<u32>(data, count).unwrap(), stride),
        "INDICES" => words(meshopt::decode_index_sequence::<u32>(data, count).unwrap(), stride),
        _ => {
            let mut plain = decode_vertices(data, count, stride);
            match filter.as_str().unwrap_or("NONE") {
                "NONE" => {}
                "OCTAHEDRAL" if stride == 4 => {
                    let mut v: Vec<[i8; 4]> = bytemuck::pod_collect_to_vec(&plain);
                    meshopt::decode_filter_oct(&mut v);
                    plain = bytemuck::cast_slice(&v).to_vec();
                }
                "OCTAHEDRAL" => {
                    let mut v: Vec<[i16; 4]> = bytemuck::pod_collect_to_vec(&plain);
                    meshopt::decode_filter_oct(&mut v);
                    plain = bytemuck::cast_slice(&v).to_vec();
                }
                "EXPONENTIAL" => {
                    let mut v: Vec<[u32; 1]> = bytemuck::pod_collect_to_vec(&plain);
                    meshopt::decode_filter_exp(&mut v);
                    plain = bytemuck::cast_slice(&v).to_vec();
                }
                other => panic!("filter {other} (no test file has it)"),
            }
            plain
        }
    }
}

/// `count` vertices of `stride` bytes (the strides the test files and seamlit's new views
/// have) through meshoptimizer's vertex decoder.
fn decode_vertices(data: &[u8], count: usize, stride: usize) -> Vec<u8> {
    fn with<const N: usize>(data: &[u8], count: usize) -> Vec<u8>
    where
        [u8; N]: Default,
    {
        meshopt::decode_vertex_buffer::<[u8; N]>(data, count).unwrap().concat()
    }
    match stride {
        4 => with::<4>(data, count),
        8 => with::<8>(data, count),
        12 => with::<12>(data, count),
        16 => with::<16>(data, count),
        other => panic!("byteStride {other} (no test file has it)"),
    }
}

/// The inputs that keep their compression, with the extension each uses.
const MESHOPT_INPUTS: [(&str, &str); 3] = [
    ("teapot_mo.glb", "EXT_meshopt_compression"),
    ("teapot_mo_khr.glb", "KHR_meshopt_compression"),
    ("teapot_mo_filters.glb", "EXT_meshopt_compression"),
];

#[test]
fn kept_compression_decodes_to_the_uncompressed_output_bit_for_bit_and_is_smaller() {
    let dir = tempfile::tempdir().unwrap();
    let cases = MESHOPT_INPUTS.iter().flat_map(|i| ["glb", "gltf"].map(|o| (i, o)));
    for (((input, extension), output), (fix, options)) in
        cases.flat_map(|c| fixes().map(|f| (c, f)))
    {
        let plain = dir.path().join(format!("plain.{output}"));
        let kept = dir.path().join(format!("kept.{output}"));
        fix_with(&model(input), &plain, &options, false).unwrap();
        let warnings = fix_with(&model(input), &kept, &options, true).unwrap();
        let what = format!("{input} -> {output}, {fix} fix");
        assert!(
            warnings.len() == 1
                && warnings[0].contains(input)
                && warnings[0].contains(&format!("5 buffer views compressed with {extension}"))
                && warnings[0].contains("kept compressed")
                && warnings[0].contains("new views"),
            "{what}: {warnings:?}"
        );
        assert_valid(&kept);
        // (a) Every accessor, decoded by this file's own reader, holds the bits of the
        // uncompressed output's.
        let (plain_file, kept_file) = (read(&plain), decoded(read(&kept)));
        let count = plain_file.json["accessors"].as_array().unwrap().len();
        assert_eq!(kept_file.json["accessors"].as_array().unwrap().len(), count, "{what}");
        for a in 0..count as u64 {
            let bits = |f: &File| -> Vec<Vec<u32>> {
                elements(f, a).into_iter().map(|e| e.into_iter().map(|c| c.0).collect()).collect()
            };
            assert_eq!(bits(&kept_file), bits(&plain_file), "{what}: accessor {a}");
        }
        // And seamlit's own loader reads the same model from both.
        let load = |p: &Path| seamlit_io::load(p, &LoadOptions::GEOMETRY).unwrap().model;
        assert!(load(&kept) == load(&plain), "{what}: the loaded models differ");
        // (b) Smaller than the uncompressed output (JSON, buffer and .bin together).
        let size = |p: &Path| {
            let bin = p.with_extension("bin");
            std::fs::metadata(p).unwrap().len() + std::fs::metadata(bin).map_or(0, |m| m.len())
        };
        assert!(size(&kept) < size(&plain), "{what}: {} >= {}", size(&kept), size(&plain));
    }
}

#[test]
fn kept_compression_keeps_the_untouched_views_bytes_and_filters() {
    // (c) teapot_mo_filters.glb: positions and UVs through EXPONENTIAL, normals and tangents
    // through OCTAHEDRAL. The views the fix did not replace (positions, UVs) are still used
    // and hold the input's compressed bytes, mode and filter, verbatim.
    let dir = tempfile::tempdir().unwrap();
    let input = model("teapot_mo_filters.glb");
    let out = dir.path().join("kept.glb");
    fix_and_keep(&input, &out).unwrap();
    let (before, after) = (read(&input), read(&out));
    let compressed_bytes = |file: &File, e: &Value| -> Vec<u8> {
        let start = usize_of(e["byteOffset"].as_u64().unwrap_or(0));
        let buffer = &file.buffers[usize_of(e["buffer"].as_u64().unwrap())];
        buffer[start..start + usize_of(e["byteLength"].as_u64().unwrap())].to_vec()
    };
    let used: Vec<u64> = after.json["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|m| m["primitives"].as_array().unwrap())
        .flat_map(|p| p["attributes"].as_object().unwrap().values())
        .filter_map(|a| {
            after.json["accessors"][usize_of(a.as_u64().unwrap())]["bufferView"].as_u64()
        })
        .collect();
    let mut filtered = Vec::new();
    for (index, view) in before.json["bufferViews"].as_array().unwrap().iter().enumerate() {
        let Some((name, e)) = meshopt_of(view) else { continue };
        if !used.contains(&(index as u64)) {
            continue;
        }
        let (_, kept) = meshopt_of(&after.json["bufferViews"][index])
            .unwrap_or_else(|| panic!("view {index} lost {name}"));
        for key in ["mode", "filter", "byteStride", "count", "byteLength"] {
            assert_eq!(kept[key], e[key], "view {index}: {key}");
        }
        assert_eq!(compressed_bytes(&after, kept), compressed_bytes(&before, e), "view {index}");
        filtered.extend(e["filter"].as_str().map(str::to_owned));
    }
    filtered.sort();
    assert_eq!(filtered, ["EXPONENTIAL", "EXPONENTIAL"], "positions and UVs, still used");
}

#[test]
fn kept_compression_has_the_fallback_buffer_and_requires_the_extension() {
    // (d) Every compressed view names a fallback buffer (no uri, `fallback: true`) long
    // enough for it; its compressed bytes lie in a buffer with data; the extension is
    // used and required.
    let dir = tempfile::tempdir().unwrap();
    for (input, extension) in MESHOPT_INPUTS {
        let out = dir.path().join("kept.gltf");
        fix_and_keep(&model(input), &out).unwrap();
        let file = read(&out);
        let buffers = file.json["buffers"].as_array().unwrap();
        let mut new_views = 0;
        for (index, view) in file.json["bufferViews"].as_array().unwrap().iter().enumerate() {
            let Some((name, e)) = meshopt_of(view) else { continue };
            assert_eq!(name, extension, "view {index}");
            let fallback = &buffers[usize_of(view["buffer"].as_u64().unwrap())];
            assert!(fallback.get("uri").is_none(), "view {index}: {fallback}");
            assert_eq!(fallback["extensions"][extension]["fallback"], true, "view {index}");
            let end =
                view["byteOffset"].as_u64().unwrap_or(0) + view["byteLength"].as_u64().unwrap();
            assert!(end <= fallback["byteLength"].as_u64().unwrap(), "view {index}");
            let data = &buffers[usize_of(e["buffer"].as_u64().unwrap())];
            assert!(data["uri"].is_string(), "view {index}: its data buffer {data}");
            new_views += usize::from(e.get("filter").is_none() && index >= 6);
        }
        // One per layout: normals (12-byte stride), tangents (16), 16-bit indices.
        assert_eq!(new_views, 3, "{input}: new compressed views");
        for list in ["extensionsUsed", "extensionsRequired"] {
            assert!(
                file.json[list].as_array().unwrap().iter().any(|n| n == extension),
                "{input}: {list}"
            );
        }
    }
}

#[test]
fn keeping_the_compression_of_an_uncompressed_input_changes_nothing_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let (plain, kept) = (dir.path().join("plain.glb"), dir.path().join("kept.glb"));
    fix_and_save(&model("teapot_q.glb"), &plain);
    let warnings = fix_and_keep(&model("teapot_q.glb"), &kept).unwrap();
    assert!(
        warnings.len() == 1
            && warnings[0].contains("teapot_q.glb")
            && warnings[0].contains("changes nothing"),
        "{warnings:?}"
    );
    assert_eq!(std::fs::read(&kept).unwrap(), std::fs::read(&plain).unwrap());
}

#[cfg(feature = "draco")]
#[test]
fn keeping_draco_compression_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.glb");
    match fix_and_keep(&model("teapot_draco.glb"), &out) {
        Err(IoError::CannotKeepCompression {
            path,
            kind: KeepCompression::Draco { primitive },
        }) => {
            assert!(path.ends_with("teapot_draco.glb"), "{}", path.display());
            assert_eq!(primitive, "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing written");
}

#[test]
fn keeping_the_compression_in_an_obj_output_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("out.obj");
    match fix_and_keep(&model("teapot_mo.glb"), &obj) {
        Err(IoError::CannotKeepCompression { path, kind: KeepCompression::ObjOutput }) => {
            assert_eq!(path, obj);
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing written");
}
