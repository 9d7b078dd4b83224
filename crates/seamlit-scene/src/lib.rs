//! # seamlit-scene
//!
//! What seamlit renders, apart from the geometry: TOML scene files (models with transforms,
//! processing options and material overrides, lights, named cameras), perspective cameras
//! with an FPS and an orbit controller written as pure maths, the default three-light rig
//! and camera a bare model gets, and the embedded demo scene (the Newell teapot with a brick
//! normal map made in code). docs/design.md section 7; the file format is in docs/scene.md.
//!
//! A scene's models come together in two calls around the fix:
//! [`SceneModel::load_asset`] loads a model with its material overrides applied, and
//! [`Scene::assemble`] places the fixed assets by their transforms and merges them into one.
//!
//! ```
//! use std::path::Path;
//! use seamlit_scene::{Invalid, Scene, SceneError};
//!
//! let text = r#"
//! [[model]]
//! path = "teapot.obj"
//! rotate = [-90, 0, 0]
//!
//! [[camera]]
//! name = "front"
//! position = [0, 2, 8]
//! target = [0, 1, 0]
//! "#;
//! let scene = Scene::parse(text, Path::new("scenes"), Path::new("scenes/tea.toml"))?;
//! assert_eq!(scene.models[0].path, Path::new("scenes/teapot.obj"));
//! assert_eq!(scene.lights_or_default().len(), 3); // no [[light]]: the default rig
//!
//! // An unknown key is an error naming the file, the line and the key.
//! let bad = Scene::parse("[[model]]\npath = \"a.obj\"\nsclae = 2\n", Path::new(""), Path::new("s.toml"));
//! let error = bad.unwrap_err();
//! assert!(matches!(&error, SceneError::Parse { line: 3, key: Some(key), .. } if key == "sclae"));
//! assert_eq!(
//!     error.to_string().split(", expected").next().unwrap(),
//!     "s.toml: line 3, column 1: unknown field `sclae`"
//! );
//! // A value that makes no sense is a typed kind, with the line of its table.
//! let bad = Scene::parse("[[model]]\npath = \"a.obj\"\nscale = [1, 0, 1]\n", Path::new(""), Path::new("s.toml"));
//! assert!(matches!(
//!     bad.unwrap_err(),
//!     SceneError::Invalid { line: 1, kind: Invalid::ZeroScale { .. }, .. }
//! ));
//! # Ok::<(), seamlit_scene::SceneError>(())
//! ```
#![deny(missing_docs)]

mod assemble;
mod bricks;
pub mod camera;
pub mod controller;
pub mod demo;
mod error;
pub mod lights;
mod scene;
mod schema;

pub use camera::{Bounds, Camera, Facing};
pub use controller::{FpsController, FpsInput, OrbitController};
pub use error::{Invalid, SceneError};
pub use scene::{
    AnimationChoice, EnvironmentChoice, MaterialOverride, NormalTexture, RenderOptions, Scene,
    SceneModel, is_scene_path,
};
