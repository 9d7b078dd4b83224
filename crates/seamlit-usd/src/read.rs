//! `usd::load`: the stage opened and composed by openusd (`stage.rs`), its prims walked as
//! USD's default traversal does (active, loaded, defined, not abstract), instance proxies
//! included, and every `Mesh` a renderer draws read as one object (`mesh.rs`) in world space
//! (`xform.rs`; a skinned mesh where its UsdSkel binding puts it at the bind pose, with its
//! joint influences: `skel.rs`) with its bound material (`material.rs`).

mod instance;
mod material;
mod memory;
mod mesh;
mod nesting;
mod resolver;
mod skel;
mod stage;
mod xform;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DMat4;
use openusd::{sdf, usd};
use rayon::prelude::*;
use seamlit_mesh::{Model, VAxis};

pub(crate) use resolver::allowed_folders;
pub(crate) use stage::{check_text_nesting, guarded};

use crate::source::{StageSource, UsdSource};
use seamlit_asset::LoadOptions;
use seamlit_asset::error::IoError;
use seamlit_asset::{Asset, SourceDocument, TriangleMaterials};

/// Reads a USD stage (`.usda`, `.usdc` or `.usdz`, by its content) and the textures its
/// materials use. A stage without a triangle loads as an empty model here; `seamlit_io::load`
/// refuses it.
///
/// What comes in: one object per `Mesh` prim a renderer draws (not invisible, not of purpose
/// guide or proxy), named by its prim path, in traversal order; an instance's meshes (instance
/// proxies) are objects of their own, and the writer learns their prototype and where its
/// opinions can be authored for every instance. Positions are the mesh's points in its local space, the
/// object's transform its world matrix (xformOps, `!resetXformStack!`), turned to +Y up where
/// the stage's `upAxis` is Z; lengths stay in the stage's units (`metersPerUnit` is not
/// applied, so a weld tolerance is in the stage's units). A skinned mesh (UsdSkel, under a
/// SkelRoot) is placed where its skin binds it, `geomBindTransform` then its skeleton's world
/// matrix, and carries its joint influences (joints numbered across the stage); a binding that
/// cannot be used is a warning, and the mesh is read unskinned. Normals from `primvars:normals`,
/// else `normals`, none on a subdivision surface (a warning says so); UVs from `primvars:st`
/// (else the first `texCoord2f[]` primvar), V up. Values are the default, else the earliest
/// time sample. Materials from UsdPreviewSurface.
///
/// # Errors
///
/// [`IoError::TooLarge`] for a root layer over `options.max_file_bytes`; [`IoError::Usd`]
/// for a layer openusd cannot read, a stage that does not compose (a missing reference or
/// sublayer, a cycle; a missing payload is a warning), a mesh whose values do not fit it;
/// [`IoError::TooManyElements`] past the limits; the texture errors of
/// [`seamlit_asset::LoadOptions::strict`].
pub fn load(path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    let (mut asset, stage) = read(path, options)?;
    let source = UsdSource {
        asset_roots: options.asset_roots.clone(),
        stage: Some(Arc::new(stage)),
        files: options.files.clone(),
    };
    asset.document = Some(SourceDocument::new(source));
    Ok(asset)
}

/// [`load`], with what the `.usda` writer needs of each object's mesh.
pub(crate) fn read(path: &Path, options: &LoadOptions) -> Result<(Asset, StageSource), IoError> {
    seamlit_asset::files::check_size(path, options)?;
    let (mut asset, sources) = guarded(path, || read_stage(path, options))?;
    let mut warnings = std::mem::take(&mut asset.warnings);
    let decoding = textures_admitted(&asset, options);
    warnings.extend(seamlit_asset::texture::decode_all(&mut asset.textures, path, &decoding)?);
    asset.warnings = warnings;
    Ok((asset, sources))
}

/// `options` for decoding the stage's textures: the texture decoder reads files only inside
/// the model's folder and the asset roots, and without asset roots a stage's textures are
/// read where USD resolves them (the materials admitted only regular files, `material.rs`):
/// their folders are allowed as well.
fn textures_admitted(asset: &Asset, options: &LoadOptions) -> LoadOptions {
    if !options.asset_roots.is_empty() {
        return options.clone();
    }
    let mut folders: Vec<PathBuf> = asset
        .textures
        .iter()
        .filter_map(|t| match &t.source {
            seamlit_asset::TextureSource::File(file) => file.parent().map(Path::to_path_buf),
            _ => None,
        })
        .collect();
    folders.sort();
    folders.dedup();
    LoadOptions { asset_roots: folders, ..options.clone() }
}

