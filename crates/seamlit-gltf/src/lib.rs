//! # seamlit-gltf
//!
//! glTF 2.0, GLB and VRM in and out. `seamlit-io` reads and writes `.gltf`, `.glb` and `.vrm`
//! with it.
//!
//! Reading ([`load`], [`parse`]) goes through the gltf crate (`read/`), decoding quantised
//! and compressed geometry at load (`decode/`). Writing an asset that came from glTF is a
//! pass-through of its input document (`passthrough/`, `docs/gltf-pass-through.md`); any
//! other asset goes through the generic writer (`write.rs`). Below both: the JSON helpers
//! and the specification's numbers (`json.rs`), the kept source document (`source.rs`), the
//! GLB container (`glb.rs`), URI resolution (`uri.rs`), where a document names accessors and
//! buffer views (`references.rs`), and the glTF error kinds ([`seamlit_asset::GltfKind`]).
#![deny(missing_docs)]

mod chunks;
pub(crate) mod decode;
pub(crate) mod glb;
pub(crate) mod json;
mod loaded;
mod passthrough;
mod read;
pub(crate) mod references;
mod source;
pub(crate) mod uri;
mod write;

use std::path::Path;

use seamlit_asset::files::Destination;
use seamlit_asset::{Asset, IoError, SaveOptions};

pub use read::{load, parse};
pub use source::GltfSource;

/// Writes `asset` as `.gltf` (JSON, with a `.bin` buffer and the textures beside it), `.glb`
/// (one binary file, textures embedded) or `.vrm` (a VRM avatar loaded from a `.vrm`), by the
/// extension of `path`; returns the warnings.
///
/// An asset read from glTF ([`GltfSource`] in its document) whose model still matches it is
/// written through the pass-through: the input document with only NORMAL, TANGENT, the split
/// vertices and the indices changed (`docs/gltf-pass-through.md`), keeping meshopt compression
/// with [`SaveOptions::keep_compression`]. Any other asset goes through the generic writer (a
/// warning says so when a source no longer matches). A `.vrm` is written only through the
/// pass-through.
///
/// # Errors
///
/// [`IoError::VrmOutput`] for a `.vrm` path when the asset is not a VRM avatar the
/// pass-through can write back; [`IoError::CannotKeepCompression`] for a Draco-compressed
/// source kept compressed; [`IoError::InvalidAsset`] for an object whose attribute arrays or
/// indices are inconsistent; [`IoError::Gltf`] for a source accessor the pass-through cannot
/// copy; [`IoError::Io`] when writing fails.
pub fn save(asset: &Asset, path: &Path, options: &SaveOptions) -> Result<Vec<String>, IoError> {
    save_to(asset, path, options, &mut Destination::files())
}

/// [`save`] to `to`: files, or memory (the web page writes its download there). The files a
/// `.gltf` names beside it come along; those the input named by file are read from it.
///
/// # Errors
///
/// As [`save`].
pub fn save_to(
    asset: &Asset,
    path: &Path,
    options: &SaveOptions,
    to: &mut Destination,
) -> Result<Vec<String>, IoError> {
    let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    let keep = options.keep_compression;
    let source = asset.document::<GltfSource>();
    if extension.as_deref() == Some("vrm") {
        let source = source.filter(|s| s.is_vrm()).ok_or_else(|| IoError::VrmOutput {
            path: path.to_path_buf(),
            reason: "the model is not a VRM avatar".into(),
        })?;
        source
            .check_model(&asset.model)
            .map_err(|reason| IoError::VrmOutput { path: path.to_path_buf(), reason })?;
        return passthrough::save(asset, source, path, true, keep, to);
    }
    let binary = extension.as_deref() == Some("glb");
    let mut warnings = Vec::new();
    if let Some(source) = source {
        match source.check_model(&asset.model) {
            Ok(()) => return passthrough::save(asset, source, path, binary, keep, to),
            Err(reason) => warnings.push(format!(
                "{}: written by the generic glTF writer (materials, skins, animations{} and extensions of the source are not kept): {reason}",
                path.display(),
                if keep { ", compression" } else { "" }
            )),
        }
    }
    write::save(asset, path, binary, to)?;
    Ok(warnings)
}
