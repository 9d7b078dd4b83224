//! Files made by other tools, read as their authors meant (issue 27): MTL statements that
//! seamlit cannot use never refuse the geometry; names in a legacy 8-bit encoding are read as
//! Windows-1252 and kept byte for byte by the OBJ pass-through; images that a texture names
//! as its core source in a format other than PNG or JPEG are not embedded in a GLB, so that no
//! output gains a validator error its input did not have.

mod common;

use std::path::{Path, PathBuf};

use seamlit_io::{IoError, LoadOptions, NotText, SaveOptions};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

#[test]
fn mtl_colours_of_one_number_are_grey_and_spectral_ones_keep_the_default() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "m.mtl",
        b"newmtl grey\nKa spectral x.rfl\nKd 0.25\nKs 0\nKe 1 2\nd -halo 0.5\nmap_Kd -foo\n\
          newmtl xyz\nKd xyz 0.950456 1 1.088754\n",
    );
    let obj = format!("mtllib m.mtl\n{QUAD}usemtl grey\nf 1 2 3\nusemtl xyz\nf 1 3 4\n");
    let path = write(dir.path(), "m.obj", obj.as_bytes());
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    let grey = &asset.materials[0];
    assert_eq!(grey.base_color, [0.25, 0.25, 0.25, 0.5]);
    assert_eq!(grey.specular, [0.0, 0.0, 0.0]);
    // D65 white in CIE XYZ is linear sRGB white.
    for c in &asset.materials[1].base_color[..3] {
        assert!((c - 1.0).abs() < 1e-3, "{:?}", asset.materials[1].base_color);
    }
    // One warning for the library: the first statement it cannot use, and the others' lines.
    assert_eq!(asset.warnings.len(), 1, "{:?}", asset.warnings);
    let warning = &asset.warnings[0];
    assert!(warning.contains("m.mtl:2: `Ka spectral x.rfl`"), "{warning}");
    assert!(warning.contains("2 more") && warning.contains("lines 5, 7"), "{warning}");
}

/// A scene from an older exporter: group and material names in Latin-1.
const LATIN_1_OBJ: &[u8] =
    b"mtllib bl\xe5.mtl\ng R\xf8d_tr\xe6\r\nusemtl Bl\xe5\nv 0 0 0\nv 1 0 0\n\
v 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
const LATIN_1_MTL: &[u8] = b"# \xe6\xf8\xe5\nnewmtl Bl\xe5\nKd 0 0 1\nmap_Kd tr\xe6.png\n";

