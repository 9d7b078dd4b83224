//! The error type of this crate.

use std::path::PathBuf;

use thiserror::Error;

/// What can go wrong when a scene file is read or applied. Every variant names the file, and
/// where it can, the line and the key at fault.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{}: cannot read the scene file: {source}", path.display())]
    Read {
        /// The scene file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The TOML is malformed, has an unknown key or a value of the wrong type.
    #[error("{}: line {line}, column {column}: {}{}", path.display(), key_prefix(key.as_deref(), error.message()), error.message().trim())]
    Parse {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the offending key or value.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The key at fault, where it could be found.
        key: Option<String>,
        /// toml's error, whose message is this error's. It is not the `source`: toml's own
        /// text repeats the message under a snippet of the file, and the one-line message
        /// would say it twice. Boxed: it is larger than every other variant.
        error: Box<toml::de::Error>,
    },
    /// A value is well-formed but makes no sense (a zero field of view, an empty name, two
    /// cameras of the same name).
    #[error("{}: line {line}: {kind}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the table that holds the value.
        line: usize,
        /// What is wrong, with the table and the key.
        #[source]
        kind: Invalid,
    },
    /// A material override names a material the model does not have.
    #[error("{}: no material named {name:?} (the model has: {available})", model.display())]
    UnknownMaterial {
        /// The model file.
        model: PathBuf,
        /// The name the scene gave.
        name: String,
        /// The model's material names, comma separated.
        available: String,
    },
    /// A model file of the scene could not be read: the loader's error, which names the file
    /// and the place in it.
    #[error(transparent)]
    Model(#[from] seamlit_io::IoError),
    /// A texture named by the scene could not be read or decoded.
    #[error("{}: cannot load the texture: {source}", path.display())]
    Texture {
        /// The texture file.
        path: PathBuf,
        /// What the image crate said.
        source: image::ImageError,
    },
}

/// What is wrong with a well-formed value of a scene file (see [`SceneError::Invalid`]).
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum Invalid {
    /// The scene has no `[[model]]`.
    #[error("the scene has no [[model]]; it needs at least one")]
    NoModel,
    /// Two cameras of one name.
    #[error("a second camera named {name:?}")]
    DuplicateCamera {
        /// The name.
        name: String,
    },
    /// A `[render]` number outside what its key takes.
    #[error("[render] {key} = {value}: must be {expected}")]
    RenderValue {
        /// The key (`exposure`, `ambient`, ...).
        key: &'static str,
        /// The value written.
        value: f32,
        /// What it must be (`a number > 0`).
        expected: &'static str,
    },
    /// A model's `time` that is not seconds >= 0.
    #[error("model {model:?}: time = {value}: must be seconds >= 0")]
    ModelTime {
        /// The model's name.
        model: String,
        /// The value written.
        value: f32,
    },
    /// A `[render]` background outside 0..1.
    #[error("[render] background = {value:?}: each of r, g, b must be in 0..1")]
    Background {
        /// The colour written.
        value: [f32; 3],
    },
    /// A model whose `path` is empty.
    #[error("model: `path` is empty")]
    EmptyModelPath,
    /// A model whose translation, rotation or scale is not finite.
    #[error("model {model:?}: the transform is not finite")]
    TransformNotFinite {
        /// The model's name.
        model: String,
    },
    /// A model whose `scale` has a zero component.
    #[error("model {model:?}: `scale` has a zero component")]
    ZeroScale {
        /// The model's name.
        model: String,
    },
    /// A model whose fix angles are negative.
    #[error("model {model:?}: fix angles must be >= 0")]
    NegativeAngle {
        /// The model's name.
        model: String,
    },
    /// A material override whose `base_color` is not 3 or 4 numbers.
    #[error("model {model:?}, material: `base_color` needs 3 or 4 numbers, found {found}")]
    BaseColorLength {
        /// The model's name.
        model: String,
        /// How many numbers it has.
        found: usize,
    },
    /// A material override value outside what its key takes.
    #[error("model {model:?}, material: `{key}` {expected}")]
    MaterialValue {
        /// The model's name.
        model: String,
        /// The key (`base_color`, `specular`, `shininess`, `normal_scale`).
        key: &'static str,
        /// What it must be (`components must lie in 0..1`).
        expected: &'static str,
    },
    /// A camera whose `name` is empty.
    #[error("camera: `name` is empty")]
    EmptyCameraName,
    /// A camera whose position, target or up is not finite.
    #[error("camera {camera:?}: a vector is not finite")]
    CameraNotFinite {
        /// The camera's name.
        camera: String,
    },
    /// A camera whose `position` is its `target`.
    #[error("camera {camera:?}: `position` equals `target`")]
    PositionIsTarget {
        /// The camera's name.
        camera: String,
    },
    /// A camera whose field of view is outside (0, 180) degrees.
    #[error("camera {camera:?}: `fov_deg` must lie in (0, 180), found {fov_deg}")]
    FieldOfView {
        /// The camera's name.
        camera: String,
        /// The field of view written.
        fov_deg: f32,
    },
    /// A camera whose clip planes are not 0 < near < far.
    #[error("camera {camera:?}: need 0 < near < far")]
    NearFar {
        /// The camera's name.
        camera: String,
    },
    /// A light without a key its type needs.
    #[error("a {light} light needs `{key}`")]
    LightNeeds {
        /// The light's type (`directional`, `point`, `spot`).
        light: &'static str,
        /// The key.
        key: &'static str,
    },
    /// A light with a key its type does not have.
    #[error("a {light} light has no `{key}`")]
    LightHasNo {
        /// The light's type.
        light: &'static str,
        /// The key (`cone` for either cone angle).
        key: &'static str,
    },
    /// A light vector that is zero or not finite.
    #[error("{light} light: `{key}` must be a non-zero vector")]
    ZeroVector {
        /// The light's type.
        light: &'static str,
        /// The key.
        key: &'static str,
    },
    /// A light whose colour or intensity is negative or not finite.
    #[error("{light} light: `color` and `intensity` must be >= 0")]
    NegativeLight {
        /// The light's type.
        light: &'static str,
    },
    /// A light whose `range` is not above 0.
    #[error("{light} light: `range` must be > 0")]
    Range {
        /// The light's type.
        light: &'static str,
    },
    /// A point light whose `position` is not finite.
    #[error("point light: `position` must be finite")]
    PositionNotFinite,
    /// A spot light whose cones are not 0 <= inner <= outer < 90 degrees, or whose position
    /// is not finite.
    #[error("spot light: need 0 <= inner_cone_deg <= outer_cone_deg < 90")]
    Cones {
        /// The inner cone angle, in degrees.
        inner_cone_deg: f32,
        /// The outer cone angle, in degrees.
        outer_cone_deg: f32,
    },
}

/// `key `name`: ` unless the message already names the key.
fn key_prefix(key: Option<&str>, message: &str) -> String {
    match key {
        Some(k) if !message.contains(&format!("`{k}`")) => format!("key `{k}`: "),
        _ => String::new(),
    }
}
