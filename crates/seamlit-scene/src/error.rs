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
    #[error("{}: line {line}, column {column}: {}{message}", path.display(), key_prefix(key.as_deref(), message))]
    Parse {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the offending key or value.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The key at fault, where it could be found.
        key: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// A value is well-formed but makes no sense (a zero field of view, an empty name, two
    /// cameras of the same name).
    #[error("{}: line {line}: {message}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// 1-based line of the table that holds the value.
        line: usize,
        /// What is wrong.
        message: String,
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
    #[error("{}: cannot load the texture: {message}", path.display())]
    Texture {
        /// The texture file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// `key `name`: ` unless the message already names the key.
fn key_prefix(key: Option<&str>, message: &str) -> String {
    match key {
        Some(k) if !message.contains(&format!("`{k}`")) => format!("key `{k}`: "),
        _ => String::new(),
    }
}