#[test]
fn latin_1_names_load_decoded_and_pass_through_as_written() {
    let dir = tempfile::tempdir().unwrap();
    // The library's own file name is Latin-1 on disk, as the exporter wrote it.
    #[cfg(unix)]
    let library = std::ffi::OsStr::from_bytes(b"bl\xe5.mtl");
    #[cfg(not(unix))]
    let library = std::ffi::OsStr::new("blå.mtl");
    std::fs::write(dir.path().join(library), LATIN_1_MTL).unwrap();
    // So is the texture's.
    #[cfg(unix)]
    let texture = std::ffi::OsStr::from_bytes(b"tr\xe6.png");
    #[cfg(not(unix))]
    let texture = std::ffi::OsStr::new("træ.png");
    image::RgbaImage::from_pixel(1, 1, image::Rgba([1, 2, 3, 255]))
        .save_with_format(dir.path().join(texture), image::ImageFormat::Png)
        .unwrap();
    let path = write(dir.path(), "old.obj", LATIN_1_OBJ);
    let mut asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(asset.model.objects[0].name, "Rød_træ");
    assert_eq!(asset.materials.len(), 1, "{:?}", asset.warnings);
    assert_eq!(asset.materials[0].name, "Blå");
    assert_eq!(asset.materials[0].base_color, [0.0, 0.0, 1.0, 1.0]);
    assert_eq!(asset.model.objects[0].material, Some(0));
    let albedo = asset.materials[0].base_color_texture.as_ref().expect("the texture");
    assert_eq!(asset.textures[albedo.texture].name, "træ.png");
    let image = asset.textures[albedo.texture].image.as_ref().expect("read from its bytes");
    assert_eq!(image.get_pixel(0, 0).0, [1, 2, 3, 255]);
    // One warning per file.
    assert_eq!(asset.warnings.len(), 2, "{:?}", asset.warnings);
    assert!(asset.warnings[0].contains("old.obj:1: text that is not UTF-8"));
    assert!(asset.warnings[1].contains("bl\u{e5}.mtl:1: text that is not UTF-8"));
    seamlit_mesh::fix_in_place(&mut asset.model, &seamlit_mesh::FixOptions::default()).unwrap();

    // OBJ out: every line but the faces and normals byte for byte, the library copied.
    let out = tempfile::tempdir().unwrap();
    let obj_out = out.path().join("old.obj");
    seamlit_io::save(&asset, &obj_out, &SaveOptions::default()).unwrap();
    let written = std::fs::read(&obj_out).unwrap();
    for line in LATIN_1_OBJ.split_inclusive(|&b| b == b'\n').filter(|l| !l.starts_with(b"f ")) {
        assert!(written.windows(line.len()).any(|w| w == line), "{:?} lost", line.escape_ascii());
    }
    assert_eq!(std::fs::read(out.path().join(library)).unwrap(), LATIN_1_MTL);
    assert!(out.path().join(texture).is_file(), "the texture copied under its bytes");

    // glTF out: the names as characters.
    let gltf_out = out.path().join("old.gltf");
    seamlit_io::save(&asset, &gltf_out, &SaveOptions::default()).unwrap();
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&gltf_out).unwrap()).unwrap();
    assert_eq!(json["materials"][0]["name"], "Blå");
    let names: Vec<&str> =
        json["nodes"].as_array().unwrap().iter().filter_map(|n| n["name"].as_str()).collect();
    assert!(names.contains(&"Rød_træ"), "{names:?}");
}

#[cfg(unix)]
use std::os::unix::ffi::OsStrExt as _;

#[test]
fn nul_bytes_and_bytes_that_are_not_text_where_numbers_belong_stay_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text, line, problem) in [
        ("nul_in_v.obj", &b"v 0 0 0\nv 1 \x000 0\nv 0 1 0\nf 1 2 3\n"[..], 2, NotText::Nul),
        ("nul_in_g.obj", b"g a\x00b\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 1, NotText::Nul),
        ("latin_1_in_v.obj", b"v 0 0 0\nv 1 \xe6 0\nv 0 1 0\nf 1 2 3\n", 2, NotText::InvalidUtf8),
        ("latin_1_in_f.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \xb3\n", 4, NotText::InvalidUtf8),
    ] {
        let path = write(dir.path(), name, text);
        match seamlit_io::load(&path, &LoadOptions::default()) {
            Err(IoError::NotText { line: l, problem: p, .. }) if (l, p) == (line, problem) => {}
            other => panic!("{name}: {:?}", other.map(|_| ())),
        }
    }
}

