//! Materials as glTF metallic-roughness, from ufbx's PBR reading of each FBX material (ufbx
//! maps the classic Lambert and Phong properties, and the 3ds Max, Maya and Blender PBR
//! shaders, onto one set of maps): base colour and factor, opacity as the base colour's
//! alpha, roughness (glossiness inverted where the shader stores it), metalness, emission
//! colour and factor, the normal map, double-sidedness. Textures are embedded bytes or files
//! by their relative path inside the model's folder (else by their file name there).

use std::collections::HashMap;
use std::path::Path;

use super::scene::f32_of;
use seamlit_asset::{AlphaMode, Material, Texture, TextureRef, TextureSource};

/// Every material of the scene, in the scene's order (so an object's material index is
/// ufbx's `typed_id`), and the textures they use, in the order first used.
pub(super) fn convert(
    scene: &ufbx::Scene,
    path: &Path,
    warnings: &mut Vec<String>,
) -> (Vec<Material>, Vec<Texture>) {
    let mut textures = Textures { list: Vec::new(), by_id: HashMap::new(), path };
    let materials = scene.materials.iter().map(|m| material(m, &mut textures, warnings)).collect();
    (materials, textures.list)
}

/// The textures converted so far, by ufbx element id.
struct Textures<'p> {
    list: Vec<Texture>,
    by_id: HashMap<u32, Option<usize>>,
    path: &'p Path,
}

impl Textures<'_> {
    /// The texture of a map, converted on first use; `None` (with a warning, once) when it
    /// has no bytes or file this crate may read.
    fn of(&mut self, map: &ufbx::MaterialMap, warnings: &mut Vec<String>) -> Option<TextureRef> {
        let texture = map.texture.as_ref().filter(|_| map.texture_enabled)?;
        let id = texture.element.element_id;
        let index = match self.by_id.get(&id) {
            Some(&index) => index,
            None => {
                let converted = convert_texture(texture, self.path, warnings);
                let index = converted.map(|t| {
                    self.list.push(t);
                    self.list.len() - 1
                });
                self.by_id.insert(id, index);
                index
            }
        };
        index.map(|texture| TextureRef { texture, tex_coord: 0, transform: None })
    }
}

fn material(
    m: &ufbx::Material,
    textures: &mut Textures<'_>,
    warnings: &mut Vec<String>,
) -> Material {
    let pbr = &m.pbr;
    let scalar = |map: &ufbx::MaterialMap, default: f32| {
        if map.has_value { f32_of(map.value_vec4.x) } else { default }
    };
    let rgb = |map: &ufbx::MaterialMap, default: [f32; 3]| {
        if map.has_value {
            let v = map.value_vec4;
            glam::DVec3::new(v.x, v.y, v.z).as_vec3().to_array()
        } else {
            default
        }
    };
    let factor = scalar(&pbr.base_factor, 1.0);
    let base = rgb(&pbr.base_color, [0.8; 3]).map(|c| (c * factor).clamp(0.0, 1.0));
    let opacity = scalar(&pbr.opacity, 1.0).clamp(0.0, 1.0);
    let mut roughness = scalar(&pbr.roughness, 0.5);
    if m.features.roughness_as_glossiness.enabled {
        roughness = 1.0 - roughness;
    }
    let roughness = roughness.clamp(0.0, 1.0);
    let metallic = scalar(&pbr.metalness, 0.0).clamp(0.0, 1.0);
    let emission = scalar(&pbr.emission_factor, 1.0);
    let emissive = rgb(&pbr.emission_color, [0.0; 3]).map(|c| (c * emission).max(0.0));
    let name = m.element.name.to_string();
    for (map, what) in
        [(&pbr.roughness, "roughness"), (&pbr.metalness, "metalness"), (&pbr.opacity, "opacity")]
    {
        if map.texture.is_some() && map.texture_enabled {
            warnings.push(format!(
                "{}: material {name:?}: the {what} texture is not carried (glTF packs roughness and metalness into one texture and opacity into the base colour's alpha); its factor is kept",
                textures.path.display()
            ));
        }
    }
    Material {
        base_color: [base[0], base[1], base[2], opacity],
        base_color_texture: textures.of(&pbr.base_color, warnings),
        normal_texture: textures.of(&pbr.normal_map, warnings),
        specular: std::array::from_fn(|i| 0.04 + (base[i] - 0.04) * metallic),
        shininess: seamlit_asset::roughness_to_shininess(roughness),
        metallic,
        roughness,
        double_sided: m.features.double_sided.enabled,
        emissive,
        emissive_texture: textures.of(&pbr.emission_color, warnings),
        alpha_mode: if opacity < 1.0 { AlphaMode::Blend } else { AlphaMode::Opaque },
        unlit: m.features.unlit.enabled,
        name,
        ..Material::default()
    }
}

/// A texture's image: the bytes the file embeds, else the file it names, by its relative
/// path inside the model's folder, else by its file name in that folder (exporters often
/// store the artist's absolute path). `None` with a warning when the path leaves the folder
/// and no file of that name is there.
fn convert_texture(
    texture: &ufbx::Texture,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Option<Texture> {
    let file = if texture.type_ == ufbx::TextureType::File {
        texture
    } else {
        texture.file_textures.first().map(AsRef::as_ref)?
    };
    let written = if file.relative_filename.is_empty() {
        file.filename.to_string()
    } else {
        file.relative_filename.to_string()
    };
    let name = file_name(&written).unwrap_or(&file.element.name).to_owned();
    if !file.content.is_empty() {
        let bytes = &file.content[..];
        let mime = if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) { "image/jpeg" } else { "image/png" };
        let source =
            TextureSource::Embedded { mime_type: mime.to_owned(), bytes: bytes.to_vec().into() };
        return Some(Texture { name, source, image: None });
    }
    let folder = path.parent().unwrap_or(Path::new(""));
    let by_path = seamlit_asset::paths::inside(&[], &written)
        .map(|parts| parts.iter().fold(folder.to_path_buf(), |p, part| p.join(part)));
    let by_name = file_name(&written).map(|n| folder.join(n));
    let found = by_path.iter().chain(&by_name).find(|p| p.is_file()).cloned();
    match found.or(by_path) {
        Some(file) => Some(Texture { name, source: TextureSource::File(file), image: None }),
        None => {
            warnings.push(format!(
                "{}: texture {written:?} is not used: its path leaves the model's folder and no file {name:?} is in it",
                path.display()
            ));
            None
        }
    }
}

/// The last part of a path written with `/` or `\`, if it is not empty.
fn file_name(written: &str) -> Option<&str> {
    written.rsplit(['/', '\\']).next().filter(|n| !n.is_empty())
}
