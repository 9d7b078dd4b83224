//! Atomic file output: a temporary file in the destination folder, renamed over the
//! destination once complete, so a failed write never leaves a half-written file.

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::IoError;

/// Writes `bytes` to `path` atomically.
///
/// # Errors
///
/// [`IoError::Io`] naming `path` when the temporary file cannot be created, written or
/// renamed.
pub(crate) fn write(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_with(path, |out| out.write_all(bytes))
}

/// Writes to `path` atomically what `contents` writes into a buffered writer: large outputs
/// are streamed to the temporary file instead of being assembled in memory first.
///
/// # Errors
///
/// [`IoError::Io`] naming `path` when the temporary file cannot be created, written (by
/// `contents` or when flushing) or renamed.
pub(crate) fn write_with(
    path: &Path,
    contents: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), IoError> {
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
    let mut out = BufWriter::with_capacity(1 << 16, file.as_file_mut());
    contents(&mut out).map_err(io)?;
    out.flush().map_err(io)?;
    drop(out);
    file.as_file().sync_all().map_err(io)?;
    file.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}
