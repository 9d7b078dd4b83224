//! Where the pass-through's output bytes go: buffer 0 (the GLB `BIN` chunk, or `NAME.bin`
//! beside a `.gltf`) holds the input's kept bytes and the appended ones; the other buffers
//! and the images named by file are copied beside a `.gltf` and embedded in a GLB.

use std::io::Write;
use std::path::Path;

use serde_json::{Value, json};

use super::OutputDocument;
use super::encode::Layout;
use super::piece::Piece;
use crate::json::usize_member;
use crate::loaded::zeros;
use seamlit_asset::error::{InvalidAsset, IoError};
use seamlit_asset::files::{Destination, Files};

impl OutputDocument<'_> {
    /// Buffer 0 holds the input's bytes and the appended ones: the GLB `BIN` chunk, or a new
    /// `NAME.bin` beside a `.gltf`. Other buffers and images named by file are copied beside
    /// a `.gltf`; in a GLB, images named by file are embedded.
    pub(super) fn embed_or_copy_files(&mut self) -> Result<(), IoError> {
        let buffer_count = self.json["buffers"].as_array().map_or(0, Vec::len);
        for b in 1..buffer_count {
            let uri = self.json["buffers"][b]["uri"].as_str().map(str::to_owned);
            if let Some(uri) = uri {
                self.copy(&uri, &format!("buffer {b}"))?;
            }
        }
        let image_count = self.json["images"].as_array().map_or(0, Vec::len);
        for i in 0..image_count {
            let Some(uri) = self.json["images"][i]["uri"].as_str().map(str::to_owned) else {
                continue;
            };
            let what = format!("image {i}");
            if self.binary && self.embed(i, &uri, &what)? {
                continue;
            }
            self.copy(&uri, &what)?;
        }
        if self.host_without_data() {
            return self.keep_host_without_data();
        }
        if buffer_count == 0 {
            if self.appended == 0 {
                return Ok(());
            }
            self.array("buffers").push(json!({ "byteLength": 0 }));
        }
        let length = if self.appended > 0 {
            self.base + self.appended
        } else {
            usize_member(&self.json["buffers"][0], "byteLength").unwrap_or(0)
        };
        let host_uri = (!self.binary).then(|| self.host_name());
        if let Some(buffer) = self.json["buffers"][0].as_object_mut() {
            buffer.insert("byteLength".to_owned(), json!(length));
            match host_uri {
                Some(uri) => buffer.insert("uri".to_owned(), json!(uri)),
                None => buffer.remove("uri"),
            };
        }
        Ok(())
    }

    /// A file name for buffer 0 beside a `.gltf` output: `STEM.bin`, or `STEM_N.bin` where a
    /// copied file has that name.
    fn host_name(&self) -> String {
        let stem = self.path.file_stem().map_or_else(
            || "model".to_owned(),
            |s| seamlit_asset::files::safe_name(&s.to_string_lossy()),
        );
        let folder = self.path.parent().unwrap_or(Path::new(""));
        let taken = |name: &str| self.copies.iter().any(|(_, to)| to == &folder.join(name));
        let mut name = format!("{stem}.bin");
        let mut n = 1;
        while taken(&name) {
            name = format!("{stem}_{n}.bin");
            n += 1;
        }
        name
    }

    /// Plans the copy of the file `uri` names to the same place beside the output. A
    /// missing file is a warning.
    fn copy(&mut self, uri: &str, what: &str) -> Result<(), IoError> {
        let Some((file, real)) =
            crate::uri::resolve_file(&self.source.path, uri, what, &self.source.files)?
        else {
            return Ok(());
        };
        let Some(real) = real else {
            self.warnings.push(format!(
                "{}: {what} {} is missing; the output names it still",
                self.source.path.display(),
                file.display()
            ));
            return Ok(());
        };
        let folder = self.source.path.parent().unwrap_or(Path::new(""));
        let relative = file.strip_prefix(folder).unwrap_or(&file);
        let destination = self.path.parent().unwrap_or(Path::new("")).join(relative);
        if !self.source.files.same_file(&real, &destination) {
            self.copies.push((real, destination));
        }
        Ok(())
    }

    /// Embeds image `i`, named by `uri`, in buffer 0 (GLB output); `false` when it stays a
    /// URI (a `data:` URI, a missing file, a format whose MIME type is unknown, or a format
    /// other than PNG and JPEG that a texture names as its core `source`: embedded, its
    /// `mimeType` would make that texture invalid, as it is not when named by file).
    fn embed(&mut self, i: usize, uri: &str, what: &str) -> Result<bool, IoError> {
        let Some((_, Some(real))) =
            crate::uri::resolve_file(&self.source.path, uri, what, &self.source.files)?
        else {
            return Ok(false);
        };
        let bytes = self.source.files.read(&real).map_err(|e| IoError::io(&real, e))?;
        let declared = self.json["images"][i]["mimeType"].as_str().map(str::to_owned);
        let Some(mime) = declared.or_else(|| sniff(&bytes).map(str::to_owned)) else {
            return Ok(false);
        };
        if !["image/png", "image/jpeg"].contains(&mime.as_str()) && self.core_source(i) {
            self.warnings.push(format!(
                "{}: {what} ({uri}, {mime}) stays a file beside the GLB: a texture names it as \
                 its core source, which glTF allows in a buffer only for PNG and JPEG",
                self.source.path.display()
            ));
            return Ok(false);
        }
        let view = self.view(Piece::Bytes(bytes), Layout::Bytes);
        if let Some(image) = self.json["images"][i].as_object_mut() {
            image.remove("uri");
            image.insert("bufferView".to_owned(), json!(view));
            image.insert("mimeType".to_owned(), json!(mime));
        }
        Ok(true)
    }

    /// Whether a texture names image `i` as its core `source` (rather than only through an
    /// extension such as KHR_texture_basisu or EXT_texture_webp).
    fn core_source(&self, i: usize) -> bool {
        let textures = self.json["textures"].as_array().map_or(&[][..], Vec::as_slice);
        textures.iter().any(|t| usize_member(t, "source") == Some(i))
    }

    /// Writes the side files, then the document.
    pub(super) fn write(&self, to: &mut Destination) -> Result<(), IoError> {
        for (from, destination) in &self.copies {
            if let Some(parent) = destination.parent() {
                to.create_folder(parent)?;
            }
            let files = &self.source.files;
            to.write_with(destination, |out| match files {
                Files::Disk => std::io::copy(&mut std::fs::File::open(from)?, out).map(|_| ()),
                Files::Memory(_) => out.write_all(&files.read(from)?),
            })?;
        }
        let has_host = self.json["buffers"].get(0).is_some() && !self.host_without_data();
        let host_length = self.json["buffers"].get(0).and_then(|b| usize_member(b, "byteLength"));
        let host_length = host_length.unwrap_or(0);
        let folder = self.path.parent().unwrap_or(Path::new(""));
        let serialise = |json: &Value, pretty: bool| {
            let bytes =
                if pretty { serde_json::to_vec_pretty(json) } else { serde_json::to_vec(json) };
            bytes.map_err(|e| IoError::InvalidAsset {
                path: self.path.to_path_buf(),
                object: String::new(),
                kind: InvalidAsset::Json { source: e },
            })
        };
        if !self.binary {
            if let Some(uri) = self.json["buffers"][0]["uri"].as_str() {
                to.write_with(&folder.join(uri), |out| self.write_host(out, host_length))?;
            }
            return to.write(self.path, &serialise(&self.json, true)?);
        }
        let json = serialise(&self.json, false)?;
        let bin = has_host.then_some(host_length);
        crate::glb::write(to, self.path, json, bin, |out| self.write_host(out, host_length))
    }

    /// Writes buffer 0: the input's bytes (those pruning kept; zeros past the input's end
    /// and where the load gave them back, `loaded.rs`), then the appended pieces, `length`
    /// bytes in all.
    fn write_host(&self, out: &mut dyn Write, length: usize) -> std::io::Result<()> {
        let input_length = if self.appended > 0 { self.base } else { length };
        let input = &self.source.buffers;
        match &self.kept {
            None => input.write_host(0..input_length, self.model, out)?,
            Some(kept) => {
                let mut at = 0;
                for (range, start) in &kept.ranges {
                    zeros(out, start - at)?;
                    input.write_host(range.clone(), self.model, out)?;
                    at = start + range.len();
                }
                zeros(out, input_length - at)?;
            }
        }
        let mut written = 0usize;
        for piece in &self.pieces {
            let padding = written.next_multiple_of(4) - written;
            out.write_all(&[0; 3][..padding])?;
            piece.write(out)?;
            written += padding + piece.len();
        }
        debug_assert_eq!(input_length + written, length);
        Ok(())
    }

    /// Whether buffer 0 of the input has no data: no `uri` and not a GLB's BIN chunk (valid
    /// glTF: its data "MAY be provided by an extension or other means"; see `read/lenient.rs`).
    fn host_without_data(&self) -> bool {
        let host = &self.source.json["buffers"][0];
        host.is_object()
            && host.get("uri").is_none()
            && self.source.buffers.len(0) < usize_member(host, "byteLength").unwrap_or(0)
    }

    /// Buffer 0 without data is written as it was (no `uri`) in a `.gltf`. A GLB cannot
    /// hold it (there, buffer 0 without `uri` is the BIN chunk), and nothing can be appended
    /// to it.
    fn keep_host_without_data(&self) -> Result<(), IoError> {
        let kind = if self.appended > 0 {
            InvalidAsset::HostCannotGrow
        } else if self.binary {
            InvalidAsset::HostInGlb
        } else {
            return Ok(());
        };
        Err(IoError::InvalidAsset { path: self.path.to_path_buf(), object: String::new(), kind })
    }
}

/// The MIME type of image bytes seamlit passes through, from their signature.
fn sniff(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some("image/png")
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        Some("image/jpeg")
    } else if bytes.starts_with(b"\xABKTX 20\xBB\r\n\x1A\n") {
        Some("image/ktx2")
    } else if bytes.len() >= 12 && &bytes[..4] == b"RIFF" && &bytes[8..12] == b"WEBP" {
        Some("image/webp")
    } else {
        None
    }
}
