//! From a path on the command line to an asset ready to render: read the scene (or wrap a
//! model path in one), load each model, apply its material overrides, fix it with its
//! options (and the command line's), place it, and merge everything into one asset.

use std::path::Path;

use glam::{Mat4, Vec3};
use seamlit_io::{Asset, LoadOptions};
use seamlit_mesh::{FixOptions, Mode};
use seamlit_render::{Light, LightingModel, ObjectPose};
use seamlit_scene::{Bounds, Camera, Facing, Scene, SceneModel};

use crate::cli::{FixFlags, SceneArgs};
use crate::failure::{Classify, Failure};

/// A scene with its models loaded but not yet fixed, so that they can be fixed again with
/// other options (the viewer does, live).
pub struct Loaded {
    /// The scene.
    pub scene: Scene,
    /// Each model of the scene with its loaded asset (materials overridden, not placed).
    pub parts: Vec<(SceneModel, Asset)>,
}

/// How the command line changes the scene's processing options.
#[derive(Clone, Debug, Default)]
pub struct FixOverride {
    /// Replaces every model's mode.
    pub mode: Option<Mode>,
    /// Replace other options.
    pub flags: FixFlags,
}

impl FixOverride {
    /// The options for `asset`, a model whose scene gives `base`.
    #[must_use]
    pub(crate) fn apply(&self, base: FixOptions, asset: &Asset) -> FixOptions {
        let o = self.flags.apply(base);
        let o = match self.mode {
            Some(m) => o.with_mode(m),
            None => o,
        };
        default_tangents(asset, o, self.flags.tangents.is_some())
    }
}

/// `options` with the tangent generator a model with a normal map and no tangents needs,
/// unless the command line `asked` for one ([`Asset::fix_options`]).
#[must_use]
pub(crate) fn default_tangents(asset: &Asset, options: FixOptions, asked: bool) -> FixOptions {
    asset.fix_options(options, asked)
}

impl SceneArgs {
    /// Reads the scene file or model file and loads every model.
    ///
    /// # Errors
    /// As [`load`].
    pub(crate) fn load(&self) -> Result<Loaded, Failure> {
        // Drawn, so USD GeomSubsets' materials are read too (`fix` reads none).
        let options = self.load.options(LoadOptions::DEFAULT).with_subset_materials();
        let mut loaded = load(&self.input, &options)?;
        loaded.select_variant(self.variant.as_deref(), true)?;
        Ok(loaded)
    }
}

/// Reads a scene file or a model file and loads every model.
///
/// # Errors
/// [`Failure::BadInput`] naming the file for a missing or malformed scene or model.
pub(crate) fn load(path: &Path, options: &LoadOptions) -> Result<Loaded, Failure> {
    if !path.exists() {
        return Err(Failure::input(format!("{}: no such file", path.display())));
    }
    if path.is_dir() {
        return Err(Failure::input(format!(
            "{}: is a folder, expected a scene or model file",
            path.display()
        )));
    }
    let scene = Scene::open(path).bad_input()?;
    let mut parts = Vec::with_capacity(scene.models.len());
    for model in &scene.models {
        let asset = model.load_asset(options).bad_input()?;
        for warning in &asset.warnings {
            eprintln!("warning: {warning}");
        }
        parts.push((model.clone(), asset));
    }
    Ok(Loaded { scene, parts })
}

