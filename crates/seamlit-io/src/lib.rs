//! seamlit-io: model files in and out (being written).
#![deny(missing_docs)]

mod asset;

pub use asset::{Asset, Material, Node, Texture, TextureRef, TextureSource, UvTransform};
