//! Paths inside model files that leave the model's folder are refused before anything is
//! read: OBJ `mtllib`, MTL texture statements (glTF URIs are covered in malformed_gltf.rs).
//! Outputs replace existing files atomically and never write through a symlink.

use std::path::{Path, PathBuf};

use seamlit_io::{IoError, LoadOptions, SaveOptions};

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
    assert!(matches!(err, IoError::InvalidAsset { .. }), "{err}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old contents");
}
