//! OBJ loading: objects, triangles and shared positions of every OBJ in assets/models,
//! checked against counts made from the file text by independent code (tests/common), plus
//! hand-counted figures from SOURCES.md and the files themselves.

mod common;

use common::{ObjCount, model, shared_positions};
use seamlit_io::{IoError, LoadOptions, TextureSource};

fn check(relative: &str) -> seamlit_io::Asset {
    let expected = ObjCount::of_file(relative);
    let asset = seamlit_io::load(&model(relative), &LoadOptions::default()).unwrap();
    let got: Vec<(&str, usize)> =
        asset.model.objects.iter().map(|o| (o.name.as_str(), o.triangle_count())).collect();
    let want: Vec<(&str, usize)> =
        expected.objects.iter().map(|(n, t, _)| (n.as_str(), *t)).collect();
    assert_eq!(got, want, "{relative}");
    assert_eq!(shared_positions(&asset.model), expected.shared_positions(), "{relative}");
    assert_eq!(asset.model.v_axis, seamlit_mesh::VAxis::Up);
    asset
}

#[test]
fn cornell_box() {
    let asset = check("cornell_box/cornell_box.obj");
    // By hand: 9 `o` statements, but front_wall's only face is commented out: 8 objects
    // (SOURCES.md). floor 3 quads, light/ceiling/back/green/red 1 quad each, blocks 5 quads
    // each: (3 + 5 + 10) quads = 36 triangles.
    assert_eq!(asset.model.objects.len(), 8);
    assert_eq!(asset.model.triangle_count(), 36);
    // SOURCES.md: the walls share 16 positions.
    assert_eq!(shared_positions(&asset.model), 16);
    // The .mtl defines white and red; cornell_box2.mtl is missing (a warning, not an error),
    // and red's textures (names with spaces) are missing files: warnings, no images.
    let names: Vec<&str> = asset.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["white", "red"]);
    let red = &asset.materials[1];
    assert_eq!(red.base_color, [1.0, 0.0, 0.0, 1.0]);
    let diffuse = &asset.textures[red.base_color_texture.as_ref().unwrap().texture];
    assert_eq!(
        diffuse.source,
        TextureSource::File(model("cornell_box/this diffuse texture has spaces.jpg"))
    );
    assert!(diffuse.image.is_none());
    assert!(red.normal_texture.is_some());
    assert!(
        asset.warnings.iter().any(|w| w.contains("cornell_box2.mtl") && w.contains(":9:")),
        "{:?}",
        asset.warnings
    );
    assert!(
        asset.warnings.iter().any(|w| w.contains("this diffuse texture has spaces.jpg")),
        "{:?}",
        asset.warnings
    );
    let floor = &asset.model.objects[0];
    assert_eq!(floor.material, Some(0));
    // `usemtl light` names no loaded material.
    assert_eq!(asset.model.objects[1].material, None);
}

