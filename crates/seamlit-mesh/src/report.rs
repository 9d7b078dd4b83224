//! The seam report: how well the attributes of a model agree across object boundaries.
//!
//! The numbers that matter are measured over *smooth cross-object edges*: edges (pairs of
//! welded positions) shared by faces of two different objects that meet at less than the
//! crease angle. At both ends of such an edge, the two faces' corners should carry the same
//! normal (and, for faces of equal handedness, the same tangent). Any angle between them is a
//! visible seam. Cross-object edges sharper than the crease are counted apart: they are hard
//! edges that should stay hard (a box built of one object per wall).

use glam::{Vec3, Vec4, Vec4Swizzles};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::face::{DEGENERATE, DEGENERATE_UV, MIRRORED};
use crate::frame::Linear;
use crate::group::Incidence;
use crate::{MeshError, Model, validate, weld};

/// Options of [`crate::report()`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ReportOptions {
    /// How close two positions must be to count as one.
    pub weld_tolerance: crate::WeldTolerance,
    /// Edges whose faces meet at more than this angle (degrees) are hard edges.
    pub crease_angle_deg: f32,
    /// Tangents are compared across an edge only where the two faces' own tangents are within
    /// this angle (degrees) and of equal handedness: elsewhere they differ by design.
    pub tangent_angle_deg: f32,
}

impl Default for ReportOptions {
    fn default() -> Self {
        let d = crate::FixOptions::DEFAULT;
        Self::from(&d)
    }
}

