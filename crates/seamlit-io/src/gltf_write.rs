//! glTF 2.0 and GLB out.
use std::path::Path;

use crate::{Asset, IoError};

pub(crate) fn save(_asset: &Asset, path: &Path, _binary: bool) -> Result<(), IoError> {
    Err(IoError::UnknownFormat { path: path.to_path_buf() })
}
