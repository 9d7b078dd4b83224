//! # seamlit-fbx
//!
//! Autodesk FBX in (binary and ASCII, FBX 6.1 to 7.7), through the ufbx crate: bindings to
//! the ufbx C library, the reader Godot's FBX importer uses. `seamlit-io` reads `.fbx` with
//! it when its `fbx` feature is on (the default).
//!
//! ufbx converts the file to glTF's conventions at load (+Y up, metres, right-handed),
//! resolves pivots and geometry transforms, and triangulates; `read/` turns its scene into an
//! [`seamlit_asset::Asset`]: the node tree (`nodes.rs`), one object per mesh part per material
//! (`mesh.rs`), materials as glTF metallic-roughness with their textures (`material.rs`),
//! skins (`skin.rs`) and animation stacks baked by ufbx (`animation.rs`). There is no FBX
//! writer: a fixed FBX is written as glTF or GLB. The errors are [`seamlit_asset::IoError`]'s,
//! their FBX kinds [`seamlit_asset::FbxKind`].
#![deny(missing_docs)]

mod read;

pub use read::{load, parse};
