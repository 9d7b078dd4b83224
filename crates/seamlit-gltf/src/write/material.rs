//! Materials, and the images, textures and sampler of the textures they use.

use std::collections::HashMap;
use std::path::Path;

use gltf_json as json;
use json::validation::Checked;

use super::Writer;
use super::bin::BinPart;
use seamlit_asset::error::IoError;
use seamlit_asset::files::safe_name;
use seamlit_asset::texture::encoded;
use seamlit_asset::{Asset, Material, TextureRef, UvTransform};

impl<'a> Writer<'a> {
    /// Images, textures and one sampler for the textures that materials use and whose bytes
    /// are available; returns, per asset texture, its glTF texture index.
    pub(super) fn textures(
        &mut self,
        asset: &'a Asset,
    ) -> Result<Vec<Option<json::Index<json::Texture>>>, IoError> {
        let used: Vec<bool> = (0..asset.textures.len())
            .map(|i| {
                asset.materials.iter().any(|m| {
                    [&m.base_color_texture, &m.normal_texture]
                        .into_iter()
                        .flatten()
                        .any(|r| r.texture == i)
                })
            })
            .collect();
        let mut out = vec![None; asset.textures.len()];
        let mut sampler = None;
        let mut names: HashMap<String, usize> = HashMap::new();
        for (i, texture) in asset.textures.iter().enumerate() {
            if !used[i] {
                continue;
            }
            let Some((bytes, mime)) = encoded(texture, self.path)? else { continue };
            let image = if self.binary {
                let view = self.view(BinPart::Bytes(bytes), None);
                json::Image {
                    buffer_view: Some(view),
                    mime_type: Some(json::image::MimeType(mime.to_owned())),
                    name: Some(texture.name.clone()),
                    uri: None,
                    extensions: None,
                    extras: Default::default(),
                }
            } else {
                let extension = if mime == "image/png" { "png" } else { "jpg" };
                let base = Path::new(&texture.name)
                    .file_stem()
                    .map_or_else(|| format!("texture{i}"), |s| s.to_string_lossy().into_owned());
                let base = format!("{}_{}", self.stem, safe_name(&base));
                let n = names.entry(base.clone()).or_default();
                let file = if *n == 0 {
                    format!("{base}.{extension}")
                } else {
                    format!("{base}_{n}.{extension}")
                };
                *n += 1;
                self.side_files.push((file.clone(), bytes));
                json::Image {
                    buffer_view: None,
                    mime_type: None,
                    name: Some(texture.name.clone()),
                    uri: Some(file),
                    extensions: None,
                    extras: Default::default(),
                }
            };
            let image = self.root.push(image);
            let sampler = *sampler.get_or_insert_with(|| {
                self.root.push(json::texture::Sampler {
                    mag_filter: Some(Checked::Valid(json::texture::MagFilter::Linear)),
                    min_filter: Some(Checked::Valid(json::texture::MinFilter::LinearMipmapLinear)),
                    ..Default::default()
                })
            });
            out[i] = Some(self.root.push(json::Texture {
                name: None,
                sampler: Some(sampler),
                source: image,
                extensions: None,
                extras: Default::default(),
            }));
        }
        Ok(out)
    }

    pub(super) fn material(
        &mut self,
        m: &Material,
        textures: &[Option<json::Index<json::Texture>>],
    ) -> json::Material {
        fn lookup<'r>(
            r: &'r Option<TextureRef>,
            textures: &[Option<json::Index<json::Texture>>],
        ) -> Option<(json::Index<json::Texture>, &'r TextureRef)> {
            r.as_ref().and_then(|r| textures.get(r.texture).copied().flatten().map(|t| (t, r)))
        }
        let base_color_texture = lookup(&m.base_color_texture, textures).map(|(index, r)| {
            let extensions = r.transform.map(|t| {
                self.use_extension("KHR_texture_transform");
                json::extensions::texture::Info {
                    texture_transform: Some(texture_transform(t, r.tex_coord)),
                    others: Default::default(),
                }
            });
            json::texture::Info {
                index,
                tex_coord: r.tex_coord,
                extensions,
                extras: Default::default(),
            }
        });
        let normal_texture = lookup(&m.normal_texture, textures).map(|(index, r)| {
            let extensions = r.transform.map(|t| {
                self.use_extension("KHR_texture_transform");
                let mut others = serde_json::Map::new();
                others.insert("KHR_texture_transform".to_owned(), serde_json::json!({ "offset": t.offset, "rotation": t.rotation, "scale": t.scale }));
                json::extensions::material::NormalTexture { others }
            });
            json::material::NormalTexture { index, scale: m.normal_scale, tex_coord: r.tex_coord, extensions, extras: Default::default() }
        });
        let alpha = m.base_color[3];
        json::Material {
            alpha_mode: Checked::Valid(if alpha < 1.0 {
                json::material::AlphaMode::Blend
            } else {
                json::material::AlphaMode::Opaque
            }),
            double_sided: m.double_sided,
            name: Some(m.name.clone()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(
                    m.base_color.map(|c| c.clamp(0.0, 1.0)),
                ),
                base_color_texture,
                metallic_factor: json::material::StrengthFactor(m.metallic.clamp(0.0, 1.0)),
                roughness_factor: json::material::StrengthFactor(m.roughness.clamp(0.0, 1.0)),
                ..Default::default()
            },
            normal_texture,
            ..Default::default()
        }
    }

    pub(super) fn use_extension(&mut self, name: &str) {
        if !self.root.extensions_used.iter().any(|e| e == name) {
            self.root.extensions_used.push(name.to_owned());
        }
    }
}

/// KHR_texture_transform of a texture read through `tex_coord`. The extension's own
/// `texCoord` repeats the texture info's: gltf-json 1.4.1 writes `None` as `null`, which the
/// validator rejects.
fn texture_transform(
    t: UvTransform,
    tex_coord: u32,
) -> json::extensions::texture::TextureTransform {
    json::extensions::texture::TextureTransform {
        offset: json::extensions::texture::TextureTransformOffset(t.offset),
        rotation: json::extensions::texture::TextureTransformRotation(t.rotation),
        scale: json::extensions::texture::TextureTransformScale(t.scale),
        tex_coord: Some(tex_coord),
        extras: Default::default(),
    }
}
