//! The page's files: a model dropped with its side files is read from memory, and its
//! download holds exactly the files the command line's library calls write for the same
//! model read from disk (load, `fix_asset` with `seamlit fix`'s defaults, save).

use std::io::Read as _;
use std::path::{Path, PathBuf};

use seamlit_io::job::{FixJob, fix_asset};
use seamlit_io::{LoadOptions, SaveOptions};
use seamlit_web::files::{self, Download};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `seamlit fix INPUT -o OUT/NAME`: the files written under `OUT`, by relative path, sorted.
fn command_line(input: &Path, name: &str) -> Vec<(String, Vec<u8>)> {
    let out = tempfile::tempdir().unwrap();
    let mut asset = seamlit_io::load(input, &LoadOptions::GEOMETRY).unwrap();
    fix_asset(&mut asset, &FixJob::DEFAULT).unwrap();
    seamlit_io::save(&asset, &out.path().join(name), &SaveOptions::default()).unwrap();
    let mut found = Vec::new();
    let mut folders = vec![out.path().to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else {
                let relative = path.strip_prefix(out.path()).unwrap();
                let relative = relative.to_string_lossy().replace('\\', "/");
                found.push((relative, std::fs::read(&path).unwrap()));
            }
        }
    }
    found.sort();
    found
}

/// What the page does with dropped files: picks the model, reads it from memory, fixes it,
/// writes the download.
fn page(files: Vec<(String, Vec<u8>)>) -> Result<Download, String> {
    let names: Vec<String> = files.iter().map(|(n, _)| n.clone()).collect();
    let model = files::pick_model(&names).unwrap().to_owned();
    let mut asset = files::read(&model, files)?;
    fix_asset(&mut asset, &FixJob::DEFAULT).map_err(|e| e.to_string())?;
    Ok(files::write(&model, &asset)?.0)
}

/// The files of `folder` (below the repository), named `prefix` + their name.
fn dropped(folder: &str, prefix: &str) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(repo().join(folder))
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| {
            (
                format!("{prefix}{}", p.file_name().unwrap().to_string_lossy()),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect();
    files.sort();
    files
}

/// The entries of a zip, by name, sorted.
fn unzip(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
    let mut entries = Vec::new();
    for i in 0..archive.len() {
        let mut entry = archive.by_index(i).unwrap();
        let mut bytes = Vec::new();
        entry.read_to_end(&mut bytes).unwrap();
        entries.push((entry.name().to_owned(), bytes));
    }
    entries.sort();
    entries
}

#[test]
fn a_gltf_with_its_buffer_and_images_comes_out_as_the_command_lines_glb() {
    let expected = command_line(
        &repo().join("assets/models/clearcoat_test/ClearCoatTest.gltf"),
        "ClearCoatTest.glb",
    );
    assert_eq!(expected.len(), 1);
    // Picked in a dialog (no folders), and dropped as a folder.
    for prefix in ["", "clearcoat_test/"] {
        let download = page(dropped("assets/models/clearcoat_test", prefix)).unwrap();
        assert_eq!(download.name, "ClearCoatTest.glb");
        assert!(
            download.bytes == expected[0].1,
            "{prefix:?}: the page's GLB is not the command line's"
        );
    }
}

#[test]
fn a_gltf_without_its_buffer_is_one_line_naming_it() {
    let files: Vec<_> = dropped("assets/models/clearcoat_test", "")
        .into_iter()
        .filter(|(n, _)| !n.ends_with(".bin"))
        .collect();
    let error = page(files).unwrap_err();
    assert!(
        error.starts_with("ClearCoatTest.gltf") && error.contains("ClearCoatTest.bin"),
        "{error}"
    );
    assert!(!error.contains('\n'), "{error}");
}

#[test]
fn an_obj_with_its_material_library_and_texture_comes_out_as_the_command_lines_files() {
    let folder = tempfile::tempdir().unwrap();
    let spot =
        std::fs::read_to_string(repo().join("assets/models/spot/spot_triangulated.obj")).unwrap();
    let obj = format!("mtllib spot.mtl\nusemtl cow\n{spot}");
    let mtl = "newmtl cow\nKd 1 1 1\nmap_Kd textures/spot_texture.png\n";
    let png = std::fs::read(repo().join("assets/models/spot/spot_texture.png")).unwrap();
    std::fs::create_dir(folder.path().join("textures")).unwrap();
    std::fs::write(folder.path().join("spot.obj"), &obj).unwrap();
    std::fs::write(folder.path().join("spot.mtl"), mtl).unwrap();
    std::fs::write(folder.path().join("textures/spot_texture.png"), &png).unwrap();
    let expected = command_line(&folder.path().join("spot.obj"), "spot.obj");
    let names: Vec<&str> = expected.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["spot.mtl", "spot.obj", "textures/spot_texture.png"]);

    let files = vec![
        ("spot.obj".to_owned(), obj.into_bytes()),
        ("spot.mtl".to_owned(), mtl.as_bytes().to_vec()),
        ("textures/spot_texture.png".to_owned(), png),
    ];
    let download = page(files).unwrap();
    assert_eq!(download.name, "spot.zip");
    assert_eq!(download.output, Path::new("spot.obj"));
    assert!(
        unzip(&download.bytes) == expected,
        "the page's zip does not hold the command line's files"
    );
}

#[test]
fn models_the_page_does_not_read_get_one_line() {
    let fbx = page(vec![("cube.fbx".to_owned(), b"Kaydara FBX Binary".to_vec())]).unwrap_err();
    assert!(fbx.starts_with("cube.fbx: FBX needs the command line"), "{fbx}");
    let text = page(vec![("notes.txt".to_owned(), b"hello".to_vec())]).unwrap_err();
    assert!(text.starts_with("notes.txt: not a model file"), "{text}");
    let broken = page(vec![("a.glb".to_owned(), b"glTF\x02\0\0\0".to_vec())]).unwrap_err();
    assert!(broken.starts_with("a.glb") && !broken.contains('\n'), "{broken}");
}

#[test]
fn a_usdz_comes_out_as_the_command_lines_package() {
    for model in
        ["assets/models/usd/head_body.usdz", "assets/models/usd/others/Rigged/RiggedFigure.usdz"]
    {
        let input = repo().join(model);
        let name = input.file_name().unwrap().to_string_lossy().into_owned();
        let expected = command_line(&input, &name);
        assert_eq!(expected.len(), 1);
        let download = page(vec![(name.clone(), std::fs::read(&input).unwrap())]).unwrap();
        assert_eq!(download.name, name);
        assert!(
            download.bytes == expected[0].1,
            "{model}: the page's package is not the command line's"
        );
    }
    let stage = page(vec![("a.usda".to_owned(), b"#usda 1.0\n".to_vec())]).unwrap_err();
    assert!(stage.starts_with("a.usda: the page reads USD stages packed as .usdz"), "{stage}");
}
