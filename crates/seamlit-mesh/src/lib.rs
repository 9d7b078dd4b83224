//! # seamlit-mesh
//!
//! Seam-free normals and tangents for models made of several objects.
//!
//! Artists deliver one surface as several objects, each with its own copy of the vertices on
//! the shared boundary. Computing normals and tangents object by object breaks per-pixel
//! lighting along those boundaries. This crate welds positions across all objects of a model
//! (with a tolerance), smooths normals and tangents across the weld with a crease angle, splits
//! tangents at mirrored UVs, re-orthogonalises the frame and stores the handedness in
//! `tangent.w`, following P. Mileff, "Per-pixel lighting for multi-object models" (2024),
//! sections 4 and 5, in O(n) rather than the paper's O(V x F).
//!
//! ```
//! use glam::{Vec2, Vec3};
//! use seamlit_mesh::{FixOptions, Model, Object, fix};
//!
//! // Two quads in two objects, sharing the edge x = 1 (each has its own copy of it).
//! let quad = |x0: f32, z: f32| {
//!     Object::new(
//!         format!("quad{x0}"),
//!         vec![
//!             Vec3::new(x0, 0.0, 0.0),
//!             Vec3::new(x0 + 1.0, 0.0, z),
//!             Vec3::new(x0 + 1.0, 1.0, z),
//!             Vec3::new(x0, 1.0, 0.0),
//!         ],
//!         vec![[0, 1, 2], [0, 2, 3]],
//!     )
//!     .with_uvs(vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)])
//! };
//! let model = Model::new(vec![quad(0.0, 0.0), quad(1.0, -0.2)]);
//! let fixed = fix(&model, &FixOptions::default())?;
//! let (a, b) = (&fixed.objects[0], &fixed.objects[1]);
//! // The shared corner (1, 0, 0) has the same normal in both objects.
//! assert_eq!(a.normals.as_ref().unwrap()[1], b.normals.as_ref().unwrap()[0]);
//! # Ok::<(), seamlit_mesh::MeshError>(())
//! ```
#![deny(missing_docs)]

mod changes;
mod error;
mod face;
mod fix;
mod frame;
mod group;
mod index;
mod judge;
mod mikk;
mod model;
mod morph;
mod options;
mod out;
#[cfg(feature = "reference")]
pub mod reference;
mod repair;
mod report;
mod skin;
mod smooth;
mod validate;
mod weld;

pub use changes::{Changes, ObjectChanges, SharedNormals};
pub use error::MeshError;
pub use fix::{fix, fix_in_place, fix_in_place_welded};
pub use model::{Influences, Model, MorphTarget, Object, VAxis};
pub use options::{FixOptions, Mode, NormalPolicy, TangentMethod, Weighting, WeldTolerance};
pub use repair::seam_copies;
pub use report::{
    AsLoaded, CrossObject, ReportOptions, SeamReport, report, report_before_fix, report_fixed,
    report_welded, report_with_weld,
};
pub use skin::{SkinMatch, SkinSeamExample, SkinSeams, match_skin_seams, shared_copies};
pub use weld::Welded;

/// The largest number of vertices (and of triangle corners, and of the two together: `fix`
/// may give an object a new vertex per corner) a model may have: indices are 32-bit.
pub const MAX_ELEMENTS: usize = u32::MAX as usize - 1;
