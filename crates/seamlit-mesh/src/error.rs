//! The error type of this crate.

use thiserror::Error;

/// What can go wrong when a model is processed. Every variant names the object (by index and
/// name) and the element at fault.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum MeshError {
    /// A position (after the object's transform) is NaN or infinite.
    #[error("object {object} ({name:?}): vertex {vertex} has a non-finite position {value:?}")]
    NonFinitePosition {
        /// Index of the object in the model.
        object: usize,
        /// The object's name.
        name: String,
        /// Index of the vertex in the object.
        vertex: usize,
        /// The offending position (after the transform).
        value: [f32; 3],
    },
    /// A UV is NaN or infinite.
    #[error(
        "object {object} ({name:?}): vertex {vertex} has a non-finite texture coordinate {value:?}"
    )]
    NonFiniteUv {
        /// Index of the object in the model.
        object: usize,
        /// The object's name.
        name: String,
        /// Index of the vertex in the object.
        vertex: usize,
        /// The offending UV.
        value: [f32; 2],
    },
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "object {object} ({name:?}): triangle {triangle} refers to vertex {index}, but the object has {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Index of the object in the model.
        object: usize,
        /// The object's name.
        name: String,
        /// Index of the triangle in the object.
        triangle: usize,
        /// The out-of-range vertex index.
        index: u32,
        /// How many vertices the object has.
        vertex_count: usize,
    },
    /// [`crate::Object::split_from`] is longer than the vertex list or names a vertex that
    /// is not an input vertex.
    #[error(
        "object {object} ({name:?}): split_from entry {entry} is {value}, but the object has {input_vertices} input vertices"
    )]
    BadSplitFrom {
        /// Index of the object in the model.
        object: usize,
        /// The object's name.
        name: String,
        /// Index of the entry in `split_from` (`usize::MAX` when the list itself is too long).
        entry: usize,
        /// The entry's value.
        value: u32,
        /// How many input vertices the object has (`positions.len() - split_from.len()`).
        input_vertices: usize,
    },
    /// A per-vertex array has a different length from `positions`.
    #[error("object {object} ({name:?}): {attribute} has {actual} entries, expected {expected}")]
    AttributeLength {
        /// Index of the object in the model.
        object: usize,
        /// The object's name.
        name: String,
        /// Which attribute (`"uvs"`, `"uvs1"`, `"normals"`, `"tangents"`, `"colors"`).
        attribute: &'static str,
        /// `positions.len()`.
        expected: usize,
        /// The attribute's length.
        actual: usize,
    },
    /// [`crate::Object::smoothing_groups`] does not have one entry per triangle.
    #[error(
        "object {object} ({name:?}): smoothing_groups has {actual} entries, expected one per triangle ({expected})"
    )]
    SmoothingGroupsLength {
        /// Index of the object in the model.
        object: usize,
        /// The object's name.
        name: String,
        /// `triangles.len()`.
        expected: usize,
        /// The length of `smoothing_groups`.
        actual: usize,
    },
    /// The object's transform is not finite or not invertible.
    #[error("object {object} ({name:?}): its transform is not finite or not invertible")]
    BadTransform {
        /// Index of the object in the model.
        object: usize,
        /// The object's name.
        name: String,
    },
    /// The model has more vertices or triangles than 32-bit indices can address, or so many
    /// that the vertices `fix` may add (at most one per triangle corner) would not fit them.
    #[error("the model has {count} {what}, more than {max}")]
    TooLarge {
        /// What was counted (`"vertices"`, `"triangle corners"`, `"vertices plus triangle
        /// corners"`).
        what: &'static str,
        /// How many there are.
        count: usize,
        /// The limit.
        max: usize,
    },
}
