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

use crate::face::{DEGENERATE, DEGENERATE_UV, Face, add_counts, count, each_face_flags, face};
use crate::frame::Linear;
use crate::skin::{self, SkinSeams};
use crate::weld::Welded;
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
    /// Shared positions whose objects disagree on their skin influences ([`SkinSeams`]).
    #[serde(default)]
    pub skin_seams: SkinSeams,
}

/// Measures a model as it is: welds it, counts shared and near-miss positions, degenerate and
/// mirrored triangles and positions whose objects disagree on skin influences, and compares
/// the normals and tangents the model carries (input or
/// computed) across every cross-object edge. Objects without normals (or tangents) are left
/// out of the normal (or tangent) comparisons.
///
/// # Errors
///
/// The input checks of [`crate::fix`] (indices, lengths, transforms, finite positions).
pub fn report(model: &Model, options: &ReportOptions) -> Result<SeamReport, MeshError> {
    report_welded(model, options, None)
}

/// [`report()`] of a model [`crate::fix_in_place_welded`] fixed, with the weld the fix gave:
/// the same report, bit for bit, without welding the model again. A `welded` of another
/// model (another vertex count) or tolerance is not used: the model is welded as by
/// [`report()`]. The model's positions must be the ones the fix left.
///
/// # Errors
///
/// As [`report()`].
pub fn report_welded(
    model: &Model,
    options: &ReportOptions,
    welded: Option<&Welded>,
) -> Result<SeamReport, MeshError> {
    measure(model, options, welded, None)
}

/// [`report_welded()`] of a model a fix changed, given `as_loaded`, the [`report()`] of the
/// model before the fix with the same options: the degenerate, degenerate-UV and mirrored
/// triangles are `as_loaded`'s, not counted again. A fix keeps every triangle's positions and
/// UVs (it only copies vertices and writes normals and tangents), so they are the fixed
/// model's, bit for bit; an `as_loaded` of another model (another triangle count or weld
/// tolerance) is not used.
///
/// # Errors
///
/// As [`report()`].
pub fn report_fixed(
    fixed: &Model,
    options: &ReportOptions,
    welded: Option<&Welded>,
    as_loaded: &SeamReport,
) -> Result<SeamReport, MeshError> {
    let counts = [
        as_loaded.degenerate_triangles,
        as_loaded.degenerate_uv_triangles,
        as_loaded.mirrored_triangles,
    ];
    measure(
        fixed,
        options,
        welded,
        (as_loaded.triangles == fixed.triangle_count())
            .then_some((counts, as_loaded.weld_tolerance)),
    )
}

/// [`report()`], also giving the weld it measured with and the triangle counts it made, for
/// [`crate::fix_in_place_welded`] to fix the same model without welding or counting it
/// again (and then for [`report_welded()`] of the fixed model).
///
/// # Errors
///
/// As [`report()`].
pub fn report_with_weld(
    model: &Model,
    options: &ReportOptions,
) -> Result<(SeamReport, Welded), MeshError> {
    let (report, roots) = weld_and_measure(model, options, None)?;
    let counts =
        [report.degenerate_triangles, report.degenerate_uv_triangles, report.mirrored_triangles];
    Ok((report, Welded::new(roots, options.weld_tolerance, Some(counts))))
}

/// The report of `model` welded afresh, with the triangle counts `known` or counted, and the
/// weld's roots.
fn weld_and_measure(
    model: &Model,
    options: &ReportOptions,
    known: Option<[usize; 3]>,
) -> Result<(SeamReport, Vec<u32>), MeshError> {
    let flat = validate::flatten(model)?;
    let tolerance = options.weld_tolerance.absolute(weld::diagonal(&flat));
    let roots = weld::roots(&flat.positions, tolerance);
    let report = measure_welded(model, options, flat, &roots, tolerance, known);
    Ok((report, roots))
}

/// The report of a model as loaded, all but its degenerate, degenerate-UV and mirrored
/// triangles, which the model's fix counts on its way ([`report_before_fix`]);
/// [`AsLoaded::with_fixed`] completes it with the fix's counts.
#[derive(Clone, Debug)]
pub struct AsLoaded {
    /// The report, its three triangle counts not yet set.
    report: SeamReport,
}

/// [`report_with_weld`] of a model about to be fixed with [`crate::fix_in_place_welded`]
/// (given the weld): the same report and weld but for the triangle counts, which that fix
/// makes in its pass over the triangles instead of a pass of their own.
///
/// # Errors
///
/// As [`report()`].
pub fn report_before_fix(
    model: &Model,
    options: &ReportOptions,
) -> Result<(AsLoaded, Welded), MeshError> {
    // Counts of zero for now: `AsLoaded::with_fixed` sets them.
    let (report, roots) = weld_and_measure(model, options, Some([0; 3]))?;
    Ok((AsLoaded { report }, Welded::new(roots, options.weld_tolerance, None)))
}

