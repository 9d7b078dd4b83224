//! glTF 2.0 and GLB in, through the gltf crate.
//!
//! The JSON is parsed and validated by gltf-json, less the few rules in which it is stricter
//! than the specification (`read/lenient.rs`); the GLB container is split by its chunk
//! headers (`glb.rs`). Buffers and images are resolved here (`read/buffers.rs`, `uri.rs`), so
//! that this reader decides what a URI may point to and names the place of every problem:
//!
//! - buffers and images come from the GLB `BIN` chunk, `data:` URIs (base64) or files beside
//!   the model; a URI that leaves the model's folder (`../`, an absolute path, a symbolic
//!   link leading out) or names another scheme is refused;
//! - every accessor a primitive uses is checked against its buffer view, and every view
//!   against its buffer, before a byte is read; every index against the vertex count; every
//!   attribute for NaN and infinity;
//! - quantised attributes (KHR_mesh_quantization) are read as floats and meshopt-compressed
//!   buffer views (EXT_meshopt_compression) are decoded at load (`decode/quantized.rs`,
//!   `decode/meshopt.rs`), and so are Draco-compressed primitives with the `draco` feature
//!   (`decode/draco.rs`); without it such a primitive is refused, naming it and a command
//!   that decompresses it;
//! - once the model is decoded, buffer 0 keeps only the bytes the pass-through writer needs
//!   from it: not those of the normals, tangents and indices it writes from the model, nor
//!   the positions and UVs the model holds bit for bit (`passthrough/unread.rs`, `loaded.rs`).
//!
//! Every primitive of every mesh instance in the default scene (or the first scene; in a file
//! without scenes, under the nodes that are no node's child) becomes an object, its
//! transform the composition of the node transforms above it (a mesh used by two nodes is
//! two objects). An object is named after its node (else its mesh, else
//! `mesh{index}`), with `.{primitive}` appended when the mesh has several primitives.
//!
//! The steps, a file each: the validated document of the bytes (`document.rs`, with the
//! leniency rules in `lenient.rs`), the buffers and images (`buffers.rs`), the scene walk
//! (`scene.rs`), each primitive (`primitive.rs`) and the checks of its accessors
//! (`accessors.rs`), skin influences and morph targets (`deform.rs`), skins and animations
//! (`animation.rs`), materials (`material.rs`) and lights (`lights.rs`).

mod accessors;
mod animation;
mod buffers;
mod deform;
mod document;
#[cfg(test)]
mod give_back_tests;
mod lenient;
mod lights;
mod material;
mod primitive;
mod scene;

use std::path::Path;

use bytes::Bytes;
use seamlit_mesh::VAxis;

use crate::loaded::LoadedBuffers;
use crate::source::GltfSource;
#[cfg(feature = "draco")]
use document::decode_draco;
use document::document;
use lights::punctual_lights;
use material::{material, variants};
use scene::SceneWalk;
use seamlit_asset::Asset;
use seamlit_asset::LoadOptions;
use seamlit_asset::error::IoError;

/// Reads a glTF (`.gltf`, with its buffers and images) or GLB file.
///
/// # Errors
///
/// [`IoError::Gltf`] for a malformed container, JSON or a document the gltf crate rejects
/// (with the JSON path), and for bad geometry data (a buffer shorter than declared, an
/// accessor out of range or of the wrong layout, an index out of range, a value not
/// finite); [`IoError::BadUri`] for a URI outside the model's folder,
/// [`IoError::LinkEscapes`] for one whose symbolic links lead out of it;
/// [`IoError::MissingFile`] for a missing buffer file (or texture, when `options.strict`).
pub fn load(path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    load_giving_back(path, options, true)
}

/// [`load`] keeping every byte of its buffers, for tests of what giving back changes.
#[cfg(test)]
pub(crate) fn load_whole(path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    load_giving_back(path, options, false)
}

/// [`load`], giving back what of buffer 0 the pass-through never reads where `give_back`.
fn load_giving_back(path: &Path, options: &LoadOptions, give_back: bool) -> Result<Asset, IoError> {
    let mut bytes = seamlit_asset::files::read_bytes(path, options)?;
    let (document, json, bin) = document(&bytes, path)?;
    // The file's bytes become the BIN chunk's buffer, moved to the front in place: a GLB is
    // never held twice. A JSON file's bytes are freed here.
    let blob = bin.map(|range| {
        let length = range.len();
        bytes.copy_within(range, 0);
        bytes.truncate(length);
        bytes.shrink_to_fit();
        bytes
    });
    let mut asset = read(&document, json, blob, path, options, give_back)?;
    asset.source = Some(path.to_path_buf());
    Ok(asset)
}

