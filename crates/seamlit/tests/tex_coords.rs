//! Texture coordinate sets: a material's texture reads the set its `texCoord` names.

use std::path::Path;
use std::process::Command;

use serde_json::json;

/// A glTF quad filling x, y in -1..1 at z = 0, facing +Z, unlit, whose base colour texture
/// (left half red, right half green) reads TEXCOORD_`set`; TEXCOORD_1 runs u from 0 at the
/// left to 1 at the right, TEXCOORD_0 the other way.
fn write_quad(dir: &Path, set: u32) -> std::path::PathBuf {
    let texture = image::RgbaImage::from_fn(2, 1, |x, _| {
        if x == 0 { image::Rgba([255, 0, 0, 255]) } else { image::Rgba([0, 255, 0, 255]) }
    });
    texture.save(dir.join("halves.png")).unwrap();
    let positions = [[-1.0f32, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]];
    let normals = [[0.0f32, 0.0, 1.0]; 4];
    let uv1 = [[0.0f32, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
    let uv0 = uv1.map(|[u, v]| [1.0 - u, v]);
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let mut bin = Vec::new();
    for p in positions.iter().chain(&normals) {
        bin.extend(p.iter().flat_map(|x| x.to_le_bytes()));
    }
    for t in uv0.iter().chain(&uv1) {
        bin.extend(t.iter().flat_map(|x| x.to_le_bytes()));
    }
    bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.join("quad.bin"), &bin).unwrap();
    let view = |offset: usize, length: usize| json!({ "buffer": 0, "byteOffset": offset, "byteLength": length });
    let doc = json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_materials_unlit"],
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "name": "quad", "mesh": 0 }],
        "meshes": [{ "primitives": [{
            "attributes": { "POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TEXCOORD_1": 3 },
            "indices": 4,
            "material": 0
        }] }],
        "materials": [{
            "pbrMetallicRoughness": { "baseColorTexture": { "index": 0, "texCoord": set } },
            "extensions": { "KHR_materials_unlit": {} }
        }],
        "textures": [{ "source": 0, "sampler": 0 }],
        "samplers": [{ "magFilter": 9728, "minFilter": 9728 }],
        "images": [{ "uri": "halves.png" }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
              "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 0.0] },
            { "bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3" },
            { "bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2" },
            { "bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2" },
            { "bufferView": 4, "componentType": 5123, "count": 6, "type": "SCALAR" }
        ],
        "bufferViews": [view(0, 48), view(48, 48), view(96, 32), view(128, 32), view(160, 12)],
        "buffers": [{ "byteLength": bin.len(), "uri": "quad.bin" }]
    });
    let path = dir.join(format!("quad{set}.gltf"));
    std::fs::write(&path, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    path
}

/// `seamlit render` of `input` at 64x64, looking at the quad from +Z.
fn render(input: &Path, out: &Path) -> image::RgbaImage {
    let output = Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .arg("render")
        .arg(input)
        .arg("-o")
        .arg(out)
        .args(["--size", "64x64", "--environment", "none", "--shadows", "off"])
        .output()
        .expect("the binary runs");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    image::open(out).expect("a PNG").to_rgba8()
}

/// Whether pixel (x, 32) is mostly red (true) or mostly green (false).
fn red_at(image: &image::RgbaImage, x: u32) -> bool {
    let p = image.get_pixel(x, 32).0;
    assert!(p[0].abs_diff(p[1]) > 100, "pixel ({x}, 32) is neither red nor green: {p:?}");
    p[0] > p[1]
}

#[test]
fn a_base_colour_texture_reads_the_texture_coordinate_set_it_names() {
    let dir = tempfile::tempdir().unwrap();
    // Set 1: red on the left, green on the right; set 0 (u reversed): the other way round.
    for (set, left_red) in [(1, true), (0, false)] {
        let quad = write_quad(dir.path(), set);
        let image = render(&quad, &dir.path().join(format!("quad{set}.png")));
        assert_eq!(red_at(&image, 20), left_red, "texCoord {set}: left half");
        assert_eq!(red_at(&image, 44), !left_red, "texCoord {set}: right half");
    }
}