impl Loaded {
    /// Draws the material variant (KHR_materials_variants) `name` where a model has it, or
    /// with `None` each model's own `variant` key (or its default materials, without one,
    /// or when `keys` is false).
    ///
    /// # Errors
    /// [`Failure::BadInput`] in one line listing the variants there are: for a `name` no
    /// model has, or a model's key that it lacks.
    pub(crate) fn select_variant(&mut self, name: Option<&str>, keys: bool) -> Result<(), Failure> {
        let has = |asset: &Asset, n: &str| asset.variants.names.iter().any(|k| k == n);
        if let Some(name) = name
            && !self.parts.iter().any(|(_, asset)| has(asset, name))
        {
            let known = self.variant_names();
            let error = seamlit_io::UnknownVariant { name: name.to_owned(), known };
            let input =
                self.scene.source.clone().or_else(|| self.parts.first().map(|p| p.0.path.clone()));
            return Err(Failure::input(match input {
                Some(input) => format!("{}: {error}", input.display()),
                None => error.to_string(),
            }));
        }
        for (model, asset) in &mut self.parts {
            // The command line's variant where this model has it, else the model's key.
            let choice = match name {
                Some(n) => has(asset, n).then_some(n),
                None => model.variant.as_deref().filter(|_| keys),
            };
            asset
                .select_variant(choice)
                .map_err(|e| Failure::input(format!("{}: {e}", model.path.display())))?;
        }
        Ok(())
    }

    /// The variants of the models (KHR_materials_variants), each name once, in model order.
    #[must_use]
    pub(crate) fn variant_names(&self) -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for (_, asset) in &self.parts {
            for n in &asset.variants.names {
                if !names.contains(n) {
                    names.push(n.clone());
                }
            }
        }
        names
    }

    /// Fixes every model with its options changed by `fix`, cuts its objects by the
    /// materials of their triangles ([`Asset::split_triangle_materials`]), places it and
    /// merges them.
    ///
    /// # Errors
    /// [`Failure::BadInput`] when a model has bad geometry (NaN positions, indices out of
    /// range), naming the model file.
    pub(crate) fn build(&self, fix: &FixOverride) -> Result<Asset, Failure> {
        let mut assets = Vec::with_capacity(self.parts.len());
        for (model, asset) in &self.parts {
            let options = fix.apply(model.fix, asset);
            let bad = |e: seamlit_mesh::MeshError| {
                Failure::input(format!("{}: {e}", model.path.display()))
            };
            let mut fixed = Asset {
                model: seamlit_mesh::fix(&asset.model, &options).map_err(bad)?,
                ..asset.clone()
            };
            // As `seamlit fix` does by default (--skin-seams match): the copies of a shared
            // position follow the same joints, so the seam stays closed when posed.
            if asset.model.objects.iter().any(|o| !o.skin.is_empty()) {
                let copies = seamlit_mesh::shared_copies(&asset.model, options.weld_tolerance)
                    .map_err(bad)?;
                seamlit_io::match_skin_seams(&mut fixed, &copies);
            }
            // Parts of an object bound to materials of their own (USD GeomSubsets) drawn as
            // objects of their own, cut after the fix: their normals are the whole object's.
            fixed.split_triangle_materials();
            assets.push(fixed);
        }
        Ok(self.scene.assemble(assets))
    }

    /// The lighting model the scene asks for (`[render] lighting`), else PBR when every model
    /// came from glTF (whose materials are metallic-roughness) and Blinn-Phong otherwise
    /// (OBJ/MTL and Newell patches, whose materials are Blinn-Phong's).
    #[must_use]
    pub(crate) fn lighting(&self) -> LightingModel {
        let all_gltf = self
            .parts
            .iter()
            .all(|(_, asset)| asset.document::<seamlit_io::GltfSource>().is_some());
        self.scene.lighting.unwrap_or(if all_gltf {
            LightingModel::Pbr
        } else {
            LightingModel::BlinnPhong
        })
    }

    /// The scene's `[[light]]`s; without any, the lights the model files carry (glTF
    /// KHR_lights_punctual, placed with their models); without those, the default rig.
    #[must_use]
    pub(crate) fn lights(&self) -> Vec<Light> {
        let from_files: Vec<Light> = self
            .parts
            .iter()
            .flat_map(|(model, asset)| {
                asset.lights.iter().map(|l| seamlit_scene::lights::from_gltf(l, model.transform))
            })
            .collect();
        if self.scene.lights.is_empty() && !from_files.is_empty() {
            from_files
        } else {
            self.scene.lights_or_default()
        }
    }

    /// The scene's cameras, or one framing `bounds` at this aspect ratio from the models'
    /// front ([`Loaded::facing`]).
    #[must_use]
    pub(crate) fn cameras(&self, bounds: Bounds, aspect: f32) -> Vec<Camera> {
        match self.facing() {
            Facing::MinusZ if self.scene.cameras.is_empty() => {
                vec![Camera::framing_facing(bounds, aspect, Facing::MinusZ)]
            }
            _ => self.scene.cameras_or_default(bounds, aspect),
        }
    }

    /// Which way the models face: -Z where every one is a VRM 0.x avatar (that version's
    /// convention; three-vrm turns them to face the viewer), +Z otherwise (glTF's).
    #[must_use]
    pub(crate) fn facing(&self) -> Facing {
        let vrm0 = |asset: &Asset| {
            asset.document::<seamlit_io::GltfSource>().is_some_and(seamlit_io::GltfSource::is_vrm0)
        };
        if !self.parts.is_empty() && self.parts.iter().all(|(_, asset)| vrm0(asset)) {
            Facing::MinusZ
        } else {
            Facing::PlusZ
        }
    }
}

