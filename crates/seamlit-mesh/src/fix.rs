//! The fix pipeline.
use crate::{FixOptions, MeshError, Model};
/// Computes seam-free normals and tangents.
///
/// # Errors
/// Bad input.
pub fn fix(model: &Model, options: &FixOptions) -> Result<Model, MeshError> {
    let _ = (model, options);
    todo!()
}
