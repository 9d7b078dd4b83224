//! The checks of an accessor before a byte of it is read (type, count, extent in its buffer
//! view, sparse indices), and the reading of a vertex attribute: one finite element per
//! vertex.

use bytes::Bytes;
use glam::{Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};

use super::Reader;
use super::primitive::Vertices;
use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::{BadAccessor, GltfKind};

/// The bytes an accessor without a buffer view (zeros, plus sparse values) may take when the
/// file's buffers hold fewer: small all-zero accessors need no buffer at all.
const ZEROS_FLOOR: u64 = 1 << 20;

/// Whether a vertex attribute's element is finite (no NaN, no infinity).
pub(super) trait Finite {
    fn finite(&self) -> bool;
}

impl Finite for Vec2 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl Finite for Vec3 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl Finite for Vec4 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl Reader<'_> {
    /// Checks an accessor's type and that every element lies inside its buffer view.
    pub(super) fn check_accessor(
        &self,
        accessor: &gltf::Accessor<'_>,
        dimensions: Dimensions,
        types: &[DataType],
        attribute: &str,
    ) -> Result<(), IoError> {
        let check = AccessorCheck { reader: self, accessor, attribute };
        // Type, count at least 1 and within the limits.
        check.layout(dimensions, types)?;
        // The elements inside their buffer view (or the zeros within what the file can hold).
        let count = accessor.count() as u64;
        let element = accessor.size() as u64;
        match accessor.view() {
            Some(view) => check.extent(view, accessor.offset() as u64, count, element)?,
            None => check.zeros(count, element)?,
        }
        // The sparse indices and values inside theirs.
        if let Some(sparse) = accessor.sparse() {
            check.sparse(&sparse, count, element)?;
        }
        Ok(())
    }

    /// A vertex attribute's checks: [`Self::check_accessor`] for its `(dimensions, types)`,
    /// its sparse indices, and as many elements as POSITION's `vertex_count`.
    pub(super) fn check_attribute(
        &self,
        accessor: &gltf::Accessor<'_>,
        (dimensions, types): (Dimensions, &[DataType]),
        name: &str,
        buffers: &[Bytes],
        vertex_count: usize,
    ) -> Result<(), IoError> {
        self.check_accessor(accessor, dimensions, types, name)?;
        self.check_sparse_indices(accessor, buffers)?;
        if accessor.count() != vertex_count {
            return Err(IoError::gltf_data(
                self.path.to_path_buf(),
                GltfKind::Accessor {
                    accessor: accessor.index(),
                    kind: Box::new(BadAccessor::CountMismatch {
                        attribute: name.to_owned(),
                        count: accessor.count(),
                        vertex_count,
                    }),
                },
            ));
        }
        Ok(())
    }

    /// A sparse accessor's indices must be below its count and strictly increasing (glTF 2.0
    /// spec, "Sparse Accessors"): gltf's reader skips the others silently, loading wrong
    /// values. The caller has checked with [`Self::check_accessor`] that they lie inside
    /// their view.
    pub(super) fn check_sparse_indices(
        &self,
        accessor: &gltf::Accessor<'_>,
        buffers: &[Bytes],
    ) -> Result<(), IoError> {
        let Some(sparse) = accessor.sparse() else { return Ok(()) };
        let error = |kind: BadAccessor| {
            IoError::gltf_data(
                self.path.to_path_buf(),
                GltfKind::Accessor { accessor: accessor.index(), kind: Box::new(kind) },
            )
        };
        let indices = sparse.indices();
        let view = indices.view();
        let size = indices.index_type().size();
        let stride = view.stride().unwrap_or(size);
        let bytes = buffers.get(view.buffer().index()).map_or(&[][..], |d| &d[..]);
        let mut previous: Option<u32> = None;
        for k in 0..sparse.count() {
            // Saturating: a view in a buffer without data is not checked against it.
            let at = view.offset().saturating_add(indices.offset()).saturating_add(k * stride);
            let index = match bytes.get(at..at.saturating_add(size)) {
                Some(&[a]) => u32::from(a),
                Some(&[a, b]) => u32::from(u16::from_le_bytes([a, b])),
                Some(&[a, b, c, d]) => u32::from_le_bytes([a, b, c, d]),
                _ => return Err(error(BadAccessor::SparseIndexOutside { element: k })),
            };
            if index as usize >= accessor.count() {
                return Err(error(BadAccessor::SparseIndexOutOfRange {
                    index,
                    element: k,
                    count: accessor.count(),
                }));
            }
            if let Some(before) = previous.filter(|&before| index <= before) {
                return Err(error(BadAccessor::SparseNotIncreasing { element: k, index, before }));
            }
            previous = Some(index);
        }
        Ok(())
    }
}

