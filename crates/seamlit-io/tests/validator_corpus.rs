//! Every file the Khronos glTF Validator reports valid is accepted (issue 11), and no file
//! of its test suite, valid or not, ends in a panic (issue 32).
//!
//! The corpus is `assets/validator-corpus/`: the validator's own test files with their
//! reports (copied by `bench/validator-corpus.sh`, which regenerates it). Every valid file
//! (`numErrors == 0`) is loaded by the glTF reader; every one with triangles is fixed; every
//! loaded one is saved as .gltf and as GLB (but where buffer 0 has no data) by the
//! pass-through writer, and the validator must report 0 errors on each output (one node
//! process for all). Every file, valid or not, is loaded and what loads goes through what
//! `seamlit fix` does with it, without a panic; a refusal is one line naming the file.

mod common;

use std::path::{Path, PathBuf};

use seamlit_io::{BadUri, Glb, GltfKind, InvalidAsset, IoError, LoadOptions, SaveOptions};

/// The valid files seamlit refuses, each with a part of the message it must give.
const REFUSED: [(&str, &str, BadUri); 1] = [
    // Remote resources are never fetched.
    (
        "test/base/data/buffer/non_relative_uri.gltf",
        "http://example.com/buffer.bin",
        BadUri::NotRelative,
    ),
];

/// The corpus folder.
fn corpus() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/validator-corpus"))
}

/// Every `.gltf` and `.glb` under `folder`, as paths relative to it, sorted.
fn models(folder: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut stack = vec![folder.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if matches!(path.extension().and_then(|e| e.to_str()), Some("gltf" | "glb")) {
                found.push(path.strip_prefix(folder).unwrap().to_string_lossy().replace('\\', "/"));
            }
        }
    }
    found.sort();
    found
}

/// Whether the file is a `.gltf` whose buffer 0 has no `uri`, read with serde_json.
fn host_without_data(file: &Path) -> bool {
    if file.extension().is_some_and(|e| e == "glb") {
        return false;
    }
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(file).unwrap()).unwrap();
    json["buffers"][0].is_object() && json["buffers"][0].get("uri").is_none()
}

/// The validator's own verdict on a corpus file: its report's `issues.numErrors`.
fn reported_errors(file: &Path) -> u64 {
    let report = PathBuf::from(format!("{}.report.json", file.display()));
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    report["issues"]["numErrors"].as_u64().unwrap()
}

