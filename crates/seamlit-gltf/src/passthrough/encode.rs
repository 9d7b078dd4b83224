//! Keeping meshopt compression on output ([`seamlit_asset::SaveOptions::keep_compression`], issue 11).
//!
//! For an input that used EXT_meshopt_compression or KHR_meshopt_compression, the
//! pass-through writer then leaves every compressed buffer view of the input as it was
//! written: its compressed bytes (which stay where they were, in buffer 0 or another
//! buffer: the pass never packs a document that uses meshopt, see `prune.rs`), mode,
//! filter and fallback buffer, so a lossy filter (OCTAHEDRAL, QUATERNION, EXPONENTIAL,
//! COLOR) is never applied twice. The data the pass writes anew (NORMAL, TANGENT, their
//! morph deltas, split vertex streams, indices) is gathered into one new view per layout
//! (vertex stride, or index size; each accessor at its offset in it, as gltfpack packs its
//! streams) and encoded here with meshoptimizer's lossless codecs, filter NONE: ATTRIBUTES
//! for vertex data; TRIANGLES for the triangle-list indices seamlit writes where that codec
//! gives the same index order back, else INDICES (TRIANGLES may rotate a triangle's
//! corners). The compressed bytes go to buffer 0; the view itself names a fallback buffer,
//! the input's first one (or a new one at the end of `buffers`), whose `byteLength` grows to
//! hold the new views' decoded bytes (EXT_meshopt_compression, "Fallback buffers"). 8-bit
//! indices, which the extension cannot hold, get plain views of their own, as without the
//! option; a gathered view the codec does not make smaller is written plain.
//!
//! The vertex codec version follows the extension: version 0 for EXT_meshopt_compression
//! (the only one it allows), version 1 for KHR_meshopt_compression.

use std::path::Path;

use serde_json::{Value, json};

use crate::decode::meshopt::{MESHOPT, Vertex, by_stride, is_fallback, meshopt};
use crate::json::{ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER, array_member, usize_member};
use seamlit_asset::{IoError, KeepCompression};

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
pub(crate) struct Recompression {
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
    /// New views left plain (data the codec does not make smaller).
    plain: usize,
    /// The new data gathered so far, one view per layout.
    pending: Vec<Gathered>,
}

/// New data of one layout, gathered into one buffer view until the save ends.
struct Gathered {
    /// The view's index (an empty entry until [`Recompression::finish`]).
    view: usize,
    /// The layout, with `element` equal to `stride` for vertices (streams of several element
    /// sizes share a view of their stride).
    layout: Layout,
    /// The data, each stream's at the offset its accessor names.
    bytes: Vec<u8>,
}

