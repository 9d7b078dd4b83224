//! Malformed OBJ files made by the test: each gets the precise error (file, line, what) and
//! no panic.

use std::path::{Path, PathBuf};

use seamlit_io::{IoError, LoadOptions, Syntax};

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

/// The parser names the line of a bad index itself: past polygons (a face of n corners is
/// n - 2 triangles), points, comments and vertices defined between faces, and in a later
/// block of a file read in blocks of a megabyte.
#[test]
fn an_index_out_of_range_is_placed_past_polygons_and_blocks() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "{QUAD}f 1 2 3 4\nf 4 3 2 1\nf 1 2\n# comment\n\nf 1 2 3\nv 0 0 1\nf 1 2 3 4 5\nf 5 4 3 6\n"
    );
    let path = write(dir.path(), "runs.obj", &text);
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::ReferenceOutOfRange { line: 14, what: "vertex", index: 6, count: 5, .. }
        ),
        "{err}"
    );
    // Over two megabytes of faces, then a relative index reaching before the first vertex.
    let mut text = QUAD.to_owned();
    let faces = 200_000;
    for _ in 0..faces {
        text.push_str("f 1 2 3 4    \n");
    }
    text.push_str("vt 0 0\nf 1/1 2/1 3/-2\n");
    let path = write(dir.path(), "blocks.obj", &text);
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::ReferenceOutOfRange {
                line,
                what: "texture coordinate",
                index: -2,
                count: 1,
                ..
            } if line == 5 + faces + 2
        ),
        "{err}"
    );
}

#[test]
fn syntax_errors_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "short.obj", "v 0 0 0\nv 1 0\nv 1 1 0\nf 1 2 3\n");
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    let short = Syntax::TooFewNumbers { keyword: "v", needed: 3, found: 2 };
    assert!(matches!(&err, IoError::Syntax { line: 2, kind, .. } if *kind == short), "{err}");
    assert!(err.to_string().ends_with("short.obj:2: `v` needs 3 numbers, found 2"), "{err}");
    let path = write(dir.path(), "word.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 two 3\n");
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    let word = Syntax::NotAnIndex { corner: "two".into(), found: "two".into() };
    assert!(matches!(&err, IoError::Syntax { line: 4, kind, .. } if *kind == word), "{err}");
    let message = r#"word.obj:4: face corner "two": expected an index, found "two""#;
    assert!(err.to_string().ends_with(message), "{err}");
    let path = write(dir.path(), "w.obj", "v 0 0 0 0\n");
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    let zero = Syntax::ZeroW { w: 0.0 };
    assert!(matches!(&err, IoError::Syntax { line: 1, kind, .. } if *kind == zero), "{err}");
    assert!(err.to_string().ends_with("w.obj:1: `v`: w = 0 cannot scale a position"), "{err}");
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
fn an_mtl_statement_seamlit_cannot_read_is_named_with_its_line_and_refuses_nothing() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "bad.mtl", "newmtl red\nKd 1 0 0\nNs many\n");
    let path =
        write(dir.path(), "bad.obj", &format!("mtllib bad.mtl\n{QUAD}usemtl red\nf 1 2 3 4\n"));
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(asset.materials[0].base_color, [1.0, 0.0, 0.0, 1.0]);
    assert_eq!(asset.materials[0].shininess, 32.0, "the default");
    assert_eq!(asset.warnings.len(), 1, "{:?}", asset.warnings);
    assert!(asset.warnings[0].contains("bad.mtl:3: `Ns many`"), "{:?}", asset.warnings);
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

/// Writes raw bytes (text that is not UTF-8, UTF-16).
fn write_bytes(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn a_file_without_triangles_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let garbage: Vec<u8> = (0..4000u32).map(|i| b"xq7 #\tzk\n"[(i * 7 % 9) as usize]).collect();
    let files = [
        write(dir.path(), "empty.obj", ""),
        write(dir.path(), "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
        // Faces of fewer than three corners, lines and points are no surface.
        write(dir.path(), "lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nl 1 2 3\np 1\n"),
        // Text whose every line is a statement this reader ignores.
        write_bytes(dir.path(), "garbage.obj", &garbage),
    ];
    for path in files {
        let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
        match &err {
            IoError::NoTriangles { path: p } => assert_eq!(p, &path),
            other => panic!("{}: unexpected {other}", path.display()),
        }
        let message = err.to_string();
        assert!(message.starts_with(&path.display().to_string()), "{message}");
        assert!(!message.contains('\n'), "{message}");
    }
    // A glTF without a mesh too.
    let path = write(dir.path(), "empty.gltf", r#"{"asset":{"version":"2.0"}}"#);
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::NoTriangles { .. }), "{err}");
}