#[test]
fn every_file_the_validator_finds_valid_loads_and_is_written_back_valid() {
    let root = corpus();
    let files: Vec<String> =
        models(&root).into_iter().filter(|name| reported_errors(&root.join(name)) == 0).collect();
    assert!(files.len() >= 120, "the corpus is missing: run bench/validator-corpus.sh");
    let out = tempfile::tempdir().unwrap();
    let mut problems = Vec::new();
    let mut written = Vec::new();
    let mut fixed = 0;
    for name in &files {
        let file = root.join(name);
        let loaded = seamlit_io::gltf::load(&file, &LoadOptions::default());
        if let Some((_, uri, kind)) = REFUSED.iter().find(|(refused, ..)| refused == name) {
            match loaded {
                Err(IoError::BadUri { uri: u, kind: k, .. })
                    if (u.as_str(), k) == (*uri, *kind) => {}
                other => problems.push(format!(
                    "{name}: expected the refusal of {uri} ({kind:?}), got {:?}",
                    other.map(|_| ())
                )),
            }
            continue;
        }
        let mut asset = match loaded {
            Ok(asset) => asset,
            Err(e) => {
                problems.push(format!("{name}: refused: {e}"));
                continue;
            }
        };
        // The front door refuses a model without triangles (nothing to fix or draw), and
        // only such a model.
        match (asset.model.triangle_count(), seamlit_io::load(&file, &LoadOptions::default())) {
            (0, Err(IoError::NoTriangles { .. })) | (1.., Ok(_)) => {}
            (triangles, other) => problems.push(format!(
                "{name}: {triangles} triangles, seamlit_io::load gave {:?}",
                other.map(|_| ()).map_err(|e| e.to_string())
            )),
        }
        if asset.model.triangle_count() > 0 {
            match seamlit_mesh::fix(&asset.model, &seamlit_mesh::FixOptions::default()) {
                Ok(model) => asset.model = model,
                Err(e) => {
                    problems.push(format!("{name}: fix failed: {e}"));
                    continue;
                }
            }
            fixed += 1;
        }
        // Written as GLB and as .gltf (in a folder of its own: side files are copied beside
        // it). A .gltf whose buffer 0 has no uri (its data comes from elsewhere) cannot
        // become a GLB, whose buffer 0 without uri is the BIN chunk: that is refused.
        let flat = name.replace('/', "__");
        let folder = out.path().join(&flat);
        std::fs::create_dir(&folder).unwrap();
        let mut outputs = vec![folder.join("model.gltf")];
        let glb = out.path().join(format!("{flat}.glb"));
        if host_without_data(&file) {
            match seamlit_io::save(&asset, &glb, &SaveOptions::default()) {
                Err(IoError::InvalidAsset { kind: InvalidAsset::HostInGlb, .. }) => {}
                other => problems.push(format!(
                    "{name}: GLB output of a buffer 0 without data gave {:?}",
                    other.map(|_| ())
                )),
            }
        } else {
            outputs.push(glb);
        }
        for output in outputs {
            match seamlit_io::save(&asset, &output, &SaveOptions::default()) {
                Ok(report) => {
                    match report.warnings.iter().find(|w| w.contains("generic glTF writer")) {
                        Some(warning) => {
                            problems.push(format!("{name}: not passed through: {warning}"));
                        }
                        None => written.push((name, output)),
                    }
                }
                Err(e) => problems.push(format!("{name}: save failed: {e}")),
            }
        }
    }
    let outputs: Vec<PathBuf> = written.iter().map(|(_, output)| output.clone()).collect();
    for ((name, _), (errors, report)) in written.iter().zip(common::validate_many(&outputs)) {
        if errors > 0 {
            problems.push(format!("{name}: the output has {errors} validator errors: {report}"));
        }
    }
    println!(
        "{} valid files: {} loaded, {} refused as listed, {fixed} fixed, {} outputs written (.gltf, and GLB but where buffer 0 has no data)",
        files.len(),
        files.len() - REFUSED.len(),
        REFUSED.len(),
        written.len()
    );
    assert!(problems.is_empty(), "{} problems:\n{}", problems.len(), problems.join("\n"));
    // Not vacuous: files with geometry were fixed, and every loaded file was written back
    // and validated.
    assert!(fixed >= 6, "only {fixed} files were fixed");
    let without_data = files.iter().filter(|name| host_without_data(&root.join(name))).count();
    assert_eq!(written.len(), 2 * (files.len() - REFUSED.len()) - without_data);
}

/// Every file of the corpus, valid or invalid, is read without a panic: it loads, and then
/// goes through what `seamlit fix` does (`common::mutate::use_asset`), or it is refused in
/// one line that names the file. Before issue 32, `unresolved_channel_target.gltf` (an
/// animation channel whose node does not exist) and KHR_animation_pointer's
/// `invalid_channel_target_node.gltf` (a `"pointer"` path on a channel with a node) panicked
/// in the gltf crate.
#[test]
fn no_file_of_the_corpus_panics() {
    let root = corpus();
    let files = models(&root);
    assert!(files.len() >= 370, "the corpus is missing: run bench/validator-corpus.sh");
    let out = tempfile::tempdir().unwrap();
    let (mut loaded, mut refused, mut problems) = (0, 0, Vec::new());
    for name in &files {
        let file = root.join(name);
        let result = std::panic::catch_unwind(|| {
            seamlit_io::gltf::load(&file, &LoadOptions::default())
                .map(|asset| common::mutate::use_asset(asset, out.path()))
        });
        match result {
            Ok(Ok(())) => loaded += 1,
            Ok(Err(e)) => {
                refused += 1;
                let (line, stem) = (e.to_string(), file.file_stem().unwrap().to_string_lossy());
                if line.contains('\n') || !line.contains(&*stem) {
                    problems.push(format!("{name}: not one line naming the file: {line:?}"));
                }
            }
            Err(_) => problems.push(format!("{name}: panicked")),
        }
    }
    println!("{} files: {loaded} loaded and used, {refused} refused in one line", files.len());
    assert!(problems.is_empty(), "{} problems:\n{}", problems.len(), problems.join("\n"));
    assert!(loaded > 200 && refused > 80, "{loaded} loaded, {refused} refused");
}

