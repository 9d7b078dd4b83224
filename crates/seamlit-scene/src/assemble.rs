//! Putting a scene's models together: material overrides, placement by the scene's
//! transform, and merging several assets into one for the renderer.

use std::path::Path;
use std::sync::Arc;

use glam::Mat4;
use seamlit_io::{Asset, LoadOptions, Material, Texture, TextureRef, TextureSource};

use crate::bricks::brick_normal_map;
use crate::error::SceneError;
use crate::scene::{MaterialOverride, NormalTexture, Scene, SceneModel};

/// Side of the generated brick normal map, texels.
const BRICKS_SIZE: u32 = 256;
/// Relief of the generated brick normal map (see [`brick_normal_map`]).
const BRICKS_STRENGTH: f32 = 6.0;

impl SceneModel {
    /// Loads the model file with `options` and gives it the scene's materials: the overrides
    /// applied in order, then a default material for every object that has none. The asset
    /// is neither fixed nor placed yet (fix it, then hand it to [`Scene::assemble`]). Its
    /// `warnings` are the loader's.
    ///
    /// # Errors
    /// [`SceneError::Model`] when the model file cannot be read (naming the file and the
    /// place in it), [`SceneError::UnknownMaterial`] when an override names a material the
    /// model lacks, [`SceneError::Texture`] when a normal map file cannot be read.
    pub fn load_asset(&self, options: &LoadOptions) -> Result<Asset, SceneError> {
        let mut asset = seamlit_io::load(&self.path, options)?;
        apply_overrides(&mut asset, &self.materials, &self.path)?;
        ensure_material(&mut asset);
        Ok(asset)
    }
}

impl Scene {
    /// One asset of the scene's models: `assets[i]` (model `i`'s, loaded with
    /// [`SceneModel::load_asset`] and fixed) is placed by model `i`'s transform, after each
    /// object's own, and the assets are merged: objects, materials, textures and nodes
    /// concatenated, their indices shifted. The first asset's V axis wins; assets whose V
    /// runs the other way have their UVs flipped (`v' = 1 - v`).
    ///
    /// # Panics
    /// If `assets` does not hold one asset per model of the scene.
    #[must_use]
    pub fn assemble(&self, assets: Vec<Asset>) -> Asset {
        assert_eq!(assets.len(), self.models.len(), "one asset per model of the scene");
        let placed = assets
            .into_iter()
            .zip(&self.models)
            .map(|(mut asset, model)| {
                place(&mut asset, model.transform);
                asset
            })
            .collect();
        merge(placed)
    }
}

/// The generated brick normal map as a texture.
#[must_use]
pub(crate) fn bricks_texture() -> Texture {
    Texture {
        name: "bricks (generated)".into(),
        source: TextureSource::Generated,
        image: Some(Arc::new(brick_normal_map(BRICKS_SIZE, BRICKS_STRENGTH))),
    }
}

/// Applies material overrides to an asset loaded from `model_path`, in order. An override
/// without a name changes every material; if the asset has no materials it first gets one
/// default material, given to every object.
///
/// # Errors
/// [`SceneError::UnknownMaterial`] when an override names a material the asset lacks,
/// [`SceneError::Texture`] when a normal map file cannot be read.
fn apply_overrides(
    asset: &mut Asset,
    overrides: &[MaterialOverride],
    model_path: &Path,
) -> Result<(), SceneError> {
    for o in overrides {
        let targets: Vec<usize> = match &o.name {
            None => {
                ensure_material(asset);
                (0..asset.materials.len()).collect()
            }
            Some(name) => {
                let found: Vec<usize> = (0..asset.materials.len())
                    .filter(|&i| asset.materials[i].name == *name)
                    .collect();
                if found.is_empty() {
                    let names: Vec<&str> =
                        asset.materials.iter().map(|m| m.name.as_str()).collect();
                    return Err(SceneError::UnknownMaterial {
                        model: model_path.to_path_buf(),
                        name: name.clone(),
                        available: if names.is_empty() { "none".into() } else { names.join(", ") },
                    });
                }
                found
            }
        };
        let normal_texture = match &o.normal_texture {
            None => None,
            Some(t) => {
                asset.textures.push(load_normal_texture(t)?);
                Some(asset.textures.len() - 1)
            }
        };
        for i in targets {
            let m = &mut asset.materials[i];
            if let Some(c) = o.base_color {
                m.base_color = c;
            }
            if let Some(s) = o.specular {
                m.specular = s;
            }
            if let Some(s) = o.shininess {
                m.shininess = s;
            }
            if let Some(t) = normal_texture {
                m.normal_texture = Some(TextureRef { texture: t, tex_coord: 0, transform: None });
            }
            if let Some(s) = o.normal_scale {
                m.normal_scale = s;
            }
            if let Some(g) = o.normal_green_down {
                m.normal_green_down = g;
            }
            if o.normal_mapping == Some(false) {
                m.normal_texture = None;
            }
            if let Some(d) = o.double_sided {
                m.double_sided = d;
            }
        }
    }
    Ok(())
}

