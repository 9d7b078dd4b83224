//! The metallic-roughness inputs and KHR_lights_punctual lights of a glTF file reach the
//! asset: every material field the renderer's PBR model reads, and each light placed by its
//! node.

use std::f32::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};

use glam::Vec3;
use seamlit_io::{AlphaMode, LoadOptions, PunctualKind};
use serde_json::{Value, json};

/// A one-triangle glTF document with `material` on its primitive, `images` textures (one per
/// image, the images being files that do not exist: a warning each, the references stay) and
/// `extra` merged into the root.
fn document(material: &Value, images: usize, extra: &Value) -> Value {
    let positions: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let bytes: Vec<u8> = positions.iter().flat_map(|x| x.to_le_bytes()).collect();
    let mut doc = json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "name": "tri", "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "material": 0 }] }],
        "materials": [material],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
              "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0] }
        ],
        "bufferViews": [{ "buffer": 0, "byteOffset": 0, "byteLength": 36 }],
        "buffers": [{ "byteLength": 36, "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&bytes)) }],
        "images": (0..images).map(|i| json!({ "uri": format!("missing{i}.png") })).collect::<Vec<_>>(),
        "textures": (0..images).map(|i| json!({ "source": i })).collect::<Vec<_>>(),
    });
    for (key, value) in extra.as_object().into_iter().flatten() {
        match (doc.get_mut(key), value) {
            (Some(Value::Array(list)), Value::Array(more)) => list.extend(more.iter().cloned()),
            _ => doc[key] = value.clone(),
        }
    }
    doc
}

fn load(dir: &Path, name: &str, doc: &Value) -> seamlit_io::Asset {
    let path: PathBuf = dir.join(name);
    std::fs::write(&path, serde_json::to_vec(doc).unwrap()).unwrap();
    seamlit_io::load(&path, &LoadOptions::default()).unwrap()
}

#[test]
fn every_metallic_roughness_input_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let material = json!({
        "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.4, 0.3, 0.9],
            "metallicFactor": 0.7,
            "roughnessFactor": 0.2,
            "metallicRoughnessTexture": {
                "index": 1,
                "extensions": { "KHR_texture_transform": { "scale": [2.0, 3.0] } }
            }
        },
        "occlusionTexture": { "index": 2, "strength": 0.6 },
        "emissiveTexture": { "index": 0 },
        "emissiveFactor": [1.0, 0.5, 0.25],
        "alphaMode": "MASK",
        "alphaCutoff": 0.3,
        "doubleSided": true,
        "extensions": {
            "KHR_materials_emissive_strength": { "emissiveStrength": 4.0 },
            "KHR_materials_unlit": {}
        }
    });
    let asset = load(dir.path(), "pbr.gltf", &document(&material, 3, &json!({})));
    let m = &asset.materials[0];
    assert_eq!(m.base_color, [0.5, 0.4, 0.3, 0.9]);
    assert_eq!((m.metallic, m.roughness), (0.7, 0.2));
    let mr = m.metallic_roughness_texture.as_ref().unwrap();
    assert_eq!(mr.texture, 1);
    assert_eq!(mr.transform.unwrap().scale, [2.0, 3.0]);
    assert_eq!(m.occlusion_texture.as_ref().unwrap().texture, 2);
    assert_eq!(m.occlusion_strength, 0.6);
    assert_eq!(m.emissive_texture.as_ref().unwrap().texture, 0);
    // emissiveFactor times emissiveStrength.
    assert_eq!(m.emissive, [4.0, 2.0, 1.0]);
    assert_eq!(m.alpha_mode, AlphaMode::Mask { cutoff: 0.3 });
    assert!(m.double_sided && m.unlit);
}

#[test]
fn a_texture_transform_texcoord_overrides_the_slots() {
    // KHR_texture_transform: "texCoord: overrides the textureInfo texCoord value if
    // supplied". Base colour and normal map name set 0 and their transform set 1; occlusion
    // names set 1 and has a transform without texCoord, so it keeps 1; emissive has none.
    let dir = tempfile::tempdir().unwrap();
    let transform = |set: Option<u32>| match set {
        Some(set) => json!({ "KHR_texture_transform": { "offset": [0.5, 0.0], "texCoord": set } }),
        None => json!({ "KHR_texture_transform": { "offset": [0.5, 0.0] } }),
    };
    let material = json!({
        "pbrMetallicRoughness": {
            "baseColorTexture": { "index": 0, "texCoord": 0, "extensions": transform(Some(1)) }
        },
        "normalTexture": { "index": 1, "extensions": transform(Some(1)) },
        "occlusionTexture": { "index": 2, "texCoord": 1, "extensions": transform(None) },
        "emissiveTexture": { "index": 0, "texCoord": 1 }
    });
    let asset = load(dir.path(), "sets.gltf", &document(&material, 3, &json!({})));
    let m = &asset.materials[0];
    let slot = |r: Option<&seamlit_io::TextureRef>| {
        let r = r.unwrap();
        (r.tex_coord, r.transform.map(|t| t.offset))
    };
    assert_eq!(slot(m.base_color_texture.as_ref()), (1, Some([0.5, 0.0])));
    assert_eq!(slot(m.normal_texture.as_ref()), (1, Some([0.5, 0.0])));
    assert_eq!(slot(m.occlusion_texture.as_ref()), (1, Some([0.5, 0.0])));
    assert_eq!(slot(m.emissive_texture.as_ref()), (1, None));
}