/// The bounds of an asset's model, or a unit cube around the origin for an empty one.
#[must_use]
pub(crate) fn bounds_of(asset: &Asset) -> Bounds {
    asset.model.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE))
}

/// The bounds of what is drawn: each object at its pose in `poses` (from
/// [`crate::animate::poses`]: skinned by its joint palette, its morph targets weighted, placed
/// by the pose's transform), as the renderer's `deform.wgsl` places its vertices; the model's
/// bounds where nothing is posed ([`bounds_of`]). A skinned character whose armature scales
/// its mesh (a Mixamo export: centimetres under a 0.01 armature) is drawn far from its
/// unskinned bounds, and the default camera frames what is drawn.
#[must_use]
pub(crate) fn drawn_bounds(asset: &Asset, poses: Option<&[ObjectPose]>) -> Bounds {
    let Some(poses) = poses else { return bounds_of(asset) };
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for (object, pose) in asset.model.objects.iter().zip(poses) {
        let palette = pose.joints.as_deref().filter(|_| !object.skin.is_empty());
        let weights: Vec<(usize, f32)> =
            pose.morph_weights.iter().copied().enumerate().filter(|&(_, w)| w != 0.0).collect();
        for (v, &position) in object.positions.iter().enumerate() {
            let mut p = position;
            for &(k, w) in &weights {
                if let Some(d) = object.morph_targets.get(k).and_then(|t| t.position_deltas.get(v))
                {
                    p += *d * w;
                }
            }
            let skin = palette.map_or(Mat4::IDENTITY, |palette| blend(object, palette, v));
            let q = pose.transform.transform_point3(skin.transform_point3(p));
            if q.is_finite() {
                (lo, hi) = (lo.min(q), hi.max(q));
            }
        }
    }
    if lo.x <= hi.x { (lo, hi) } else { bounds_of(asset) }
}

/// Vertex `v`'s blend of the joint matrices in `palette` by its skin influences.
fn blend(object: &seamlit_mesh::Object, palette: &[Mat4], v: usize) -> Mat4 {
    let mut m = Mat4::ZERO;
    for set in &object.skin {
        for (joint, weight) in set.joints[v].into_iter().zip(set.weights[v]) {
            if weight != 0.0 {
                m += palette.get(joint as usize).copied().unwrap_or(Mat4::IDENTITY) * weight;
            }
        }
    }
    m
}

