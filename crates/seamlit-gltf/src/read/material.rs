//! glTF materials as seamlit's [`Material`]: metallic-roughness with its textures and their
//! KHR_texture_transform, emissive strength, alpha mode, unlit, and the extensions that add
//! to the BRDF (ior, specular, clearcoat, sheen: [`PbrExtensions`]), read from their raw JSON
//! with each specification's defaults; and KHR_materials_variants (the variants' names and
//! each primitive instance's mappings, [`variants`]).

use crate::source::Instance;
use seamlit_asset::{
    AlphaMode, Anisotropy, Clearcoat, Iridescence, Material, PbrExtensions, Sheen, Specular,
    TextureFilter, TextureRef, TextureSampling, Transmission, UvTransform, VariantObject, Variants,
    Volume, Wrap,
};

/// A texture reference: glTF texture -> its image (the index into [`Asset::textures`]): its
/// `source`, else the image its KHR_texture_basisu names (Basis Universal KTX2, which the
/// decoder then names in a warning); `None` for a texture whose image only another extension
/// names (EXT_texture_webp), which seamlit does not decode. The coordinate set is the texture
/// info's `texCoord` unless its KHR_texture_transform gives its own, which then overrides it
/// (the extension's specification).
fn texture_ref(
    images: usize,
    texture: &gltf::Texture<'_>,
    tex_coord: u32,
    transform: Option<(UvTransform, Option<u32>)>,
) -> Option<TextureRef> {
    let tex_coord = transform.and_then(|(_, own)| own).unwrap_or(tex_coord);
    let transform = transform.map(|(t, _)| t);
    let image = match texture.source() {
        Some(image) => image.index(),
        None => texture
            .extension_value("KHR_texture_basisu")?
            .get("source")?
            .as_u64()
            .and_then(|i| usize::try_from(i).ok())
            .filter(|&i| i < images)?,
    };
    Some(TextureRef { texture: image, tex_coord, transform })
}

/// KHR_texture_transform as the gltf crate types it, with its `texCoord` override.
fn uv_transform(t: &gltf::texture::TextureTransform<'_>) -> (UvTransform, Option<u32>) {
    (UvTransform { offset: t.offset(), rotation: t.rotation(), scale: t.scale() }, t.tex_coord())
}

/// A JSON number as the `f32` that glTF's float properties are: rounded to nearest (a
/// magnitude past f32's range becomes infinite); `None` for anything else.
#[expect(clippy::cast_possible_truncation, reason = "glTF's floats are f32: rounding is the point")]
pub(super) fn json_f32(value: &serde_json::Value) -> Option<f32> {
    value.as_f64().map(|x| x as f32)
}

/// KHR_texture_transform from raw extension JSON (the gltf crate does not type it on
/// normal and occlusion textures), with its `texCoord` override.
fn uv_transform_json(value: &serde_json::Value) -> (UvTransform, Option<u32>) {
    let pair = |key: &str, default: [f32; 2]| -> [f32; 2] {
        value
            .get(key)
            .and_then(|v| v.as_array())
            .and_then(|a| Some([json_f32(a.first()?)?, json_f32(a.get(1)?)?]))
            .unwrap_or(default)
    };
    let transform = UvTransform {
        offset: pair("offset", [0.0, 0.0]),
        rotation: value.get("rotation").and_then(json_f32).unwrap_or(0.0),
        scale: pair("scale", [1.0, 1.0]),
    };
    let tex_coord = value
        .get("texCoord")
        .and_then(serde_json::Value::as_u64)
        .and_then(|set| u32::try_from(set).ok());
    (transform, tex_coord)
}

