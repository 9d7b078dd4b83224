//! glTF vertex data that is not plain floats in plain buffer views (issue 11):
//!
//! - **KHR_mesh_quantization**: POSITION, NORMAL, TANGENT and TEXCOORD_n stored as 8- or
//!   16-bit integers, normalised or not. [`read_floats`] reads any of them as floats, by the
//!   specification's conversion (`max(c / 127, -1)` for a normalised byte, `c / 65535` for a
//!   normalised unsigned short, the integer itself when not normalised); the node transform
//!   that usually undoes a quantised position's scale is applied as any node transform is.
//!   The pass-through writer keeps these accessors' bytes as they are.
//! - **EXT_meshopt_compression** (or **KHR_meshopt_compression**, its successor with the
//!   COLOR filter): a buffer view whose extension names compressed bytes in
//!   another buffer. [`decode_meshopt`] decodes each such view once, at load, into the bytes
//!   the view itself names (in a "fallback" buffer that has no data of its own, bytes are
//!   made for it first: [`fallback_length`]), with the `meshopt` crate (meshoptimizer's own
//!   decoder and filters). From then on the loader and the pass-through writer read plain
//!   data; the writer moves the decoded views into buffer 0 and removes the extension
//!   ([`uncompress_views`]), so the output needs no meshopt decoder, unless the save keeps
//!   the compression (`crate::gltf_encode`).

use std::path::Path;

use gltf::accessor::{DataType, Item, Iter};
use serde_json::{Value, json};

use crate::gltf_pass::uint;
use crate::{GltfKind, IoError, Meshopt};

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

/// Reads an accessor of `N` components as floats, whatever its component type: `FLOAT` as
/// is; `BYTE`, `UNSIGNED_BYTE`, `SHORT`, `UNSIGNED_SHORT` normalised when the accessor says
/// `normalized` (glTF 2.0, "Accessor data types"), else converted as integers
/// (KHR_mesh_quantization). Sparse values are substituted. `None` for `UNSIGNED_INT` or when
/// the accessor's data cannot be reached (the caller checked it lies in its view).
pub(crate) fn read_floats<const N: usize>(
    accessor: &gltf::Accessor<'_>,
    buffers: &[Vec<u8>],
) -> Option<Vec<[f32; N]>>
where
    [f32; N]: Item,
    [i8; N]: Item,
    [u8; N]: Item,
    [i16; N]: Item,
    [u16; N]: Item,
{
    let get = |b: gltf::Buffer<'_>| buffers.get(b.index()).map(Vec::as_slice);
    let normalized = accessor.normalized();
    fn convert<T: Copy, const N: usize>(
        iter: impl Iterator<Item = [T; N]>,
        f: impl Fn(T) -> f32,
    ) -> Vec<[f32; N]> {
        iter.map(|element| element.map(&f)).collect()
    }
    let a = accessor.clone();
    Some(match accessor.data_type() {
        DataType::F32 => Iter::<[f32; N]>::new(a, get)?.collect(),
        DataType::I8 => convert(Iter::<[i8; N]>::new(a, get)?, |c| match normalized {
            true => (f32::from(c) / 127.0).max(-1.0),
            false => f32::from(c),
        }),
        DataType::U8 => convert(Iter::<[u8; N]>::new(a, get)?, |c| match normalized {
            true => f32::from(c) / 255.0,
            false => f32::from(c),
        }),
        DataType::I16 => convert(Iter::<[i16; N]>::new(a, get)?, |c| match normalized {
            true => (f32::from(c) / 32767.0).max(-1.0),
            false => f32::from(c),
        }),
        DataType::U16 => convert(Iter::<[u16; N]>::new(a, get)?, |c| match normalized {
            true => f32::from(c) / 65535.0,
            false => f32::from(c),
        }),
        DataType::U32 => return None,
    })
}

