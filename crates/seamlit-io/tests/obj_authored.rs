//! OBJ files as their authors wrote them: concave polygons, vertex colours, materials with
//! empty or unknown names. Every fixture is made here, with expected values computed
//! independently of the loader.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::{DQuat, DVec2, DVec3};
use seamlit_io::LoadOptions;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A star of 33 points (66 corners, every other one reflex) in the plane z = 0.
fn star() -> Vec<DVec2> {
    (0..66)
        .map(|k| {
            let angle = f64::from(k) * std::f64::consts::TAU / 66.0;
            let radius = if k % 2 == 0 { 1.0 } else { 0.45 };
            DVec2::new(angle.cos(), angle.sin()) * radius
        })
        .collect()
}

#[test]
fn a_concave_66_gon_is_ear_clipped_facing_its_normal_with_its_area() {
    let star = star();
    // The polygon's area by the shoelace formula, in its own plane.
    let area = (0..66).map(|i| star[i].perp_dot(star[(i + 1) % 66])).sum::<f64>() / 2.0;
    assert!(area > 0.5, "counter-clockwise, {area}");
    // Placed on a tilted plane away from the origin.
    let rotation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let offset = DVec3::new(5.0, -2.0, 1.0);
    let normal = (rotation * DVec3::Z).as_vec3();
    let mut text = String::from("o star\n");
    for p in &star {
        let q = (rotation * p.extend(0.0) + offset).as_vec3();
        writeln!(text, "v {} {} {}", q.x, q.y, q.z).unwrap();
    }
    text.push('f');
    for k in 1..=66 {
        write!(text, " {k}").unwrap();
    }
    text.push('\n');
    let dir = tempfile::tempdir().unwrap();
    let asset =
        seamlit_io::load(&write(dir.path(), "star.obj", &text), &LoadOptions::default()).unwrap();
    let object = &asset.model.objects[0];
    let p = &object.positions;
    let twice_area = |t: [u32; 3]| {
        let [a, b, c] = t.map(|i| p[i as usize]);
        (b - a).cross(c - a)
    };
    // The fixture is one a fan gets wrong: some fan triangles face backwards.
    let fan_backwards = (1..65)
        .filter(|&k| {
            let [a, b, c] = [0, k, k + 1].map(|i| (rotation * star[i].extend(0.0)).as_vec3());
            (b - a).cross(c - a).dot(normal) < 0.0
        })
        .count();
    assert!(fan_backwards > 10, "{fan_backwards}");

    assert_eq!(object.triangles.len(), 64);
    let mut total = 0.0f64;
    for &t in &object.triangles {
        let n = twice_area(t);
        assert!(n.dot(normal) > 0.0, "{t:?} faces away from the polygon's normal");
        total += f64::from(n.length()) / 2.0;
    }
    assert!((total - area).abs() < 1e-5 * area, "{total} vs {area}");
}

#[test]
fn convex_polygons_keep_the_fan() {
    // A regular octagon and a square, as exporters write n-gons: the fan, exactly.
    let mut text = String::new();
    for k in 0..8 {
        let a = k as f32 * std::f32::consts::TAU / 8.0;
        writeln!(text, "v {} {} 0.5", a.cos(), a.sin()).unwrap();
    }
    text.push_str("f 1 2 3 4 5 6 7 8\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 9 10 11 12\n");
    let dir = tempfile::tempdir().unwrap();
    let asset =
        seamlit_io::load(&write(dir.path(), "convex.obj", &text), &LoadOptions::default()).unwrap();
    let fan: Vec<[u32; 3]> =
        (1..7).map(|k| [0, k, k + 1]).chain([[8, 9, 10], [8, 10, 11]]).collect();
    assert_eq!(asset.model.objects[0].triangles, fan);
}

#[test]
fn a_self_intersecting_polygon_keeps_its_fan() {
    // A bow tie has no right triangulation: what tobj gives stays.
    let text = "v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n";
    let dir = tempfile::tempdir().unwrap();
    let asset =
        seamlit_io::load(&write(dir.path(), "bow.obj", text), &LoadOptions::default()).unwrap();
    assert_eq!(asset.model.objects[0].triangles, [[0, 1, 2], [0, 2, 3]]);
}

/// Per triangle corner, the colour's bits.
fn corner_colors(object: &seamlit_mesh::Object) -> Vec<[u32; 4]> {
    let colors = object.colors.as_ref().expect("colours");
    object
        .triangles
        .iter()
        .flatten()
        .map(|&i| colors[i as usize].to_array().map(f32::to_bits))
        .collect()
}

#[test]
fn vertex_colours_are_read_and_written_back_to_gltf_and_obj() {
    let text = "o tile\n\
                v 0 0 0 1 0 0\n\
                v 1 0 0 0 1 0\n\
                v 1 1 0 0 0 1 0.25\n\
                v 0 1 0 0.1 0.2 0.3\n\
                vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
                f 1/1 2/2 3/3 4/4\n";
    let dir = tempfile::tempdir().unwrap();
    let asset =
        seamlit_io::load(&write(dir.path(), "tile.obj", text), &LoadOptions::default()).unwrap();
    let object = &asset.model.objects[0];
    let colors: Vec<[f32; 4]> =
        object.colors.as_ref().unwrap().iter().map(|c| c.to_array()).collect();
    assert_eq!(
        colors,
        [[1.0, 0.0, 0.0, 1.0], [0.0, 1.0, 0.0, 1.0], [0.0, 0.0, 1.0, 0.25], [0.1, 0.2, 0.3, 1.0]]
    );
    let expected = corner_colors(object);
    for name in ["back.glb", "back.gltf", "back.obj"] {
        let out = dir.path().join(name);
        seamlit_io::save(&asset, &out, &seamlit_io::SaveOptions::default()).unwrap();
        let back = seamlit_io::load(&out, &LoadOptions::default()).unwrap();
        assert_eq!(corner_colors(&back.model.objects[0]), expected, "{name}");
    }
}

