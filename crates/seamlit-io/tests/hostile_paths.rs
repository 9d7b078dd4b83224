//! Paths inside model files that leave the model's folder are refused before anything is
//! read: OBJ `mtllib`, MTL texture statements (glTF URIs are covered in malformed_gltf.rs);
//! glTF buffers and images and MTL textures that are symbolic links leading out are refused.
//! Outputs replace existing files atomically and never write through a symlink.

use std::path::{Path, PathBuf};

use seamlit_io::{InvalidAsset, IoError, LoadOptions, SaveOptions};

fn write(path: &Path, text: &str) -> PathBuf {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).unwrap();
    }
    std::fs::write(path, text).unwrap();
    path.to_path_buf()
}

const TRIANGLE: &str =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n";

/// A folder with `outside.mtl` (a valid library) beside the model's folder `model/`.
fn layout() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("outside.mtl"), "newmtl m\nKd 1 0 0\n");
    dir
}

#[test]
fn an_mtllib_that_climbs_out_of_the_folder_is_refused_with_its_line() {
    let dir = layout();
    let obj =
        write(&dir.path().join("model/m.obj"), &format!("# c\nmtllib ../outside.mtl\n{TRIANGLE}"));
    let err = seamlit_io::load(&obj, &LoadOptions::default()).unwrap_err();
    match &err {
        IoError::PathEscapes { path, line, what, reference } => {
            assert_eq!(path, &obj);
            assert_eq!(*line, Some(2));
            assert_eq!(*what, "material library");
            assert_eq!(reference, "../outside.mtl");
        }
        other => panic!("unexpected {other}"),
    }
    assert!(err.to_string().contains("m.obj:2: material library path"), "{err}");
}

#[test]
fn an_absolute_mtllib_is_refused_even_when_the_file_exists() {
    let dir = layout();
    let absolute = dir.path().join("outside.mtl");
    let obj = write(
        &dir.path().join("model/m.obj"),
        &format!("mtllib {}\n{TRIANGLE}", absolute.display()),
    );
    let err = seamlit_io::load(&obj, &LoadOptions::default()).unwrap_err();
    assert!(matches!(&err, IoError::PathEscapes { line: Some(1), .. }), "{err}");
}

#[test]
fn a_texture_that_climbs_out_of_the_folder_is_refused_naming_the_mtl() {
    let dir = layout();
    let mtl = write(&dir.path().join("model/sub/m.mtl"), "newmtl m\nmap_Kd ../../secret.png\n");
    let obj = write(&dir.path().join("model/m.obj"), &format!("mtllib sub/m.mtl\n{TRIANGLE}"));
    let err = seamlit_io::load(&obj, &LoadOptions::default()).unwrap_err();
    match &err {
        IoError::PathEscapes { path, what, reference, .. } => {
            assert_eq!(path, &mtl);
            assert_eq!(*what, "texture");
            assert_eq!(reference, "../../secret.png");
        }
        other => panic!("unexpected {other}"),
    }
    // A bump map with options, an absolute path: refused the same way.
    write(&mtl, "newmtl m\nmap_Bump -bm 2 /etc/hostname\n");
    let err = seamlit_io::load(&obj, &LoadOptions::default()).unwrap_err();
    assert!(matches!(&err, IoError::PathEscapes { what: "texture", .. }), "{err}");
}

#[test]
fn paths_that_go_up_but_stay_inside_the_folder_are_read() {
    let dir = layout();
    write(&dir.path().join("model/sub/m.mtl"), "newmtl m\nKd 0 1 0\nmap_Kd ../tex/albedo.png\n");
    let obj = write(&dir.path().join("model/m.obj"), &format!("mtllib ./sub/m.mtl\n{TRIANGLE}"));
    let asset = seamlit_io::load(&obj, &LoadOptions::GEOMETRY).unwrap();
    assert_eq!(asset.materials.len(), 1);
    assert_eq!(asset.materials[0].base_color, [0.0, 1.0, 0.0, 1.0]);
    let texture = &asset.textures[asset.materials[0].base_color_texture.as_ref().unwrap().texture];
    assert_eq!(
        texture.source,
        seamlit_io::TextureSource::File(dir.path().join("model").join("tex").join("albedo.png"))
    );
}

