//! Files in and out, for every format: whole files read under the size limit
//! ([`read_bytes`], [`read_text`]), and atomic output ([`write`], [`write_with`]): a
//! temporary file in the destination folder, renamed over the destination once complete,
//! so a failed write never leaves a half-written file. Also the names the writers give the
//! files they write beside their output ([`safe_name`]), and whether two paths are one
//! file ([`same_file`]). A writer that can write into memory takes a [`Destination`]: the
//! files (atomically, as above) or a list of named byte buffers (the web page's download).
//! Files are read from [`Files`]: the file system, or a set of files in memory (the web
//! page's dropped files), named in [`LoadOptions::files`] and kept by the readers' sources
//! for their writers.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

pub use crate::origin::{Files, MemoryFiles, normalize, same_file};

use crate::error::IoError;
use crate::options::LoadOptions;

/// Writes `bytes` to `path` atomically.
///
/// # Errors
///
/// [`IoError::Io`] naming `path` when the temporary file cannot be created, written or
/// renamed.
pub fn write(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_with(path, |out| out.write_all(bytes))
}

/// Writes to `path` atomically what `contents` writes into a buffered writer: large outputs
/// are streamed to the temporary file instead of being assembled in memory first.
///
/// # Errors
///
/// [`IoError::Io`] naming `path` when the temporary file cannot be created, written (by
/// `contents` or when flushing) or renamed.
pub fn write_with(
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

/// Where a writer's files go: to the file system, each written atomically ([`write_with`]),
/// or into memory, each as a path and its bytes, in the order written (a page that offers
/// the output as a download, where there is no file system).
#[derive(Debug, Default)]
pub struct Destination {
    memory: Option<Vec<(PathBuf, Vec<u8>)>>,
}

impl Destination {
    /// The file system.
    #[must_use]
    pub fn files() -> Self {
        Self { memory: None }
    }

    /// Memory: [`Destination::into_memory`] gives the files written.
    #[must_use]
    pub fn memory() -> Self {
        Self { memory: Some(Vec::new()) }
    }

    /// Writes to `path` what `contents` writes (atomically to a file, or into memory).
    ///
    /// # Errors
    ///
    /// As [`write_with`]; into memory, what `contents` returns.
    pub fn write_with(
        &mut self,
        path: &Path,
        contents: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
    ) -> Result<(), IoError> {
        let Some(memory) = &mut self.memory else {
            return write_with(path, contents);
        };
        let mut bytes = Vec::new();
        contents(&mut bytes).map_err(|e| IoError::io(path, e))?;
        memory.push((path.to_path_buf(), bytes));
        Ok(())
    }

    /// Writes `bytes` to `path`.
    ///
    /// # Errors
    ///
    /// As [`Destination::write_with`].
    pub fn write(&mut self, path: &Path, bytes: &[u8]) -> Result<(), IoError> {
        self.write_with(path, |out| out.write_all(bytes))
    }

    /// Makes the folder `path` and its parents (nothing in memory).
    ///
    /// # Errors
    ///
    /// [`IoError::Io`] naming `path` when a folder cannot be made.
    pub fn create_folder(&mut self, path: &Path) -> Result<(), IoError> {
        match self.memory {
            Some(_) => Ok(()),
            None => std::fs::create_dir_all(path).map_err(|e| IoError::io(path, e)),
        }
    }

    /// The files written into memory, in order (none for the file system).
    #[must_use]
    pub fn into_memory(self) -> Vec<(PathBuf, Vec<u8>)> {
        self.memory.unwrap_or_default()
    }
}

/// A file name of ASCII letters, digits, `_`, `-` and `.` only (a URI without escapes).
pub fn safe_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(
            |c| if c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.' { c } else { '_' },
        )
        .collect();
    if s.is_empty() || s.starts_with('.') { format!("model{s}") } else { s }
}

/// Refuses a file over `options.max_file_bytes` (and one that cannot be looked at), read
/// from [`LoadOptions::files`].
pub fn check_size(path: &Path, options: &LoadOptions) -> Result<(), IoError> {
    let size = options.files.size(path).map_err(|e| IoError::io(path, e))?;
    if size > options.max_file_bytes {
        return Err(IoError::TooLarge {
            path: path.to_path_buf(),
            limit: options.max_file_bytes,
            actual: size,
        });
    }
    Ok(())
}

/// Reads a file whole from [`LoadOptions::files`], refusing files over
/// `options.max_file_bytes`.
pub fn read_bytes(path: &Path, options: &LoadOptions) -> Result<Vec<u8>, IoError> {
    check_size(path, options)?;
    options.files.read(path).map_err(|e| IoError::io(path, e))
}

/// Reads a text file whole (invalid UTF-8 replaced), refusing files over the size limit.
pub fn read_text(path: &Path, options: &LoadOptions) -> Result<String, IoError> {
    let bytes = read_bytes(path, options)?;
    Ok(match String::from_utf8(bytes) {
        Ok(text) => text,
        Err(err) => String::from_utf8_lossy(err.as_bytes()).into_owned(),
    })
}