#[test]
fn colours_on_some_vertices_only_are_dropped_with_a_warning() {
    let text = "o part\nv 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 0 0 1\nf 1 2 3\n";
    let dir = tempfile::tempdir().unwrap();
    let asset =
        seamlit_io::load(&write(dir.path(), "some.obj", text), &LoadOptions::default()).unwrap();
    assert_eq!(asset.model.objects[0].colors, None);
    assert!(
        asset.warnings.iter().any(|w| w.contains("\"part\"") && w.contains("vertex colours")),
        "{:?}",
        asset.warnings
    );
    // Five numbers are neither a w nor a colour.
    let path = write(dir.path(), "five.obj", "v 0 0 0\nv 1 0 0 1 0\nv 0 1 0\nf 1 2 3\n");
    let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
    assert!(matches!(err, seamlit_io::IoError::Syntax { line: 2, .. }), "{err}");
}

/// A glTF of one triangle whose COLOR_0 (normalised integers of `component_type`, `kind`
/// VEC3 or VEC4) is `colors`, each element `stride` bytes apart.
fn gltf_with_colors(component_type: u32, kind: &str, stride: usize, colors: &[u8]) -> String {
    let positions: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let mut buffer = positions.clone();
    buffer.extend(colors);
    while !buffer.len().is_multiple_of(4) {
        buffer.push(0);
    }
    let data = base64::encode(&buffer);
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"COLOR_0":1}}}}]}}],
        "buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{data}"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":{},"byteStride":{stride}}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
        {{"bufferView":1,"componentType":{component_type},"normalized":true,"count":3,"type":"{kind}"}}]}}"#,
        buffer.len(),
        colors.len()
    )
}

#[test]
fn gltf_color_0_is_read_as_rgb_or_rgba_of_normalised_integers() {
    let dir = tempfile::tempdir().unwrap();
    // Unsigned bytes, RGB (padded to 4 bytes per element, as glTF requires): alpha 1.
    let bytes = [255, 0, 51, 0, 0, 255, 0, 0, 102, 102, 102, 0];
    let path = write(dir.path(), "u8.gltf", &gltf_with_colors(5121, "VEC3", 4, &bytes));
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert_colors(&asset, [[1.0, 0.0, 0.2, 1.0], [0.0, 1.0, 0.0, 1.0], [0.4, 0.4, 0.4, 1.0]]);
    // Unsigned shorts, RGBA.
    let shorts: Vec<u8> = [65535u16, 0, 0, 32768, 0, 65535, 0, 65535, 13107, 13107, 13107, 0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let path = write(dir.path(), "u16.gltf", &gltf_with_colors(5123, "VEC4", 8, &shorts));
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert_colors(
        &asset,
        [[1.0, 0.0, 0.0, 32768.0 / 65535.0], [0.0, 1.0, 0.0, 1.0], [0.2, 0.2, 0.2, 0.0]],
    );
}

/// The first object's colours are `expected`, to rounding (n / 255 or n / 65535 in f32).
fn assert_colors(asset: &seamlit_io::Asset, expected: [[f32; 4]; 3]) {
    let colors = asset.model.objects[0].colors.as_ref().expect("colours");
    assert_eq!(colors.len(), 3);
    for (got, want) in colors.iter().zip(expected) {
        assert!(got.abs_diff_eq(glam::Vec4::from_array(want), 1e-6), "{got} vs {want:?}");
    }
}

const TRIANGLES: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";

#[test]
fn a_material_without_a_name_is_read() {
    let dir = tempfile::tempdir().unwrap();
    // As Blender 2.61 writes it: `newmtl` and `usemtl` with nothing after them.
    write(dir.path(), "m.mtl", "newmtl\nKd 1 0 0\n\nnewmtl blue\nKd 0 0 1\n");
    let text = format!("mtllib m.mtl\n{TRIANGLES}usemtl\nf 1 2 3\nusemtl blue\nf 2 4 3\n");
    let asset =
        seamlit_io::load(&write(dir.path(), "m.obj", &text), &LoadOptions::default()).unwrap();
    assert!(asset.warnings.is_empty(), "{:?}", asset.warnings);
    let names: Vec<&str> = asset.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["", "blue"]);
    assert_eq!(asset.materials[0].base_color, [1.0, 0.0, 0.0, 1.0]);
    let materials: Vec<Option<usize>> = asset.model.objects.iter().map(|o| o.material).collect();
    assert_eq!(materials, [Some(0), Some(1)]);
}

#[test]
fn a_usemtl_of_a_material_no_library_defines_gets_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.mtl", "newmtl red\nKd 1 0 0\n");
    let text = format!(
        "mtllib m.mtl\n{TRIANGLES}usemtl red\nf 1 2 3\nusemtl green\nf 2 4 3\nusemtl green\nf 1 2 4\n"
    );
    let path = write(dir.path(), "m.obj", &text);
    let asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(asset.warnings.len(), 1, "{:?}", asset.warnings);
    let warning = &asset.warnings[0];
    assert!(warning.contains("m.obj:8:") && warning.contains("usemtl green"), "{warning}");
    assert_eq!(asset.model.objects[1].material, None);
    // Without any library, the same.
    let text = format!("{TRIANGLES}usemtl green\nf 1 2 3\n");
    let asset =
        seamlit_io::load(&write(dir.path(), "bare.obj", &text), &LoadOptions::default()).unwrap();
    assert_eq!(asset.warnings.len(), 1, "{:?}", asset.warnings);
    assert!(asset.warnings[0].contains("bare.obj:5:"), "{:?}", asset.warnings);
}