#[test]
fn saving_over_a_symlink_replaces_the_link_and_leaves_its_target_alone() {
    let dir = tempfile::tempdir().unwrap();
    let victim = write(&dir.path().join("victim.txt"), "precious");
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    for name in ["m.obj", "m.mtl", "m.glb", "m.gltf", "m.bin"] {
        std::os::unix::fs::symlink(&victim, out.join(name)).unwrap();
    }
    let source = write(&dir.path().join("in/m.obj"), "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let asset = seamlit_io::load(&source, &LoadOptions::GEOMETRY).unwrap();
    for name in ["m.obj", "m.glb", "m.gltf"] {
        seamlit_io::save(&asset, &out.join(name), &SaveOptions::default()).unwrap();
        let meta = std::fs::symlink_metadata(out.join(name)).unwrap();
        assert!(meta.file_type().is_file(), "{name} is still a link");
    }
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    // No temporary files are left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn a_failed_save_leaves_the_existing_output_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let out = write(&dir.path().join("m.glb"), "old contents");
    // An object whose triangle indexes past its vertices cannot be written.
    let mut asset = seamlit_io::Asset::default();
    asset.model.objects.push(seamlit_mesh::Object::new(
        "broken",
        vec![glam::Vec3::ZERO; 3],
        vec![[0, 1, 7]],
    ));
    let err = seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap_err();
    assert!(
        matches!(
            &err,
            IoError::InvalidAsset {
                kind: InvalidAsset::IndexOutOfRange { triangle: [0, 1, 7], vertices: 3 },
                object,
                ..
            } if object == "broken"
        ),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old contents");
}

/// A one-triangle glTF whose buffer is the file `buffer_uri` and whose material uses the
/// image `image_uri`; the buffer bytes, for writing them where the test wants.
fn gltf_with_files(buffer_uri: &str, image_uri: &str) -> (String, Vec<u8>) {
    let floats: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let bytes: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    let json = serde_json::json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "material": 0 }] }],
        "materials": [{ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } } }],
        "textures": [{ "source": 0 }],
        "images": [{ "uri": image_uri }],
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0] }],
        "bufferViews": [{ "buffer": 0, "byteLength": 36 }],
        "buffers": [{ "byteLength": 36, "uri": buffer_uri }]
    });
    (json.to_string(), bytes)
}

/// `model/` with `model/data/tri.bin` and `model/data/albedo.png` (a 2 x 2 image), and
/// `outside/` beside it with the same two files; returns the temporary folder.
#[cfg(unix)]
fn linked_layout() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let (_, bin) = gltf_with_files("", "");
    for folder in ["model/data", "outside"] {
        let folder = dir.path().join(folder);
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::write(folder.join("tri.bin"), &bin).unwrap();
        image::RgbaImage::new(2, 2).save(folder.join("albedo.png")).unwrap();
    }
    dir
}

/// Asserts that `err` refuses, in `file`, the reference `reference` (what it is for: `what`)
/// because a link leads it to `target`.
#[cfg(unix)]
fn assert_link_escape(err: &IoError, file: &Path, what: &str, reference: &str, target: &Path) {
    match err {
        IoError::LinkEscapes { path, what: w, reference: r, target: t } => {
            assert_eq!((path.as_path(), w.as_str(), r.as_str()), (file, what, reference));
            assert_eq!(t, &target.canonicalize().unwrap());
        }
        other => panic!("unexpected {other}"),
    }
}

#[cfg(unix)]
#[test]
fn a_gltf_buffer_that_is_a_link_out_of_the_folder_is_refused() {
    use std::os::unix::fs::symlink;
    let dir = linked_layout();
    let model = dir.path().join("model");
    symlink(dir.path().join("outside/tri.bin"), model.join("link.bin")).unwrap();
    let (json, _) = gltf_with_files("link.bin", "data/albedo.png");
    let gltf = write(&model.join("m.gltf"), &json);
    let err = seamlit_io::load(&gltf, &LoadOptions::GEOMETRY).unwrap_err();
    assert_link_escape(&err, &gltf, "buffer 0", "link.bin", &dir.path().join("outside/tri.bin"));
    assert!(err.to_string().contains("buffer 0 \"link.bin\" is refused"), "{err}");
}

#[cfg(unix)]
#[test]
fn a_gltf_image_in_a_linked_folder_leading_out_is_refused_even_when_not_decoded() {
    use std::os::unix::fs::symlink;
    let dir = linked_layout();
    let model = dir.path().join("model");
    symlink(dir.path().join("outside"), model.join("shared")).unwrap();
    let (json, _) = gltf_with_files("data/tri.bin", "shared/albedo.png");
    let gltf = write(&model.join("m.gltf"), &json);
    for options in [LoadOptions::GEOMETRY, LoadOptions::DEFAULT] {
        let err = seamlit_io::load(&gltf, &options).unwrap_err();
        assert!(
            matches!(&err, IoError::LinkEscapes { what, reference, .. }
                if what == "image 0" && reference == "shared/albedo.png"),
            "{err}"
        );
    }
}