/// Gives an asset without materials one default material, used by every object that has
/// none.
fn ensure_material(asset: &mut Asset) {
    if asset.materials.is_empty() {
        asset.materials.push(Material { name: "default".into(), ..Material::default() });
    }
    if asset.model.objects.iter().any(|o| o.material.is_none()) {
        let default =
            asset.materials.iter().position(|m| m.name == "default").unwrap_or_else(|| {
                asset.materials.push(Material { name: "default".into(), ..Material::default() });
                asset.materials.len() - 1
            });
        for object in &mut asset.model.objects {
            object.material.get_or_insert(default);
        }
    }
}

fn load_normal_texture(t: &NormalTexture) -> Result<Texture, SceneError> {
    match t {
        NormalTexture::Bricks => Ok(bricks_texture()),
        NormalTexture::File(path) => {
            let image = image::open(path)
                .map_err(|source| SceneError::Texture { path: path.clone(), source })?;
            Ok(Texture {
                name: path
                    .file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
                source: TextureSource::File(path.clone()),
                image: Some(Arc::new(image.to_rgba8())),
            })
        }
    }
}

/// Places an asset in the world: `transform` is applied after each object's own transform.
/// An asset with nodes gets a new root node carrying `transform` above its roots (node 0,
/// the others renumbered), so that its poses ([`seamlit_io::pose`]) are placed too (a skinned
/// object's joint matrices then include `transform`, and replace its own).
pub(crate) fn place(asset: &mut Asset, transform: Mat4) {
    if transform == Mat4::IDENTITY {
        return;
    }
    for object in &mut asset.model.objects {
        object.transform = Some(transform * object.model_transform());
    }
    if !asset.nodes.is_empty() {
        let mut nodes = std::mem::take(&mut asset.nodes);
        renumber_nodes(asset, &mut nodes, 1);
        for node in &mut nodes {
            node.parent = Some(node.parent.unwrap_or(0));
        }
        asset.nodes = std::iter::once(seamlit_io::Node::new("placement", transform, None))
            .chain(nodes)
            .collect();
    }
}

/// Adds `offset` to every node index of `asset` but its nodes' parents (which the caller
/// shifts with `nodes`): the objects' skin joints, the skins' joints, the animations'
/// channels, and the parents of `nodes`.
fn renumber_nodes(asset: &mut Asset, nodes: &mut [seamlit_io::Node], offset: usize) {
    let shift = |n: &mut usize| *n += offset;
    for node in nodes {
        node.parent.as_mut().map(shift);
    }
    let joint_offset = u32::try_from(offset).unwrap_or(u32::MAX);
    for object in &mut asset.model.objects {
        for set in &mut object.skin {
            for joints in &mut set.joints {
                for j in joints {
                    *j = j.saturating_add(joint_offset);
                }
            }
        }
    }
    for skin in &mut asset.skins {
        skin.joints.iter_mut().for_each(shift);
    }
    for animation in &mut asset.animations {
        for channel in &mut animation.channels {
            shift(&mut channel.node);
        }
    }
}

