//! The seam report: how well the attributes of a model agree across object boundaries.
//!
//! The numbers that matter are measured over *smooth cross-object edges*: edges (pairs of
//! welded positions) shared by faces of two different objects that meet at less than the
//! crease angle. At both ends of such an edge, the two faces' corners should carry the same
//! normal (and, for faces of equal handedness, the same tangent). Any angle between them is a
//! visible seam. Cross-object edges sharper than the crease are counted apart: they are hard
//! edges that should stay hard (a box built of one object per wall).

use serde::{Deserialize, Serialize};

/// Options of [`crate::report()`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ReportOptions {
    /// How close two positions must be to count as one.
    pub weld_tolerance: crate::WeldTolerance,
    /// Edges whose faces meet at more than this angle (degrees) are hard edges.
    pub crease_angle_deg: f32,
}

impl Default for ReportOptions {
    fn default() -> Self {
        let d = crate::FixOptions::DEFAULT;
        Self { weld_tolerance: d.weld_tolerance, crease_angle_deg: d.crease_angle_deg }
    }
}

impl From<&crate::FixOptions> for ReportOptions {
    fn from(o: &crate::FixOptions) -> Self {
        Self { weld_tolerance: o.weld_tolerance, crease_angle_deg: o.crease_angle_deg }
    }
}

/// Agreement of attributes across object boundaries. Angles are in degrees; a field is `None`
/// when there was nothing to measure (no normals, no tangents, or no smooth cross-object edge).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CrossObject {
    /// Edges shared by faces of two different objects.
    pub edges: usize,
    /// Of those, edges whose faces meet at more than the crease angle.
    pub hard_edges: usize,
    /// Corner pairs compared (two per smooth cross-object edge and face pair).
    pub corner_pairs: usize,
    /// Largest angle between the normals of coincident corners across a smooth edge.
    pub max_normal_angle_deg: Option<f32>,
    /// Mean of those angles.
    pub mean_normal_angle_deg: Option<f32>,
    /// Corner pairs across smooth edges whose normals differ by more than 1 degree.
    pub normal_breaks: usize,
    /// Largest angle between tangents of coincident corners of equal handedness.
    pub max_tangent_angle_deg: Option<f32>,
    /// Mean of those angles.
    pub mean_tangent_angle_deg: Option<f32>,
    /// Smallest angle between the two sides' normals at a hard edge: near 0 means the hard
    /// edge was smoothed away.
    pub min_hard_edge_normal_angle_deg: Option<f32>,
}

/// The seam report of one model (as loaded, or after a fix).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SeamReport {
    /// Number of objects.
    pub objects: usize,
    /// Number of triangles over all objects.
    pub triangles: usize,
    /// Number of vertices over all objects.
    pub vertices: usize,
    /// Distinct positions after welding.
    pub welded_positions: usize,
    /// The absolute weld tolerance used (model units; 0 = exact bits).
    pub weld_tolerance: f32,
    /// Welded positions used by vertices of two or more objects.
    pub shared_positions: usize,
    /// Welded positions whose vertices are within the tolerance but not bit-equal.
    pub near_miss_positions: usize,
    /// Triangles with (near) zero area.
    pub degenerate_triangles: usize,
    /// Triangles whose UVs span (near) zero area, so that no tangent follows from them.
    pub degenerate_uv_triangles: usize,
    /// Triangles whose UV mapping is mirrored (negative handedness).
    pub mirrored_triangles: usize,
    /// Agreement across object boundaries.
    pub cross_object: CrossObject,
    /// Largest |dot(N, T)| over all vertices with tangents (0 for an orthogonal frame).
    pub max_abs_dot_nt: Option<f32>,
    /// Largest ||N| - 1| over all vertices with normals.
    pub max_normal_length_error: Option<f32>,
    /// Largest ||T.xyz| - 1| over all vertices with tangents.
    pub max_tangent_length_error: Option<f32>,
    /// Vertices whose tangent w is neither +1 nor -1.
    pub bad_handedness: usize,
}

/// Measures a model.
///
/// # Errors
/// Bad input.
pub fn report(model: &crate::Model, options: &ReportOptions) -> Result<SeamReport, crate::MeshError> {
    let _ = (model, options);
    todo!()
}