#[test]
fn the_specification_defaults_apply_when_the_file_is_silent() {
    let dir = tempfile::tempdir().unwrap();
    let asset =
        load(dir.path(), "plain.gltf", &document(&json!({ "alphaMode": "MASK" }), 0, &json!({})));
    let m = &asset.materials[0];
    assert_eq!((m.metallic, m.roughness, m.occlusion_strength), (1.0, 1.0, 1.0));
    assert_eq!(m.emissive, [0.0; 3]);
    assert_eq!(m.alpha_mode, AlphaMode::Mask { cutoff: 0.5 });
    assert!(!m.unlit && m.metallic_roughness_texture.is_none() && m.occlusion_texture.is_none());
    assert!(asset.lights.is_empty());
    let blend =
        load(dir.path(), "blend.gltf", &document(&json!({ "alphaMode": "BLEND" }), 0, &json!({})));
    assert_eq!(blend.materials[0].alpha_mode, AlphaMode::Blend);
}

/// The glTF sampler of a material's base colour texture (else of its first core texture
/// that names one) is its `sampling`; a material whose textures name none reads as glTF's
/// default sampler (repeat, trilinear).
#[test]
fn a_material_s_textures_are_sampled_as_its_gltf_sampler_says() {
    use seamlit_io::{TextureFilter, TextureSampling, Wrap};
    let dir = tempfile::tempdir().unwrap();
    let material = json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } },
                           "normalTexture": { "index": 1 } });
    let samplers = json!({ "samplers": [
        { "wrapS": 33071, "wrapT": 33648, "magFilter": 9728, "minFilter": 9729 },
        { "wrapS": 10497 } ] });
    let mut doc = document(&material, 2, &samplers);
    doc["textures"][0]["sampler"] = json!(0);
    doc["textures"][1]["sampler"] = json!(1);
    let asset = load(dir.path(), "clamped.gltf", &doc);
    let expected = TextureSampling {
        wrap: [Wrap::ClampToEdge, Wrap::MirroredRepeat],
        mag_filter: TextureFilter::Nearest,
        min_filter: TextureFilter::Linear,
        mipmap_filter: None,
    };
    assert_eq!(asset.materials[0].sampling, expected);
    // Without a sampler on the base colour texture, the normal map's (repeat, and glTF's
    // defaults for what it leaves out) is the material's.
    doc["textures"][0].as_object_mut().unwrap().remove("sampler");
    let asset = load(dir.path(), "normal.gltf", &doc);
    assert_eq!(asset.materials[0].sampling, TextureSampling::default());
    let khronos = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/models/texture_transform_test/TextureTransformTest.gltf");
    let asset = seamlit_io::load(&khronos, &LoadOptions::default()).unwrap();
    let clamped = TextureSampling { wrap: [Wrap::ClampToEdge; 2], mipmap_filter: None, ..expected };
    let clamped = TextureSampling { mag_filter: TextureFilter::Linear, ..clamped };
    assert_eq!(asset.materials[0].sampling, clamped, "{}", asset.materials[0].name);
}

