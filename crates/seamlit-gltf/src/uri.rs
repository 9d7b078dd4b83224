//! What a URI of a glTF file may name: `data:` bytes (base64 or percent-encoded), or a file
//! inside the model's folder (percent-decoded, `.` and `..` resolved by name, symbolic links
//! followed and checked to stay inside). Anything else is refused: another scheme, an
//! absolute path, a path that leaves the folder. The reader resolves buffers and images with
//! it, the pass-through writer the files it copies beside its output.

use std::path::{Path, PathBuf};

use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::BadUri;
use seamlit_asset::files::Files;

/// For the pass-through writer: the file that a URI of the model at `path` names, checked
/// as the loader checks it (inside the model's folder, links included): the file as named
/// and its real path when it exists. `None` for a `data:` URI.
///
/// # Errors
///
/// [`IoError::BadUri`] or [`IoError::LinkEscapes`], as when loading.
pub(crate) fn resolve_file(
    path: &Path,
    uri: &str,
    what: &str,
    files: &Files,
) -> Result<Option<(PathBuf, Option<PathBuf>)>, IoError> {
    if uri.starts_with("data:") {
        return Ok(None);
    }
    match resolve(path, uri, what, files)? {
        Resolved::File { file, real } => Ok(Some((file, real))),
        Resolved::Data(..) => Ok(None),
    }
}

/// What a URI resolved to.
pub(crate) enum Resolved {
    /// Decoded `data:` bytes, with the MIME type the URI declared.
    Data(Vec<u8>, String),
    /// A file inside the model's folder: its path as named, and its real path (links
    /// followed, checked to stay inside) when it exists.
    File {
        /// The model's folder joined with the URI's parts.
        file: PathBuf,
        /// The canonical path to read; `None` when it could not be resolved (missing).
        real: Option<PathBuf>,
    },
}

/// The error for a refused URI.
fn bad_uri(path: &Path, what: &str, uri: &str, kind: BadUri) -> IoError {
    IoError::BadUri { path: path.to_path_buf(), what: what.to_owned(), uri: uri.to_owned(), kind }
}

/// Resolves a URI of the model at `path`: `data:` URIs are decoded (base64 or
/// percent-encoded), relative paths are percent-decoded and joined to the model's folder;
/// anything that would leave the folder is refused. Files are looked for in `files`.
///
/// # Errors
///
/// [`IoError::BadUri`] for a URI refused by its form, [`IoError::LinkEscapes`] for a file
/// whose symbolic links lead out of the folder.
pub(crate) fn resolve(
    path: &Path,
    uri: &str,
    what: &str,
    files: &Files,
) -> Result<Resolved, IoError> {
    let folder = path.parent().unwrap_or(Path::new(""));
    if let Some(data) = uri.strip_prefix("data:") {
        let Some((header, payload)) = data.split_once(',') else {
            return Err(bad_uri(path, what, uri, BadUri::DataWithoutComma));
        };
        // RFC 2397: base64, or the bytes themselves, percent-encoded where needed.
        let (mime, bytes) = match header.strip_suffix(";base64") {
            Some(mime) => (
                mime,
                base64::decode(payload)
                    .map_err(|_| bad_uri(path, what, uri, BadUri::MalformedBase64))?,
            ),
            None => (header, percent_encoding::percent_decode_str(payload).collect()),
        };
        return Ok(Resolved::Data(bytes, mime.to_owned()));
    }
    if uri.contains("://") || uri.split_once(':').is_some_and(|(s, _)| s.len() > 1) {
        return Err(bad_uri(path, what, uri, BadUri::NotRelative));
    }
    let decoded = percent_encoding::percent_decode_str(uri).decode_utf8_lossy();
    if decoded.starts_with('/') || decoded.starts_with('\\') || decoded.contains(':') {
        return Err(bad_uri(path, what, uri, BadUri::Absolute));
    }
    let mut parts: Vec<&str> = Vec::new();
    for part in decoded.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => {
                if parts.pop().is_none() {
                    return Err(bad_uri(path, what, uri, BadUri::LeavesFolder));
                }
            }
            part => parts.push(part),
        }
    }
    if parts.is_empty() {
        return Err(bad_uri(path, what, uri, BadUri::NoFile));
    }
    let file = parts.iter().fold(folder.to_path_buf(), |p, part| p.join(part));
    // Inside by name; a symbolic link on the way must not lead out either.
    let real = match files.real_inside(folder, &file) {
        Ok(real) => Some(real),
        // Missing or unreadable: the read names the problem.
        Err(seamlit_asset::paths::NotInside::Io(_)) => None,
        Err(seamlit_asset::paths::NotInside::Outside(target)) => {
            return Err(IoError::LinkEscapes {
                path: path.to_path_buf(),
                what: what.to_owned(),
                reference: uri.to_owned(),
                target,
            });
        }
    };
    Ok(Resolved::File { file, real })
}