/// A quad textured by three KTX2 images that its textures name as their core `source` (no
/// KHR_texture_basisu), and one PNG; valid with warnings only.
fn ktx2_model(dir: &Path) -> PathBuf {
    // A KTX2 file's identifier and a header of a 1 x 1 image; the validator does not decode
    // KTX2 data, seamlit neither: only the signature matters.
    let mut ktx2 = b"\xABKTX 20\xBB\r\n\x1A\n".to_vec();
    ktx2.extend_from_slice(&[0; 68]);
    for name in ["a.ktx2", "b.ktx2", "c.ktx2"] {
        write(dir, name, &ktx2);
    }
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(1, 1, image::Rgba([200, 100, 50, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    write(dir, "d.png", &png);
    let positions: [[f32; 3]; 4] =
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let uvs: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let mut bin: Vec<u8> = bytemuck::cast_slice(&positions).to_vec();
    bin.extend_from_slice(bytemuck::cast_slice(&uvs));
    bin.extend_from_slice(bytemuck::cast_slice(&indices));
    bin.extend_from_slice(&[0, 0]);
    write(dir, "quad.bin", &bin);
    let json = serde_json::json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0, "name": "quad" }],
        "meshes": [{ "primitives": [{
            "attributes": { "POSITION": 0, "TEXCOORD_0": 1 }, "indices": 2, "material": 0 }] }],
        "materials": [{
            "pbrMetallicRoughness": {
                "baseColorTexture": { "index": 0 },
                "metallicRoughnessTexture": { "index": 1 }
            },
            "normalTexture": { "index": 2 },
            "occlusionTexture": { "index": 3 }
        }],
        "textures": [{ "source": 0 }, { "source": 1 }, { "source": 2 }, { "source": 3 }],
        "images": [{ "uri": "a.ktx2" }, { "uri": "b.ktx2" }, { "uri": "c.ktx2" }, { "uri": "d.png" }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
              "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0] },
            { "bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2" },
            { "bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR" }
        ],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 48, "target": 34962 },
            { "buffer": 0, "byteOffset": 48, "byteLength": 32, "target": 34962 },
            { "buffer": 0, "byteOffset": 80, "byteLength": 12, "target": 34963 }
        ],
        "buffers": [{ "uri": "quad.bin", "byteLength": 92 }]
    });
    write(dir, "quad.gltf", &serde_json::to_vec_pretty(&json).unwrap())
}

/// The validator's error messages of a report line, without the place they point at.
fn error_codes(report: &str) -> Vec<String> {
    let report: serde_json::Value = serde_json::from_str(report).unwrap();
    let mut codes: Vec<String> = report["messages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m.as_str().unwrap().split(' ').next().unwrap().to_owned())
        .collect();
    codes.sort();
    codes
}

#[test]
fn ktx2_images_named_as_core_sources_stay_files_and_gain_no_validator_error() {
    let dir = tempfile::tempdir().unwrap();
    let input = ktx2_model(dir.path());
    let out = tempfile::tempdir().unwrap();
    let glb = out.path().join("quad.glb");
    let gltf = out.path().join("gltf/quad.gltf");
    std::fs::create_dir(out.path().join("gltf")).unwrap();
    let mut warnings = Vec::new();
    for output in [&glb, &gltf] {
        warnings.push(common::fix_and_save(&input, output));
    }
    let reports = common::validate_many(&[input.clone(), glb.clone(), gltf.clone()]);
    let (input_errors, input_report) = &reports[0];
    assert_eq!(*input_errors, 0, "the input must be valid: {input_report}");
    for (output, (errors, report)) in [&glb, &gltf].into_iter().zip(&reports[1..]) {
        assert_eq!(error_codes(report), error_codes(input_report), "{}", output.display());
        assert_eq!(*errors, 0, "{}: {report}", output.display());
    }
    // In the GLB: the PNG embedded, the KTX2 images beside it, said in one line each.
    let json = common::gltf::glb_json(&glb);
    let images = json["images"].as_array().unwrap();
    for (i, name) in ["a.ktx2", "b.ktx2", "c.ktx2"].iter().enumerate() {
        assert_eq!(images[i]["uri"], *name);
        assert!(out.path().join(name).is_file(), "{name} not copied");
        let said = warnings[0].iter().filter(|w| w.contains(&format!("image {i} ({name}"))).count();
        assert_eq!(said, 1, "{:?}", warnings[0]);
    }
    assert!(images[3].get("uri").is_none() && images[3]["mimeType"] == "image/png");
    assert_eq!(warnings[1], Vec::<String>::new(), "a .gltf keeps every image a file");
}

#[test]
fn a_gltf_1_document_is_refused_by_its_version() {
    let dir = tempfile::tempdir().unwrap();
    for (name, version) in [("one.gltf", r#""1.0""#), ("number.gltf", "1")] {
        // glTF 1.0 keys its objects by id, which glTF 2.0's reader cannot parse.
        let text = format!(
            r#"{{"asset": {{"version": {version}}}, "meshes": {{"m": {{"primitives": []}}}}}}"#
        );
        let path = write(dir.path(), name, text.as_bytes());
        match seamlit_io::load(&path, &LoadOptions::default()) {
            Err(err @ IoError::Gltf { kind: seamlit_io::GltfKind::OldVersion { .. }, .. }) => {
                assert!(err.to_string().contains("seamlit reads glTF 2.0"), "{err}");
            }
            other => panic!("{name}: {:?}", other.map(|_| ())),
        }
    }
}

/// A quad as a triangle strip (mode 5, no indices) and as a fan (mode 6, indexed), two
/// primitives of one mesh over the same positions.
fn strip_and_fan(dir: &Path) -> PathBuf {
    let positions: [[f32; 3]; 4] =
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
    let fan: [u16; 4] = [0, 1, 3, 2];
    let mut bin: Vec<u8> = bytemuck::cast_slice(&positions).to_vec();
    bin.extend_from_slice(bytemuck::cast_slice(&fan));
    write(dir, "strip.bin", &bin);
    let json = serde_json::json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [
            { "attributes": { "POSITION": 0 }, "mode": 5 },
            { "attributes": { "POSITION": 0 }, "indices": 1, "mode": 6 }
        ] }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
              "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0] },
            { "bufferView": 1, "componentType": 5123, "count": 4, "type": "SCALAR" }
        ],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 48, "target": 34962 },
            { "buffer": 0, "byteOffset": 48, "byteLength": 8, "target": 34963 }
        ],
        "buffers": [{ "uri": "strip.bin", "byteLength": 56 }]
    });
    write(dir, "strip.gltf", &serde_json::to_vec_pretty(&json).unwrap())
}

