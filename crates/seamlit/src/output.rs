//! Where outputs go: one rule for every command that writes a file (`fix`, `render`,
//! `compare`, `view --screenshot`, `demo --out`, folder-mode `fix`): a missing output folder is
//! created, as `mkdir -p` would. It is created when the output is written, so that bad input
//! leaves nothing behind; `view` creates it before the window opens, so that a screenshot path
//! that cannot be written fails at once instead of after the frames are drawn.

use std::path::Path;

use crate::failure::Failure;

/// Creates the folder that will hold `file`, if it is missing.
///
/// # Errors
/// A processing failure (exit status 1) naming the folder when it cannot be created (a file of
/// that name, no permission).
pub(crate) fn prepare_folder_of(file: &Path) -> Result<(), Failure> {
    match file.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => prepare_folder(folder),
        _ => Ok(()),
    }
}

/// Creates `folder` (and its parents) if it is missing.
///
/// # Errors
/// As [`prepare_folder_of`].
pub(crate) fn prepare_folder(folder: &Path) -> Result<(), Failure> {
    if folder.is_dir() {
        return Ok(());
    }
    std::fs::create_dir_all(folder).map_err(|e| {
        let reason = if folder.exists() { "it is a file".to_owned() } else { e.to_string() };
        Failure::processing(format!(
            "{}: cannot create the output folder: {reason}",
            folder.display()
        ))
    })
}
