//! # seamlit-io
//!
//! The front door to seamlit's model files: [`load`] picks the reader and [`save`] the writer
//! by the file's extension ([`Format::of`]), and [`folder`] holds the rules by which
//! `seamlit fix DIR -o DIR` picks a folder's model files and names their outputs. Every file
//! becomes a [`seamlit_asset::Asset`]: a [`seamlit_mesh::Model`] of named objects plus the
//! materials, textures, nodes, skins and animations that lighting and writing need.
//!
//! Each format is a crate of its own, re-exported here under its name, and the only one this
//! crate holds itself is Newell's Bezier patches ([`newell`], a few hundred lines):
//!
//! | module | crate | reads | writes | feature |
//! |---|---|---|---|---|
//! | [`gltf`] | seamlit-gltf | `.gltf`, `.glb`, `.vrm` (quantised, meshopt, Draco) | the same, as a pass-through of the input | `draco` for Draco |
//! | [`obj`] | seamlit-obj | `.obj` + `.mtl` | `.obj` + `.mtl`, as a pass-through of the input | |
//! | `fbx` | seamlit-fbx | `.fbx` (through the ufbx C library) | | `fbx` |
//! | `usd` | seamlit-usd | `.usda`, `.usdc`, `.usdz`, `.usd` | a layer of the fixed normals, or a `.usdz` | `usd` |
//! | [`newell`] | here | Newell's patches (`.bpt`, ...) | | |
//!
//! The features are on by default; without `fbx` and `usd` (and `draco`) the crate builds
//! without a C library, for `wasm32-unknown-unknown` too.
//!
//! ```
//! use seamlit_io::{LoadOptions, newell};
//!
//! // One bicubic patch: a flat 4 x 4 grid of control points (16 indices, 16 points).
//! let mut text = String::from("1\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n16\n");
//! for j in 0..4 {
//!     for i in 0..4 {
//!         text.push_str(&format!("{i},{j},0\n"));
//!     }
//! }
//! let asset = newell::parse(&text, "square", 4)?;
//! let object = &asset.model.objects[0];
//! assert_eq!(object.name, "square_patch00");
//! assert_eq!(object.triangle_count(), 2 * 4 * 4);
//! assert_eq!(object.vertex_count(), 5 * 5);
//! # Ok::<(), seamlit_io::IoError>(())
//! ```
//!
//! Loading dispatches on the extension: [`load`]. Writing too: [`save`], always to a
//! temporary file in the destination folder that is then renamed over the destination.
//!
//! ## The glTF pass-through
//!
//! An asset loaded from glTF or GLB keeps its document ([`GltfSource`] in
//! [`Asset::document`]). Saved as glTF
//! or GLB, it is written as that document with only what seamlit owns changed: new NORMAL and
//! TANGENT accessors, new indices, and, for the vertices [`seamlit_mesh::fix`] split, every
//! other attribute and morph target duplicated from the vertex each copy came from. Skins,
//! animations, materials and their extensions, images (bytes untouched), cameras, lights,
//! extras and unknown extensions pass through; existing accessors keep their indices. A mesh
//! whose instances got different frames is cloned, and [`SaveReport::warnings`] says so.
//! The design: `docs/gltf-pass-through.md`.
//!
//! ## The OBJ pass-through
//!
//! An asset loaded from OBJ keeps its text ([`ObjSource`] in [`Asset::document`]). Saved as
//! OBJ, it is
//! written as that text with only the `vn` lines new and each face corner's normal reference
//! pointing at its fixed normal; every other line (comments, `o`/`g` names, `s`, `usemtl`,
//! vertex colours, `vt`, `l`, unknown statements, line ends) is copied byte for byte, faces
//! keep their corners and `v`/`vt` references, and the material libraries and their textures
//! are copied beside the output as written. OBJ has no tangents: [`SaveReport::warnings`] says
//! when computed ones are not written. The design: `docs/obj-pass-through.md`.
#![deny(missing_docs)]

pub mod folder;
pub mod job;
pub mod newell;

use std::path::Path;

