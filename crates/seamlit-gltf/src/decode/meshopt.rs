//! EXT_meshopt_compression (or KHR_meshopt_compression, its successor with the COLOR
//! filter, issue 11): a buffer view whose extension names compressed bytes in another
//! buffer. [`decode_meshopt`] decodes each such view once, at load, into the bytes the view
//! itself names (in a "fallback" buffer that has no data of its own, bytes are made for it
//! first: [`fallback_length`]), with the `meshopt` crate (meshoptimizer's own decoder and
//! filters). From then on the loader and the pass-through writer read plain data; the
//! writer moves the decoded views into buffer 0 and removes the extension
//! (`passthrough/uncompress.rs`), so the output needs no meshopt decoder, unless the save
//! keeps the compression (`passthrough/encode.rs`).

use std::path::Path;

use serde_json::Value;

use crate::json::usize_member;
use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::{GltfKind, Meshopt};

/// The extension's names: the vendor one and its Khronos successor, which adds the COLOR
/// filter and version 1 of the vertex codec (meshoptimizer decodes both).
pub(crate) const MESHOPT: [&str; 2] = ["EXT_meshopt_compression", "KHR_meshopt_compression"];

/// The meshopt extension object of a buffer or buffer view, with the name it is under.
pub(crate) fn meshopt(item: &Value) -> Option<(&'static str, &Value)> {
    MESHOPT.into_iter().find_map(|name| Some((name, item["extensions"].get(name)?)))
}

/// Whether a buffer is a meshopt fallback buffer.
pub(crate) fn is_fallback(buffer: &Value) -> bool {
    meshopt(buffer).is_some_and(|(_, e)| e["fallback"].as_bool() == Some(true))
}

/// The number of bytes to make for buffer `index` when it is an EXT_meshopt_compression
/// fallback buffer without data of its own (no `uri`): its `byteLength`. `None` for any
/// other buffer.
///
/// # Errors
///
/// [`IoError::TooLarge`] when the declared length exceeds `limit` (the loader's file size
/// limit): the allocation is refused before it is made.
pub(crate) fn fallback_length(
    document: &Value,
    index: usize,
    limit: u64,
    path: &Path,
) -> Result<Option<usize>, IoError> {
    let buffer = &document["buffers"][index];
    if !is_fallback(buffer) || buffer.get("uri").is_some() {
        return Ok(None);
    }
    let length = usize_member(buffer, "byteLength").unwrap_or(0);
    if length as u64 > limit {
        return Err(IoError::TooLarge { path: path.to_path_buf(), limit, actual: length as u64 });
    }
    Ok(Some(length))
}

/// What one EXT_meshopt_compression buffer view holds, from its extension object.
struct Compressed {
    /// The buffer holding the compressed bytes, and where they lie in it.
    buffer: usize,
    offset: usize,
    length: usize,
    /// Bytes per decoded element, and the number of elements.
    stride: usize,
    count: usize,
    mode: Mode,
    filter: Filter,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Attributes,
    Triangles,
    Indices,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
    /// KHR_meshopt_compression only: YCoCg colours.
    Color,
}