impl AsLoaded {
    /// The report as loaded and [`report_fixed()`] of `fixed`, the model fixed with the weld
    /// [`report_before_fix`] gave, and `welded`, the weld that fix gave back: the counts are
    /// the fix's where it made them, else counted over the fixed model. A fix keeps every
    /// triangle's positions and UVs, so those of the fixed model are those as loaded.
    ///
    /// # Errors
    ///
    /// As [`report()`].
    pub fn with_fixed(
        self,
        fixed: &Model,
        options: &ReportOptions,
        welded: Option<&Welded>,
    ) -> Result<(SeamReport, SeamReport), MeshError> {
        let mut as_loaded = self.report;
        debug_assert_eq!(as_loaded.triangles, fixed.triangle_count(), "a fix keeps the triangles");
        let vertices = fixed.vertex_count();
        let counted = welded.and_then(|w| w.counts_for(vertices, options.weld_tolerance));
        let report =
            measure(fixed, options, welded, counted.map(|c| (c, as_loaded.weld_tolerance)))?;
        as_loaded.degenerate_triangles = report.degenerate_triangles;
        as_loaded.degenerate_uv_triangles = report.degenerate_uv_triangles;
        as_loaded.mirrored_triangles = report.mirrored_triangles;
        Ok((as_loaded, report))
    }
}

/// The report, with the triangle counts given where they are known (with the absolute weld
/// tolerance they were counted at).
fn measure(
    model: &Model,
    options: &ReportOptions,
    welded: Option<&Welded>,
    known: Option<([usize; 3], f32)>,
) -> Result<SeamReport, MeshError> {
    let flat = validate::flatten(model)?;
    let tolerance = options.weld_tolerance.absolute(weld::diagonal(&flat));
    let known = known.filter(|&(_, at)| at.to_bits() == tolerance.to_bits()).map(|(c, _)| c);
    let vertices = flat.positions.len();
    match welded.and_then(|w| w.roots_for(vertices, options.weld_tolerance)) {
        Some(roots) => {
            let counted = welded.and_then(|w| w.counts_for(vertices, options.weld_tolerance));
            Ok(measure_welded(model, options, flat, roots, tolerance, known.or(counted)))
        }
        None => {
            let roots = weld::roots(&flat.positions, tolerance);
            Ok(measure_welded(model, options, flat, &roots, tolerance, known))
        }
    }
}

/// The report of `model` (flattened into `flat`) welded into `roots` at the absolute
/// `tolerance`, with the triangle counts `known` or counted.
fn measure_welded(
    model: &Model,
    options: &ReportOptions,
    mut flat: validate::Flat,
    roots: &[u32],
    tolerance: f32,
    known: Option<[usize; 3]>,
) -> SeamReport {
    let shared = flat.shared_positions(roots);
    let near_miss = weld::near_misses(&flat.positions, roots);
    weld::snap_to_roots(&mut flat.positions, roots);

    let counts = known.unwrap_or_else(|| face_counts(model, &flat));
    let mut report = SeamReport {
        objects: model.objects.len(),
        triangles: model.triangle_count(),
        vertices: flat.positions.len(),
        welded_positions: roots.par_iter().enumerate().filter(|&(v, &r)| r as usize == v).count(),
        weld_tolerance: tolerance,
        shared_positions: shared.par_iter().filter(|&&s| s).count(),
        near_miss_positions: near_miss.par_iter().filter(|&&s| s).count(),
        degenerate_triangles: counts[0],
        degenerate_uv_triangles: counts[1],
        mirrored_triangles: counts[2],
        ..SeamReport::default()
    };
    drop(near_miss);
    report.skin_seams = skin::skin_seams(model, &flat, roots, &shared);
    frame_quality(model, &mut report);
    report.cross_object = cross_object(model, &flat, roots, &shared, options);
    report
}

/// Degenerate, degenerate-UV (of objects with UVs) and mirrored triangles. Each object's
/// triangles read straight from its slices of the model-space positions and of its UVs: as
/// [`validate::Flat::corners`] returned them, through memory, the loads of a triangle waited
/// on the stores just made (BENCHMARKS.md).
fn face_counts(model: &Model, flat: &validate::Flat) -> [usize; 3] {
    model
        .objects
        .par_iter()
        .enumerate()
        .map(|(o, object)| {
            let base = flat.vertex_start[o] as usize;
            let positions = &flat.positions[base..flat.vertex_start[o + 1] as usize];
            let uvs = object.uvs.as_deref();
            let mut n = [0; 3];
            each_face_flags(positions, uvs, &object.triangles, model.v_axis, |flags| {
                count(&mut n, flags);
            });
            n
        })
        .reduce(|| [0; 3], add_counts)
}

