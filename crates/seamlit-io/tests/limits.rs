//! Resource limits of the readers: the caps in `LoadOptions` (file size, elements, texture
//! size, decoded texture bytes per model) are enforced before the memory is spent, and node
//! hierarchies of any depth are read without recursion.

use std::path::{Path, PathBuf};

use seamlit_io::{IoError, LoadOptions};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

const TRIANGLE: &str =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n";

/// A one-triangle glTF (positions in a data: URI) whose scene is a chain of `depth` nodes,
/// each translated by +1 in x; the last one holds the mesh.
fn chain(depth: usize) -> String {
    let floats: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let bytes: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    let mut data = String::new();
    for chunk in bytes.chunks(3) {
        // base64 by hand, to keep the test free of another dependency
        const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let n = chunk.iter().fold(0u32, |n, &b| n << 8 | u32::from(b)) << (8 * (3 - chunk.len()));
        for i in 0..4 {
            data.push(if i <= chunk.len() {
                T[(n >> (18 - 6 * i) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    let mut nodes = Vec::with_capacity(depth);
    for i in 0..depth {
        let next = if i + 1 < depth {
            format!(r#","children":[{}]"#, i + 1)
        } else {
            r#","mesh":0"#.to_owned()
        };
        nodes.push(format!(r#"{{"translation":[1,0,0]{next}}}"#));
    }
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{data}"}}],
"bufferViews":[{{"buffer":0,"byteLength":36}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]}}"#,
        nodes.join(",")
    )
}

#[test]
fn a_node_chain_100000_deep_loads_without_recursion_and_composes_every_transform() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "deep.gltf", chain(100_000).as_bytes());
    // A small stack: a recursive walk would overflow it long before 100,000 levels.
    let handle = std::thread::Builder::new()
        .stack_size(256 * 1024)
        .spawn(move || seamlit_io::load(&path, &LoadOptions::GEOMETRY))
        .unwrap();
    let asset = handle.join().expect("no stack overflow").unwrap();
    assert_eq!(asset.nodes.len(), 100_000);
    assert_eq!(asset.model.objects.len(), 1);
    let transform = asset.model.objects[0].transform.unwrap();
    assert_eq!(transform.w_axis.x, 100_000.0);
}

#[test]
fn the_element_cap_refuses_a_larger_object_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let small = LoadOptions { max_elements: 2, ..LoadOptions::GEOMETRY };
    let obj = write(dir.path(), "t.obj", format!("o tri\n{TRIANGLE}").as_bytes());
    let err = seamlit_io::load(&obj, &small).unwrap_err();
    assert!(
        matches!(&err, IoError::TooManyElements { limit: 2, actual: 3, what, .. } if what.contains("tri")),
        "{err}"
    );
    let gltf = write(dir.path(), "t.gltf", chain(1).as_bytes());
    let err = seamlit_io::load(&gltf, &small).unwrap_err();
    assert!(
        matches!(&err, IoError::TooManyElements { limit: 2, actual: 3, what, .. } if what.contains("accessor 0")),
        "{err}"
    );
    // At the cap, both load.
    let exact = LoadOptions { max_elements: 3, ..LoadOptions::GEOMETRY };
    assert!(seamlit_io::load(&obj, &exact).is_ok());
    assert!(seamlit_io::load(&gltf, &exact).is_ok());
}

#[test]
fn the_file_size_cap_refuses_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(dir.path(), "t.obj", TRIANGLE.as_bytes());
    let options = LoadOptions { max_file_bytes: 10, ..LoadOptions::GEOMETRY };
    let err = seamlit_io::load(&obj, &options).unwrap_err();
    let size = TRIANGLE.len() as u64;
    assert!(matches!(err, IoError::TooLarge { limit: 10, actual, .. } if actual == size), "{err}");
}

#[test]
fn a_texture_over_the_size_cap_is_not_decoded_and_gets_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    image::RgbaImage::from_pixel(8, 4, image::Rgba([255, 0, 0, 255]))
        .save(dir.path().join("albedo.png"))
        .unwrap();
    write(dir.path(), "t.mtl", b"newmtl m\nmap_Kd albedo.png\n");
    let obj = write(dir.path(), "t.obj", format!("mtllib t.mtl\n{TRIANGLE}").as_bytes());
    let capped = LoadOptions { max_texture_size: 7, ..LoadOptions::DEFAULT };
    let asset = seamlit_io::load(&obj, &capped).unwrap();
    assert!(asset.textures[0].image.is_none());
    assert!(
        asset.warnings.iter().any(|w| w.contains("albedo.png") && w.contains("cannot be decoded")),
        "{:?}",
        asset.warnings
    );
    let fits = LoadOptions { max_texture_size: 8, ..LoadOptions::DEFAULT };
    let asset = seamlit_io::load(&obj, &fits).unwrap();
    let image = asset.textures[0].image.as_ref().expect("decoded");
    assert_eq!(image.dimensions(), (8, 4));
}

/// An OBJ whose three materials use a.png (8 x 4), b.png (4 x 4) and c.png (8 x 8): 128, 64
/// and 256 bytes decoded (RGBA8).
fn three_textures(dir: &Path) -> PathBuf {
    for (name, w, h) in [("a.png", 8, 4), ("b.png", 4, 4), ("c.png", 8, 8)] {
        image::RgbaImage::from_pixel(w, h, image::Rgba([0, 255, 0, 255]))
            .save(dir.join(name))
            .unwrap();
    }
    write(
        dir,
        "t.mtl",
        b"newmtl m\nmap_Kd a.png\nnewmtl n\nmap_Kd b.png\nnewmtl o\nmap_Kd c.png\n",
    );
    write(dir, "t.obj", format!("mtllib t.mtl\n{TRIANGLE}").as_bytes())
}

fn decoded(asset: &seamlit_io::Asset) -> Vec<Option<(u32, u32)>> {
    asset.textures.iter().map(|t| t.image.as_ref().map(|i| i.dimensions())).collect()
}

#[test]
fn textures_past_the_model_budget_are_refused_in_file_order_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let obj = three_textures(dir.path());
    let all = seamlit_io::load(&obj, &LoadOptions::DEFAULT).unwrap();
    assert_eq!(decoded(&all), [Some((8, 4)), Some((4, 4)), Some((8, 8))]);
    assert!(all.warnings.is_empty(), "{:?}", all.warnings);

    // 200 bytes: a (128) and b (64) fit, c (256 more) does not.
    let options = LoadOptions { max_texture_bytes: 200, ..LoadOptions::DEFAULT };
    let asset = seamlit_io::load(&obj, &options).unwrap();
    assert_eq!(decoded(&asset), [Some((8, 4)), Some((4, 4)), None]);
    assert_eq!(asset.warnings.len(), 1, "{:?}", asset.warnings);
    let warning = &asset.warnings[0];
    assert!(
        warning.contains("\"c.png\" needs 256 bytes")
            && warning.contains("192 bytes")
            && warning.contains("budget of 200 bytes"),
        "{warning}"
    );

    // 191 bytes: only a fits (a and b would take 192).
    let options = LoadOptions { max_texture_bytes: 191, ..LoadOptions::DEFAULT };
    let asset = seamlit_io::load(&obj, &options).unwrap();
    assert_eq!(decoded(&asset), [Some((8, 4)), None, None]);
    assert_eq!(asset.warnings.len(), 2, "{:?}", asset.warnings);

    // No budget at all: nothing is decoded, nothing fails.
    let options = LoadOptions { max_texture_bytes: 0, ..LoadOptions::DEFAULT };
    let asset = seamlit_io::load(&obj, &options).unwrap();
    assert_eq!(decoded(&asset), [None, None, None]);
    assert_eq!(asset.warnings.len(), 3, "{:?}", asset.warnings);
}

/// A glTF whose scene holds `instances` sibling nodes, all instancing one triangle mesh.
fn instances(instances: usize) -> String {
    let one = chain(1);
    let nodes = vec![r#"{"mesh":0}"#; instances].join(",");
    let roots = (0..instances).map(|i| i.to_string()).collect::<Vec<_>>().join(",");
    one.replace(r#""nodes":[{"translation":[1,0,0],"mesh":0}]"#, &format!(r#""nodes":[{nodes}]"#))
        .replace(r#""scenes":[{"nodes":[0]}]"#, &format!(r#""scenes":[{{"nodes":[{roots}]}}]"#))
}

#[test]
fn mesh_instancing_cannot_multiply_a_small_file_past_the_model_cap() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "many.gltf", instances(1000).as_bytes());
    let fits = LoadOptions { max_model_triangles: 1000, ..LoadOptions::GEOMETRY };
    assert_eq!(seamlit_io::load(&path, &fits).unwrap().model.objects.len(), 1000);
    let capped = LoadOptions { max_model_triangles: 999, ..LoadOptions::GEOMETRY };
    let err = seamlit_io::load(&path, &capped).unwrap_err();
    assert!(
        matches!(&err, IoError::TooManyElements { limit: 999, actual: 1000, what, .. } if what.contains("nodes[999]")),
        "{err}"
    );
}

#[test]
fn newell_patches_times_tessellation_are_capped_before_tessellating() {
    let dir = tempfile::tempdir().unwrap();
    // 1000 patches of 16 copies of one point: 32 bytes a patch, 2 * 16^2 triangles each.
    let mut text = String::from("1000\n");
    for _ in 0..1000 {
        text.push_str("1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1\n");
    }
    text.push_str("1\n0,0,0\n");
    let path = write(dir.path(), "many.bpt", text.as_bytes());
    let fits = LoadOptions { max_model_triangles: 512_000, ..LoadOptions::GEOMETRY };
    assert_eq!(seamlit_io::load(&path, &fits).unwrap().model.objects.len(), 1000);
    let capped = LoadOptions { max_model_triangles: 511_999, ..LoadOptions::GEOMETRY };
    let err = seamlit_io::load(&path, &capped).unwrap_err();
    assert!(
        matches!(&err, IoError::TooManyElements { limit: 511_999, actual: 512_000, .. }),
        "{err}"
    );
}