use seamlit_asset::files::same_file;
pub use seamlit_asset::{
    AlphaMode, Animation, Anisotropy, Asset, BadAccessor, BadUri, Channel, Clearcoat, Draco,
    FbxKind, Glb, GltfKind, Interpolation, InvalidAsset, IoError, Iridescence, KeepCompression,
    LoadOptions, Material, Meshopt, Node, NotText, PbrExtensions, Property, PunctualKind,
    PunctualLight, Sampler, SaveOptions, Sheen, Skin, SkinsChanged, SourceDocument, Specular,
    Syntax, Texture, TextureFilter, TextureRef, TextureSampling, TextureSource, Transmission,
    TriangleMaterials, Trs, UnknownVariant, UsdKind, UsdOutput, UvTransform, VariantObject,
    Variants, Volume, Wrap, files, match_skin_seams, motion, pose, roughness_to_shininess,
    shininess_to_roughness,
};
#[cfg(feature = "fbx")]
pub use seamlit_fbx as fbx;
pub use seamlit_gltf as gltf;
pub use seamlit_gltf::GltfSource;
pub use seamlit_obj as obj;
pub use seamlit_obj::ObjSource;
#[cfg(feature = "usd")]
pub use seamlit_usd as usd;
#[cfg(feature = "usd")]
pub use seamlit_usd::UsdSource;

/// A model file format this crate reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ.
    Obj,
    /// glTF 2.0, JSON.
    Gltf,
    /// glTF 2.0, binary container.
    Glb,
    /// Newell's Bezier patch text.
    Newell,
    /// Autodesk FBX, binary or ASCII (read only, with the `fbx` feature).
    Fbx,
    /// An OpenUSD stage: `.usda` (text), `.usdc` (binary), `.usdz` (package) or `.usd`
    /// (either), with the `usd` feature; written as a `.usda` layer over the input.
    Usd,
}

impl Format {
    /// The format of `path`, from its extension (case-insensitive): `.obj`, `.gltf`, `.glb`
    /// (and `.vrm`, a VRM avatar: a GLB with VRM's extensions), `.fbx` (with the `fbx`
    /// feature), `.usda`, `.usdc`, `.usdz`, `.usd` (with the `usd` feature), and for Newell
    /// patches `.bpt`, `.patch`, `.patches`, `.newell`. A file without an
    /// extension is a Newell patch file if its first token is an integer (the patch count).
    ///
    /// Returns `None` for anything else (and for an extension-less file that cannot be read).
    #[must_use]
    pub fn of(path: &Path) -> Option<Self> {
        let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("obj") => Some(Self::Obj),
            Some("gltf") => Some(Self::Gltf),
            Some("glb" | "vrm") => Some(Self::Glb),
            Some("fbx") if cfg!(feature = "fbx") => Some(Self::Fbx),
            Some("usda" | "usdc" | "usdz" | "usd") if cfg!(feature = "usd") => Some(Self::Usd),
            Some("bpt" | "patch" | "patches" | "newell") => Some(Self::Newell),
            None => {
                let mut head = [0u8; 64];
                let n =
                    std::io::Read::read(&mut std::fs::File::open(path).ok()?, &mut head).ok()?;
                let text = String::from_utf8_lossy(&head[..n]);
                let first =
                    text.split(|c: char| c.is_whitespace() || c == ',').find(|t| !t.is_empty())?;
                first.parse::<u64>().is_ok().then_some(Self::Newell)
            }
            Some(_) => None,
        }
    }
}

/// Loads a model file, choosing the reader by [`Format::of`].
///
/// # Errors
///
/// [`IoError::UnknownFormat`] for an extension no reader handles, the errors of
/// [`obj::load`], [`gltf::load`], [`newell::load`], (with the `fbx` feature) `fbx::load` and
/// (with the `usd` feature) `usd::load`,
/// and [`IoError::NoTriangles`] for a
/// file that holds no triangle (those readers return such a file as an empty model).
pub fn load(path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    let asset = match Format::of(path) {
        Some(Format::Obj) => obj::load(path, options),
        Some(Format::Gltf | Format::Glb) => gltf::load(path, options),
        Some(Format::Newell) => newell::load(path, options),
        #[cfg(feature = "fbx")]
        Some(Format::Fbx) => fbx::load(path, options),
        #[cfg(not(feature = "fbx"))]
        Some(Format::Fbx) => Err(IoError::UnknownFormat { path: path.to_path_buf() }),
        #[cfg(feature = "usd")]
        Some(Format::Usd) => usd::load(path, options),
        #[cfg(not(feature = "usd"))]
        Some(Format::Usd) => Err(IoError::UnknownFormat { path: path.to_path_buf() }),
        None if !path.exists() => {
            Err(IoError::io(path, std::io::Error::from(std::io::ErrorKind::NotFound)))
        }
        None => Err(IoError::UnknownFormat { path: path.to_path_buf() }),
    }?;
    if asset.model.triangle_count() == 0 {
        return Err(IoError::NoTriangles { path: path.to_path_buf() });
    }
    Ok(asset)
}

