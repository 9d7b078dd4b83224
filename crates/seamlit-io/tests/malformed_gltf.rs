//! Malformed glTF and GLB files made by the test: each gets the precise error (file, and the
//! accessor, buffer, view or JSON place) and no panic.

use std::path::{Path, PathBuf};

use seamlit_io::{BadAccessor, BadUri, Glb, GltfKind, IoError, LoadOptions, SaveOptions};
use serde_json::{Value, json};

/// A valid one-triangle glTF document: buffer 0 is a data URI holding 3 positions
/// (36 bytes) and 3 u16 indices (6 bytes + 2 padding).
fn triangle(positions: [f32; 9], indices: [u16; 3]) -> Value {
    let mut bytes: Vec<u8> = positions.iter().flat_map(|x| x.to_le_bytes()).collect();
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    bytes.extend([0, 0]);
    json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "name": "tri", "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
              "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0] },
            { "bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR" }
        ],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 36 },
            { "buffer": 0, "byteOffset": 36, "byteLength": 6 }
        ],
        "buffers": [{ "byteLength": 44, "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&bytes)) }]
    })
}

const POSITIONS: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

fn write(dir: &Path, name: &str, document: &Value) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec(document).unwrap()).unwrap();
    path
}

fn load(path: &Path) -> IoError {
    seamlit_io::load(path, &LoadOptions::default()).unwrap_err()
}

