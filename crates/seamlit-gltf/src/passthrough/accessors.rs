//! Reading an input accessor's elements for the pass-through writer, which duplicates them
//! for split vertices: each element's bytes as stored, from its buffer view or zeros, with
//! the sparse values substituted; every offset checked against the view and the buffer.

use serde_json::Value;

use crate::json::{
    BYTE, FLOAT, SHORT, UNSIGNED_BYTE, UNSIGNED_INT, UNSIGNED_SHORT, integer, shape, usize_member,
};
use crate::source::Source;
use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::{BadAccessor, GltfKind};

/// An accessor's elements, densely packed (sparse substitution applied).
pub(super) struct Elements {
    /// The elements' bytes, one after the other.
    pub(super) bytes: Vec<u8>,
    /// Bytes per element, as stored (matrix columns padded to 4 bytes).
    pub(super) size: usize,
}

/// Reads accessor `index` of the source, which must have `expected` elements: every
/// element's bytes, from its buffer view (or zeros) with the sparse values substituted.
pub(super) fn read_elements(
    source: &Source,
    index: usize,
    expected: usize,
) -> Result<Elements, IoError> {
    let accessor = &source.json["accessors"][index];
    let at = AccessorAt { source, index };
    // Bytes per element, from componentType and type.
    let size = at.element_size(accessor)?;
    let count =
        usize_member(accessor, "count").ok_or_else(|| at.accessor_error(BadAccessor::NoCount))?;
    if count != expected {
        return Err(at.accessor_error(BadAccessor::PrimitiveCount { count, vertices: expected }));
    }
    // The dense elements: from the buffer view, or zeros.
    let mut bytes = vec![0u8; count * size];
    if let Some(view) = usize_member(accessor, "bufferView") {
        at.copy_dense(accessor, view, size, &mut bytes)?;
    }
    // The sparse values over them.
    if let Some(sparse) = accessor.get("sparse") {
        at.substitute_sparse(sparse, size, &mut bytes)?;
    }
    Ok(Elements { bytes, size })
}

/// Accessor `index` of `source`, being read by [`read_elements`].
struct AccessorAt<'a> {
    source: &'a Source,
    index: usize,
}