/// A glTF material of `document` as seamlit's.
pub(super) fn material(m: &gltf::Material<'_>, document: &gltf::Document) -> Material {
    let images = document.images().len();
    let pbr = m.pbr_metallic_roughness();
    let base_color_texture = pbr.base_color_texture().and_then(|info| {
        let transform = info.texture_transform().map(|t| uv_transform(&t));
        texture_ref(images, &info.texture(), info.tex_coord(), transform)
    });
    let normal = m.normal_texture();
    let normal_texture = normal.as_ref().and_then(|n| {
        let transform = n.extension_value("KHR_texture_transform").map(uv_transform_json);
        texture_ref(images, &n.texture(), n.tex_coord(), transform)
    });
    let base = pbr.base_color_factor();
    let metallic = pbr.metallic_factor();
    let roughness = pbr.roughness_factor();
    // Specular colour: 4 % for dielectrics, the base colour for metals (the usual
    // metallic-roughness to specular-glossiness conversion).
    let specular = std::array::from_fn(|i| 0.04 + (base[i] - 0.04) * metallic);
    Material {
        name: m.name().map_or_else(|| format!("material{}", m.index().unwrap_or(0)), str::to_owned),
        base_color: base,
        base_color_texture,
        normal_texture,
        normal_scale: normal.as_ref().map_or(1.0, gltf::material::NormalTexture::scale),
        normal_green_down: false,
        specular,
        shininess: seamlit_asset::roughness_to_shininess(roughness),
        metallic,
        roughness,
        double_sided: m.double_sided(),
        metallic_roughness_texture: pbr
            .metallic_roughness_texture()
            .and_then(|i| info_ref(images, &i)),
        occlusion_texture: m.occlusion_texture().and_then(|o| {
            let transform = o.extension_value("KHR_texture_transform").map(uv_transform_json);
            texture_ref(images, &o.texture(), o.tex_coord(), transform)
        }),
        occlusion_strength: m.occlusion_texture().map_or(1.0, |o| o.strength()),
        emissive: m.emissive_factor().map(|c| c * emissive_strength(m)),
        emissive_texture: m.emissive_texture().and_then(|i| info_ref(images, &i)),
        alpha_mode: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => {
                AlphaMode::Mask { cutoff: m.alpha_cutoff().unwrap_or(0.5) }
            }
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        },
        unlit: m.extension_value("KHR_materials_unlit").is_some(),
        extensions: extensions(m, document, images),
        sampling: sampling(m),
    }
}

/// The sampler of `m`'s base colour texture, else of its first core texture that names one
/// (normal, metallic-roughness, occlusion, emissive); glTF's default sampling without.
fn sampling(m: &gltf::Material<'_>) -> TextureSampling {
    let pbr = m.pbr_metallic_roughness();
    let textures = [
        pbr.base_color_texture().map(|i| i.texture()),
        m.normal_texture().map(|n| n.texture()),
        pbr.metallic_roughness_texture().map(|i| i.texture()),
        m.occlusion_texture().map(|o| o.texture()),
        m.emissive_texture().map(|i| i.texture()),
    ];
    let Some(sampler) = textures.into_iter().flatten().find_map(|t| {
        let sampler = t.sampler();
        sampler.index().map(|_| sampler)
    }) else {
        return TextureSampling::default();
    };
    let wrap = |mode: gltf::texture::WrappingMode| match mode {
        gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
    };
    use TextureFilter::{Linear, Nearest};
    use gltf::texture::MinFilter as Min;
    let (min_filter, mipmap_filter) = match sampler.min_filter() {
        Some(Min::Nearest) => (Nearest, None),
        Some(Min::Linear) => (Linear, None),
        Some(Min::NearestMipmapNearest) => (Nearest, Some(Nearest)),
        Some(Min::LinearMipmapNearest) => (Linear, Some(Nearest)),
        Some(Min::NearestMipmapLinear) => (Nearest, Some(Linear)),
        Some(Min::LinearMipmapLinear) | None => (Linear, Some(Linear)),
    };
    TextureSampling {
        wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
        mag_filter: match sampler.mag_filter() {
            Some(gltf::texture::MagFilter::Nearest) => Nearest,
            _ => Linear,
        },
        min_filter,
        mipmap_filter,
    }
}