#[test]
fn the_fixture_itself_loads() {
    let dir = tempfile::tempdir().unwrap();
    let asset = seamlit_io::load(
        &write(dir.path(), "ok.gltf", &triangle(POSITIONS, [0, 1, 2])),
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(asset.model.objects.len(), 1);
    assert_eq!(asset.model.objects[0].name, "tri");
    assert_eq!(asset.model.objects[0].triangles, [[0, 1, 2]]);
}

#[test]
fn truncated_glb() {
    let dir = tempfile::tempdir().unwrap();
    let asset = seamlit_io::load(
        &write(dir.path(), "ok.gltf", &triangle(POSITIONS, [0, 1, 2])),
        &LoadOptions::default(),
    )
    .unwrap();
    let glb = dir.path().join("whole.glb");
    seamlit_io::save(&asset, &glb, &SaveOptions::default()).unwrap();
    let bytes = std::fs::read(&glb).unwrap();
    for cut in [0, 7, 12, 30, bytes.len() / 2, bytes.len() - 1] {
        let path = dir.path().join(format!("cut{cut}.glb"));
        std::fs::write(&path, &bytes[..cut]).unwrap();
        let err = load(&path);
        match &err {
            IoError::Gltf { path: p, place, kind } => {
                assert_eq!(p, &path);
                if cut >= 4 {
                    assert_eq!(place, "GLB container", "{err}");
                    assert!(
                        matches!(
                            kind,
                            GltfKind::Glb(
                                Glb::ShortHeader { .. }
                                    | Glb::Truncated { .. }
                                    | Glb::ShortChunkHeader { .. }
                                    | Glb::ShortChunk { .. }
                            )
                        ),
                        "{err}"
                    );
                }
            }
            other => panic!("cut at {cut}: unexpected {other}"),
        }
    }
    // The header's own length says how much is missing.
    let err = load(&dir.path().join(format!("cut{}.glb", bytes.len() - 1)));
    let (declared, have) = (bytes.len(), bytes.len() - 1);
    assert!(
        matches!(
            err,
            IoError::Gltf { kind: GltfKind::Glb(Glb::Truncated { declared: d, bytes: b }), .. }
                if (d, b) == (declared, have)
        ),
        "{err}"
    );
}

#[test]
fn accessor_out_of_range() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["accessors"][0]["count"] = json!(4);
    let err = load(&write(dir.path(), "acc.gltf", &doc));
    assert!(
        matches!(
            err,
            IoError::Gltf {
                kind: GltfKind::AccessorOutOfRange {
                    accessor: 0,
                    view: 0,
                    needed: 48,
                    available: 36,
                    ..
                },
                ..
            }
        ),
        "{err}"
    );
    // An offset pushing the index accessor past its view.
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["accessors"][1]["byteOffset"] = json!(2);
    let err = load(&write(dir.path(), "offset.gltf", &doc));
    assert!(
        matches!(
            err,
            IoError::Gltf {
                kind: GltfKind::AccessorOutOfRange {
                    accessor: 1,
                    view: 1,
                    needed: 8,
                    available: 6,
                    ..
                },
                ..
            }
        ),
        "{err}"
    );
    // A view past its buffer.
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["bufferViews"][1]["byteLength"] = json!(600);
    let err = load(&write(dir.path(), "view.gltf", &doc));
    match &err {
        IoError::Gltf { place, kind, .. } => {
            assert_eq!(place, "bufferViews[1]");
            assert!(
                matches!(kind, GltfKind::ViewOutsideBuffer { end: 636, buffer: 0, available: 44 }),
                "{err}"
            );
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn index_out_of_range() {
    let dir = tempfile::tempdir().unwrap();
    let err = load(&write(dir.path(), "index.gltf", &triangle(POSITIONS, [0, 1, 7])));
    assert!(
        matches!(
            err,
            IoError::Gltf {
                kind: GltfKind::IndexOutOfRange {
                    mesh: 0,
                    primitive: 0,
                    accessor: 1,
                    index: 7,
                    vertex_count: 3,
                    ..
                },
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn huge_declared_counts() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["accessors"][0]["count"] = json!(4_000_000_000u64);
    let err = load(&write(dir.path(), "count.gltf", &doc));
    assert!(matches!(err, IoError::TooManyElements { actual: 4_000_000_000, .. }), "{err}");
    // Below the element limit, the accessor still has to fit its view.
    let options = LoadOptions { max_elements: usize::MAX, ..LoadOptions::default() };
    let err = seamlit_io::load(&dir.path().join("count.gltf"), &options).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::Gltf {
                kind: GltfKind::AccessorOutOfRange { accessor: 0, available: 36, .. },
                ..
            }
        ),
        "{err}"
    );
    // A buffer that declares more bytes than it holds.
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["buffers"][0]["byteLength"] = json!(1u64 << 40);
    let err = load(&write(dir.path(), "buffer.gltf", &doc));
    assert!(
        matches!(
            err,
            IoError::Gltf {
                kind: GltfKind::BufferLength {
                    buffer: 0,
                    expected: 1_099_511_627_776,
                    actual: 44,
                    ..
                },
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn nan_positions() {
    let dir = tempfile::tempdir().unwrap();
    let mut positions = POSITIONS;
    positions[4] = f32::NAN;
    let err = load(&write(dir.path(), "nan.gltf", &triangle(positions, [0, 1, 2])));
    assert!(
        matches!(
            err,
            IoError::Gltf {
                kind: GltfKind::AccessorNotFinite {
                    accessor: 0,
                    attribute: "POSITION",
                    element: 1,
                    ..
                },
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn uris_outside_the_folder_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("model")).unwrap();
    std::fs::write(dir.path().join("secret.bin"), [0u8; 44]).unwrap();
    for (uri, kind) in [
        ("../secret.bin", BadUri::LeavesFolder),
        ("sub/../../secret.bin", BadUri::LeavesFolder),
        ("%2E%2E/secret.bin", BadUri::LeavesFolder),
        ("/etc/passwd", BadUri::Absolute),
        ("C:/Windows/win.ini", BadUri::Absolute),
        ("https://example.invalid/x.bin", BadUri::NotRelative),
    ] {
        let mut doc = triangle(POSITIONS, [0, 1, 2]);
        doc["buffers"][0]["uri"] = json!(uri);
        let err = load(&write(&dir.path().join("model"), "uri.gltf", &doc));
        match &err {
            IoError::BadUri { what, uri: u, kind: k, .. } => {
                assert_eq!((what.as_str(), u.as_str(), *k), ("buffer 0", uri, kind), "{err}");
            }
            other => panic!("{uri}: unexpected {other}"),
        }
    }
    // An image URI too.
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["images"] = json!([{ "uri": "../albedo.png" }]);
    let err = load(&write(&dir.path().join("model"), "image.gltf", &doc));
    assert!(matches!(&err, IoError::BadUri { what, .. } if what == "image 0"), "{err}");
}

#[test]
fn missing_buffer_file_and_missing_texture() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["buffers"][0]["uri"] = json!("nowhere.bin");
    let err = load(&write(dir.path(), "buf.gltf", &doc));
    assert!(
        matches!(&err, IoError::MissingFile { missing, what, .. } if missing.ends_with("nowhere.bin") && what == "buffer 0"),
        "{err}"
    );
    // A missing image is a warning and a neutral default, never a crash.
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["images"] = json!([{ "uri": "albedo.png" }]);
    doc["textures"] = json!([{ "source": 0 }]);
    doc["materials"] = json!([{ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } } }]);
    doc["meshes"][0]["primitives"][0]["material"] = json!(0);
    let asset =
        seamlit_io::load(&write(dir.path(), "tex.gltf", &doc), &LoadOptions::default()).unwrap();
    assert!(asset.textures[0].image.is_none());
    assert_eq!(asset.warnings.len(), 1);
    assert!(asset.warnings[0].contains("albedo.png"), "{:?}", asset.warnings);
}

#[test]
fn invalid_documents_name_the_json_place() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["meshes"][0]["primitives"][0]["indices"] = json!(99);
    let err = load(&write(dir.path(), "ref.gltf", &doc));
    assert!(
        matches!(
            &err,
            IoError::Gltf { place, kind: GltfKind::Validation { .. }, .. }
                if place.contains("meshes[0].primitives[0].indices")
        ),
        "{err}"
    );
    // Broken JSON names the line and column.
    let path = dir.path().join("broken.gltf");
    std::fs::write(&path, "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"nodes\": [,]\n}").unwrap();
    let err = load(&path);
    assert!(
        matches!(
            &err,
            IoError::Gltf { place, kind: GltfKind::Json { source }, .. }
                if place.starts_with("JSON line 3") && source.is_syntax()
        ),
        "{err}"
    );
    // A node that is its own child.
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["nodes"][0]["children"] = json!([0]);
    let err = load(&write(dir.path(), "cycle.gltf", &doc));
    assert!(
        matches!(&err, IoError::Gltf { place, kind: GltfKind::NodeReachedTwice, .. } if place == "nodes[0]"),
        "{err}"
    );
    // A POSITION accessor of the wrong type.
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["accessors"][0]["type"] = json!("VEC2");
    let err = load(&write(dir.path(), "type.gltf", &doc));
    assert!(
        matches!(
            &err,
            IoError::Gltf { kind: GltfKind::Accessor { accessor: 0, kind }, .. }
                if matches!(&**kind, BadAccessor::WrongType { attribute, .. } if attribute == "POSITION")
        ),
        "{err}"
    );
}

#[test]
fn a_mesh_used_by_two_nodes_is_two_objects() {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = triangle(POSITIONS, [0, 1, 2]);
    doc["nodes"] = json!([
        { "name": "root", "children": [1, 2], "translation": [0.0, 0.0, 5.0] },
        { "name": "left", "mesh": 0, "translation": [-2.0, 0.0, 0.0] },
        { "name": "right", "mesh": 0, "scale": [2.0, 2.0, 2.0] }
    ]);
    let asset =
        seamlit_io::load(&write(dir.path(), "two.gltf", &doc), &LoadOptions::default()).unwrap();
    let names: Vec<&str> = asset.model.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["left", "right"]);
    // Transforms composed by hand: root (0,0,5) then left (-2,0,0); root then scale 2.
    let left = asset.model.objects[0].model_transform();
    assert_eq!(
        left.transform_point3(glam::Vec3::new(1.0, 0.0, 0.0)),
        glam::Vec3::new(-1.0, 0.0, 5.0)
    );
    let right = asset.model.objects[1].model_transform();
    assert_eq!(
        right.transform_point3(glam::Vec3::new(1.0, 0.0, 0.0)),
        glam::Vec3::new(2.0, 0.0, 5.0)
    );
    assert_eq!(asset.nodes.len(), 3);
    assert_eq!(asset.nodes[1].parent, Some(0));
}

#[test]
fn required_extensions_are_read_unless_they_change_how_vertices_are_stored() {
    let dir = tempfile::tempdir().unwrap();
    let mut document = triangle(POSITIONS, [0, 1, 2]);
    document["extensionsUsed"] = json!(["KHR_lights_punctual", "VENDOR_anything"]);
    document["extensionsRequired"] = json!(["KHR_lights_punctual", "VENDOR_anything"]);
    let path = write(dir.path(), "lights.gltf", &document);
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(asset.model.objects.len(), 1);
    // Decoded (tests/compressed.rs): a file that requires them is read.
    for extension in ["EXT_meshopt_compression", "KHR_mesh_quantization"] {
        document["extensionsUsed"] = json!(["KHR_lights_punctual", extension]);
        document["extensionsRequired"] = json!(["KHR_lights_punctual", extension]);
        let path = write(dir.path(), "decoded.gltf", &document);
        assert!(seamlit_io::load(&path, &LoadOptions::default()).is_ok(), "{extension}");
    }
    // Decoded with the `draco` feature, refused without it.
    document["extensionsUsed"] = json!(["KHR_lights_punctual", "KHR_draco_mesh_compression"]);
    document["extensionsRequired"] = json!(["KHR_lights_punctual", "KHR_draco_mesh_compression"]);
    let path = write(dir.path(), "compressed.gltf", &document);
    if cfg!(feature = "draco") {
        assert!(seamlit_io::load(&path, &LoadOptions::default()).is_ok());
    } else {
        let err = load(&path);
        assert!(
            matches!(
                &err,
                IoError::Gltf { place, kind: GltfKind::UnsupportedExtension { extension }, .. }
                    if place == "extensionsRequired[1]" && extension == "KHR_draco_mesh_compression"
            ),
            "{err}"
        );
    }
}

#[test]
fn a_scene_without_nodes_is_an_empty_scene() {
    let dir = tempfile::tempdir().unwrap();
    let mut document = triangle(POSITIONS, [0, 1, 2]);
    document["scenes"] = json!([{ "nodes": [0] }, { "name": "empty" }]);
    let path = write(dir.path(), "scenes.gltf", &document);
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(asset.model.objects.len(), 1);
    document["scene"] = json!(1);
    let path = write(dir.path(), "empty.gltf", &document);
    // The glTF reader accepts it (the validator does); `seamlit_io::load`, which every command
    // uses, refuses a model with nothing to fix.
    let asset = seamlit_io::gltf::load(&path, &LoadOptions::default()).unwrap();
    assert!(asset.model.objects.is_empty());
    assert!(matches!(
        seamlit_io::load(&path, &LoadOptions::default()),
        Err(IoError::NoTriangles { .. })
    ));
}

#[test]
fn whole_numbers_written_as_floats_are_integers() {
    let dir = tempfile::tempdir().unwrap();
    let document = triangle(POSITIONS, [0, 1, 2]);
    // Every integer of the document written as a float: `"count": 3.0`, `"mesh": 0.0`...
    let text = serde_json::to_string(&document).unwrap();
    let floats = with_integers_as_floats(&text);
    assert!(floats.contains("\"count\":3.0"), "{floats}");
    let path = dir.path().join("floats.gltf");
    std::fs::write(&path, &floats).unwrap();
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(asset.model.objects[0].triangles, [[0, 1, 2]]);
    // The pass-through reads them too, and writes them back as they were.
    let out = dir.path().join("out.gltf");
    let report = seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap();
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    let written: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(written["accessors"][0]["count"], json!(3.0));
    assert_eq!(written["nodes"][0]["mesh"], json!(0.0));
}

/// `text` with every integer outside strings written as a float (`3` -> `3.0`).
fn with_integers_as_floats(text: &str) -> String {
    let mut out = String::new();
    let (mut in_string, mut escaped, mut number) = (false, false, String::new());
    for c in text.chars() {
        if in_string {
            out.push(c);
            in_string = escaped || c != '"';
            escaped = !escaped && c == '\\';
            continue;
        }
        if c.is_ascii_digit() || c == '-' || c == '.' || c == 'e' || c == 'E' || c == '+' {
            number.push(c);
            continue;
        }
        if !number.is_empty() {
            out.push_str(&number);
            if !number.contains(['.', 'e', 'E']) {
                out.push_str(".0");
            }
            number.clear();
        }
        in_string = c == '"';
        out.push(c);
    }
    out
}

#[test]
fn a_percent_encoded_data_uri_is_read_like_a_base64_one() {
    let dir = tempfile::tempdir().unwrap();
    let mut document = triangle(POSITIONS, [0, 1, 2]);
    let uri = document["buffers"][0]["uri"].as_str().unwrap().to_owned();
    let base64 = uri.split_once(',').unwrap().1;
    let bytes = base64::decode(base64).unwrap();
    // Every byte percent-encoded (RFC 2397 without `;base64`).
    let encoded: String = bytes.iter().map(|b| format!("%{b:02X}")).collect();
    document["buffers"][0]["uri"] = json!(format!("data:application/octet-stream,{encoded}"));
    let path = write(dir.path(), "percent.gltf", &document);
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    let positions: Vec<f32> =
        asset.model.objects[0].positions.iter().flat_map(|p| p.to_array()).collect();
    assert_eq!(positions, POSITIONS);
    assert_eq!(asset.model.objects[0].triangles, [[0, 1, 2]]);
}

/// The fixture with four meshes over its buffer, each made by `primitive(mesh)`, reached
/// through four nodes: node `k` holds mesh `order[k]`.
fn four_meshes(order: [usize; 4], primitive: impl Fn(usize) -> Value) -> Value {
    let mut document = triangle(POSITIONS, [0, 1, 2]);
    document["meshes"] = (0..4).map(|m| json!({ "primitives": [primitive(m)] })).collect();
    document["nodes"] =
        order.iter().map(|&m| json!({ "name": format!("n{m}"), "mesh": m })).collect();
    document["scenes"] = json!([{ "nodes": [0, 1, 2, 3] }]);
    document
}

/// Primitives are decoded on several threads ahead of the scene walk; what the walk says is
/// still in its order: the warnings of skipped primitives (the walk's own) and of decoding
/// (a primitive without POSITION) interleaved as the nodes are reached.
#[test]
fn warnings_come_in_the_order_the_nodes_are_reached() {
    let dir = tempfile::tempdir().unwrap();
    let document = four_meshes([2, 1, 3, 0], |m| match m {
        0 => json!({ "attributes": { "POSITION": 0 }, "indices": 1 }),
        1 => json!({ "attributes": { "POSITION": 0 }, "mode": 0 }),
        _ => json!({ "attributes": { "NORMAL": 0 } }),
    });
    let asset =
        seamlit_io::load(&write(dir.path(), "order.gltf", &document), &LoadOptions::default())
            .unwrap();
    let said: Vec<String> =
        asset.warnings.iter().map(|w| w.split(": ").nth(1).unwrap_or(w).to_owned()).collect();
    assert_eq!(
        said,
        [
            "mesh 2 primitive 0 has no POSITION; skipped",
            "mesh 1 primitive 0",
            "mesh 3 primitive 0 has no POSITION; skipped",
        ]
        .map(str::to_owned),
        "{:?}",
        asset.warnings
    );
    assert_eq!(asset.model.objects.len(), 1);
}

/// Of two primitives with a bad index, the error is the one of the first node's mesh, as a
/// walk decoding one primitive after another gives it.
#[test]
fn the_first_error_is_the_first_reached_primitives() {
    let dir = tempfile::tempdir().unwrap();
    for first in [0, 3] {
        let order = if first == 0 { [0, 3, 1, 2] } else { [3, 0, 1, 2] };
        let mut document = four_meshes(order, |m| match m {
            0 | 3 => json!({ "attributes": { "POSITION": 0 }, "indices": 2 + m / 3 }),
            _ => json!({ "attributes": { "POSITION": 0 }, "indices": 1 }),
        });
        // Accessors 2 and 3: the indices 0, 1, 7 (out of range), as the fixture stores them.
        let bad = triangle(POSITIONS, [0, 1, 7]);
        let buffer = bad["buffers"][0].clone();
        document["buffers"].as_array_mut().unwrap().push(buffer);
        document["bufferViews"]
            .as_array_mut()
            .unwrap()
            .push(json!({ "buffer": 1, "byteOffset": 36, "byteLength": 6 }));
        for _ in 0..2 {
            let accessor =
                json!({ "bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR" });
            document["accessors"].as_array_mut().unwrap().push(accessor);
        }
        let err = load(&write(dir.path(), "first.gltf", &document));
        assert!(
            matches!(
                err,
                IoError::Gltf { kind: GltfKind::IndexOutOfRange { mesh, index: 7, .. }, .. }
                    if mesh == first
            ),
            "first {first}: {err}"
        );
    }
}