impl AccessorAt<'_> {
    fn accessor_error(&self, kind: BadAccessor) -> IoError {
        IoError::gltf_data(
            self.source.path.clone(),
            GltfKind::Accessor { accessor: self.index, kind: Box::new(kind) },
        )
    }

    /// Bytes per element as stored (matrix columns padded to 4 bytes).
    fn element_size(&self, accessor: &Value) -> Result<usize, IoError> {
        let component: usize = match integer(&accessor["componentType"]) {
            Some(BYTE | UNSIGNED_BYTE) => 1,
            Some(SHORT | UNSIGNED_SHORT) => 2,
            Some(UNSIGNED_INT | FLOAT) => 4,
            found => return Err(self.accessor_error(BadAccessor::UnknownComponentType { found })),
        };
        let Some((columns, rows)) = accessor["type"].as_str().and_then(shape) else {
            let found = accessor["type"].as_str().map(str::to_owned);
            return Err(self.accessor_error(BadAccessor::UnknownType { found }));
        };
        Ok(if columns == 1 {
            rows * component
        } else {
            columns * (rows * component).next_multiple_of(4)
        })
    }

    /// Copies the elements of buffer view `view` into `bytes` (`size` bytes each).
    fn copy_dense(
        &self,
        accessor: &Value,
        view: usize,
        size: usize,
        bytes: &mut [u8],
    ) -> Result<(), IoError> {
        let count = bytes.len() / size;
        let (data, stride) = view_bytes(self.source, self.index, view, size)?;
        let offset = usize_member(accessor, "byteOffset").unwrap_or(0);
        // Saturating: offsets and strides come from the file.
        let needed = match count {
            0 => 0,
            _ => offset.saturating_add(stride.saturating_mul(count - 1)).saturating_add(size),
        };
        if needed > data.len() {
            return Err(IoError::gltf_data(
                self.source.path.clone(),
                GltfKind::AccessorOutOfRange {
                    accessor: self.index,
                    view,
                    needed: needed as u64,
                    available: data.len() as u64,
                },
            ));
        }
        for (k, element) in bytes.chunks_exact_mut(size).enumerate() {
            let at = offset + k * stride;
            element.copy_from_slice(&data[at..at + size]);
        }
        Ok(())
    }

    /// Writes the accessor's sparse values over `bytes` (`size` bytes an element).
    fn substitute_sparse(
        &self,
        sparse: &Value,
        size: usize,
        bytes: &mut [u8],
    ) -> Result<(), IoError> {
        let count = bytes.len() / size;
        let n = usize_member(sparse, "count")
            .ok_or_else(|| self.accessor_error(BadAccessor::SparseWithoutCount))?;
        let indices = &sparse["indices"];
        let index_size = match integer(&indices["componentType"]) {
            Some(UNSIGNED_BYTE) => 1,
            Some(UNSIGNED_SHORT) => 2,
            Some(UNSIGNED_INT) => 4,
            found => return Err(self.accessor_error(BadAccessor::SparseIndexType { found })),
        };
        let sparse_indices = self.sparse_part(indices, n, index_size)?;
        let values = self.sparse_part(&sparse["values"], n, size)?;
        for (k, value) in values.chunks_exact(size).enumerate() {
            let at = &sparse_indices[k * index_size..(k + 1) * index_size];
            let mut word = [0u8; 4];
            word[..index_size].copy_from_slice(at);
            let target = u32::from_le_bytes(word) as usize;
            if target >= count {
                return Err(
                    self.accessor_error(BadAccessor::SparseIndexPast { index: target, count })
                );
            }
            bytes[target * size..(target + 1) * size].copy_from_slice(value);
        }
        Ok(())
    }

    /// The bytes of a sparse part (`indices` or `values`): `n` elements of `element` bytes.
    fn sparse_part<'s>(
        &'s self,
        part: &Value,
        n: usize,
        element: usize,
    ) -> Result<&'s [u8], IoError> {
        let view = usize_member(part, "bufferView")
            .ok_or_else(|| self.accessor_error(BadAccessor::SparseWithoutView))?;
        let (data, _) = view_bytes(self.source, self.index, view, element)?;
        let offset = usize_member(part, "byteOffset").unwrap_or(0);
        let needed = offset.saturating_add(n.saturating_mul(element));
        data.get(offset..needed).ok_or_else(|| {
            IoError::gltf_data(
                self.source.path.clone(),
                GltfKind::AccessorOutOfRange {
                    accessor: self.index,
                    view,
                    needed: needed as u64,
                    available: data.len() as u64,
                },
            )
        })
    }
}

/// A buffer view's bytes and its stride (`element` when it declares none).
fn view_bytes(
    source: &Source,
    accessor: usize,
    index: usize,
    element: usize,
) -> Result<(&[u8], usize), IoError> {
    let view = &source.json["bufferViews"][index];
    let buffer = usize_member(view, "buffer").filter(|&b| b < source.buffers.count());
    let offset = usize_member(view, "byteOffset").unwrap_or(0);
    let length = usize_member(view, "byteLength").unwrap_or(0);
    let data = buffer.and_then(|b| source.buffers.get(b, offset..offset.checked_add(length)?));
    // Never a view whose bytes the load gave back: no accessor read here is replaced.
    debug_assert!(
        data.is_some()
            || buffer.is_none_or(|b| offset.saturating_add(length) > source.buffers.len(b)),
        "buffer view {index}'s bytes were given back at load"
    );
    let Some(data) = data else {
        return Err(IoError::gltf_data(
            source.path.clone(),
            GltfKind::AccessorOutOfRange {
                accessor,
                view: index,
                needed: offset.saturating_add(length) as u64,
                available: buffer.map_or(0, |b| source.buffers.len(b)) as u64,
            },
        ));
    };
    Ok((data, usize_member(view, "byteStride").unwrap_or(element)))
}
