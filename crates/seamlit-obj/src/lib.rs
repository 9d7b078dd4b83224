//! # seamlit-obj
//!
//! Wavefront OBJ (+ MTL) in and out. `seamlit-io` reads and writes `.obj` with it.
//!
//! Reading ([`load`], `read.rs`) parses the geometry with this crate's parallel parser
//! (`parse.rs`, faces of more than three corners triangulated by
//! [`seamlit_asset::polygon`]) and the material libraries with tobj (`mtl.rs`). Writing an
//! asset that came from OBJ is a pass-through of its input text (`passthrough.rs`,
//! `docs/obj-pass-through.md`), kept in the asset as its document ([`ObjSource`]); any other
//! asset goes through the generic writer (`write.rs`).
#![deny(missing_docs)]

mod mtl;
mod parse;
mod passthrough;
mod read;
mod source;
mod write;

use std::path::Path;

use seamlit_asset::files::Destination;
use seamlit_asset::{Asset, IoError, KeepCompression, SaveOptions};

pub use read::{load, parse};
pub use source::ObjSource;

/// Writes `asset` as an `.obj` at `path`, with a `.mtl` and the textures beside it; returns
/// the warnings.
///
/// An asset read from OBJ ([`ObjSource`] in its document) whose model still matches it is
/// written through the pass-through: the input file with only the `vn` lines and the faces'
/// normal references changed, its material libraries and textures copied as written
/// (`docs/obj-pass-through.md`). Any other asset goes through the generic writer (a warning
/// says so when a source no longer matches). OBJ holds no tangents: a model with tangents gets
/// a warning.
///
/// # Errors
///
/// [`IoError::CannotKeepCompression`] with [`SaveOptions::keep_compression`] (OBJ has no
/// compression); [`IoError::InvalidAsset`] for an object whose arrays or indices are
/// inconsistent; [`IoError::LinkEscapes`] for a material library or texture reached through a
/// link that leaves the model's folder; [`IoError::Io`] when writing fails.
pub fn save(asset: &Asset, path: &Path, options: &SaveOptions) -> Result<Vec<String>, IoError> {
    save_to(asset, path, options, &mut Destination::files())
}

/// [`save`] to `to`: files, or memory (the web page offers the OBJ, its material libraries
/// and textures as one download). The side files the input named are read from where it was
/// read ([`seamlit_asset::LoadOptions::files`]).
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
    if options.keep_compression {
        return Err(IoError::CannotKeepCompression {
            path: path.to_path_buf(),
            kind: KeepCompression::ObjOutput,
        });
    }
    let mut warnings: Vec<String> =
        passthrough::tangents_not_written(&asset.model, path).into_iter().collect();
    if let Some(source) = asset.document::<ObjSource>() {
        match source.check_model(&asset.model) {
            Ok(()) => {
                warnings.extend(passthrough::save(asset, source, path, to)?);
                return Ok(warnings);
            }
            Err(reason) => warnings.push(format!(
                "{}: written by the generic OBJ writer (the material library is regenerated from seamlit's materials; comments, groups and statements seamlit does not use are not kept): {reason}",
                path.display()
            )),
        }
    }
    write::save(asset, path, to)?;
    Ok(warnings)
}