/// Parses glTF or GLB bytes; `path` names the file in errors and its folder resolves
/// relative URIs.
///
/// # Errors
///
/// As [`load`].
pub fn parse(bytes: &[u8], path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    let (document, json, bin) = document(bytes, path)?;
    read(&document, json, bin.map(|range| bytes[range].to_vec()), path, options, true)
}

/// Reads the asset of a validated document; `blob` is the GLB's BIN chunk. The buffers and
/// `json` (the document as written, Draco primitives decoded) end in the asset's
/// [`GltfSource`], for the pass-through writer, less what of buffer 0 it never reads where
/// `give_back` (`passthrough/unread.rs`).
fn read(
    document: &gltf::Document,
    json: serde_json::Value,
    blob: Option<Vec<u8>>,
    path: &Path,
    options: &LoadOptions,
    give_back: bool,
) -> Result<Asset, IoError> {
    let reader = Reader { path, options, buffer_bytes: 0 };
    let without_data = buffers_without_data(document, &json, blob.is_some());
    let mut buffers = reader.buffers(document, &json, blob)?;
    crate::decode::meshopt::decode_meshopt(&json, &mut buffers, path)?;
    #[cfg(feature = "draco")]
    let mut json = json;
    #[cfg(feature = "draco")]
    let decoded = decode_draco(&mut json, &mut buffers, options, path)?;
    #[cfg(feature = "draco")]
    let document = decoded.as_ref().unwrap_or(document);
    let reader = Reader { buffer_bytes: buffers.iter().map(|b| b.len() as u64).sum(), ..reader };
    reader.check_views(document, &buffers, &without_data)?;
    let buffers: Vec<Bytes> = buffers.into_iter().map(Bytes::from).collect();

    let mut asset = Asset::default();
    let mut warnings = Vec::new();
    asset.materials = document.materials().map(|m| material(&m, document)).collect();
    let scene = document.default_scene().or_else(|| document.scenes().next());
    let roots: Vec<gltf::Node<'_>> = match &scene {
        Some(scene) => scene.nodes().collect(),
        None => lenient::root_nodes(document),
    };
    if scene.is_none() && document.meshes().len() > 0 {
        warnings.push(format!(
            "{}: no scene; the nodes that are no node's child are placed as one",
            path.display()
        ));
    }
    let mut scene_walk = SceneWalk::new(&reader, &buffers, &without_data);
    scene_walk.decode_ahead(&roots);
    scene_walk.walk(roots, &mut asset, &mut warnings)?;
    let (instances, mut node_indices) = (scene_walk.instances, scene_walk.node_indices);
    reader.skins_and_animations(
        (document, &json),
        &buffers,
        &mut node_indices,
        &mut asset,
        &mut warnings,
    )?;
    // Every accessor is decoded: buffer 0 keeps only what the pass-through writer reads again.
    let buffers = LoadedBuffers::new(buffers);
    let unread = give_back.then(|| crate::passthrough::unread(&json, &instances)).flatten();
    let buffers = match unread {
        Some(unread) => buffers.keeping_of_host(unread.kept, unread.from_model),
        None => buffers,
    };
    // The embedded images are slices of their buffer, not copies of it.
    asset.textures = reader.images(document, &buffers)?;
    asset.model.v_axis = VAxis::Down;
    asset.lights = punctual_lights(document, scene.as_ref(), &mut warnings);
    let mut document_nodes = vec![usize::MAX; asset.nodes.len()];
    for (&d, &a) in &node_indices {
        document_nodes[a] = d;
    }
    asset.variants = variants(&json, &instances, asset.materials.len(), path, &mut warnings);
    let source =
        GltfSource::new(json, buffers, path, instances, document_nodes, options.files.clone());
    asset.document = Some(seamlit_asset::SourceDocument::new(source));
    warnings.extend(seamlit_asset::texture::decode_all(&mut asset.textures, path, options)?);
    asset.warnings = warnings;
    Ok(asset)
}

/// The buffers without data (see `lenient.rs`): a buffer without `uri` outside a GLB, unless
/// it is a meshopt fallback buffer, which `decode_meshopt` fills.
fn buffers_without_data(
    document: &gltf::Document,
    json: &serde_json::Value,
    glb: bool,
) -> Vec<usize> {
    let meshopt_fallback = |b: &usize| {
        let extensions = &json["buffers"][*b]["extensions"];
        extensions.get("EXT_meshopt_compression").is_some()
            || extensions.get("KHR_meshopt_compression").is_some()
    };
    lenient::buffers_without_data(document, glb)
        .into_iter()
        .filter(|b| !meshopt_fallback(b))
        .collect()
}

/// What reading one file needs to know: the file (errors name it, relative URIs resolve
/// against its folder), the options, and the size of its buffers.
struct Reader<'a> {
    path: &'a Path,
    options: &'a LoadOptions,
    /// The bytes of all buffers together: what the file can hold.
    buffer_bytes: u64,
}