/// A corner at a shared position, with what the comparisons need.
struct SharedCorner {
    object: usize,
    /// The roots of its triangle's three positions.
    roots: [u32; 3],
    face: Face,
    /// The model's own frame at the corner's vertex, in model space (zero where it has none).
    normal: Vec3,
    tangent: Vec4,
}

/// Compares the frames across every cross-object edge: gathers the corners at shared
/// positions (sorted by position, then corner) and compares the corners of different objects
/// at each.
fn cross_object(
    model: &Model,
    flat: &validate::Flat,
    roots: &[u32],
    shared: &[bool],
    options: &ReportOptions,
) -> CrossObject {
    // The corners at shared positions, sorted by position.
    let entries = flat.corners_at(model, roots, |r| shared[r as usize]);
    let linear: Vec<Option<Linear>> = flat.linear.iter().map(|m| m.map(Linear::new)).collect();
    let corners = Corners { model, flat, roots, linear: &linear };
    let limits = Limits {
        crease_cos: options.crease_angle_deg.clamp(0.0, 180.0).to_radians().cos(),
        tangent_cos: options.tangent_angle_deg.clamp(0.0, 180.0).to_radians().cos(),
    };
    // Every pair of corners of different objects at each position, one position per task.
    let stats = entries
        .par_chunk_by(|a, b| a >> 32 == b >> 32)
        .fold(Stats::default, |mut s, run| {
            let p = (run[0] >> 32) as u32;
            let at: Vec<SharedCorner> = run.iter().map(|&e| corners.get(e)).collect();
            for (i, ca) in at.iter().enumerate() {
                for cb in &at[i + 1..] {
                    s.compare(p, ca, cb, limits);
                }
            }
            s
        })
        .reduce(Stats::default, Stats::merge);

    CrossObject {
        edges: stats.edges,
        hard_edges: stats.hard_edges,
        corner_pairs: stats.pairs,
        max_normal_angle_deg: stats.normal.max(),
        mean_normal_angle_deg: stats.normal.mean(),
        normal_breaks: stats.normal_breaks,
        max_tangent_angle_deg: stats.tangent.max(),
        mean_tangent_angle_deg: stats.tangent.mean(),
        min_hard_edge_normal_angle_deg: stats.min_hard,
    }
}

/// What [`Corners::get`] needs to build a [`SharedCorner`].
struct Corners<'a> {
    model: &'a Model,
    flat: &'a validate::Flat,
    roots: &'a [u32],
    /// Per object, the linear part of its transform (`None`: the identity).
    linear: &'a [Option<Linear>],
}

impl Corners<'_> {
    /// The corner of entry `e` (position in the high 32 bits, global corner in the low).
    fn get(&self, e: u64) -> SharedCorner {
        let (model, flat) = (self.model, self.flat);
        let c = (e & 0xFFFF_FFFF) as usize;
        let t = c / 3;
        let o = flat.object_of_triangle(t);
        let local = t - flat.triangle_start[o] as usize;
        let cs = flat.corners(model, o, local);
        let i = model.objects[o].triangles[local][c % 3] as usize;
        let (normal, tangent) = model_space_frame(&model.objects[o], i, self.linear[o].as_ref());
        SharedCorner {
            object: o,
            roots: cs.vertices.map(|v| self.roots[v as usize]),
            face: face(cs.positions, cs.uvs, model.v_axis),
            normal,
            tangent,
        }
    }
}