/// The two files of the validator's corpus that panicked before issue 32 load, and each
/// warns that the channel it cannot play is not played, naming it.
#[test]
fn channels_that_cannot_be_played_are_skipped_with_a_warning() {
    let root = corpus();
    for (name, why) in [
        (
            "test/base/data/animation/unresolved_channel_target.gltf",
            "channel 0: its target node 0 does not exist (the file has 0 nodes)",
        ),
        (
            "test/ext/KHR_animation_pointer/data/animation/channel/target/invalid_channel_target_node.gltf",
            "channel 0: its target path is not translation, rotation, scale or weights",
        ),
    ] {
        let asset = seamlit_io::gltf::load(&root.join(name), &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let warning = asset.warnings.iter().find(|w| w.contains("animations[0]"));
        assert!(
            warning.is_some_and(|w| w.contains("not played") && w.contains(why)),
            "{name}: {:?}",
            asset.warnings
        );
        assert!(asset.animations[0].channels.is_empty(), "{name}");
    }
}

/// An index accessor without a buffer view is three zeros per triangle (glTF 2.0, 5.1
/// Accessor), read as degenerate triangles: never as a missing one (a non-indexed list).
#[test]
fn an_index_accessor_without_data_is_zeros() {
    let positions: Vec<u8> = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        .repeat(2)
        .into_iter()
        .flatten()
        .flat_map(f32::to_le_bytes)
        .collect();
    let document = serde_json::json!({
        "asset": { "version": "2.0" },
        "buffers": [{
            "byteLength": positions.len(),
            "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&positions)),
        }],
        "bufferViews": [{ "buffer": 0, "byteLength": positions.len() }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
              "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0] },
            { "componentType": 5123, "count": 6, "type": "SCALAR" },
        ],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "nodes": [{ "mesh": 0 }],
        "scenes": [{ "nodes": [0] }],
    });
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("zeros.gltf");
    std::fs::write(&file, serde_json::to_vec(&document).unwrap()).unwrap();
    assert_eq!(common::validate(&file).0, 0, "the fixture is valid glTF");
    let asset = seamlit_io::gltf::load(&file, &LoadOptions::default()).unwrap();
    assert_eq!(asset.model.objects[0].triangles, vec![[0, 0, 0], [0, 0, 0]]);
}

/// A GLB: the 12-byte header, then each chunk (type, data padded to 4 bytes), then `trailing`
/// bytes after the declared length.
fn glb(chunks: &[(&[u8; 4], &[u8])], trailing: &[u8]) -> Vec<u8> {
    let mut body = Vec::new();
    for (kind, data) in chunks {
        let padded = data.len().next_multiple_of(4);
        body.extend_from_slice(&u32::try_from(padded).unwrap().to_le_bytes());
        body.extend_from_slice(*kind);
        body.extend_from_slice(data);
        body.resize(body.len() + padded - data.len(), if *kind == b"JSON" { b' ' } else { 0 });
    }
    let mut file = b"glTF".to_vec();
    file.extend_from_slice(&2u32.to_le_bytes());
    file.extend_from_slice(&u32::try_from(12 + body.len()).unwrap().to_le_bytes());
    file.extend(body);
    file.extend_from_slice(trailing);
    file
}

/// "Client implementations MUST ignore chunks with unknown types" (glTF 2.0, 4.4.3), and
/// bytes after the declared length are not part of the GLB.
#[test]
fn a_glb_with_an_unknown_chunk_and_trailing_bytes_loads() {
    let positions: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .into_iter()
        .flat_map(f32::to_le_bytes)
        .collect();
    let json = serde_json::json!({
        "asset": { "version": "2.0" },
        "buffers": [{ "byteLength": 36 }],
        "bufferViews": [{ "buffer": 0, "byteLength": 36 }],
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0] }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
        "nodes": [{ "mesh": 0 }],
        "scenes": [{ "nodes": [0] }],
    });
    let json = serde_json::to_vec(&json).unwrap();
    let bytes = glb(&[(b"JSON", &json), (b"BIN\0", &positions), (b"XTRA", b"unknown")], b"end");
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("chunks.glb");
    std::fs::write(&file, &bytes).unwrap();
    assert_eq!(common::validate(&file).0, 0, "the fixture is valid glTF");
    let asset = seamlit_io::gltf::load(&file, &LoadOptions::default()).unwrap();
    let read: Vec<[f32; 3]> =
        asset.model.objects[0].positions.iter().map(|p| p.to_array()).collect();
    assert_eq!(read, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);

    // The JSON chunk must come first.
    let swapped = glb(&[(b"BIN\0", &positions), (b"JSON", &json)], b"");
    std::fs::write(&file, &swapped).unwrap();
    let error = seamlit_io::gltf::load(&file, &LoadOptions::default()).unwrap_err();
    assert!(
        matches!(
            &error,
            IoError::Gltf { kind: GltfKind::Glb(Glb::FirstChunkNotJson { chunk_type }), .. }
                if chunk_type == "BIN"
        ),
        "{error}"
    );
}