#[test]
fn cornell_box_strict_refuses_the_missing_library() {
    let err = seamlit_io::load(
        &model("cornell_box/cornell_box.obj"),
        &LoadOptions::default().with_strict(true),
    )
    .unwrap_err();
    match &err {
        IoError::MissingFile { line: Some(9), missing, .. } => {
            assert!(missing.ends_with("cornell_box2.mtl"));
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn groups() {
    let asset = check("groups.obj");
    // SOURCES.md: 14 `g` groups plus one `o`, 2,308 triangles; every face has `vn`.
    assert_eq!(asset.model.objects.len(), 15);
    assert_eq!(asset.model.triangle_count(), 2308);
    assert_eq!(asset.model.objects[14].name, "something!");
    assert!(asset.model.objects.iter().all(|o| o.normals.is_some() && o.uvs.is_none()));
}

#[test]
fn spot() {
    for file in ["spot/spot_triangulated.obj", "spot/spot_quadrangulated.obj"] {
        let asset = check(file);
        assert_eq!(asset.model.objects.len(), 1);
        // 5,856 triangles = 2,928 quads x 2 (counted with `grep -c '^f'`).
        assert_eq!(asset.model.triangle_count(), 5856, "{file}");
        assert!(asset.model.objects[0].uvs.is_some());
    }
}

/// The geometry parser follows tobj's rules: on every shared OBJ, it gives what tobj gives
/// (single index, triangulated): the same objects, names, vertex arrays and triangles.
#[test]
fn the_parser_agrees_with_tobj() {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    for file in [
        "cornell_box/cornell_box.obj",
        "groups.obj",
        "spot/spot_triangulated.obj",
        "spot/spot_quadrangulated.obj",
    ] {
        let (models, _) = tobj::load_obj(model(file), &options).unwrap();
        let models: Vec<_> = models.into_iter().filter(|m| !m.mesh.indices.is_empty()).collect();
        let asset = seamlit_io::load(&model(file), &LoadOptions::default()).unwrap();
        assert_eq!(asset.model.objects.len(), models.len(), "{file}");
        for (ours, theirs) in asset.model.objects.iter().zip(&models) {
            assert_eq!(ours.name, theirs.name, "{file}");
            let flat: Vec<f32> = ours.positions.iter().flat_map(|p| p.to_array()).collect();
            assert_eq!(flat, theirs.mesh.positions, "{file} {}", ours.name);
            let uvs: Vec<f32> = ours.uvs.iter().flatten().flat_map(|t| t.to_array()).collect();
            assert_eq!(uvs, theirs.mesh.texcoords, "{file} {}", ours.name);
            let normals: Vec<f32> =
                ours.normals.iter().flatten().flat_map(|n| n.to_array()).collect();
            assert_eq!(normals, theirs.mesh.normals, "{file} {}", ours.name);
            let indices: Vec<u32> = ours.triangles.iter().flatten().copied().collect();
            assert_eq!(indices, theirs.mesh.indices, "{file} {}", ours.name);
        }
    }
}

/// `usemtl` inside an object with faces starts a part of the same name; an `o` right after
/// renames that empty part: it is a new object, not a continuation of the first (the parser
/// merged it back, losing the name "leg", until tests/obj_generated.rs found it).
#[test]
fn an_object_named_after_a_usemtl_split_keeps_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("split.obj");
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
                f 1 2 3\nusemtl red\no leg\nf 1 2 4\nf 2 3 4\nusemtl blue\nf 1 3 4\n";
    std::fs::write(&path, text).unwrap();
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    // No material library: `red` and `blue` resolve to no material, so the second
    // `usemtl` does not split "leg" (as in tobj).
    let objects: Vec<(&str, &[[u32; 3]])> =
        asset.model.objects.iter().map(|o| (o.name.as_str(), o.triangles.as_slice())).collect();
    assert_eq!(
        objects,
        [("unnamed_object", &[[0, 1, 2]][..]), ("leg", &[[0, 1, 2], [1, 3, 2], [0, 3, 2]][..])]
    );
}

/// `seamlit_obj::parse` (a file held in memory: the web page's) reads what `load` reads from
/// the file: the same model, materials, warnings and source text, for every committed OBJ
/// (UTF-16 files and those with material libraries and textures among them), and writes the
/// same bytes back.
#[test]
fn an_obj_in_memory_reads_as_the_file_does() {
    let mut files = Vec::new();
    let mut stack = vec![model("")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj")) {
                files.push(path);
            }
        }
    }
    assert!(files.len() >= 4, "{files:?}");
    // And one of several megabytes, cut into several blocks (parse.rs reads a megabyte a block).
    let big = tempfile::tempdir().unwrap();
    let mut text = String::new();
    let n = 400;
    for j in 0..=n {
        for i in 0..=n {
            text.push_str(&format!("v {i}.25 {}.5 {j}.125\n", (i * j) % 7));
        }
    }
    for j in 0..n {
        text.push_str(&format!("o strip{j}\n"));
        for i in 0..n {
            let a = j * (n + 1) + i + 1;
            text.push_str(&format!("f {a} {} {} {}\n", a + 1, a + n + 2, a + n + 1));
        }
    }
    assert!(text.len() > 3 << 20, "{} bytes", text.len());
    std::fs::write(big.path().join("big.obj"), &text).unwrap();
    files.push(big.path().join("big.obj"));
    for path in files {
        let loaded = seamlit_io::obj::load(&path, &LoadOptions::DEFAULT);
        let bytes = std::fs::read(&path).unwrap();
        let parsed = seamlit_io::obj::parse(&bytes, &path, &LoadOptions::DEFAULT);
        let (loaded, parsed) = match (loaded, parsed) {
            (Ok(a), Ok(b)) => (a, b),
            (Err(a), Err(b)) => {
                assert_eq!(a.to_string(), b.to_string(), "{}", path.display());
                continue;
            }
            (a, b) => panic!("{}: {:?} against {:?}", path.display(), a.err(), b.err()),
        };
        assert!(loaded.model == parsed.model, "{}: the model", path.display());
        assert_eq!(loaded.materials.len(), parsed.materials.len(), "{}", path.display());
        assert_eq!(loaded.warnings, parsed.warnings, "{}", path.display());
        let dir = tempfile::tempdir().unwrap();
        let save = |asset: &seamlit_io::Asset, name: &str| {
            let out = dir.path().join(name).join("out.obj");
            std::fs::create_dir_all(out.parent().unwrap()).unwrap();
            seamlit_io::save(asset, &out, &seamlit_io::SaveOptions::default()).unwrap();
            std::fs::read(&out).unwrap()
        };
        assert!(save(&loaded, "a") == save(&parsed, "b"), "{}: the bytes written", path.display());
    }
}
