//! From a path on the command line to an asset ready to render: read the scene (or wrap a
//! model path in one), load each model, apply its material overrides, fix it with its
//! options (and the command line's), place it, and merge everything into one asset.

use std::path::Path;

use seamlit_io::{Asset, LoadOptions};
use seamlit_mesh::{FixOptions, Mode};
use seamlit_render::{Light, LightingModel};
use seamlit_scene::{Bounds, Camera, Scene, SceneModel};

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

    /// The scene's cameras, or one framing `bounds` at this aspect ratio.
    #[must_use]
    pub(crate) fn cameras(&self, bounds: Bounds, aspect: f32) -> Vec<Camera> {
        self.scene.cameras_or_default(bounds, aspect)
    }
}

/// The bounds of an asset's model, or a unit cube around the origin for an empty one.
#[must_use]
pub(crate) fn bounds_of(asset: &Asset) -> Bounds {
    asset.model.bounds().unwrap_or((glam::Vec3::splat(-1.0), glam::Vec3::ONE))
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
}