/// Decodes every buffer view that carries EXT_meshopt_compression into the bytes the view
/// names in its own buffer (`buffers` as read; a fallback buffer is zeros until then).
///
/// # Errors
///
/// [`IoError::Gltf`] naming `bufferViews[i].extensions.EXT_meshopt_compression` for a
/// malformed extension (unknown mode or filter, a stride or count the mode does not allow,
/// compressed bytes outside their buffer, a decoded size that is not the view's length) or
/// compressed data meshoptimizer refuses.
pub(crate) fn decode_meshopt(
    document: &Value,
    buffers: &mut [Vec<u8>],
    path: &Path,
) -> Result<(), IoError> {
    let views = document["bufferViews"].as_array().map_or(&[][..], Vec::as_slice);
    for (index, view) in views.iter().enumerate() {
        let Some((name, extension)) = meshopt(view) else { continue };
        let error = |kind: Meshopt| IoError::Gltf {
            path: path.to_path_buf(),
            place: format!("bufferViews[{index}].extensions.{name}"),
            kind: GltfKind::Meshopt(kind),
        };
        let compressed = compressed(extension).map_err(error)?;
        let bytes = buffers
            .get(compressed.buffer)
            .and_then(|b| {
                b.get(compressed.offset..compressed.offset.checked_add(compressed.length)?)
            })
            .ok_or_else(|| {
                error(Meshopt::CompressedOutside {
                    start: compressed.offset,
                    end: compressed.offset.saturating_add(compressed.length),
                    buffer: compressed.buffer,
                })
            })?;
        // Sizes are checked before decoding: the decoder allocates `count` elements.
        let target = usize_member(view, "buffer").unwrap_or(usize::MAX);
        let offset = usize_member(view, "byteOffset").unwrap_or(0);
        let length = usize_member(view, "byteLength").unwrap_or(0);
        if compressed.count.checked_mul(compressed.stride) != Some(length) {
            return Err(error(Meshopt::LengthMismatch {
                count: compressed.count,
                stride: compressed.stride,
                length,
            }));
        }
        let end = offset.checked_add(length);
        let available = buffers.get(target).map_or(0, Vec::len);
        if end.is_none_or(|end| end > available) {
            return Err(error(Meshopt::ViewOutside {
                start: offset,
                end: offset.saturating_add(length),
                buffer: target,
                available,
            }));
        }
        let plain = decode(bytes, &compressed).map_err(error)?;
        let Some(place) = buffers.get_mut(target).and_then(|b| b.get_mut(offset..offset + length))
        else {
            return Err(error(Meshopt::ViewOutside {
                start: offset,
                end: offset.saturating_add(length),
                buffer: target,
                available,
            }));
        };
        if plain.len() != length {
            return Err(error(Meshopt::DecodedLength { decoded: plain.len(), length }));
        }
        place.copy_from_slice(&plain);
    }
    Ok(())
}

/// Reads a view's extension object.
fn compressed(extension: &Value) -> Result<Compressed, Meshopt> {
    let need =
        |member: &'static str| usize_member(extension, member).ok_or(Meshopt::Missing { member });
    let mode = match extension["mode"].as_str() {
        Some("ATTRIBUTES") => Mode::Attributes,
        Some("TRIANGLES") => Mode::Triangles,
        Some("INDICES") => Mode::Indices,
        other => return Err(Meshopt::UnknownMode { found: other.map(str::to_owned) }),
    };
    let filter = match extension.get("filter").map(Value::as_str) {
        None | Some(Some("NONE")) => Filter::None,
        Some(Some("OCTAHEDRAL")) => Filter::Octahedral,
        Some(Some("QUATERNION")) => Filter::Quaternion,
        Some(Some("EXPONENTIAL")) => Filter::Exponential,
        Some(Some("COLOR")) => Filter::Color,
        Some(other) => return Err(Meshopt::UnknownFilter { found: other.map(str::to_owned) }),
    };
    let compressed = Compressed {
        buffer: need("buffer")?,
        offset: usize_member(extension, "byteOffset").unwrap_or(0),
        length: need("byteLength")?,
        stride: need("byteStride")?,
        count: need("count")?,
        mode,
        filter,
    };
    // EXT_meshopt_compression, "Specifying compressed views".
    let stride = compressed.stride;
    let allowed = match (mode, filter) {
        (Mode::Attributes, Filter::None | Filter::Exponential) => {
            stride.is_multiple_of(4) && (4..=256).contains(&stride)
        }
        (Mode::Attributes, Filter::Octahedral | Filter::Color) => stride == 4 || stride == 8,
        (Mode::Attributes, Filter::Quaternion) => stride == 8,
        (Mode::Triangles | Mode::Indices, Filter::None) => stride == 2 || stride == 4,
        (Mode::Triangles | Mode::Indices, _) => false,
    };
    if !allowed {
        return Err(Meshopt::StrideNotAllowed {
            stride,
            mode: format!("{mode:?}").to_uppercase(),
            filter: format!("{filter:?}").to_uppercase(),
        });
    }
    if mode == Mode::Triangles && !compressed.count.is_multiple_of(3) {
        return Err(Meshopt::NotTriangles { count: compressed.count });
    }
    Ok(compressed)
}