impl Reader<'_> {
    /// The error for an accessor that gave fewer elements than its count.
    pub(super) fn short(&self, accessor: &gltf::Accessor<'_>, got: usize) -> IoError {
        IoError::gltf_data(
            self.path.to_path_buf(),
            GltfKind::Accessor {
                accessor: accessor.index(),
                kind: Box::new(BadAccessor::ShortRead { expected: accessor.count(), read: got }),
            },
        )
    }

    /// A primitive's attribute `semantic`, read by `read` (zeros when its accessor has
    /// neither a view nor sparse data), checked to hold one finite element per vertex;
    /// `None` when the primitive has no such attribute or `read` gives nothing.
    pub(super) fn vertex_attribute<T: Clone + Default + Finite>(
        &self,
        vertices: &Vertices<'_, '_>,
        semantic: gltf::Semantic,
        attribute: &'static str,
        read: impl FnOnce(&gltf::Accessor<'_>) -> Option<Vec<T>>,
    ) -> Result<Option<Vec<T>>, IoError> {
        let Some(accessor) = vertices.primitive.get(&semantic) else { return Ok(None) };
        let values = super::lenient::zeros_without_view(Some(&accessor), read(&accessor));
        let Some(values) = values else { return Ok(None) };
        if values.len() != vertices.count {
            return Err(self.short(&accessor, values.len()));
        }
        if let Some(element) = values.iter().position(|v| !v.finite()) {
            return Err(IoError::gltf_data(
                self.path.to_path_buf(),
                GltfKind::AccessorNotFinite { accessor: accessor.index(), attribute, element },
            ));
        }
        Ok(Some(values))
    }
}

/// One accessor being checked by [`Reader::check_accessor`], with what its errors name.
struct AccessorCheck<'a, 'r, 'd> {
    reader: &'a Reader<'r>,
    accessor: &'a gltf::Accessor<'d>,
    attribute: &'a str,
}

impl AccessorCheck<'_, '_, '_> {
    fn accessor_error(&self, kind: BadAccessor) -> IoError {
        IoError::gltf_data(
            self.reader.path.to_path_buf(),
            GltfKind::Accessor { accessor: self.accessor.index(), kind: Box::new(kind) },
        )
    }

    /// The accessor's type is one of `(dimensions, types)`; its count is at least 1 and
    /// within [`seamlit_asset::LoadOptions::max_elements`].
    fn layout(&self, dimensions: Dimensions, types: &[DataType]) -> Result<(), IoError> {
        let (accessor, attribute) = (self.accessor, self.attribute);
        if accessor.dimensions() != dimensions || !types.contains(&accessor.data_type()) {
            return Err(self.accessor_error(BadAccessor::WrongType {
                attribute: attribute.to_owned(),
                expected: format!("{dimensions:?} of {types:?}"),
                found: format!("{:?} of {:?}", accessor.dimensions(), accessor.data_type()),
            }));
        }
        let count = accessor.count() as u64;
        // glTF requires count >= 1; gltf 1.4.1's reader computes `count - 1` unchecked (found
        // by the `gltf` fuzz target: regression input `gltf_index_accessor_count_0.gltf`).
        if count == 0 {
            return Err(
                self.accessor_error(BadAccessor::ZeroCount { attribute: attribute.to_owned() })
            );
        }
        if count > self.reader.options.max_elements as u64 {
            return Err(IoError::TooManyElements {
                path: self.reader.path.to_path_buf(),
                what: format!("accessor {} ({attribute})", accessor.index()),
                limit: self.reader.options.max_elements,
                actual: accessor.count(),
            });
        }
        Ok(())
    }

    /// `count` elements of `element` bytes from `offset` lie inside `view`.
    fn extent(
        &self,
        view: gltf::buffer::View<'_>,
        offset: u64,
        count: u64,
        element: u64,
    ) -> Result<(), IoError> {
        if let Some(stride) = view.stride().filter(|&s| (s as u64) < element) {
            return Err(self.accessor_error(BadAccessor::StrideBelowElement {
                view: view.index(),
                stride,
                element,
            }));
        }
        let stride = view.stride().map_or(element, |s| s as u64);
        // Saturating: offsets and strides come from the file and may be near u64::MAX.
        let needed = if count == 0 {
            0
        } else {
            offset.saturating_add(stride.saturating_mul(count - 1)).saturating_add(element)
        };
        if needed > view.length() as u64 {
            return Err(IoError::gltf_data(
                self.reader.path.to_path_buf(),
                GltfKind::AccessorOutOfRange {
                    accessor: self.accessor.index(),
                    view: view.index(),
                    needed,
                    available: view.length() as u64,
                },
            ));
        }
        Ok(())
    }

    /// An accessor without a view is zeros (plus its sparse values): its count costs memory
    /// that the file does not hold, so it may not exceed the file's bytes.
    fn zeros(&self, count: u64, element: u64) -> Result<(), IoError> {
        if count.saturating_mul(element) > self.reader.buffer_bytes.max(ZEROS_FLOOR) {
            return Err(self.accessor_error(BadAccessor::ZerosTooLarge {
                attribute: self.attribute.to_owned(),
                count,
                element,
                buffer_bytes: self.reader.buffer_bytes,
            }));
        }
        Ok(())
    }

    /// The sparse count is 1 to `count`, and its indices and values lie inside their views.
    fn sparse(
        &self,
        sparse: &gltf::accessor::sparse::Sparse<'_>,
        count: u64,
        element: u64,
    ) -> Result<(), IoError> {
        let n = sparse.count() as u64;
        // glTF requires sparse.count >= 1; gltf 1.4.1's reader computes `count - 1`
        // unchecked (tests/sparse.rs).
        if n == 0 {
            return Err(self.accessor_error(BadAccessor::ZeroSparseCount {
                attribute: self.attribute.to_owned(),
            }));
        }
        if n > count {
            return Err(self.accessor_error(BadAccessor::SparseCountExceeds { sparse: n, count }));
        }
        let indices = sparse.indices();
        self.extent(
            indices.view(),
            indices.offset() as u64,
            n,
            indices.index_type().size() as u64,
        )?;
        let values = sparse.values();
        self.extent(values.view(), values.offset() as u64, n, element)
    }
}
