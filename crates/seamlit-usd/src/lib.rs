//! # seamlit-usd
//!
//! OpenUSD in (`.usda`, `.usdc`, `.usdz`) and out (a `.usda` or `.usdc` layer of the fixed
//! normals, or a `.usdz` package of that layer and the input), through the openusd crate (pure
//! Rust; 0.6.0 with the fixes of `vendor/openusd/PATCHES.md`). `seamlit-io` reads and writes
//! these extensions with it when its `usd` feature is on (the default).
//!
//! `read/` opens the file as a composed stage (sublayers, references, payloads, the selected
//! variants, inherits; `stage.rs`), walks its meshes, instance proxies included, and turns each
//! `Mesh` prim into one object in world space (`xform.rs`: the xformOps and
//! `!resetXformStack!`; `upAxis` Z turned to +Y up), its polygons triangulated and its
//! primvars expanded by their interpolation (`mesh.rs`); UsdSkel skin bindings (`skel.rs`);
//! UsdPreviewSurface materials bound by `material:binding` (`material.rs`). The reader keeps
//! how it read the stage in the asset ([`UsdSource`]). `write.rs` writes a layer that
//! sublayers the input and overrides only the normals (and matched skin influences) seamlit
//! changed; `package.rs` puts that layer, the input's layers and its textures in one `.usdz`
//! package. The design, and what is not read or written yet: docs/usd.md.
#![deny(missing_docs)]

mod package;
mod read;
mod source;
mod write;

use std::path::Path;

use seamlit_asset::files::Destination;
use seamlit_asset::{Asset, IoError};

pub use read::load;
pub use source::UsdSource;

/// Writes `asset`, loaded from a USD stage, by the extension of `path`: a `.usda` (or `.usd`)
/// text layer over the input stage, a `.usdc` binary layer, or a `.usdz` package of that
/// layer and the input's files; returns the warnings (meshes whose normals are not written,
/// and why).
///
/// # Errors
///
/// [`IoError::UsdOutput`] when the asset did not come from USD or no longer matches its
/// stage, holds a normal that is not finite, a package's input file cannot be read, or
/// openusd cannot write a binary layer; [`IoError::UnknownFormat`] for another extension; the
/// errors of reading the stage again; [`IoError::Io`] when writing fails.
pub fn save(asset: &Asset, path: &Path) -> Result<Vec<String>, IoError> {
    let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("usda" | "usd") => write::save(asset, path),
        Some("usdc") => write::save_usdc(asset, path),
        Some("usdz") => package::save(asset, path, &mut Destination::files()),
        _ => Err(IoError::UnknownFormat { path: path.to_path_buf() }),
    }
}

/// Writes `asset` as a `.usdz` package at `path` into `to` (files, or memory: the web page's
/// download), as [`save`] does for a `.usdz` path. The input's files are read from where the
/// stage was read ([`seamlit_asset::LoadOptions::files`]); a stage read from memory is
/// packed only from a `.usdz` input.
///
/// # Errors
///
/// As [`save`]; [`IoError::UnknownFormat`] for a path that is not a `.usdz`.
pub fn save_package_to(
    asset: &Asset,
    path: &Path,
    to: &mut Destination,
) -> Result<Vec<String>, IoError> {
    let usdz = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("usdz"));
    if !usdz {
        return Err(IoError::UnknownFormat { path: path.to_path_buf() });
    }
    package::save(asset, path, to)
}