/// Picks the camera called `name` (or the first).
///
/// # Errors
/// [`Failure::BadInput`] listing the cameras there are.
pub(crate) fn pick_camera(
    cameras: &[Camera],
    name: Option<&str>,
    input: &Path,
) -> Result<Camera, Failure> {
    Scene::find_camera(cameras, name)
        .cloned()
        .map_err(|e| Failure::input(format!("{}: {e}", input.display())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::character;

    /// What `render`, `compare` and `view` draw is fixed as `seamlit fix` fixes: the neck's
    /// copies get one set of skin influences, so the seam stays closed when posed.
    #[test]
    fn what_is_drawn_has_its_skin_seams_matched() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("character.gltf");
        character::write(&path);
        let loaded = load(&path, &LoadOptions::DEFAULT).unwrap();
        let skin_seams = |asset: &Asset| {
            let report = seamlit_mesh::report(&asset.model, &Default::default()).unwrap();
            report.skin_seams.positions
        };
        assert_eq!(skin_seams(&loaded.parts[0].1), 12, "the neck's copies differ as loaded");
        let built = loaded.build(&FixOverride::default()).unwrap();
        assert_eq!(skin_seams(&built), 0, "and agree in what is drawn");
    }

    /// The default camera frames what is drawn: a skinned character whose mesh is stored in
    /// centimetres and brought to metres by its joints (a Mixamo export under an armature
    /// that scales by 0.01) is framed as drawn, not by its stored, 100 times larger bounds.
    #[test]
    fn a_skinned_character_is_framed_as_drawn_not_as_stored() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("character.gltf");
        character::write(&path);
        let asset = load(&path, &LoadOptions::DEFAULT).unwrap().build(&FixOverride::default());
        let metres = asset.unwrap();
        let mut centimetres = metres.clone();
        for object in &mut centimetres.model.objects {
            object.positions.iter_mut().for_each(|p| *p *= 100.0);
        }
        for skin in &mut centimetres.skins {
            for m in &mut skin.inverse_bind_matrices {
                *m *= Mat4::from_scale(Vec3::splat(0.01));
            }
        }
        let rest = crate::animate::Moment { animation: None, time: 0.0 };
        let framed =
            |asset: &Asset| drawn_bounds(asset, crate::animate::poses(asset, rest, &[]).as_deref());
        let (want, got) = (framed(&metres), framed(&centimetres));
        let size = (want.1 - want.0).length();
        assert!(size > 0.1, "{want:?}");
        let off = (want.0 - got.0).length().max((want.1 - got.1).length());
        assert!(off < 1e-4 * size, "drawn bounds {got:?}, expected {want:?}");
        // What the camera framed before: the stored bounds, a hundred times too large.
        let stored = bounds_of(&centimetres);
        assert!((stored.1 - stored.0).length() > 50.0 * size, "{stored:?}");
    }

    /// A VRM 0.x avatar faces -Z: the default camera looks at its front from there, as at a
    /// VRM 1.0 avatar's (and any glTF model's) from +Z.
    #[test]
    fn a_vrm_0_avatar_is_seen_from_the_front() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("avatar.gltf");
        character::write(&path);
        let text = std::fs::read_to_string(&path).unwrap();
        let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
        let mut camera_z = |extension: &str| {
            json["extensionsUsed"] = serde_json::json!([extension]);
            json["extensions"] = serde_json::json!({ extension: {} });
            std::fs::write(&path, json.to_string()).unwrap();
            let loaded = load(&path, &LoadOptions::DEFAULT).unwrap();
            let bounds = bounds_of(&loaded.parts[0].1);
            let camera = &loaded.cameras(bounds, 1.0)[0];
            (loaded.facing(), camera.position.z - camera.target.z)
        };
        let (facing, z) = camera_z("VRM");
        assert_eq!(facing, Facing::MinusZ);
        assert!(z < 0.0, "a VRM 0.x avatar seen from {z} along z");
        let (facing, z) = camera_z("VRMC_vrm");
        assert_eq!(facing, Facing::PlusZ);
        assert!(z > 0.0, "a VRM 1.0 avatar seen from {z} along z");
    }
}
