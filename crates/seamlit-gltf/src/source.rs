//! The glTF document an asset was loaded from, kept for the pass-through writer: the JSON as
//! written, the buffers' bytes, and for each object of the model the node, mesh and
//! primitive it came from. The reader makes it, the writer reads it, [`seamlit_asset::Asset`] holds
//! it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use seamlit_asset::files::Files;
use seamlit_mesh::Model;
use serde_json::Value;

use crate::json::usize_member;
use crate::loaded::LoadedBuffers;

/// The glTF document an [`seamlit_asset::Asset`] was loaded from: the JSON as written, the buffers'
/// bytes, and for each object of the model the node, mesh and primitive it came from.
///
/// Opaque and cheap to clone (shared). `seamlit_io::save` uses it to write the input back with
/// only normals, tangents, split vertices and indices changed.
#[derive(Clone)]
pub struct GltfSource(pub(crate) Arc<Source>);

/// What a [`GltfSource`] shares.
pub(crate) struct Source {
    /// The document, as parsed from the file.
    pub(crate) json: Value,
    /// Each buffer's bytes (at least its `byteLength`), less those of buffer 0 that the
    /// writer never reads (`passthrough/unread.rs`).
    pub(crate) buffers: LoadedBuffers,
    /// The file it was read from: relative URIs are resolved against its folder.
    pub(crate) path: PathBuf,
    /// Per object of the loaded model: where it came from.
    pub(crate) instances: Vec<Instance>,
    /// Per node of [`seamlit_asset::Asset::nodes`]: its index in the document's `nodes`.
    pub(crate) nodes: Vec<usize>,
    /// Where the files its URIs name were read from (the pass-through copies them from there).
    pub(crate) files: Files,
}

/// Where an object came from: a primitive of a mesh, instanced by a node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Instance {
    /// Index into `nodes`.
    pub node: usize,
    /// Index into `meshes`.
    pub mesh: usize,
    /// Index into the mesh's `primitives`.
    pub primitive: usize,
}

impl std::fmt::Debug for GltfSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GltfSource")
            .field("path", &self.0.path)
            .field("objects", &self.0.instances.len())
            .field("buffers", &self.0.buffers.count())
            .finish_non_exhaustive()
    }
}

impl GltfSource {
    /// Keeps a loaded document for the pass-through writer.
    pub(crate) fn new(
        json: Value,
        buffers: LoadedBuffers,
        path: &Path,
        instances: Vec<Instance>,
        nodes: Vec<usize>,
        files: Files,
    ) -> Self {
        let path = path.to_path_buf();
        Self(Arc::new(Source { json, buffers, path, instances, nodes, files }))
    }

    /// Whether the document is a VRM avatar: VRM 0.x's `VRM` or VRM 1.0's `VRMC_vrm`
    /// extension on the root.
    pub fn is_vrm(&self) -> bool {
        let extensions = &self.0.json["extensions"];
        extensions.get("VRM").is_some() || extensions.get("VRMC_vrm").is_some()
    }

    /// Whether the document is a VRM 0.x avatar (its root `VRM` extension): such an avatar
    /// faces -Z, where glTF models and VRM 1.0 avatars face +Z.
    pub fn is_vrm0(&self) -> bool {
        let extensions = &self.0.json["extensions"];
        extensions.get("VRM").is_some() && extensions.get("VRMC_vrm").is_none()
    }

    /// Whether `model` is still the model of this source: one object per primitive instance,
    /// each with the input's vertices first (plus split copies of them). Returns why not.
    pub fn check_model(&self, model: &Model) -> Result<(), String> {
        let source = &*self.0;
        if model.objects.len() != source.instances.len() {
            return Err(format!(
                "the model has {} objects, its glTF source {} primitive instances",
                model.objects.len(),
                source.instances.len()
            ));
        }
        for (object, instance) in model.objects.iter().zip(&source.instances) {
            let expected = source
                .primitive(*instance)
                .and_then(|p| usize_member(&p["attributes"], "POSITION"))
                .and_then(|a| usize_member(&source.json["accessors"][a], "count"));
            let input = object.vertex_count().checked_sub(object.split_from.len());
            if input.is_none() || input != expected {
                return Err(format!(
                    "object {:?} has {} input vertices, mesh {} primitive {} has {}",
                    object.name,
                    input.map_or_else(|| "fewer than no".to_owned(), |n| n.to_string()),
                    instance.mesh,
                    instance.primitive,
                    expected.map_or_else(|| "none".to_owned(), |n| n.to_string())
                ));
            }
            let input = input.unwrap_or_default();
            if let Some(&v) = object.split_from.iter().find(|&&v| v as usize >= input) {
                return Err(format!(
                    "object {:?}: a split vertex copies vertex {v}, past the {input} input vertices",
                    object.name
                ));
            }
        }
        source.buffers.check_model(model)
    }
}

impl Source {
    /// The JSON of a primitive.
    pub(crate) fn primitive(&self, instance: Instance) -> Option<&Value> {
        self.json["meshes"].get(instance.mesh)?["primitives"].get(instance.primitive)
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use seamlit_asset::{LoadOptions, TextureSource};

    use super::GltfSource;

    /// A GLB's embedded images are read in place: each one's bytes lie inside the BIN chunk's
    /// buffer the asset keeps (a copy would double the textures' memory).
    #[test]
    fn embedded_images_are_slices_of_the_buffer() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models/NormalTangentTest.glb");
        let asset = crate::read::load(&path, &LoadOptions::FIX).unwrap();
        let source = asset.document.as_ref().and_then(|d| d.get::<GltfSource>()).unwrap();
        let bin = source.0.buffers.stored_bytes(0).as_ptr_range();
        let mut embedded = 0;
        for texture in &asset.textures {
            if let TextureSource::Embedded { bytes, .. } = &texture.source {
                let inside = bin.start <= bytes.as_ptr() && bytes.as_ptr_range().end <= bin.end;
                assert!(inside, "{} copied out of its buffer", texture.name);
                embedded += 1;
            }
        }
        assert!(embedded >= 2, "{embedded} embedded images");
    }
}