#[test]
fn punctual_lights_are_placed_by_their_nodes() {
    let dir = tempfile::tempdir().unwrap();
    let extra = json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": { "KHR_lights_punctual": { "lights": [
            { "type": "spot", "name": "cone", "color": [1.0, 0.5, 0.0], "intensity": 30.0,
              "range": 12.0, "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.5 } },
            { "type": "directional", "intensity": 3.0 },
            { "type": "laser" }
        ] } },
        "scenes": [],
        "nodes": [
            // Node 1 (a root), turned 90 degrees about Y (-Z goes to -X) and raised by 5,
            // carries node 2, moved 1 along its parent's +Z, with the spot.
            { "translation": [0.0, 5.0, 0.0], "rotation": [0.0, (FRAC_PI_2 / 2.0).sin(), 0.0, (FRAC_PI_2 / 2.0).cos()],
              "children": [2] },
            { "translation": [0.0, 0.0, 1.0],
              "extensions": { "KHR_lights_punctual": { "light": 0 } } },
            { "extensions": { "KHR_lights_punctual": { "light": 1 } } },
            { "extensions": { "KHR_lights_punctual": { "light": 2 } } },
            { "extensions": { "KHR_lights_punctual": { "light": 9 } } }
        ]
    });
    let mut doc = document(&json!({}), 0, &extra);
    doc["scenes"] = json!([{ "nodes": [0, 1, 3, 4, 5] }]);
    let asset = load(dir.path(), "lights.gltf", &doc);
    assert_eq!(asset.lights.len(), 2, "{:?}", asset.lights);
    let spot = asset.lights.iter().find(|l| l.name == "cone").unwrap();
    assert_eq!(spot.kind, PunctualKind::Spot { inner_cone_angle: 0.2, outer_cone_angle: 0.5 });
    assert_eq!((spot.color, spot.intensity, spot.range), ([1.0, 0.5, 0.0], 30.0, Some(12.0)));
    // The child's +Z offset turned by the parent: +Z goes to +X.
    assert!((spot.position - Vec3::new(1.0, 5.0, 0.0)).length() < 1e-5, "{}", spot.position);
    assert!((spot.direction - Vec3::NEG_X).length() < 1e-5, "{}", spot.direction);
    let sun = asset.lights.iter().find(|l| l.kind == PunctualKind::Directional).unwrap();
    assert_eq!(
        (sun.color, sun.intensity, sun.range, sun.direction),
        ([1.0; 3], 3.0, None, Vec3::NEG_Z)
    );
    // The unknown type and the missing light are warnings that name the node.
    let warned = |needle: &str| asset.warnings.iter().any(|w| w.contains(needle));
    assert!(warned("nodes[4]") && warned("\"laser\""), "{:?}", asset.warnings);
    assert!(warned("nodes[5]") && warned("does not exist"), "{:?}", asset.warnings);
}

/// The material extensions that add to the BRDF (issue 34), read from the Sample Viewer
/// comparison's models with each specification's defaults for what a model leaves out.
#[test]
fn ior_specular_clearcoat_and_sheen_are_read_with_their_defaults() {
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/sample-viewer");
    let load = |name: &str| seamlit_io::load(&models.join(name), &LoadOptions::default()).unwrap();
    let by_name = |asset: &seamlit_io::Asset, name: &str| {
        asset.materials.iter().find(|m| m.name == name).unwrap().extensions.clone()
    };

    let specular = load("specular.glb");
    assert_eq!(by_name(&specular, "ior 2.4").ior, Some(2.4));
    assert_eq!(by_name(&specular, "ior 2.4").specular, None);
    let weak = by_name(&specular, "specular 0.3").specular.unwrap();
    assert_eq!((weak.factor, weak.color, weak.texture), (0.3, [1.0; 3], None));
    let tinted = by_name(&specular, "specular colour").specular.unwrap();
    assert_eq!(tinted.factor, 1.0, "specularFactor defaults to 1");
    assert!(tinted.color_texture.is_some());

    let clearcoat = load("clearcoat.glb");
    let coat = by_name(&clearcoat, "half coat").clearcoat.unwrap();
    assert_eq!((coat.factor, coat.roughness, coat.normal_texture), (0.5, 0.35, None));
    let striped = by_name(&clearcoat, "striped coat").clearcoat.unwrap();
    assert!(striped.texture.is_some() && striped.normal_texture.is_some());
    assert_eq!(striped.normal_scale, 1.0);
    assert_eq!(by_name(&clearcoat, "coat").names(), ["KHR_materials_clearcoat"]);

    let sheen = load("sheen.glb");
    let velvet = by_name(&sheen, "sheen 0.8").sheen.unwrap();
    assert_eq!((velvet.color, velvet.roughness), ([1.0, 0.45, 0.7], 0.8));
    let textured = by_name(&sheen, "textured sheen").sheen.unwrap();
    assert!(textured.color_texture.is_some() && textured.roughness_texture.is_some());
    let anisotropy = load("anisotropy.glb");
    let across = by_name(&anisotropy, "across").anisotropy.unwrap();
    assert_eq!((across.strength, across.rotation), (0.9, FRAC_PI_2));
    assert_eq!(by_name(&anisotropy, "isotropic"), seamlit_io::PbrExtensions::default());
    // A model without them: nothing.
    let spheres = load("spheres.glb");
    assert!(spheres.materials.iter().all(|m| m.extensions == seamlit_io::PbrExtensions::default()));
}