impl From<&crate::FixOptions> for ReportOptions {
    fn from(o: &crate::FixOptions) -> Self {
        Self {
            weld_tolerance: o.weld_tolerance,
            crease_angle_deg: o.crease_angle_deg,
            tangent_angle_deg: o.tangent_angle_deg,
        }
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
    /// Triangles of non-zero area whose UVs span (near) zero area, so that no tangent follows
    /// from them.
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

/// Measures a model as it is: welds it, counts shared and near-miss positions, degenerate and
/// mirrored triangles, and compares the normals and tangents the model carries (input or
/// computed) across every cross-object edge. Objects without normals (or tangents) are left
/// out of the normal (or tangent) comparisons.
///
/// # Errors
///
/// The input checks of [`crate::fix`] (indices, lengths, transforms, finite positions).
pub fn report(model: &Model, options: &ReportOptions) -> Result<SeamReport, MeshError> {
    let mut flat = validate::flatten(model)?;
    let tolerance = options.weld_tolerance.absolute(crate::fix::diagonal(&flat));
    let weld = weld::weld(&flat.positions, tolerance);
    let near_miss_positions = weld.near_misses(&flat.positions);
    weld.snap(&mut flat.positions);
    let faces = crate::face::faces(&flat, model.v_axis);
    let vertex_objects = flat.vertex_objects();

    let mut first_object = vec![u32::MAX; weld.count];
    let mut shared = vec![false; weld.count];
    for (&id, &o) in weld.ids.iter().zip(&vertex_objects) {
        let f = &mut first_object[id as usize];
        if *f == u32::MAX {
            *f = o;
        } else if *f != o {
            shared[id as usize] = true;
        }
    }

    // Per vertex, the model's own frame in model space (zero where it has none).
    let (normals, tangents) = model_space_frames(model, &flat);

    let mut report = SeamReport {
        objects: model.objects.len(),
        triangles: flat.triangles.len(),
        vertices: flat.positions.len(),
        welded_positions: weld.count,
        weld_tolerance: tolerance,
        shared_positions: shared.iter().filter(|&&s| s).count(),
        near_miss_positions,
        degenerate_triangles: faces.iter().filter(|f| f.is(DEGENERATE)).count(),
        degenerate_uv_triangles: faces
            .iter()
            .filter(|f| f.is(DEGENERATE_UV) && !f.is(crate::face::NO_UV | DEGENERATE))
            .count(),
        mirrored_triangles: faces.iter().filter(|f| f.is(MIRRORED)).count(),
        ..SeamReport::default()
    };
    frame_quality(model, &mut report);

    let corner_positions: Vec<u32> =
        flat.triangles.iter().flat_map(|t| t.map(|v| weld.ids[v as usize])).collect();
    let incidence = Incidence::new(&corner_positions, weld.count);
    let triangle_objects = flat.triangle_objects();
    let crease_cos = options.crease_angle_deg.clamp(0.0, 180.0).to_radians().cos();
    let tangent_cos = options.tangent_angle_deg.clamp(0.0, 180.0).to_radians().cos();
    let stats = (0..weld.count)
        .into_par_iter()
        .filter(|&p| shared[p])
        .fold(Stats::default, |mut s, p| {
            let corners = incidence.at(p);
            for (i, &ca) in corners.iter().enumerate() {
                let fa = ca as usize / 3;
                for &cb in &corners[i + 1..] {
                    let fb = cb as usize / 3;
                    if triangle_objects[fa] == triangle_objects[fb] {
                        continue;
                    }
                    let (a, b) = (&faces[fa], &faces[fb]);
                    if a.is(DEGENERATE) || b.is(DEGENERATE) {
                        continue;
                    }
                    let pa = &corner_positions[fa * 3..fa * 3 + 3];
                    let pb = &corner_positions[fb * 3..fb * 3 + 3];
                    let Some(&q) = pa.iter().find(|&&q| q as usize != p && pb.contains(&q)) else {
                        continue;
                    };
                    let va = flat.triangles[fa][ca as usize % 3] as usize;
                    let vb = flat.triangles[fb][cb as usize % 3] as usize;
                    let (na, nb) = (normals[va], normals[vb]);
                    let hard = a.normal.dot(b.normal) < crease_cos;
                    if (p as u32) < q {
                        s.edges += 1;
                        s.hard_edges += usize::from(hard);
                    }
                    if na == Vec3::ZERO || nb == Vec3::ZERO {
                        continue;
                    }
                    let normal_angle = angle_deg(na, nb);
                    if hard {
                        s.min_hard =
                            Some(s.min_hard.map_or(normal_angle, |m: f32| m.min(normal_angle)));
                        continue;
                    }
                    s.pairs += 1;
                    s.normal.add(normal_angle);
                    s.normal_breaks += usize::from(normal_angle > 1.0);
                    let (ta, tb) = (tangents[va], tangents[vb]);
                    let comparable = ta != Vec4::ZERO
                        && tb != Vec4::ZERO
                        && !a.is(DEGENERATE_UV)
                        && !b.is(DEGENERATE_UV)
                        && a.sign() == b.sign()
                        && a.tangent.dot(b.tangent) >= tangent_cos;
                    if comparable {
                        s.tangent.add(angle_deg(ta.xyz(), tb.xyz()));
                    }
                }
            }
            s
        })
        .reduce(Stats::default, Stats::merge);

    report.cross_object = CrossObject {
        edges: stats.edges,
        hard_edges: stats.hard_edges,
        corner_pairs: stats.pairs,
        max_normal_angle_deg: stats.normal.max(),
        mean_normal_angle_deg: stats.normal.mean(),
        normal_breaks: stats.normal_breaks,
        max_tangent_angle_deg: stats.tangent.max(),
        mean_tangent_angle_deg: stats.tangent.mean(),
        min_hard_edge_normal_angle_deg: stats.min_hard,
    };
    Ok(report)
}

/// Angle between two directions, degrees (0 for bit-equal ones).
fn angle_deg(a: Vec3, b: Vec3) -> f32 {
    let (a, b) = (a.normalize_or_zero(), b.normalize_or_zero());
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

#[derive(Clone, Copy, Default)]
struct Running {
    count: usize,
    sum: f64,
    max: f32,
}

impl Running {
    fn add(&mut self, x: f32) {
        self.count += 1;
        self.sum += f64::from(x);
        self.max = self.max.max(x);
    }
    fn merge(self, o: Self) -> Self {
        Self { count: self.count + o.count, sum: self.sum + o.sum, max: self.max.max(o.max) }
    }
    fn max(&self) -> Option<f32> {
        (self.count > 0).then_some(self.max)
    }
    fn mean(&self) -> Option<f32> {
        (self.count > 0).then(|| (self.sum / self.count as f64) as f32)
    }
}

#[derive(Clone, Copy, Default)]
struct Stats {
    edges: usize,
    hard_edges: usize,
    pairs: usize,
    normal_breaks: usize,
    normal: Running,
    tangent: Running,
    min_hard: Option<f32>,
}

impl Stats {
    fn merge(self, o: Self) -> Self {
        Self {
            edges: self.edges + o.edges,
            hard_edges: self.hard_edges + o.hard_edges,
            pairs: self.pairs + o.pairs,
            normal_breaks: self.normal_breaks + o.normal_breaks,
            normal: self.normal.merge(o.normal),
            tangent: self.tangent.merge(o.tangent),
            min_hard: match (self.min_hard, o.min_hard) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            },
        }
    }
}

/// Per vertex, its normal and tangent in model space; zero where the object has none (or the
/// stored value is not finite).
fn model_space_frames(model: &Model, flat: &validate::Flat) -> (Vec<Vec3>, Vec<Vec4>) {
    let mut normals = vec![Vec3::ZERO; flat.positions.len()];
    let mut tangents = vec![Vec4::ZERO; flat.positions.len()];
    for (o, object) in model.objects.iter().enumerate() {
        let start = flat.vertex_start[o] as usize;
        let linear = flat.linear[o].map(Linear::new);
        let Some(ns) = &object.normals else { continue };
        for (i, &n) in ns.iter().enumerate() {
            let t = object.tangents.as_ref().map_or(Vec4::ZERO, |ts| ts[i]);
            if !n.is_finite() || n == Vec3::ZERO {
                continue;
            }
            let t_ok = t.is_finite() && t.xyz() != Vec3::ZERO;
            let (nm, tm) = match (&linear, t_ok) {
                (Some(l), true) => l.frame_to_model(n, t),
                (Some(l), false) => (l.normal_to_model(n), Vec4::ZERO),
                (None, true) => (n, t),
                (None, false) => (n, Vec4::ZERO),
            };
            normals[start + i] = nm;
            tangents[start + i] = tm;
        }
    }
    (normals, tangents)
}

/// Orthogonality, unit length and handedness of the stored frames (in each object's space).
fn frame_quality(model: &Model, report: &mut SeamReport) {
    let mut dot_nt: Option<f32> = None;
    let mut n_err: Option<f32> = None;
    let mut t_err: Option<f32> = None;
    let mut bad = 0;
    let max = |acc: &mut Option<f32>, x: f32| *acc = Some(acc.map_or(x, |m| m.max(x)));
    for object in &model.objects {
        let Some(ns) = &object.normals else { continue };
        for (i, &n) in ns.iter().enumerate() {
            max(&mut n_err, (n.length() - 1.0).abs());
            if let Some(t) = object.tangents.as_ref().map(|ts| ts[i]) {
                max(&mut dot_nt, n.dot(t.xyz()).abs());
                max(&mut t_err, (t.xyz().length() - 1.0).abs());
                bad += usize::from(t.w != 1.0 && t.w != -1.0);
            }
        }
    }
    report.max_abs_dot_nt = dot_nt;
    report.max_normal_length_error = n_err;
    report.max_tangent_length_error = t_err;
    report.bad_handedness = bad;
}