/// A texture info of an extension (`{ "index", "texCoord", "extensions":
/// { "KHR_texture_transform" } }`) as a reference; `None` where it names no texture of the
/// document.
fn json_texture(
    document: &gltf::Document,
    images: usize,
    info: Option<&serde_json::Value>,
) -> Option<TextureRef> {
    let info = info?;
    let index = usize::try_from(info.get("index")?.as_u64()?).ok()?;
    let texture = document.textures().nth(index)?;
    let tex_coord = info
        .get("texCoord")
        .and_then(serde_json::Value::as_u64)
        .and_then(|set| u32::try_from(set).ok())
        .unwrap_or(0);
    let transform =
        info.get("extensions").and_then(|e| e.get("KHR_texture_transform")).map(uv_transform_json);
    texture_ref(images, &texture, tex_coord, transform)
}

/// A number of an extension's JSON, or its default.
fn number(value: &serde_json::Value, key: &str, default: f32) -> f32 {
    value.get(key).and_then(json_f32).unwrap_or(default)
}

/// An RGB colour of an extension's JSON, or its default.
fn color(value: &serde_json::Value, key: &str, default: [f32; 3]) -> [f32; 3] {
    value
        .get(key)
        .and_then(serde_json::Value::as_array)
        .and_then(|a| Some([json_f32(a.first()?)?, json_f32(a.get(1)?)?, json_f32(a.get(2)?)?]))
        .unwrap_or(default)
}

/// KHR_materials_ior, _specular, _clearcoat, _sheen, _anisotropy, _transmission, _volume,
/// _iridescence and _dispersion of a material.
fn extensions(m: &gltf::Material<'_>, document: &gltf::Document, images: usize) -> PbrExtensions {
    let texture = |e: &serde_json::Value, key: &str| json_texture(document, images, e.get(key));
    PbrExtensions {
        ior: m.extension_value("KHR_materials_ior").map(|e| number(e, "ior", 1.5)),
        // The gltf crate types this one (its KHR_materials_specular feature is on), and so
        // keeps it out of the raw extension JSON.
        specular: m.specular().map(|s| Specular {
            factor: s.specular_factor(),
            texture: s.specular_texture().and_then(|i| info_ref(images, &i)),
            color: s.specular_color_factor(),
            color_texture: s.specular_color_texture().and_then(|i| info_ref(images, &i)),
        }),
        clearcoat: m.extension_value("KHR_materials_clearcoat").map(|e| Clearcoat {
            factor: number(e, "clearcoatFactor", 0.0),
            texture: texture(e, "clearcoatTexture"),
            roughness: number(e, "clearcoatRoughnessFactor", 0.0),
            roughness_texture: texture(e, "clearcoatRoughnessTexture"),
            normal_texture: texture(e, "clearcoatNormalTexture"),
            normal_scale: e
                .get("clearcoatNormalTexture")
                .map_or(1.0, |info| number(info, "scale", 1.0)),
        }),
        sheen: m.extension_value("KHR_materials_sheen").map(|e| Sheen {
            color: color(e, "sheenColorFactor", [0.0; 3]),
            color_texture: texture(e, "sheenColorTexture"),
            roughness: number(e, "sheenRoughnessFactor", 0.0),
            roughness_texture: texture(e, "sheenRoughnessTexture"),
        }),
        anisotropy: m.extension_value("KHR_materials_anisotropy").map(|e| Anisotropy {
            strength: number(e, "anisotropyStrength", 0.0),
            rotation: number(e, "anisotropyRotation", 0.0),
            texture: texture(e, "anisotropyTexture"),
        }),
        transmission: m.extension_value("KHR_materials_transmission").map(|e| Transmission {
            factor: number(e, "transmissionFactor", 0.0),
            texture: texture(e, "transmissionTexture"),
        }),
        volume: m.extension_value("KHR_materials_volume").map(|e| Volume {
            thickness: number(e, "thicknessFactor", 0.0),
            thickness_texture: texture(e, "thicknessTexture"),
            attenuation_distance: e
                .get("attenuationDistance")
                .and_then(json_f32)
                .filter(|d| d.is_finite() && *d > 0.0),
            attenuation_color: color(e, "attenuationColor", [1.0; 3]),
        }),
        iridescence: m.extension_value("KHR_materials_iridescence").map(|e| Iridescence {
            factor: number(e, "iridescenceFactor", 0.0),
            texture: texture(e, "iridescenceTexture"),
            ior: number(e, "iridescenceIor", 1.3),
            thickness_minimum: number(e, "iridescenceThicknessMinimum", 100.0),
            thickness_maximum: number(e, "iridescenceThicknessMaximum", 400.0),
            thickness_texture: texture(e, "iridescenceThicknessTexture"),
        }),
        dispersion: m
            .extension_value("KHR_materials_dispersion")
            .map(|e| number(e, "dispersion", 0.0)),
    }
}

