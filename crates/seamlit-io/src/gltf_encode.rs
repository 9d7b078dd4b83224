//! Keeping meshopt compression on output ([`crate::SaveOptions::keep_compression`], issue 11).
//!
//! For an input that used EXT_meshopt_compression or KHR_meshopt_compression, the
//! pass-through writer then leaves every compressed buffer view of the input as it was
//! written: its compressed bytes (which stay where they were, in buffer 0 or another
//! buffer: the pass never packs a document that uses meshopt, see `gltf_prune`), mode,
//! filter and fallback buffer, so a lossy filter (OCTAHEDRAL, QUATERNION, EXPONENTIAL,
//! COLOR) is never applied twice. The views the pass writes anew (NORMAL, TANGENT, their
//! morph deltas, split vertex streams, indices) are encoded here with meshoptimizer's
//! lossless codecs, filter NONE: ATTRIBUTES for vertex data; TRIANGLES for the triangle-list
//! index buffers seamlit writes where that codec gives the same index order back, else
//! INDICES (TRIANGLES may rotate a triangle's corners). The compressed bytes go to buffer 0; the view itself names
//! a fallback buffer, the input's first one (or a new one at the end of `buffers`), whose
//! `byteLength` grows to hold the new views' decoded bytes (EXT_meshopt_compression,
//! "Fallback buffers"). Index views of 8-bit indices, which the extension cannot hold, stay
//! plain data.
//!
//! The vertex codec version follows the extension: version 0 for EXT_meshopt_compression
//! (the only one it allows), version 1 for KHR_meshopt_compression.

use std::path::Path;

use serde_json::{Value, json};

use crate::IoError;
use crate::gltf_decode::{MESHOPT, Vertex, by_stride, is_fallback, meshopt};
use crate::gltf_pass::uint;

/// What a new buffer view holds: how it is described and whether it can be compressed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Layout {
    /// Vertex attribute elements (`target` ARRAY_BUFFER), `stride` bytes apart, a multiple
    /// of 4; `element` bytes each (less than `stride` where the elements are padded).
    Vertices { element: usize, stride: usize },
    /// A triangle list's indices (`target` ELEMENT_ARRAY_BUFFER), `size` bytes each.
    Triangles { size: usize },
    /// Other bytes (an embedded image): never compressed.
    Bytes,
}

/// The state of a save that keeps meshopt compression: which extension, which fallback
/// buffer, and what was kept and encoded, for the report.
pub(crate) struct Keep {
    /// The extension's name, as the input used it.
    name: &'static str,
    /// The fallback buffer that names the new views' decoded bytes.
    fallback: usize,
    /// Its `byteLength` so far.
    fallback_length: usize,
    /// Compressed views of the input, written as they were.
    kept: usize,
    /// New views encoded.
    encoded: usize,
    /// New views left plain (8-bit indices, data the codec does not make smaller).
    plain: usize,
}

impl Keep {
    /// Starts a save of `json` (the output document, the input's until now) that keeps the
    /// compression. `None` when no buffer view is meshopt-compressed (nothing to keep).
    ///
    /// # Errors
    ///
    /// [`IoError::CannotKeepCompression`] naming `source` (the input) when it has
    /// Draco-compressed primitives: seamlit has no Draco encoder.
    pub(crate) fn start(json: &mut Value, source: &Path) -> Result<Option<Self>, IoError> {
        if let Some(&(m, p)) = crate::gltf_draco::draco_primitives(json).first() {
            return Err(IoError::CannotKeepCompression {
                path: source.to_path_buf(),
                reason: format!(
                    "{} is Draco-compressed and seamlit has no Draco encoder; write it uncompressed (without --keep-compression, or keep_compression: false), then compress the output, e.g. `npx @gltf-transform/cli draco OUT.glb OUT.glb`",
                    crate::gltf_draco::place(m, p)
                ),
            });
        }
        let views = json["bufferViews"].as_array().map_or(&[][..], Vec::as_slice);
        let names: Vec<&'static str> =
            views.iter().filter_map(|v| meshopt(v).map(|m| m.0)).collect();
        let Some(&name) = names.first() else { return Ok(None) };
        let kept = names.len();
        let buffers = json["buffers"].as_array().map_or(&[][..], Vec::as_slice);
        let existing = buffers.iter().enumerate().skip(1).find(|(_, b)| {
            is_fallback(b) && b.get("uri").is_none() && b["extensions"].get(name).is_some()
        });
        let (fallback, fallback_length) = match existing {
            Some((index, buffer)) => (index, uint(buffer, "byteLength").unwrap_or(0)),
            None => {
                let fallback =
                    json!({ "byteLength": 0, "extensions": { name: { "fallback": true } } });
                let buffers = array(json, "buffers");
                buffers.push(fallback);
                (buffers.len() - 1, 0)
            }
        };
        Ok(Some(Self { name, fallback, fallback_length, kept, encoded: 0, plain: 0 }))
    }

