//! glTF 2.0 and GLB in and out.
//!
//! Reading ([`load`], [`parse`]) goes through the gltf crate (`read/`), decoding quantised
//! and compressed geometry at load (`decode/`). Writing an asset that came from glTF is a
//! pass-through of its input document (`passthrough/`, `docs/gltf-pass-through.md`); any
//! other asset goes through the generic writer (`write.rs`). Below both: the JSON helpers
//! and the specification's numbers (`json.rs`), the kept source document (`source.rs`), the
//! GLB container (`glb.rs`), URI resolution (`uri.rs`), where a document names accessors and
//! buffer views (`references.rs`), and the glTF error kinds (`error.rs`).

pub(crate) mod decode;
pub(crate) mod error;
pub(crate) mod glb;
pub(crate) mod json;
pub(crate) mod passthrough;
mod read;
pub(crate) mod references;
pub(crate) mod source;
pub(crate) mod uri;
pub(crate) mod write;

pub use read::{load, parse};
