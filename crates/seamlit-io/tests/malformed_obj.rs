//! Malformed OBJ files made by the test: each gets the precise error (file, line, what) and
//! no panic.

use std::path::{Path, PathBuf};

use seamlit_io::{IoError, LoadOptions};

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

const QUAD: &str = "o quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

#[test]
fn nan_in_v() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "nan.obj", "o quad\nv 0 0 0\nv 1 NaN 0\nv 1 1 0\nf 1 2 3\n");
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    match &err {
        IoError::NotFinite { path: p, line: 3, what: "vertex position", text } => {
            assert_eq!(p, &path);
            assert_eq!(text, "NaN");
        }
        other => panic!("unexpected {other}"),
    }
    assert!(err.to_string().contains("nan.obj:3:"), "{err}");
    // Infinity too.
    let path = write(dir.path(), "inf.obj", "v 0 0 0\nv 1 0 0\nv 1 1 inf\nf 1 2 3\n");
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::NotFinite { line: 3, .. }), "{err}");
}

#[test]
fn face_referring_to_missing_vertices() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "range.obj", &format!("{QUAD}f 1 2 3\nf 1 3 5\n"));
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::ReferenceOutOfRange { line: 7, what: "vertex", index: 5, count: 4, .. }
        ),
        "{err}"
    );
    // A relative index reaching before the first vertex.
    let path = write(dir.path(), "negative.obj", &format!("{QUAD}f -1 -2 -9\n"));
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(
        matches!(err, IoError::ReferenceOutOfRange { line: 6, index: -9, count: 4, .. }),
        "{err}"
    );
    // Index 0 does not exist in OBJ.
    let path = write(dir.path(), "zero.obj", &format!("{QUAD}f 0 1 2\n"));
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::ReferenceOutOfRange { line: 6, index: 0, .. }), "{err}");
    // A texture coordinate that does not exist, and a huge normal index.
    let path = write(dir.path(), "vt.obj", &format!("{QUAD}vt 0 0\nf 1/1 2/2 3/1\n"));
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::ReferenceOutOfRange {
                line: 7,
                what: "texture coordinate",
                index: 2,
                count: 1,
                ..
            }
        ),
        "{err}"
    );
    let path =
        write(dir.path(), "vn.obj", &format!("{QUAD}vn 0 0 1\nf 1//1 2//-99999999999 3//1\n"));
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::ReferenceOutOfRange { line: 7, what: "normal", .. }), "{err}");
}

#[test]
fn syntax_errors_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "short.obj", "v 0 0 0\nv 1 0\nv 1 1 0\nf 1 2 3\n");
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::Syntax { line: 2, .. }), "{err}");
    let path = write(dir.path(), "word.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 two 3\n");
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::Syntax { line: 4, .. }), "{err}");
}

#[test]
fn missing_mtl() {
    let dir = tempfile::tempdir().unwrap();
    let path =
        write(dir.path(), "mtl.obj", &format!("mtllib nowhere.mtl\n{QUAD}usemtl red\nf 1 2 3 4\n"));
    // Default: loads, with a warning naming the line and the library.
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(asset.model.triangle_count(), 2);
    assert!(asset.materials.is_empty());
    assert_eq!(asset.warnings.len(), 1);
    assert!(
        asset.warnings[0].contains("mtl.obj:1:") && asset.warnings[0].contains("nowhere.mtl"),
        "{:?}",
        asset.warnings
    );
    // Strict: the precise error.
    let err = seamlit_io::load(&path, &LoadOptions::default().with_strict(true)).unwrap_err();
    match &err {
        IoError::MissingFile { path: p, line: Some(1), missing, what } => {
            assert_eq!(p, &path);
            assert_eq!(missing, &dir.path().join("nowhere.mtl"));
            assert_eq!(what, "material library");
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn malformed_mtl_names_its_line() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "bad.mtl", "newmtl red\nKd 1 0 0\nNs many\n");
    let path =
        write(dir.path(), "bad.obj", &format!("mtllib bad.mtl\n{QUAD}usemtl red\nf 1 2 3 4\n"));
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    match &err {
        IoError::Syntax { path: p, line: 3, .. } => assert!(p.ends_with("bad.mtl")),
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn mtl_textures_resolve_against_the_mtl_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("materials")).unwrap();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([10, 20, 30, 255]))
        .save(dir.path().join("materials/albedo.png"))
        .unwrap();
    image::RgbaImage::from_pixel(1, 1, image::Rgba([128, 128, 255, 255]))
        .save(dir.path().join("materials/n.png"))
        .unwrap();
    write(
        dir.path(),
        "materials/m.mtl",
        "newmtl m\nKd 0.5 0.25 1\nKs 0.1 0.2 0.3\nNs 50\nd 0.5\nmap_Kd albedo.png\nnorm -bm 0.3 n.png\n",
    );
    let path = write(
        dir.path(),
        "t.obj",
        &format!("mtllib materials/m.mtl\n{QUAD}vt 0 0\nvt 1 0\nvt 1 1\nusemtl m\nf 1/1 2/2 3/3\n"),
    );
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert!(asset.warnings.is_empty(), "{:?}", asset.warnings);
    let m = &asset.materials[0];
    assert_eq!(m.base_color, [0.5, 0.25, 1.0, 0.5]);
    assert_eq!(m.specular, [0.1, 0.2, 0.3]);
    assert_eq!(m.shininess, 50.0);
    assert_eq!(m.normal_scale, 0.3);
    let albedo =
        asset.textures[m.base_color_texture.as_ref().unwrap().texture].image.as_ref().unwrap();
    assert_eq!(albedo.get_pixel(1, 1).0, [10, 20, 30, 255]);
    let normal = asset.textures[m.normal_texture.as_ref().unwrap().texture].image.as_ref().unwrap();
    assert_eq!(normal.get_pixel(0, 0).0, [128, 128, 255, 255]);
    assert_eq!(asset.model.objects[0].material, Some(0));
}

#[test]
fn too_large_and_missing_files() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "big.obj", &format!("{QUAD}f 1 2 3\n"));
    let options = LoadOptions { max_file_bytes: 10, ..LoadOptions::default() };
    assert!(matches!(
        seamlit_io::load(&path, &options).unwrap_err(),
        IoError::TooLarge { limit: 10, .. }
    ));
    let err =
        seamlit_io::load(&dir.path().join("absent.obj"), &LoadOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::Io { .. }) && err.to_string().contains("absent.obj"), "{err}");
    let err = seamlit_io::load(&write(dir.path(), "x.stl", "solid"), &LoadOptions::default())
        .unwrap_err();
    assert!(matches!(err, IoError::UnknownFormat { .. }), "{err}");
}