    /// Encodes the new view `bytes` laid out as `layout`: the compressed bytes go to buffer
    /// 0 through `append` (which returns their offset there); returns the buffer view, in
    /// the fallback buffer with its extension object. `None` when it stays plain (image
    /// bytes, 8-bit indices, a stride the codec does not take, data that would not come out
    /// smaller): nothing was appended.
    pub(crate) fn encode(
        &mut self,
        bytes: &[u8],
        layout: Layout,
        append: impl FnOnce(Vec<u8>) -> usize,
    ) -> Option<Value> {
        let (compressed, stride, count, mode) = match layout {
            Layout::Bytes => return None,
            Layout::Vertices { stride, .. } => {
                let version = if self.name == MESHOPT[0] { 0 } else { 1 };
                let compressed = vertices(bytes, stride, version);
                (compressed, stride, bytes.len() / stride, "ATTRIBUTES")
            }
            Layout::Triangles { size } => match indices(bytes, size) {
                Some((compressed, mode)) => (Some(compressed), size, bytes.len() / size, mode),
                None => (None, size, 0, ""),
            },
        };
        // A stream of a few vertices can come out larger than it went in: it stays plain.
        let Some(compressed) = compressed.filter(|c| c.len() < bytes.len()) else {
            self.plain += 1;
            return None;
        };
        let offset = self.fallback_length.next_multiple_of(4);
        self.fallback_length = offset + bytes.len();
        self.encoded += 1;
        let length = compressed.len();
        let at = append(compressed);
        let mut view = json!({
            "buffer": self.fallback,
            "byteOffset": offset,
            "byteLength": bytes.len(),
            "extensions": { self.name: {
                "buffer": 0,
                "byteOffset": at,
                "byteLength": length,
                "byteStride": stride,
                "mode": mode,
                "count": count,
            } },
        });
        if let Layout::Vertices { .. } = layout {
            view["byteStride"] = json!(stride);
            view["target"] = json!(crate::gltf_pass::ARRAY_BUFFER);
        } else {
            view["target"] = json!(crate::gltf_pass::ELEMENT_ARRAY_BUFFER);
        }
        Some(view)
    }

    /// Ends the save: the fallback buffer's `byteLength`, the extension in `extensionsUsed`
    /// and `extensionsRequired` (the new views have no uncompressed data). Returns the
    /// report's sentence.
    pub(crate) fn finish(self, json: &mut Value, source: &Path) -> String {
        json["buffers"][self.fallback]["byteLength"] = json!(self.fallback_length);
        for list in ["extensionsUsed", "extensionsRequired"] {
            let names = array(json, list);
            if !names.iter().any(|n| n == self.name) {
                names.push(json!(self.name));
            }
        }
        let plain = match self.plain {
            0 => String::new(),
            n => format!(
                "; {n} new views stay plain (8-bit indices, which the extension cannot hold, or data the codec does not make smaller)"
            ),
        };
        format!(
            "{}: {} buffer views compressed with {} are kept compressed as written (bytes, mode and filter); {} new views (normals, tangents, split vertices, indices) are compressed losslessly (filter NONE){plain}",
            source.display(),
            self.kept,
            self.name,
            self.encoded
        )
    }
}

/// The sentence of a save asked to keep the compression of an input that has none.
pub(crate) fn nothing_to_keep(source: &Path) -> String {
    format!(
        "{}: keeping the compression changes nothing: the input has no meshopt-compressed buffer views",
        source.display()
    )
}

/// The array member `key` of the document, created when missing.
fn array<'j>(json: &'j mut Value, key: &str) -> &'j mut Vec<Value> {
    if !json[key].is_array() {
        json[key] = json!([]);
    }
    json[key].as_array_mut().expect("made an array above")
}

/// Vertex data of `stride` bytes per vertex through meshoptimizer's vertex codec, the given
/// version. `None` for a stride the extension does not allow (not a multiple of 4 up to
/// 256).
fn vertices(bytes: &[u8], stride: usize, version: i32) -> Option<Vec<u8>> {
    fn encode<const N: usize>(bytes: &[u8], version: i32) -> Option<Vec<u8>> {
        let vertices: Vec<Vertex<N>> = bytes
            .chunks_exact(N)
            .map(|chunk| Vertex(<[u8; N]>::try_from(chunk).unwrap_or([0; N])))
            .collect();
        meshopt::encode_vertex_buffer_level(&vertices, 2, Some(version)).ok()
    }
    if !bytes.len().is_multiple_of(stride.max(1)) {
        return None;
    }
    by_stride!(stride, |N| encode::<N>(bytes, version)).flatten()
}

/// Triangle-list indices of `size` bytes through meshoptimizer's index codecs, with the
/// mode: TRIANGLES where it gives the indices back in the same order, else INDICES. (The
/// TRIANGLES codec may rotate a triangle's corners, keeping its winding: the same mesh to a
/// renderer, but not the same bytes, and the save changes nothing it does not own.) `None`
/// for 8-bit indices (the extension takes 2 or 4 bytes).
fn indices(bytes: &[u8], size: usize) -> Option<(Vec<u8>, &'static str)> {
    let indices: Vec<u32> = match size {
        2 => bytes.chunks_exact(2).map(|c| u32::from(u16::from_le_bytes([c[0], c[1]]))).collect(),
        4 => bytes.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect(),
        _ => return None,
    };
    let vertex_count = indices.iter().max().map_or(0, |&m| m as usize + 1);
    if indices.len().is_multiple_of(3) {
        let compressed = meshopt::encode_index_buffer(&indices, vertex_count).ok()?;
        let back = meshopt::decode_index_buffer::<u32>(&compressed, indices.len()).ok();
        if back.as_deref() == Some(&indices[..]) {
            return Some((compressed, "TRIANGLES"));
        }
    }
    Some((meshopt::encode_index_sequence(&indices, vertex_count).ok()?, "INDICES"))
}