impl Recompression {
    /// Starts a save of `json` (the output document, the input's until now) that keeps the
    /// compression. `None` when no buffer view is meshopt-compressed (nothing to keep).
    ///
    /// # Errors
    ///
    /// [`IoError::CannotKeepCompression`] naming `source` (the input) when it has
    /// Draco-compressed primitives: seamlit has no Draco encoder.
    pub(crate) fn start(json: &mut Value, source: &Path) -> Result<Option<Self>, IoError> {
        if let Some(&(m, p)) = crate::decode::draco::draco_primitives(json).first() {
            return Err(IoError::CannotKeepCompression {
                path: source.to_path_buf(),
                kind: KeepCompression::Draco {
                    primitive: crate::decode::draco::extension_path(m, p),
                },
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
            Some((index, buffer)) => (index, usize_member(buffer, "byteLength").unwrap_or(0)),
            None => {
                let fallback =
                    json!({ "byteLength": 0, "extensions": { name: { "fallback": true } } });
                let buffers = array_member(json, "buffers");
                buffers.push(fallback);
                (buffers.len() - 1, 0)
            }
        };
        Ok(Some(Self {
            name,
            fallback,
            fallback_length,
            kept,
            encoded: 0,
            plain: 0,
            pending: Vec::new(),
        }))
    }

    /// Gathers the new data `bytes`, laid out as `layout`, into the one new view of its layout
    /// (an empty entry pushed to `views` the first time, filled in by [`Recompression::finish`]);
    /// returns that view and the offset of `bytes` in it. `None` for data that is never
    /// compressed (image bytes, 8-bit indices, a stride the codec does not take).
    pub(crate) fn gather(
        &mut self,
        bytes: &[u8],
        layout: Layout,
        views: &mut Vec<Value>,
    ) -> Option<(usize, usize)> {
        let key = match layout {
            Layout::Vertices { stride, .. }
                if stride.is_multiple_of(4) && (4..=256).contains(&stride) =>
            {
                Layout::Vertices { element: stride, stride }
            }
            Layout::Triangles { size: 2 | 4 } => layout,
            _ => return None,
        };
        let group = match self.pending.iter().position(|g| g.layout == key) {
            Some(group) => group,
            None => {
                views.push(json!({}));
                self.pending.push(Gathered {
                    view: views.len() - 1,
                    layout: key,
                    bytes: Vec::new(),
                });
                self.pending.len() - 1
            }
        };
        let group = &mut self.pending[group];
        let offset = group.bytes.len();
        group.bytes.extend_from_slice(bytes);
        Some((group.view, offset))
    }

    /// Writes one gathered view: compressed (its bytes to buffer 0 through `append`, the
    /// view in the fallback buffer with its extension object), or plain where the codec
    /// does not make it smaller.
    fn write(&mut self, gathered: &Gathered, append: &mut impl FnMut(Vec<u8>) -> usize) -> Value {
        let bytes = &gathered.bytes;
        let (stride, count, mode, compressed) = match gathered.layout {
            Layout::Vertices { stride, .. } => {
                let version = if self.name == MESHOPT[0] { 0 } else { 1 };
                (stride, bytes.len() / stride, "ATTRIBUTES", vertices(bytes, stride, version))
            }
            Layout::Triangles { size } => {
                let (mode, compressed) =
                    indices(bytes, size).map_or(("", None), |(c, m)| (m, Some(c)));
                (size, bytes.len() / size, mode, compressed)
            }
            Layout::Bytes => (1, bytes.len(), "", None),
        };
        let mut view = match compressed.filter(|c| c.len() < bytes.len()) {
            Some(compressed) => {
                self.encoded += 1;
                let offset = self.fallback_length.next_multiple_of(4);
                self.fallback_length = offset + bytes.len();
                let length = compressed.len();
                let at = append(compressed);
                json!({
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
                })
            }
            None => {
                self.plain += 1;
                let at = append(bytes.clone());
                json!({ "buffer": 0, "byteOffset": at, "byteLength": bytes.len() })
            }
        };
        match gathered.layout {
            Layout::Vertices { .. } => {
                view["byteStride"] = json!(stride);
                view["target"] = json!(ARRAY_BUFFER);
            }
            Layout::Triangles { .. } => {
                view["target"] = json!(ELEMENT_ARRAY_BUFFER);
            }
            Layout::Bytes => {}
        }
        view
    }

    /// Ends the save: writes the gathered views (compressed bytes, or plain ones, to buffer
    /// 0 through `append`, which returns their offset there), the fallback buffer's
    /// `byteLength`, the extension in `extensionsUsed` and `extensionsRequired` (the new
    /// views have no uncompressed data). Returns the report's sentence.
    pub(crate) fn finish(
        mut self,
        json: &mut Value,
        source: &Path,
        mut append: impl FnMut(Vec<u8>) -> usize,
    ) -> String {
        for gathered in std::mem::take(&mut self.pending) {
            json["bufferViews"][gathered.view] = self.write(&gathered, &mut append);
        }
        json["buffers"][self.fallback]["byteLength"] = json!(self.fallback_length);
        for list in ["extensionsUsed", "extensionsRequired"] {
            let names = array_member(json, list);
            if !names.iter().any(|n| n == self.name) {
                names.push(json!(self.name));
            }
        }
        let plain = match self.plain {
            0 => String::new(),
            n => format!("; {n} stay plain (the codec does not make them smaller)"),
        };
        format!(
            "{}: {} buffer views compressed with {} are kept compressed as written (bytes, mode and filter); the new data (normals, tangents, split vertices, indices) is gathered by layout into new views, {} of them compressed losslessly (filter NONE){plain}",
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

/// Vertex data of `stride` bytes per vertex through meshoptimizer's vertex codec, the given
/// version. `None` for a stride the extension does not allow (not a multiple of 4 up to
/// 256).
fn vertices(bytes: &[u8], stride: usize, version: i32) -> Option<Vec<u8>> {
    fn encode<const N: usize>(bytes: &[u8], version: i32) -> Option<Vec<u8>> {
        let vertices: Vec<Vertex<N>> =
            bytes.as_chunks::<N>().0.iter().map(|&c| Vertex(c)).collect();
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
        2 => bytes.as_chunks::<2>().0.iter().map(|&c| u32::from(u16::from_le_bytes(c))).collect(),
        4 => bytes.as_chunks::<4>().0.iter().map(|&c| u32::from_le_bytes(c)).collect(),
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
