//! glTF 2.0 and GLB in.
use std::path::Path;

use crate::{Asset, IoError, LoadOptions};

/// Reads a glTF or GLB file.
///
/// # Errors
///
/// Not yet.
pub fn load(path: &Path, _options: &LoadOptions) -> Result<Asset, IoError> {
    Err(IoError::UnknownFormat { path: path.to_path_buf() })
}
