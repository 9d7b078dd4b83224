//! Wavefront OBJ (+ MTL) in and out.
//!
//! Reading ([`load`], `read.rs`) parses the geometry with this crate's parallel parser
//! (`parse.rs`, faces of more than three corners triangulated by `polygon.rs`) and the
//! material libraries with tobj (`mtl.rs`). Writing an asset that came from OBJ is a
//! pass-through of its input text (`passthrough.rs`, `docs/obj-pass-through.md`), kept in
//! the asset as its source (`source.rs`); any other asset goes through the generic writer
//! (`write.rs`).

pub(crate) mod mtl;
pub(crate) mod parse;
pub(crate) mod passthrough;
pub(crate) mod polygon;
mod read;
pub(crate) mod source;
pub(crate) mod write;

pub use read::load;