/// Decodes one view's compressed bytes: `count * stride` plain bytes, filter applied.
fn decode(bytes: &[u8], view: &Compressed) -> Result<Vec<u8>, Meshopt> {
    let refused = |e: meshopt::Error| Meshopt::Refused { reason: e.to_string() };
    match (view.mode, view.stride) {
        (Mode::Triangles, 2) => Ok(le_bytes(
            meshopt::decode_index_buffer::<u16>(bytes, view.count).map_err(refused)?,
            u16::to_le_bytes,
        )),
        (Mode::Triangles, _) => Ok(le_bytes(
            meshopt::decode_index_buffer::<u32>(bytes, view.count).map_err(refused)?,
            u32::to_le_bytes,
        )),
        (Mode::Indices, 2) => Ok(le_bytes(
            meshopt::decode_index_sequence::<u16>(bytes, view.count).map_err(refused)?,
            u16::to_le_bytes,
        )),
        (Mode::Indices, _) => Ok(le_bytes(
            meshopt::decode_index_sequence::<u32>(bytes, view.count).map_err(refused)?,
            u32::to_le_bytes,
        )),
        (Mode::Attributes, stride) => {
            let mut plain = vertices(bytes, view.count, stride)
                .ok_or(Meshopt::NotAVertexSize { stride })?
                .map_err(refused)?;
            filter(&mut plain, view.filter, stride);
            Ok(plain)
        }
    }
}

/// Little-endian bytes of decoded indices.
fn le_bytes<T: Copy, const N: usize>(values: Vec<T>, f: fn(T) -> [u8; N]) -> Vec<u8> {
    values.into_iter().flat_map(f).collect()
}

/// One vertex of `N` bytes: meshoptimizer decodes into (and encodes from) elements of the
/// vertex size.
#[derive(Clone, Copy)]
pub(crate) struct Vertex<const N: usize>(pub(crate) [u8; N]);

/// `Some($call)` with the const `$n` set to `$stride` when it is a vertex size meshoptimizer's
/// codec takes in glTF (a multiple of 4, 4 to 256 bytes), else `None`: the codec's element
/// type is `Vertex<N>`, one monomorphisation per size.
macro_rules! by_stride {
    ($stride:expr, |$n:ident| $call:expr) => {
        by_stride!(@ $stride, $n, $call, 4 8 12 16 20 24 28 32 36 40 44 48 52 56 60 64 68 72 76
            80 84 88 92 96 100 104 108 112 116 120 124 128 132 136 140 144 148 152 156 160 164
            168 172 176 180 184 188 192 196 200 204 208 212 216 220 224 228 232 236 240 244 248
            252 256)
    };
    (@ $stride:expr, $n:ident, $call:expr, $($size:literal)*) => {
        match $stride {
            $($size => {
                const $n: usize = $size;
                Some($call)
            })*
            _ => None,
        }
    };
}
pub(crate) use by_stride;

impl<const N: usize> Default for Vertex<N> {
    fn default() -> Self {
        Self([0; N])
    }
}

/// Decodes `count` vertices of `stride` bytes; `None` unless `stride` is a multiple of 4
/// up to 256.
fn vertices(bytes: &[u8], count: usize, stride: usize) -> Option<Result<Vec<u8>, meshopt::Error>> {
    fn decode<const N: usize>(bytes: &[u8], count: usize) -> Result<Vec<u8>, meshopt::Error> {
        let vertices = meshopt::decode_vertex_buffer::<Vertex<N>>(bytes, count)?;
        Ok(vertices.into_iter().flat_map(|v| v.0).collect())
    }
    by_stride!(stride, |N| decode::<N>(bytes, count))
}

/// Applies a view's filter to its decoded vertices, in place. Every filter works on each
/// element (OCTAHEDRAL, QUATERNION, COLOR) or each 32-bit word (EXPONENTIAL) alone, so the
/// stride only says the element size.
fn filter(plain: &mut [u8], filter: Filter, stride: usize) {
    match (filter, stride) {
        (Filter::None, _) => {}
        (Filter::Octahedral, 4) => in_place(plain, meshopt::decode_filter_oct::<i8>),
        (Filter::Octahedral, _) => in_place(plain, meshopt::decode_filter_oct::<i16>),
        (Filter::Quaternion, _) => in_place(plain, meshopt::decode_filter_quat),
        (Filter::Exponential, _) => in_place(plain, meshopt::decode_filter_exp::<1>),
        (Filter::Color, 4) => in_place(plain, meshopt::decode_filter_color::<u8>),
        (Filter::Color, _) => in_place(plain, meshopt::decode_filter_color::<u16>),
    }
}

/// Runs `f` over `plain` seen as elements of type `T` (copied to and from an aligned
/// vector; glTF's little-endian bytes are the machine's own on every platform seamlit
/// builds for).
fn in_place<T: bytemuck::Pod>(plain: &mut [u8], f: impl FnOnce(&mut [T])) {
    let mut elements: Vec<T> = bytemuck::pod_collect_to_vec(plain);
    f(&mut elements);
    plain.copy_from_slice(bytemuck::cast_slice(&elements));
}
