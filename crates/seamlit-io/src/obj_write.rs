//! OBJ out.
use std::path::Path;

use crate::{Asset, IoError};

pub(crate) fn save(_asset: &Asset, path: &Path) -> Result<(), IoError> {
    crate::atomic::write(path, b"")
}