#[cfg(unix)]
#[test]
fn an_mtl_texture_that_is_a_link_out_of_the_folder_is_refused() {
    use std::os::unix::fs::symlink;
    let dir = linked_layout();
    let model = dir.path().join("model");
    symlink(dir.path().join("outside/albedo.png"), model.join("data/link.png")).unwrap();
    write(&model.join("m.mtl"), "newmtl m\nmap_Kd data/link.png\n");
    let obj = write(&model.join("m.obj"), &format!("mtllib m.mtl\n{TRIANGLE}"));
    // Refused whether or not textures are decoded: a writer would copy the file.
    for options in [LoadOptions::GEOMETRY, LoadOptions::DEFAULT] {
        let err = seamlit_io::load(&obj, &options).unwrap_err();
        let target = dir.path().join("outside/albedo.png");
        assert_link_escape(&err, &obj, "texture", "data/link.png", &target);
    }
}

#[cfg(unix)]
#[test]
fn an_mtl_library_that_is_a_link_out_of_the_folder_is_refused() {
    use std::os::unix::fs::symlink;
    let dir = linked_layout();
    let model = dir.path().join("model");
    write(&dir.path().join("outside/secret.mtl"), "newmtl m\nKd 1 0 0\n");
    symlink(dir.path().join("outside/secret.mtl"), model.join("m.mtl")).unwrap();
    let obj = write(&model.join("m.obj"), &format!("mtllib m.mtl\n{TRIANGLE}"));
    for options in [LoadOptions::GEOMETRY, LoadOptions::DEFAULT] {
        let err = seamlit_io::load(&obj, &options).unwrap_err();
        let target = dir.path().join("outside/secret.mtl");
        assert_link_escape(&err, &obj, "material library", "m.mtl", &target);
    }
    // A library linked from inside the folder is read.
    std::fs::remove_file(model.join("m.mtl")).unwrap();
    write(&model.join("data/real.mtl"), "newmtl m\nKd 1 0 0\n");
    symlink("data/real.mtl", model.join("m.mtl")).unwrap();
    let asset = seamlit_io::load(&obj, &LoadOptions::GEOMETRY).unwrap();
    assert!(asset.warnings.is_empty(), "{:?}", asset.warnings);
}

#[cfg(unix)]
#[test]
fn links_that_stay_inside_the_folder_are_followed() {
    use std::os::unix::fs::symlink;
    let dir = linked_layout();
    let model = dir.path().join("model");
    symlink("data/tri.bin", model.join("link.bin")).unwrap();
    symlink(model.join("data"), model.join("textures")).unwrap();
    let (json, _) = gltf_with_files("link.bin", "textures/albedo.png");
    let gltf = write(&model.join("m.gltf"), &json);
    let asset = seamlit_io::load(&gltf, &LoadOptions::DEFAULT).unwrap();
    assert_eq!(asset.model.objects[0].positions.len(), 3);
    assert!(asset.warnings.is_empty(), "{:?}", asset.warnings);
    assert_eq!(asset.textures[0].image.as_ref().map(|i| i.dimensions()), Some((2, 2)));

    write(&model.join("m.mtl"), "newmtl m\nmap_Kd textures/albedo.png\n");
    let obj = write(&model.join("m.obj"), &format!("mtllib m.mtl\n{TRIANGLE}"));
    let asset = seamlit_io::load(&obj, &LoadOptions::DEFAULT).unwrap();
    assert!(asset.warnings.is_empty(), "{:?}", asset.warnings);
    assert_eq!(asset.textures[0].image.as_ref().map(|i| i.dimensions()), Some((2, 2)));
    // The model itself reached through a linked folder: its own files are inside.
    symlink(&model, dir.path().join("model_link")).unwrap();
    let asset =
        seamlit_io::load(&dir.path().join("model_link/m.gltf"), &LoadOptions::DEFAULT).unwrap();
    assert_eq!(asset.textures[0].image.as_ref().map(|i| i.dimensions()), Some((2, 2)));
}

#[test]
fn a_missing_texture_matters_only_when_textures_are_decoded() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("m.mtl"), "newmtl m\nmap_Kd nowhere.png\n");
    let obj = write(&dir.path().join("m.obj"), &format!("mtllib m.mtl\n{TRIANGLE}"));
    let geometry = LoadOptions::GEOMETRY.with_strict(true);
    let asset = seamlit_io::load(&obj, &geometry).unwrap();
    assert!(asset.warnings.is_empty(), "{:?}", asset.warnings);
    let err = seamlit_io::load(&obj, &LoadOptions::DEFAULT.with_strict(true)).unwrap_err();
    assert!(
        matches!(&err, IoError::MissingFile { missing, .. } if missing.ends_with("nowhere.png")),
        "{err}"
    );
    let asset = seamlit_io::load(&obj, &LoadOptions::DEFAULT).unwrap();
    assert_eq!(asset.warnings.len(), 1, "{:?}", asset.warnings);
    assert!(asset.warnings[0].contains("nowhere.png"), "{:?}", asset.warnings);
}
