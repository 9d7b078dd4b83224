//! OpenUSD in (`.usda`, `.usdc`, `.usdz`) and out (`.usda`), through the openusd crate (pure
//! Rust; 0.6.0, pinned: later versions need a newer Rust). Behind the `usd` cargo feature (on
//! by default); without it those extensions are unknown formats.
//!
//! `read/` opens the file as a composed stage (sublayers, references, payloads, the selected
//! variants, inherits; `stage.rs`), walks its meshes, instance proxies included, and turns each
//! `Mesh` prim into one object in world space (`xform.rs`: the xformOps and
//! `!resetXformStack!`; `upAxis` Z turned to +Y up), its polygons triangulated and its
//! primvars expanded by their interpolation (`mesh.rs`); UsdSkel skin bindings (`skel.rs`);
//! UsdPreviewSurface materials bound by `material:binding` (`material.rs`). `write.rs` writes
//! a `.usda` layer that sublayers the input and overrides only the normals (and matched skin
//! influences) seamlit changed; `package.rs` puts that layer, the
//! input's layers and its textures in one `.usdz` package. The design, and what is not read or
//! written yet: docs/usd.md.

pub(crate) mod error;
#[cfg(feature = "usd")]
pub(crate) mod package;
#[cfg(feature = "usd")]
mod read;
#[cfg(feature = "usd")]
pub(crate) mod source;
#[cfg(feature = "usd")]
pub(crate) mod write;

#[cfg(feature = "usd")]
pub use read::load;