fn read_stage(path: &Path, options: &LoadOptions) -> Result<(Asset, StageSource), IoError> {
    let opened = stage::open(path, options)?;
    let stage = &opened.stage;
    let mut warnings = Vec::new();
    let root = sdf::Path::abs_root();
    let at_root = |e: anyhow::Error| stage::prim_error(path, &root, &e);
    let mut prims = Vec::new();
    stage
        .traverse(usd::PrimPredicate::DEFAULT_PROXIES, |p| prims.push(p.clone()))
        .map_err(at_root)?;
    stage::composition(&opened, path, &mut warnings)?;
    let up = stage::up_axis(stage).map_err(at_root)?;
    let mut xforms = xform::Xforms::new(stage);
    let mut materials = material::Materials::new(stage, path, &options.asset_roots, &options.files);
    let mut skels = skel::Skels::new(stage);
    let mut instances = instance::Instances::new(stage);
    let mut objects = Vec::new();
    let mut sources = Vec::new();
    let mut triangles = 0usize;
    let (meshes, subsets) = meshes_and_subsets(stage, prims, path, options)?;
    let mut triangle_materials = Vec::new();
    let mut meshes = meshes.into_iter().peekable();
    while meshes.peek().is_some() {
        let mut reading =
            Reading { stage, xforms: &mut xforms, skels: &mut skels, up, path, options };
        let (batch, stop) = reading.batch(&mut meshes);
        for (prim_path, mesh_warnings, read) in batch {
            warnings.extend(mesh_warnings);
            let mut read = read?;
            let prim = stage.prim(prim_path.clone());
            let at = |e: anyhow::Error| stage::prim_error(path, &prim_path, &e);
            read.source.instance = instances.source(&prim).map_err(at)?;
            if read.source.instance.is_none() {
                read.source.root_sites = instances.root_sites(&prim_path).map_err(at)?;
            }
            let mut object = read.object;
            object.material = materials.bound(&prim_path, &mut warnings).map_err(at)?;
            if let Some(subsets) = subsets.get(prim_path.as_str()) {
                let faces = (read.triangle_faces.as_slice(), read.faces);
                let parts =
                    materials.subsets(&prim_path, subsets, faces, &mut warnings).map_err(at)?;
                if let Some(materials) = parts {
                    triangle_materials.push(TriangleMaterials { object: objects.len(), materials });
                }
            }
            triangles += object.triangle_count();
            if triangles > options.max_model_triangles {
                return Err(IoError::TooManyElements {
                    path: path.to_path_buf(),
                    what: "the model (every mesh)".to_owned(),
                    limit: options.max_model_triangles,
                    actual: triangles,
                });
            }
            objects.push(object);
            sources.push(read.source);
        }
        if let Some(error) = stop {
            return Err(error);
        }
    }
    // Reading values composes prims' arcs too: their errors count as the walk's.
    stage::composition(&opened, path, &mut warnings)?;
    let asset = Asset {
        model: Model { objects, v_axis: VAxis::Up },
        materials: std::mem::take(&mut materials.list),
        textures: std::mem::take(&mut materials.textures),
        source: Some(path.to_path_buf()),
        warnings,
        triangle_materials,
        ..Asset::default()
    };
    let metadata = stage::metadata(stage).map_err(at_root)?;
    Ok((asset, StageSource { meshes: sources, metadata, joints: skels.joints }))
}

/// The face corners of the meshes built side by side at most: a batch's arrays are held at
/// once, and a model past its limit is found at most a batch late.
const BATCH_CORNERS: usize = 1 << 21;

/// A mesh of a batch: its path, its warnings so far, and its object and source or the error
/// that stopped them.
type Built = (sdf::Path, Vec<String>, Result<mesh::Read, IoError>);

/// What reading the meshes of a stage takes from it, one mesh after another.
struct Reading<'a, 's> {
    stage: &'s usd::Stage,
    xforms: &'a mut xform::Xforms<'s>,
    skels: &'a mut skel::Skels<'s>,
    up: DMat4,
    path: &'a Path,
    options: &'a LoadOptions,
}