/// Reads a NORMAL (`N = 3`) or TANGENT (`N = 4`) accessor as [`read_floats`] does; when it
/// is stored as integers (KHR_mesh_quantization), the `xyz` of each element is rescaled to
/// unit length: an 8-bit normal is a unit vector only up to its rounding (a length of 0.99
/// is common), and the frames seamlit keeps or orthogonalises against must be unit.
pub(crate) fn read_directions<const N: usize>(
    accessor: &gltf::Accessor<'_>,
    buffers: &[Vec<u8>],
) -> Option<Vec<[f32; N]>>
where
    [f32; N]: Item,
    [i8; N]: Item,
    [u8; N]: Item,
    [i16; N]: Item,
    [u16; N]: Item,
{
    let mut values = read_floats::<N>(accessor, buffers)?;
    if accessor.data_type() != DataType::F32 {
        for v in &mut values {
            let length = v.iter().take(3).map(|c| c * c).sum::<f32>().sqrt();
            if length > 0.0 {
                v.iter_mut().take(3).for_each(|c| *c /= length);
            }
        }
    }
    Some(values)
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
    let length = uint(buffer, "byteLength").unwrap_or(0);
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
        let target = uint(view, "buffer").unwrap_or(usize::MAX);
        let offset = uint(view, "byteOffset").unwrap_or(0);
        let length = uint(view, "byteLength").unwrap_or(0);
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
    let need = |member: &'static str| uint(extension, member).ok_or(Meshopt::Missing { member });
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
        offset: uint(extension, "byteOffset").unwrap_or(0),
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
    let refused = |source: meshopt::Error| Meshopt::Refused { source };
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

/// For the pass-through writer: every view of `json` (the output document) that carries
/// EXT_meshopt_compression is given its decoded bytes (`source_buffers`, decoded at load)
/// as new data in buffer 0, by `append` (which returns their offset there), and loses the
/// extension; fallback buffers no view uses any more are removed when they are the last
/// buffers, or else given their bytes as a `data:` URI; the extension is removed from
/// `extensionsUsed` and `extensionsRequired` when nothing uses it any more. Returns one
/// sentence for the save report, or `None` when nothing was compressed.
pub(crate) fn uncompress_views(
    json: &mut Value,
    source_buffers: &[Vec<u8>],
    path: &Path,
    mut append: impl FnMut(Vec<u8>) -> usize,
) -> Option<String> {
    let view_count = json["bufferViews"].as_array().map_or(0, Vec::len);
    let mut moved = 0;
    let mut names = std::collections::BTreeSet::new();
    for index in 0..view_count {
        let view = &json["bufferViews"][index];
        let Some((name, _)) = meshopt(view) else { continue };
        names.insert(name);
        let offset = uint(view, "byteOffset").unwrap_or(0);
        let length = uint(view, "byteLength").unwrap_or(0);
        // Decoded and checked at load: the bytes are there.
        let bytes = uint(view, "buffer")
            .and_then(|b| source_buffers.get(b))
            .and_then(|b| b.get(offset..offset + length))
            .map(<[u8]>::to_vec)
            .unwrap_or_default();
        let at = append(bytes);
        let view = &mut json["bufferViews"][index];
        view["buffer"] = json!(0);
        view["byteOffset"] = json!(at);
        remove_extension(view);
        moved += 1;
    }
    if moved == 0 {
        return None;
    }
    drop_unused_fallbacks(json, source_buffers);
    let still_used = json["buffers"]
        .as_array()
        .into_iter()
        .flatten()
        .chain(json["bufferViews"].as_array().into_iter().flatten())
        .any(|item| meshopt(item).is_some());
    if !still_used {
        for list in ["extensionsUsed", "extensionsRequired"] {
            if let Some(names) = json[list].as_array_mut() {
                names.retain(|name| !MESHOPT.iter().any(|m| name == m));
                if names.is_empty()
                    && let Some(root) = json.as_object_mut()
                {
                    root.remove(list);
                }
            }
        }
    }
    Some(format!(
        "{}: {moved} buffer views compressed with {} were decompressed; the output stores them uncompressed",
        path.display(),
        names.into_iter().collect::<Vec<_>>().join(" and ")
    ))
}

/// Fallback buffers (no data of their own) that no buffer view uses any more: the last ones
/// are removed (no index changes); one followed by a buffer that stays is given its bytes
/// as a `data:` URI, so that every buffer of the output has data. Every fallback buffer
/// left loses the extension.
fn drop_unused_fallbacks(json: &mut Value, source_buffers: &[Vec<u8>]) {
    let used: std::collections::BTreeSet<usize> = json["bufferViews"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|view| uint(view, "buffer"))
        .collect();
    let Some(buffers) = json["buffers"].as_array_mut() else { return };
    let unused_fallback =
        |index: usize, buffer: &Value| index > 0 && !used.contains(&index) && is_fallback(buffer);
    while buffers.len() > 1 && unused_fallback(buffers.len() - 1, &buffers[buffers.len() - 1]) {
        buffers.pop();
    }
    for (index, buffer) in buffers.iter_mut().enumerate() {
        if !is_fallback(buffer) {
            continue;
        }
        // Buffer 0 is written by the pass-through itself (BIN chunk or `NAME.bin`).
        if index > 0 && buffer.get("uri").is_none() {
            let bytes = source_buffers.get(index).map_or(&[][..], Vec::as_slice);
            buffer["uri"] =
                json!(format!("data:application/octet-stream;base64,{}", base64::encode(bytes)));
        }
        remove_extension(buffer);
    }
}

/// Removes EXT_meshopt_compression from an object's `extensions` (and `extensions` when it
/// is left empty).
fn remove_extension(item: &mut Value) {
    let Some(object) = item.as_object_mut() else { return };
    let empty = object
        .get_mut("extensions")
        .and_then(Value::as_object_mut)
        .map(|extensions| {
            MESHOPT.iter().for_each(|name| {
                extensions.remove(*name);
            });
            extensions.is_empty()
        })
        .unwrap_or(false);
    if empty {
        object.remove("extensions");
    }
}
