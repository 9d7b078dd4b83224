//! # seamlit-asset
//!
//! What a model file becomes in seamlit, whatever its format: an [`Asset`], a
//! [`seamlit_mesh::Model`] of named objects plus the materials, textures, nodes, lights,
//! skins and animations that drawing and writing need; the asset posed at a time of an
//! animation ([`pose`]), its skin seams matched ([`match_skin_seams`]) and its seams measured
//! in motion ([`motion`]); texture decoding (PNG, JPEG, KTX2).
//!
//! It is also what every format crate (seamlit-gltf, seamlit-obj, seamlit-fbx, seamlit-usd)
//! shares and the only seamlit crate they depend on besides seamlit-mesh: the one error type
//! [`IoError`] with each format's kinds, [`LoadOptions`] and [`SaveOptions`], whole files read
//! under the size limit and atomic output ([`files`]), paths that must stay inside a model's
//! folder ([`paths`]), what every writer checks of an object ([`check`]), polygon
//! triangulation ([`polygon`]), and the slot in which a reader keeps its input document for
//! its own writer ([`SourceDocument`]). It knows no file format: `seamlit-io` picks the
//! reader and the writer.
//!
//! ```
//! use seamlit_asset::{Asset, Material, shininess_to_roughness};
//!
//! let mut asset = Asset::default();
//! asset.materials.push(Material { name: "clay".into(), ..Material::default() });
//! assert_eq!(asset.materials[0].name, "clay");
//! assert!(asset.document.is_none());
//! assert!(shininess_to_roughness(0.0) > shininess_to_roughness(1000.0));
//! ```
#![deny(missing_docs)]

mod animation;
mod asset;
pub mod check;
mod document;
pub mod error;
pub mod files;
pub mod motion;
mod options;
mod origin;
pub mod paths;
pub mod polygon;
pub mod pose;
mod skins;
pub mod texture;

pub use animation::{
    Animation, Channel, Interpolation, Property, Sampler, Skin, SkinsChanged, Trs,
};
pub use asset::{
    AlphaMode, Anisotropy, Asset, Clearcoat, Iridescence, Material, Node, PbrExtensions,
    PunctualKind, PunctualLight, Sheen, Specular, Texture, TextureFilter, TextureRef,
    TextureSampling, TextureSource, Transmission, TriangleMaterials, UnknownVariant, UvTransform,
    VariantObject, Variants, Volume, Wrap, roughness_to_shininess, shininess_to_roughness,
};
pub use document::SourceDocument;
pub use error::fbx::FbxKind;
pub use error::gltf::{BadAccessor, BadUri, Draco, Glb, GltfKind, Meshopt};
pub use error::usd::{UsdKind, UsdOutput};
pub use error::{InvalidAsset, IoError, KeepCompression, NotText, Syntax};
pub use options::{LoadOptions, SaveOptions};
pub use skins::match_skin_seams;