impl Reading<'_, '_> {
    /// The next meshes of `meshes`, read from the stage in turn (hidden ones skipped) until
    /// [`BATCH_CORNERS`] face corners, then built side by side ([`mesh::Authored::build`]), in
    /// their order; and the error that stopped the reading, if one did (it comes after the
    /// meshes read before it, as in reading one mesh after another).
    fn batch(
        &mut self,
        meshes: &mut impl Iterator<Item = sdf::Path>,
    ) -> (Vec<Built>, Option<IoError>) {
        let mut read = Vec::new();
        let mut corners = 0;
        let mut stop = None;
        for prim_path in meshes.by_ref() {
            let mut warnings = Vec::new();
            match self.mesh(&prim_path, &mut warnings) {
                Ok(None) => {}
                Ok(Some(authored)) => {
                    corners += authored.corners();
                    read.push((prim_path, warnings, authored));
                    if corners >= BATCH_CORNERS {
                        break;
                    }
                }
                Err(error) => {
                    stop = Some(error);
                    break;
                }
            }
        }
        let path = self.path;
        let built = read
            .into_par_iter()
            .map(|(prim_path, warnings, authored)| (prim_path, warnings, authored.build(path)))
            .collect();
        (built, stop)
    }

    /// The mesh at `prim_path` as read from the stage; `None` where it is hidden.
    fn mesh(
        &mut self,
        prim_path: &sdf::Path,
        warnings: &mut Vec<String>,
    ) -> Result<Option<mesh::Authored>, IoError> {
        let prim = self.stage.prim(prim_path.clone());
        let at = |e: anyhow::Error| stage::prim_error(self.path, prim_path, &e);
        if self.xforms.hidden(prim_path).map_err(at)? {
            return Ok(None);
        }
        let world = self.xforms.world(prim_path).map_err(at)?;
        let xforms = &mut *self.xforms;
        let binding = self.skels.binding(&prim, &mut |p| xforms.world(p)).map_err(at)?;
        let skin = usable_skin(binding, self.path, prim_path, warnings);
        let placement = mesh::Placement { world, up: self.up, skin };
        mesh::read(&prim, placement, self.path, self.options, warnings).map(Some)
    }
}

/// The stage's meshes among `prims`, and the GeomSubsets under each (by the mesh's path;
/// only where `options` asks for subset materials).
type MeshesAndSubsets = (Vec<sdf::Path>, HashMap<String, Vec<sdf::Path>>);

fn meshes_and_subsets(
    stage: &usd::Stage,
    prims: Vec<sdf::Path>,
    path: &Path,
    options: &LoadOptions,
) -> Result<MeshesAndSubsets, IoError> {
    let mut meshes = Vec::new();
    let mut subsets: HashMap<String, Vec<sdf::Path>> = HashMap::new();
    for prim_path in prims {
        let at = |e: anyhow::Error| stage::prim_error(path, &prim_path, &e);
        match stage.prim(prim_path.clone()).type_name().map_err(at)?.as_ref().map(|t| t.as_str()) {
            Some("Mesh") => meshes.push(prim_path),
            Some("GeomSubset") if options.subset_materials => {
                if let Some(parent) = prim_path.parent() {
                    subsets.entry(parent.as_str().to_owned()).or_default().push(prim_path);
                }
            }
            _ => {}
        }
    }
    Ok((meshes, subsets))
}

/// The mesh's skin binding where it can be used; one warning naming the mesh where it cannot
/// (the mesh is then read unskinned, at its own transform).
fn usable_skin(
    binding: Option<Result<skel::Binding, String>>,
    path: &Path,
    prim_path: &sdf::Path,
    warnings: &mut Vec<String>,
) -> Option<skel::Binding> {
    match binding? {
        Ok(binding) => Some(binding),
        Err(reason) => {
            warnings.push(format!(
                "{}: mesh <{}>: its skin is ignored ({reason}): read unskinned, at its own transform",
                path.display(),
                prim_path.as_str()
            ));
            None
        }
    }
}

/// An attribute's value: its default, else its earliest time sample (the rest pose of a
/// skinned or animated mesh, the first frame of time-sampled points).
fn value(attribute: &usd::Attribute) -> anyhow::Result<Option<sdf::Value>> {
    if let Some(v) = attribute.get::<sdf::Value>()? {
        return Ok(Some(v));
    }
    // The sample of the smallest time, found here: openusd 0.6 keeps a layer's samples in the
    // order the file writes them, and its lookups by time assume them sorted.
    let samples = attribute.time_samples()?.unwrap_or_default();
    let earliest =
        samples.into_iter().filter(|(t, _)| t.is_finite()).min_by(|a, b| a.0.total_cmp(&b.0));
    Ok(earliest.map(|(_, v)| v).filter(|v| !matches!(v, sdf::Value::ValueBlock | sdf::Value::None)))
}

/// A double rounded to the `f32` seamlit stores.
#[expect(clippy::cast_possible_truncation, reason = "rounding to f32 is the point")]
fn f32_of(x: f64) -> f32 {
    x as f32
}