#[test]
fn triangle_strips_and_fans_are_read_as_the_specification_draws_them() {
    let dir = tempfile::tempdir().unwrap();
    let input = strip_and_fan(dir.path());
    let asset = seamlit_io::load(&input, &LoadOptions::default()).unwrap();
    let triangles: Vec<&Vec<[u32; 3]>> = asset.model.objects.iter().map(|o| &o.triangles).collect();
    assert_eq!(triangles, [&vec![[0, 1, 2], [1, 3, 2]], &vec![[1, 3, 0], [3, 2, 0]]]);
    // Written back as lists of triangles (mode 4), valid, with the same triangles.
    let out = tempfile::tempdir().unwrap();
    let outputs = [out.path().join("strip.glb"), out.path().join("strip.gltf")];
    for output in &outputs {
        common::fix_and_save(&input, output);
        let again = seamlit_io::load(output, &LoadOptions::default()).unwrap();
        let positions = |a: &seamlit_io::Asset| -> Vec<Vec<[[u32; 3]; 3]>> {
            a.model
                .objects
                .iter()
                .map(|o| {
                    let p = |v: u32| o.positions[v as usize].to_array().map(|x| x.to_bits());
                    o.triangles.iter().map(|t| t.map(p)).collect()
                })
                .collect()
        };
        assert_eq!(positions(&again), positions(&asset), "{}", output.display());
    }
    let json = common::gltf::glb_json(&outputs[0]);
    for primitive in json["meshes"][0]["primitives"].as_array().unwrap() {
        assert_eq!(primitive["mode"], 4, "{primitive}");
    }
    for (output, (errors, report)) in outputs.iter().zip(common::validate_many(&outputs)) {
        assert_eq!(errors, 0, "{}: {report}", output.display());
    }
}