/// Merges assets into one: objects, materials, textures, nodes, skins and animations are
/// concatenated and their indices shifted (an animation moves the nodes of its own asset). The first asset's V axis wins; assets whose V runs the other way have
/// their UVs flipped (`v' = 1 - v`) and their tangent handedness kept, as a conversion
/// between OBJ and glTF does.
#[must_use]
fn merge(parts: Vec<Asset>) -> Asset {
    let mut parts = parts.into_iter();
    let Some(mut out) = parts.next() else { return Asset::default() };
    for mut part in parts {
        let (objects, materials, textures, nodes) =
            (out.model.objects.len(), out.materials.len(), out.textures.len(), out.nodes.len());
        if part.model.v_axis != out.model.v_axis {
            for object in &mut part.model.objects {
                for uvs in [&mut object.uvs, &mut object.uvs1].into_iter().flatten() {
                    for uv in uvs {
                        uv.y = 1.0 - uv.y;
                    }
                }
            }
        }
        for object in &mut part.model.objects {
            object.material = object.material.map(|m| m + materials);
        }
        for material in &mut part.materials {
            for t in material.textures_mut() {
                t.texture += textures;
            }
        }
        let mut part_nodes = std::mem::take(&mut part.nodes);
        renumber_nodes(&mut part, &mut part_nodes, nodes);
        let skins = out.skins.len();
        for node in &mut part_nodes {
            node.skin = node.skin.map(|s| s + skins);
            for o in &mut node.objects {
                *o += objects;
            }
        }
        out.model.objects.append(&mut part.model.objects);
        out.nodes.append(&mut part_nodes);
        out.skins.append(&mut part.skins);
        out.animations.append(&mut part.animations);
        out.materials.append(&mut part.materials);
        out.textures.append(&mut part.textures);
        out.warnings.append(&mut part.warnings);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};
    use seamlit_mesh::{Model, Object, VAxis};

    fn asset(name: &str, materials: usize) -> Asset {
        let object = Object::new(name, vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]])
            .with_uvs(vec![Vec2::ZERO, Vec2::X, Vec2::new(0.0, 0.25)]);
        let mut a = Asset { model: Model::new(vec![object]), ..Asset::default() };
        for i in 0..materials {
            a.materials.push(Material { name: format!("{name}{i}"), ..Material::default() });
        }
        if materials > 0 {
            a.model.objects[0].material = Some(materials - 1);
        }
        a
    }

    /// A second model's textures come after the first's: every slot that names one, the
    /// extensions' included, is moved by as many.
    #[test]
    fn merging_moves_every_texture_index_of_the_later_models() {
        use seamlit_io::{Clearcoat, Volume};
        let texture = |texture| Some(TextureRef { texture, tex_coord: 0, transform: None });
        let blank =
            || Texture { name: String::new(), source: TextureSource::Generated, image: None };
        let mut first = asset("a", 1);
        first.textures = vec![blank(), blank()];
        let mut second = asset("b", 1);
        second.textures = (0..4).map(|_| blank()).collect();
        let m = &mut second.materials[0];
        m.base_color_texture = texture(0);
        m.extensions.clearcoat = Some(Clearcoat {
            factor: 1.0,
            texture: texture(1),
            roughness: 0.0,
            roughness_texture: None,
            normal_texture: texture(2),
            normal_scale: 1.0,
        });
        m.extensions.volume = Some(Volume {
            thickness: 1.0,
            thickness_texture: texture(3),
            attenuation_distance: None,
            attenuation_color: [1.0; 3],
        });
        let merged = merge(vec![first, second]);
        assert_eq!(merged.textures.len(), 6);
        let mut m = merged.materials[1].clone();
        let indices: Vec<usize> = m.textures_mut().map(|t| t.texture).collect();
        assert_eq!(indices, [2, 3, 4, 5]);
    }

    #[test]
    fn an_unnamed_override_gives_a_bare_model_a_material_with_the_bricks() {
        let mut a = asset("a", 0);
        let o = MaterialOverride {
            base_color: Some([1.0, 0.0, 0.0, 1.0]),
            normal_texture: Some(NormalTexture::Bricks),
            ..MaterialOverride::default()
        };
        apply_overrides(&mut a, &[o], Path::new("a.obj")).unwrap();
        assert_eq!(a.materials.len(), 1);
        assert_eq!(a.model.objects[0].material, Some(0));
        assert_eq!(a.materials[0].base_color, [1.0, 0.0, 0.0, 1.0]);
        let t = a.materials[0].normal_texture.as_ref().unwrap().texture;
        assert_eq!(a.textures[t].source, TextureSource::Generated);
        assert_eq!(a.textures[t].image.as_ref().unwrap().dimensions(), (BRICKS_SIZE, BRICKS_SIZE));
    }

    #[test]
    fn a_named_override_changes_only_that_material_and_a_wrong_name_is_an_error() {
        let mut a = asset("m", 2);
        let o = MaterialOverride {
            name: Some("m1".into()),
            shininess: Some(7.0),
            normal_mapping: Some(false),
            ..MaterialOverride::default()
        };
        apply_overrides(&mut a, &[o], Path::new("a.obj")).unwrap();
        assert_eq!(a.materials[1].shininess, 7.0);
        assert_eq!(a.materials[0].shininess, Material::default().shininess);
        let bad = MaterialOverride { name: Some("nope".into()), ..MaterialOverride::default() };
        let e = apply_overrides(&mut a, &[bad], Path::new("dir/a.obj")).unwrap_err().to_string();
        assert_eq!(e, "dir/a.obj: no material named \"nope\" (the model has: m0, m1)");
    }

    #[test]
    fn a_missing_normal_map_file_names_the_file() {
        let mut a = asset("a", 1);
        let o = MaterialOverride {
            normal_texture: Some(NormalTexture::File("/nonexistent/n.png".into())),
            ..MaterialOverride::default()
        };
        let e = apply_overrides(&mut a, &[o], Path::new("a.obj")).unwrap_err();
        assert!(
            matches!(
                &e,
                SceneError::Texture { path, source: image::ImageError::IoError(io) }
                    if path == Path::new("/nonexistent/n.png")
                        && io.kind() == std::io::ErrorKind::NotFound
            ),
            "{e:?}"
        );
        assert!(e.to_string().starts_with("/nonexistent/n.png: cannot load the texture"), "{e}");
    }

    #[test]
    fn placing_composes_with_the_object_transform() {
        let mut a = asset("a", 0);
        a.model.objects[0].transform = Some(Mat4::from_translation(Vec3::X));
        place(&mut a, Mat4::from_scale(Vec3::splat(2.0)));
        let p = a.model.objects[0].model_transform().transform_point3(Vec3::ZERO);
        assert_eq!(p, Vec3::new(2.0, 0.0, 0.0));
    }

    #[test]
    fn merging_shifts_indices_and_flips_v_of_the_other_convention() {
        let mut a = asset("a", 1);
        a.textures.push(bricks_texture());
        let mut b = asset("b", 2);
        b.model.v_axis = VAxis::Down;
        b.textures.push(bricks_texture());
        let first = Some(TextureRef { texture: 0, tex_coord: 0, transform: None });
        b.materials[1].normal_texture = first.clone();
        b.materials[1].metallic_roughness_texture = first.clone();
        b.materials[1].occlusion_texture = first.clone();
        b.materials[1].emissive_texture = first;
        let m = merge(vec![a, b]);
        let slots = [
            &m.materials[2].metallic_roughness_texture,
            &m.materials[2].occlusion_texture,
            &m.materials[2].emissive_texture,
        ];
        assert!(slots.iter().all(|t| t.as_ref().unwrap().texture == 1), "{slots:?}");
        assert_eq!(m.model.objects.len(), 2);
        assert_eq!(m.model.objects[1].material, Some(2));
        assert_eq!(m.materials[2].normal_texture.as_ref().unwrap().texture, 1);
        assert_eq!(m.textures.len(), 2);
        assert_eq!(m.model.v_axis, VAxis::Up);
        assert_eq!(m.model.objects[1].uvs.as_ref().unwrap()[2], Vec2::new(0.0, 0.75));
        assert_eq!(m.model.objects[0].uvs.as_ref().unwrap()[2], Vec2::new(0.0, 0.25));
    }

    #[test]
    fn placing_and_merging_keep_skins_and_morph_targets() {
        let mut a = asset("a", 1);
        let skin = seamlit_mesh::Influences {
            joints: vec![[2, 3, 0, 0]; 3],
            weights: vec![[0.25, 0.75, 0.0, 0.0]; 3],
        };
        let target = seamlit_mesh::MorphTarget {
            name: "smile".into(),
            position_deltas: vec![Vec3::Z; 3],
            normal_deltas: Some(vec![Vec3::X * 0.1; 3]),
            tangent_deltas: None,
        };
        a.model.objects[0].skin = vec![skin.clone()];
        a.model.objects[0].morph_targets = vec![target.clone()];
        place(&mut a, Mat4::from_translation(Vec3::X));
        let m = merge(vec![asset("b", 1), a]);
        assert_eq!(m.model.objects[1].skin, vec![skin]);
        assert_eq!(m.model.objects[1].morph_targets, vec![target]);
        assert!(m.model.objects[0].skin.is_empty() && m.model.objects[0].morph_targets.is_empty());
    }
}