/// A texture slot's reference with its KHR_texture_transform.
fn info_ref(images: usize, info: &gltf::texture::Info<'_>) -> Option<TextureRef> {
    let transform = info.texture_transform().map(|t| uv_transform(&t));
    texture_ref(images, &info.texture(), info.tex_coord(), transform)
}

/// KHR_materials_emissive_strength's `emissiveStrength`, 1 without it. Read from the raw
/// extension JSON, as the texture transforms of normal maps are, so that gltf-json's typed
/// extension features (which would re-serialise the pass-through's JSON) stay off.
fn emissive_strength(m: &gltf::Material<'_>) -> f32 {
    m.extension_value("KHR_materials_emissive_strength")
        .and_then(|e| e.get("emissiveStrength"))
        .and_then(json_f32)
        .unwrap_or(1.0)
}

/// KHR_materials_variants of a document (its raw JSON): the root's variant names and, for
/// each object (`instances[i]` is object `i`'s node, mesh and primitive), the primitive's
/// mappings. A mapping that names a material or a variant the document does not have is
/// left out with a warning; a variant without a name is called `variant{index}`.
pub(super) fn variants(
    json: &serde_json::Value,
    instances: &[Instance],
    materials: usize,
    path: &std::path::Path,
    warnings: &mut Vec<String>,
) -> Variants {
    let Some(root) = json.pointer("/extensions/KHR_materials_variants/variants") else {
        return Variants::default();
    };
    let names: Vec<String> = root
        .as_array()
        .map(|list| {
            list.iter()
                .enumerate()
                .map(|(i, v)| {
                    v.get("name")
                        .and_then(serde_json::Value::as_str)
                        .map_or_else(|| format!("variant{i}"), str::to_owned)
                })
                .collect()
        })
        .unwrap_or_default();
    let index = |v: &serde_json::Value| v.as_u64().and_then(|i| usize::try_from(i).ok());
    let mut objects = Vec::new();
    for (object, instance) in instances.iter().enumerate() {
        let primitive = &json["meshes"][instance.mesh]["primitives"][instance.primitive];
        let Some(list) = primitive
            .pointer("/extensions/KHR_materials_variants/mappings")
            .and_then(serde_json::Value::as_array)
        else {
            continue;
        };
        let mut mappings = Vec::new();
        for mapping in list {
            let material = mapping.get("material").and_then(index).filter(|&m| m < materials);
            let variants = mapping.get("variants").and_then(serde_json::Value::as_array);
            let (Some(material), Some(variants)) = (material, variants) else {
                warnings.push(format!(
                    "{}: mesh {} primitive {}: a KHR_materials_variants mapping without a valid \
                     material or variants list is ignored",
                    path.display(),
                    instance.mesh,
                    instance.primitive
                ));
                continue;
            };
            for variant in variants.iter().map(index) {
                match variant.filter(|&v| v < names.len()) {
                    Some(v) => mappings.push((v, material)),
                    None => warnings.push(format!(
                        "{}: mesh {} primitive {}: a KHR_materials_variants mapping names a \
                         variant the file does not have; ignored",
                        path.display(),
                        instance.mesh,
                        instance.primitive
                    )),
                }
            }
        }
        let default = primitive.get("material").and_then(index).filter(|&m| m < materials);
        objects.push(VariantObject { object, default, mappings });
    }
    Variants { names, objects }
}