/// Writes an asset, choosing the writer by the extension of `path`: `.gltf` (JSON, with a
/// `.bin` buffer and the textures beside it), `.glb` (one binary file, textures embedded),
/// `.vrm` (a VRM avatar loaded from a `.vrm`, through the pass-through, which keeps every VRM
/// extension) or `.obj` (with a `.mtl` and the textures beside it).
///
/// An asset loaded from glTF or GLB ([`GltfSource`]) and saved as `.gltf` or `.glb`
/// goes through the pass-through writer: the output is the input document with only NORMAL,
/// TANGENT, the split vertices and the indices changed (see `docs/gltf-pass-through.md`).
/// An asset loaded from OBJ ([`ObjSource`]) and saved as `.obj` goes through the OBJ
/// pass-through: the input file with only the `vn` lines and the faces' normal references
/// changed, its material libraries and textures copied as written (see
/// `docs/obj-pass-through.md`). Other assets, and an asset whose model no longer matches its
/// source (objects added or removed; a warning says so), go through the generic writers.
/// OBJ holds no tangents: an OBJ output of a model with tangents gets a warning.
///
/// With `options.keep_compression`, a glTF or GLB asset whose source used meshopt
/// compression is written with it ([`SaveOptions::keep_compression`]).
///
/// Each file is written to a temporary name in the destination folder, then renamed.
///
/// # Errors
///
/// [`IoError::WouldOverwriteInput`] when `path` is the asset's own source and
/// `options.overwrite_input` is not set; [`IoError::CannotKeepCompression`] with
/// `options.keep_compression` for a Draco-compressed source or an `.obj` path;
/// [`IoError::FbxOutput`] for an `.fbx` path (seamlit writes no FBX);
/// [`IoError::VrmOutput`] for a `.vrm` path when the asset is not a VRM avatar the
/// pass-through can write back;
/// [`IoError::UsdOutput`] for a `.usda`, `.usdc` or `.usdz` path when the asset did not come
/// from USD or no longer matches its stage, a package whose input file cannot be read, a
/// binary layer openusd cannot write;
/// [`IoError::UnknownFormat`] for another extension;
/// [`IoError::InvalidAsset`] for an object whose attribute arrays or indices are
/// inconsistent; [`IoError::Gltf`] ([`GltfKind::AccessorOutOfRange`] or
/// [`GltfKind::Accessor`]) for a source accessor the pass-through cannot copy;
/// [`IoError::Io`] when writing fails.
pub fn save(asset: &Asset, path: &Path, options: &SaveOptions) -> Result<SaveReport, IoError> {
    if !options.overwrite_input
        && asset.source.as_deref().is_some_and(|source| same_file(source, path))
    {
        return Err(IoError::WouldOverwriteInput { path: path.to_path_buf() });
    }
    let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    let warnings = match extension.as_deref() {
        Some("gltf" | "glb" | "vrm") => gltf::save(asset, path, options)?,
        Some("obj") => obj::save(asset, path, options)?,
        Some("fbx") => return Err(IoError::FbxOutput { path: path.to_path_buf() }),
        #[cfg(feature = "usd")]
        Some("usda" | "usd" | "usdc" | "usdz") => usd::save(asset, path)?,
        _ => return Err(IoError::UnknownFormat { path: path.to_path_buf() }),
    };
    Ok(SaveReport { warnings })
}

/// Whether [`save`] to `path` with `options` streams its output from the model into the file
/// (glTF, GLB and VRM, their new data encoded a chunk at a time) rather than building it in
/// memory first (OBJ text, USD layers and packages, meshopt views re-encoded). A streaming
/// save holds little of its own, so other work on the model may run beside it
/// ([`job::Unmeasured::measure_with`]) without adding to the peak memory; beside one that
/// builds, the two memories add up (9 MiB more for the 1M teapot's `.usdc`).
#[must_use]
pub fn save_streams(path: &Path, options: &SaveOptions) -> bool {
    let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    matches!(extension.as_deref(), Some("gltf" | "glb" | "vrm")) && !options.keep_compression
}

/// What [`save`] reports besides the files it wrote.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct SaveReport {
    /// Problems that did not stop writing, one sentence each: a glTF mesh cloned because its
    /// instances got different normals, an image file that could not be copied beside the
    /// output, a glTF or OBJ source the model no longer matches, a material library or texture
    /// of an OBJ that is missing, tangents that an OBJ output cannot hold, buffer views (EXT_
    /// or KHR_meshopt_compression) and primitives (KHR_draco_mesh_compression) the input
    /// stored compressed that the output stores uncompressed; with
    /// [`SaveOptions::keep_compression`], which views were kept compressed and how many new
    /// ones were encoded, or that the input had no compression to keep.
    pub warnings: Vec<String>,
}
