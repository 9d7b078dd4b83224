//! Autodesk FBX in (binary and ASCII, FBX 6.1 to 7.7), through the ufbx crate: bindings to
//! the ufbx C library, the reader Godot's FBX importer uses. Behind the `fbx` cargo feature
//! (on by default); without it `.fbx` is an unknown format.
//!
//! ufbx converts the file to glTF's conventions at load (+Y up, metres, right-handed),
//! resolves pivots and geometry transforms, and triangulates; `read/` turns its scene into an
//! [`crate::Asset`]: the node tree (`nodes.rs`), one object per mesh part per material
//! (`mesh.rs`), materials as glTF metallic-roughness with their textures (`material.rs`).
//! There is no FBX writer: a fixed FBX is written as glTF or GLB.

pub(crate) mod error;
#[cfg(feature = "fbx")]
mod read;

#[cfg(feature = "fbx")]
pub use read::{load, parse};