#[test]
fn a_nul_byte_or_invalid_utf8_in_a_statement_names_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &[u8], usize, seamlit_io::NotText); 4] = [
        (
            "nul.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nvt 0\x00 0\n",
            5,
            seamlit_io::NotText::Nul,
        ),
        // A NUL in an unknown statement: binary data, not ignored.
        (
            "binary.obj",
            b"v 0 0 0\nv 1 0 0\n\x7fELF\x02\x01\x01\x00\nv 0 1 0\nf 1 2 3\n",
            3,
            seamlit_io::NotText::Nul,
        ),
        // Latin-1 where a number belongs (a name in Latin-1 is read: others_files.rs).
        (
            "latin1.obj",
            b"o cafe\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \xb3\n",
            5,
            seamlit_io::NotText::InvalidUtf8,
        ),
        // UTF-16 without a byte-order mark.
        ("utf16.obj", b"v\x00 \x000\x00 \x000\x00 \x000\x00\n\x00", 1, seamlit_io::NotText::Nul),
    ];
    for (name, bytes, line, problem) in cases {
        let path = write_bytes(dir.path(), name, bytes);
        let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
        match &err {
            IoError::NotText { path: p, line: l, problem: q } => {
                assert_eq!((p, *l, *q), (&path, line, problem), "{name}");
            }
            other => panic!("{name}: unexpected {other}"),
        }
        assert!(err.to_string().contains(&format!("{name}:{line}:")), "{err}");
    }
    // Comments may hold anything.
    let path = write_bytes(
        dir.path(),
        "comment.obj",
        b"# caf\xe9 \x00\n  # \xff\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(asset.model.triangle_count(), 1);
}

/// The text as UTF-16 with its byte-order mark, little or big endian.
fn utf16(text: &str, little: bool) -> Vec<u8> {
    let mut out = if little { vec![0xFF, 0xFE] } else { vec![0xFE, 0xFF] };
    for unit in text.encode_utf16() {
        out.extend(if little { unit.to_le_bytes() } else { unit.to_be_bytes() });
    }
    out
}

#[test]
fn utf16_and_utf8_byte_order_marks_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let text = "o caf\u{e9}\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
    let plain = seamlit_io::load(&write(dir.path(), "plain.obj", text), &LoadOptions::default())
        .unwrap()
        .model;
    assert_eq!(plain.triangle_count(), 2);
    assert_eq!(plain.objects[0].name, "caf\u{e9}");
    for (name, bytes) in [
        ("le.obj", utf16(text, true)),
        ("be.obj", utf16(text, false)),
        ("bom.obj", [b"\xEF\xBB\xBF".as_slice(), text.as_bytes()].concat()),
    ] {
        let path = write_bytes(dir.path(), name, &bytes);
        let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
        assert_eq!(asset.model, plain, "{name}");
    }
    // A face index out of range is placed in the decoded text.
    let path = write_bytes(dir.path(), "range16.obj", &utf16("v 0 0 0\nv 1 0 0\nf 1 2 3\n", true));
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(matches!(err, IoError::ReferenceOutOfRange { line: 3, index: 3, .. }), "{err}");
    // An unpaired surrogate on line 2.
    let mut bad = utf16("v 0 0 0\nv ", true);
    bad.extend([0x00, 0xD8]);
    bad.extend(&utf16("1 0 0\n", true)[2..]);
    let path = write_bytes(dir.path(), "surrogate.obj", &bad);
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(
        matches!(err, IoError::NotText { line: 2, problem: seamlit_io::NotText::InvalidUtf16, .. }),
        "{err}"
    );
}