/// Cosines of the report's crease and tangent angles.
#[derive(Clone, Copy)]
struct Limits {
    crease_cos: f32,
    tangent_cos: f32,
}

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
    #[expect(
        clippy::cast_possible_truncation,
        reason = "the mean of f32 values, summed in f64 for accuracy, lies within f32's range"
    )]
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
    /// Adds corners `ca` and `cb` at position `p`, when they belong to different objects and
    /// their triangles share an edge from `p`: the edge (counted once, from its lower end),
    /// whether it is hard, and the angles between the model's frames on its two sides.
    fn compare(&mut self, p: u32, ca: &SharedCorner, cb: &SharedCorner, limits: Limits) {
        if ca.object == cb.object {
            return;
        }
        let (a, b) = (&ca.face, &cb.face);
        if a.is(DEGENERATE) || b.is(DEGENERATE) {
            return;
        }
        let Some(&q) = ca.roots.iter().find(|&&q| q != p && cb.roots.contains(&q)) else {
            return;
        };
        let hard = a.normal.dot(b.normal) < limits.crease_cos;
        if p < q {
            self.edges += 1;
            self.hard_edges += usize::from(hard);
        }
        let (na, nb) = (ca.normal, cb.normal);
        if na == Vec3::ZERO || nb == Vec3::ZERO {
            return;
        }
        let normal_angle = angle_deg(na, nb);
        if hard {
            self.min_hard = Some(self.min_hard.map_or(normal_angle, |m: f32| m.min(normal_angle)));
            return;
        }
        self.pairs += 1;
        self.normal.add(normal_angle);
        self.normal_breaks += usize::from(normal_angle > 1.0);
        let (ta, tb) = (ca.tangent, cb.tangent);
        let comparable = ta != Vec4::ZERO
            && tb != Vec4::ZERO
            && !a.is(DEGENERATE_UV)
            && !b.is(DEGENERATE_UV)
            && a.sign() == b.sign()
            && a.tangent.dot(b.tangent) >= limits.tangent_cos;
        if comparable {
            self.tangent.add(angle_deg(ta.xyz(), tb.xyz()));
        }
    }

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

/// Vertex `i` of `object`'s own frame, in model space (zero where it has none or it is not
/// finite; a zero tangent where only the normal is usable).
fn model_space_frame(object: &crate::Object, i: usize, linear: Option<&Linear>) -> (Vec3, Vec4) {
    let Some(n) = object.normals.as_ref().map(|ns| ns[i]) else {
        return (Vec3::ZERO, Vec4::ZERO);
    };
    if !n.is_finite() || n == Vec3::ZERO {
        return (Vec3::ZERO, Vec4::ZERO);
    }
    let t = object.tangents.as_ref().map_or(Vec4::ZERO, |ts| ts[i]);
    let t_ok = t.is_finite() && t.xyz() != Vec3::ZERO;
    match (linear, t_ok) {
        (Some(l), true) => l.frame_to_model(n, t),
        (Some(l), false) => (l.normal_to_model(n), Vec4::ZERO),
        (None, true) => (n, t),
        (None, false) => (n, Vec4::ZERO),
    }
}

/// What [`frame_quality`] finds, over some vertices.
#[derive(Clone, Copy, Default)]
struct Quality {
    dot_nt: Option<f32>,
    n_err: Option<f32>,
    t_err: Option<f32>,
    bad: usize,
}

impl Quality {
    /// Both parts together: maxima and a sum, the same in any order.
    fn merge(self, o: Self) -> Self {
        let max = |a: Option<f32>, b: Option<f32>| match (a, b) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
        Self {
            dot_nt: max(self.dot_nt, o.dot_nt),
            n_err: max(self.n_err, o.n_err),
            t_err: max(self.t_err, o.t_err),
            bad: self.bad + o.bad,
        }
    }

    /// Of the vertices with `normals` and, where the object has them, `tangents`.
    fn of(normals: &[Vec3], tangents: Option<&[Vec4]>) -> Self {
        let mut q = Self::default();
        let max = |acc: &mut Option<f32>, x: f32| *acc = Some(acc.map_or(x, |m| m.max(x)));
        for (i, &n) in normals.iter().enumerate() {
            max(&mut q.n_err, (n.length() - 1.0).abs());
            if let Some(t) = tangents.map(|ts| ts[i]) {
                max(&mut q.dot_nt, n.dot(t.xyz()).abs());
                max(&mut q.t_err, (t.xyz().length() - 1.0).abs());
                q.bad += usize::from(t.w != 1.0 && t.w != -1.0);
            }
        }
        q
    }
}

/// Vertices measured per parallel task in [`frame_quality`].
const QUALITY_CHUNK: usize = 1 << 14;

/// Orthogonality, unit length and handedness of the stored frames (in each object's space),
/// in parallel: maxima and a count, the same in any order.
fn frame_quality(model: &Model, report: &mut SeamReport) {
    let q = model
        .objects
        .par_iter()
        .filter_map(|o| o.normals.as_deref().map(|ns| (ns, o.tangents.as_deref())))
        .flat_map(|(normals, tangents)| {
            normals.par_chunks(QUALITY_CHUNK).enumerate().map(move |(k, ns)| {
                let start = k * QUALITY_CHUNK;
                Quality::of(ns, tangents.map(|ts| &ts[start..start + ns.len()]))
            })
        })
        .reduce(Quality::default, Quality::merge);
    report.max_abs_dot_nt = q.dot_nt;
    report.max_normal_length_error = q.n_err;
    report.max_tangent_length_error = q.t_err;
    report.bad_handedness = q.bad;
}

#[cfg(test)]
mod welded_tests;
