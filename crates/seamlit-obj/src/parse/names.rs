//! Names in a legacy 8-bit encoding: older exporters write `o`, `g`, `usemtl`, `mtllib`,
//! `newmtl` and texture file names in the system's code page rather than UTF-8. A name that
//! is not UTF-8 is decoded as Windows-1252 (a superset of Latin-1; `encoding_rs`) for display
//! and glTF output; the OBJ pass-through still copies its line's bytes as written. A file
//! named that way is looked for under the bytes it was written with as well (Unix).

use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// `bytes` as text: UTF-8 as it is, anything else decoded as Windows-1252; and whether it
/// was (every byte sequence decodes, none is lost).
pub(crate) fn decode(bytes: &[u8]) -> (Cow<'_, str>, bool) {
    match std::str::from_utf8(bytes) {
        Ok(text) => (Cow::Borrowed(text), false),
        Err(_) => {
            let (text, _) = encoding_rs::WINDOWS_1252.decode_without_bom_handling(bytes);
            (text, true)
        }
    }
}

/// A text file's bytes as text, line by line with [`decode`] (line ends kept); and the
/// first line (counted from 1) decoded as Windows-1252, if any.
pub(crate) fn decode_lines(bytes: &[u8]) -> (String, Option<usize>) {
    if let Ok(text) = std::str::from_utf8(bytes) {
        return (text.to_owned(), None);
    }
    let mut text = String::with_capacity(bytes.len() + bytes.len() / 8);
    let mut first = None;
    for (i, line) in bytes.split_inclusive(|&b| b == b'\n').enumerate() {
        let (line, legacy) = decode(line);
        if legacy && first.is_none() {
            first = Some(i + 1);
        }
        text.push_str(&line);
    }
    (text, first)
}

/// The one warning for a file (`path`) whose names are not all UTF-8; `line` is the first.
pub(crate) fn legacy_warning(path: &Path, line: usize) -> String {
    format!(
        "{}:{line}: text that is not UTF-8 (the first of it here), read as Windows-1252 \
         (Latin-1); an OBJ output keeps its bytes as written",
        path.display()
    )
}

/// The file at `parts` below `folder`: as written where it exists, else (on Unix) where a
/// file exists under the names' Windows-1252 bytes, which a name decoded by [`decode`] had;
/// else as written (for the caller to report missing).
pub(crate) fn on_disk(folder: &Path, parts: &[String]) -> PathBuf {
    let path = parts.iter().fold(folder.to_path_buf(), |p, s| p.join(s));
    if path.symlink_metadata().is_ok() || parts.iter().all(|p| p.is_ascii()) {
        return path;
    }
    match legacy(folder, parts) {
        Some(legacy) if legacy.symlink_metadata().is_ok() => legacy,
        _ => path,
    }
}

/// `parts` below `folder`, each encoded back to the Windows-1252 bytes it was decoded from.
#[cfg(unix)]
fn legacy(folder: &Path, parts: &[String]) -> Option<PathBuf> {
    use std::os::unix::ffi::OsStrExt as _;
    let mut path = folder.to_path_buf();
    for part in parts {
        let (bytes, _, unmappable) = encoding_rs::WINDOWS_1252.encode(part);
        if unmappable {
            return None;
        }
        path.push(std::ffi::OsStr::from_bytes(&bytes));
    }
    Some(path)
}

/// File names are Unicode on other systems: the decoded name is the name.
#[cfg(not(unix))]
fn legacy(_folder: &Path, _parts: &[String]) -> Option<PathBuf> {
    None
}

#[cfg(test)]
mod tests {
    use super::{decode, decode_lines};

    #[test]
    fn latin_1_names_decode_and_utf_8_stays() {
        assert_eq!(decode(b"R\xf8d_tr\xe6").0, "Rød_træ");
        assert!(decode(b"R\xf8d").1);
        assert_eq!(decode("Rød".as_bytes()), ("Rød".into(), false));
        // Windows-1252's own characters in 0x80..0xA0.
        assert_eq!(decode(b"\x80 \x93x\x94").0, "€ “x”");
        let (text, first) = decode_lines(b"newmtl a\nnewmtl \xe6\r\nKd 1 1 1\n");
        assert_eq!(text, "newmtl a\nnewmtl æ\r\nKd 1 1 1\n");
        assert_eq!(first, Some(2));
    }
}
