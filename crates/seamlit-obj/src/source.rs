//! The OBJ file an asset was loaded from, kept for the pass-through writer: its text as
//! read, its `mtllib` statements, and for each object of the model where its triangles came
//! from in the file. The reader makes it, the writer reads it, [`seamlit_asset::Asset`] holds it.

use std::hash::{Hash as _, Hasher as _};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Mat4;
use seamlit_asset::files::Files;
use seamlit_mesh::{Model, Object};

/// The OBJ file an [`seamlit_asset::Asset`] was loaded from: its text as read, its `mtllib`
/// statements, and for each object of the model where its triangles came from in the file.
///
/// Opaque and cheap to clone (shared). `seamlit_io::save` to `.obj` uses it to write the input
/// back with only the normals and the faces' normal references changed.
#[derive(Clone)]
pub struct ObjSource(pub(crate) Arc<Source>);

/// What an [`ObjSource`] shares.
pub(crate) struct Source {
    /// The file's bytes (a UTF-16 file: its text, decoded to UTF-8).
    pub(crate) text: Vec<u8>,
    /// The file it was read from: `mtllib` paths are resolved against its folder.
    pub(crate) path: PathBuf,
    /// The `mtllib` statements: the name as written and the line.
    pub(crate) libraries: Vec<(String, usize)>,
    /// Per object of the loaded model.
    pub(crate) objects: Vec<SourceObject>,
    /// Where its material libraries and textures were read from (the pass-through copies
    /// them from there).
    pub(crate) files: Files,
}

/// Where a loaded object's triangles came from.
pub(crate) struct SourceObject {
    /// The object's vertex count as loaded.
    pub vertices: usize,
    /// [`fingerprint`] of its triangles as loaded.
    pub fingerprint: u64,
    /// Runs of its triangles among the file's: first (counted over the file) and length.
    pub runs: Vec<(usize, usize)>,
    /// Its ear-clipped polygons: first triangle (in the object) and corners (vertices).
    pub clipped: Vec<(usize, Vec<u32>)>,
}

impl std::fmt::Debug for ObjSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ObjSource")
            .field("path", &self.0.path)
            .field("objects", &self.0.objects.len())
            .field("bytes", &self.0.text.len())
            .finish_non_exhaustive()
    }
}

/// A hash of an object's triangles (as input vertices), to see that a model still has the
/// faces it was loaded with.
pub(crate) fn fingerprint(triangles: impl Iterator<Item = [u32; 3]>) -> u64 {
    let mut hasher = std::hash::DefaultHasher::new();
    for triangle in triangles {
        triangle.hash(&mut hasher);
    }
    hasher.finish()
}

impl ObjSource {
    /// Keeps a loaded file for the pass-through writer.
    pub(crate) fn new(
        text: Vec<u8>,
        path: &Path,
        libraries: Vec<(String, usize)>,
        objects: Vec<SourceObject>,
        files: Files,
    ) -> Self {
        let path = path.to_path_buf();
        Self(Arc::new(Source { text, path, libraries, objects, files }))
    }

    /// Whether `model` is still the model of this source: the same objects, each without a
    /// transform, with its input vertices first (plus split copies of them) and the same
    /// triangles, in order, up to split copies. Returns why not.
    pub fn check_model(&self, model: &Model) -> Result<(), String> {
        let source = &*self.0;
        if model.objects.len() != source.objects.len() {
            return Err(format!(
                "the model has {} objects, its OBJ source {}",
                model.objects.len(),
                source.objects.len()
            ));
        }
        for (object, loaded) in model.objects.iter().zip(&source.objects) {
            if object.transform.is_some_and(|m| m != Mat4::IDENTITY) {
                return Err(format!("object {:?} has a transform", object.name));
            }
            let input = object.vertex_count().checked_sub(object.split_from.len());
            if input != Some(loaded.vertices) {
                return Err(format!(
                    "object {:?} has {} input vertices, {} were loaded",
                    object.name,
                    input.map_or_else(|| "fewer than no".to_owned(), |n| n.to_string()),
                    loaded.vertices
                ));
            }
            if object.split_from.iter().any(|&v| v as usize >= loaded.vertices) {
                return Err(format!(
                    "object {:?}: a split vertex copies a vertex past the {} input vertices",
                    object.name, loaded.vertices
                ));
            }
            if fingerprint(input_triangles(object)) != loaded.fingerprint {
                return Err(format!(
                    "object {:?} does not have the triangles it was loaded with",
                    object.name
                ));
            }
        }
        Ok(())
    }
}

/// An object's triangles as the input vertices their corners are or copy (an index out of
/// range as `u32::MAX`, which no fingerprint of a loaded object holds).
fn input_triangles(object: &Object) -> impl Iterator<Item = [u32; 3]> + '_ {
    let count = object.vertex_count();
    object.triangles.iter().map(move |triangle| {
        triangle.map(|v| if (v as usize) < count { object.source_vertex(v) } else { u32::MAX })
    })
}
