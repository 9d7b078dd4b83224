//! Atomic file output: a temporary file in the destination folder, renamed over the
//! destination once complete, so a failed write never leaves a half-written file.

use std::io::Write;
use std::path::Path;

use crate::IoError;

/// Writes `bytes` to `path` atomically.
///
/// # Errors
///
/// [`IoError::Io`] naming `path` when the temporary file cannot be created, written or
/// renamed.
pub(crate) fn write(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let io = |e| IoError::io(path, e);
    let mut builder = tempfile::Builder::new();
    // A finished output is an ordinary file (tempfile would leave it readable by its owner
    // only).
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
    let mut file = builder.prefix(".seamlit-").suffix(".tmp").tempfile_in(folder).map_err(io)?;
    file.write_all(bytes).map_err(io)?;
    file.as_file().sync_all().map_err(io)?;
    file.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}
