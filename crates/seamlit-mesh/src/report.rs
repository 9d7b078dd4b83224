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

use crate::face::{DEGENERATE, DEGENERATE_UV, Face, add_counts, count, face, face_flags};
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
    let flat = validate::flatten(model)?;
    let tolerance = options.weld_tolerance.absolute(weld::diagonal(&flat));
    let roots = weld::roots(&flat.positions, tolerance);
    let report = measure_welded(model, options, flat, &roots, tolerance, None);
    let counts =
        [report.degenerate_triangles, report.degenerate_uv_triangles, report.mirrored_triangles];
    Ok((report, Welded::new(roots, options.weld_tolerance, Some(counts))))
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
        welded_positions: roots.iter().enumerate().filter(|&(v, &r)| r as usize == v).count(),
        weld_tolerance: tolerance,
        shared_positions: shared.iter().filter(|&&s| s).count(),
        near_miss_positions: near_miss.iter().filter(|&&s| s).count(),
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

/// Degenerate, degenerate-UV (of objects with UVs) and mirrored triangles.
fn face_counts(model: &Model, flat: &validate::Flat) -> [usize; 3] {
    model
        .objects
        .par_iter()
        .enumerate()
        .map(|(o, object)| {
            let mut n = [0; 3];
            for t in 0..object.triangles.len() {
                let c = flat.corners(model, o, t);
                count(&mut n, face_flags(c.positions, c.uvs, model.v_axis));
            }
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
mod welded_tests {
    use glam::{Mat4, Quat, Vec2, Vec3};

    use super::*;
    use crate::{FixOptions, Mode, Object, TangentMethod, fix_in_place_welded};

    /// A cylinder standing on a ring (a 90-degree fold between them inside the first object: a
    /// crease), with the U of its last quarter of columns mirrored, cut into three objects by
    /// rows; each object has its own copy of the rows it shares, and the middle one has a
    /// transform (its positions put back through the inverse, so they round differently:
    /// welded by the tolerance).
    fn folded_tube() -> Model {
        let (columns, rows) = (16u32, 12u32);
        let point = |i: u32, j: u32| {
            let a = i as f32 / columns as f32 * std::f32::consts::TAU;
            let (r, y) =
                if j <= 2 { (0.5 + j as f32 * 0.25, 0.0) } else { (1.0, (j - 2) as f32 * 0.3) };
            let u = if i > columns * 3 / 4 {
                1.5 - i as f32 / columns as f32
            } else {
                i as f32 / columns as f32
            };
            (Vec3::new(r * a.cos(), y, r * a.sin()), Vec2::new(u, j as f32 / rows as f32))
        };
        let transform =
            Mat4::from_rotation_translation(Quat::from_rotation_y(0.7), Vec3::new(0.3, -0.2, 0.1));
        let part = |name: &str, band: std::ops::Range<u32>, moved: bool| {
            let (mut positions, mut uvs, mut triangles) = (vec![], vec![], vec![]);
            for j in band.clone() {
                for i in 0..=columns {
                    let (p, uv) = point(i % columns, j);
                    positions.push(if moved { transform.inverse().transform_point3(p) } else { p });
                    uvs.push(uv);
                }
            }
            let w = columns + 1;
            for j in 0..band.end - band.start - 1 {
                for i in 0..columns {
                    let a = j * w + i;
                    triangles.push([a, a + w, a + w + 1]);
                    triangles.push([a, a + w + 1, a + 1]);
                }
            }
            let object = Object::new(name, positions, triangles).with_uvs(uvs);
            if moved { object.with_transform(transform) } else { object }
        };
        Model::new(vec![
            part("ring", 0..5, false),
            part("middle", 4..9, true),
            part("top", 8..rows, false),
        ])
    }

    /// The report of a fixed model with the fix's weld is the report that welds it again, in
    /// every field; and the fix's weld is the one used (it fits the fixed model).
    #[test]
    fn the_fixs_weld_gives_the_same_report() {
        let model = folded_tube();
        for tangents in [TangentMethod::Mikktspace, TangentMethod::Seamlit, TangentMethod::None] {
            let options = FixOptions { tangents, ..FixOptions::DEFAULT };
            let mut fixed = model.clone();
            let (changes, welded) = fix_in_place_welded(&mut fixed, &options, None).expect("valid");
            // Vertices were split at the crease and at the mirror line: the renumbering is
            // exercised, as is the weld across objects and transforms.
            assert!(changes.vertices_split() > 0, "{tangents:?}: nothing split");
            let welded = welded.expect("a weld in model mode");
            let report_options = ReportOptions::from(&options);
            let again = report(&fixed, &report_options).expect("valid");
            assert!(again.shared_positions > 0 && again.near_miss_positions > 0, "{again:?}");
            let flat = validate::flatten(&fixed).expect("valid");
            assert!(welded.roots_for(flat.positions.len(), options.weld_tolerance).is_some());
            let with = report_welded(&fixed, &report_options, Some(&welded)).expect("valid");
            assert_eq!(with, again, "{tangents:?}");
        }
    }

    /// The folded tube and a fourth object with a degenerate triangle (three points on a line)
    /// and one whose UVs collapse to a point, so that every count is above zero.
    fn tube_with_bad_faces() -> Model {
        let mut model = folded_tube();
        let positions =
            vec![Vec3::new(3.0, 0.0, 0.0), Vec3::new(4.0, 0.0, 0.0), Vec3::new(5.0, 0.0, 0.0)];
        let positions = [positions, vec![Vec3::new(3.0, 1.0, 0.0)]].concat();
        let uvs = vec![Vec2::ZERO, Vec2::X, Vec2::new(2.0, 0.0), Vec2::X];
        let object = Object::new("bad", positions, vec![[0, 1, 2], [0, 1, 3], [1, 3, 0]]);
        model.objects.push(object.with_uvs(uvs));
        model
    }

    /// The folded tube with authored normals: every object's ("all"), and all but the first
    /// object's ("partly"; the first as made, its vertices not yet split, so the others' move
    /// when they are). The normals are each object's own: seams where the objects meet, for
    /// the repair.
    fn tubes_with_normals() -> [(&'static str, Model); 2] {
        let mut authored = folded_tube();
        let per_object = FixOptions { mode: Mode::Object, ..FixOptions::DEFAULT };
        fix_in_place_welded(&mut authored, &per_object, None).expect("valid");
        for object in &mut authored.objects {
            object.tangents = None;
            object.split_from.clear();
        }
        let mut partly = authored.clone();
        partly.objects[0] = folded_tube().objects.swap_remove(0);
        [("all", authored), ("partly", partly)]
    }

    /// With authored normals (every object's, or all but one's), where the fix repairs seams
    /// and makes tangents instead of smoothing, its weld still gives the report that welds the
    /// fixed model again.
    #[test]
    fn the_weld_of_a_fix_that_keeps_normals_gives_the_same_report() {
        for (name, model) in tubes_with_normals() {
            let mut fixed = model.clone();
            let options = FixOptions::DEFAULT;
            let (changes, welded) = fix_in_place_welded(&mut fixed, &options, None).expect("valid");
            assert!(changes.objects.iter().any(|o| o.kept_normals), "{name}");
            // Where one object's normals are computed, its vertices split at the mirror line
            // after the weld: the renumbering is exercised.
            assert!(name == "all" || changes.vertices_split() > 0, "{name}: nothing split");
            let welded = welded.unwrap_or_else(|| panic!("{name}: no weld"));
            let report_options = ReportOptions::from(&options);
            let again = report(&fixed, &report_options).expect("valid");
            assert!(again.shared_positions > 0 && again.mirrored_triangles > 0, "{again:?}");
            let with = report_welded(&fixed, &report_options, Some(&welded)).expect("valid");
            assert_eq!(with, again, "{name}");
        }
    }

    /// The weld and counts of the report as loaded, handed to the fix, give the same fixed
    /// model and the same report of it, with every object's normals computed, all kept, and
    /// all but the first object's kept; and the fix uses them (its weld carries the counts as
    /// loaded, which it would not count with them given).
    #[test]
    fn the_weld_as_loaded_fixes_as_a_fresh_weld() {
        let [all, partly] = tubes_with_normals();
        for (name, model) in [("computed", tube_with_bad_faces()), all, partly] {
            let options = FixOptions::DEFAULT;
            let report_options = ReportOptions::from(&options);
            let (as_loaded, loaded) = report_with_weld(&model, &report_options).expect("valid");
            assert_eq!(as_loaded, report(&model, &report_options).expect("valid"), "{name}");
            let (mut fresh, mut given) = (model.clone(), model.clone());
            let (changes, welded) = fix_in_place_welded(&mut fresh, &options, None).expect("ok");
            let (changes_given, welded_given) =
                fix_in_place_welded(&mut given, &options, Some(&loaded)).expect("ok");
            assert_eq!(given, fresh, "{name}");
            assert_eq!(changes_given, changes, "{name}");
            let welded_given = welded_given.expect("a weld in model mode");
            let counts = [
                as_loaded.degenerate_triangles,
                as_loaded.degenerate_uv_triangles,
                as_loaded.mirrored_triangles,
            ];
            let vertices = validate::flatten(&given).expect("valid").positions.len();
            assert_eq!(welded_given.counts_for(vertices, options.weld_tolerance), Some(counts));
            let with = report_welded(&given, &report_options, Some(&welded_given));
            let again = report_welded(&fresh, &report_options, welded.as_ref());
            assert_eq!(with.expect("valid"), again.expect("valid"), "{name}");
        }
        // What is given is what is used: counts it would not make, roots it would not weld.
        let model = tube_with_bad_faces();
        let tolerance = FixOptions::DEFAULT.weld_tolerance;
        let vertices = model.vertex_count();
        let (_, loaded) = report_with_weld(&model, &ReportOptions::default()).expect("valid");
        let roots = loaded.roots_for(vertices, tolerance).expect("the model's").to_vec();
        let odd = Welded::new(roots, tolerance, Some([7, 8, 9]));
        let mut fixed = model.clone();
        let (_, welded) =
            fix_in_place_welded(&mut fixed, &FixOptions::DEFAULT, Some(&odd)).expect("valid");
        let fixed_vertices = validate::flatten(&fixed).expect("valid").positions.len();
        let counts = welded.expect("a weld").counts_for(fixed_vertices, tolerance);
        assert_eq!(counts, Some([7, 8, 9]));
        let apart =
            Welded::new((0..u32::try_from(vertices).expect("small")).collect(), tolerance, None);
        let (mut fresh, mut unwelded) = (model.clone(), model.clone());
        fix_in_place_welded(&mut fresh, &FixOptions::DEFAULT, None).expect("valid");
        fix_in_place_welded(&mut unwelded, &FixOptions::DEFAULT, Some(&apart)).expect("valid");
        assert_ne!(unwelded, fresh);
    }

    /// The triangle counts a fix makes on its way (in the smoothing's pass, with or without
    /// the faces' UV frames) are the report's, and the report of the fixed model takes them.
    #[test]
    fn the_fixs_counts_are_the_reports() {
        let model = tube_with_bad_faces();
        for tangents in [TangentMethod::Mikktspace, TangentMethod::Seamlit, TangentMethod::None] {
            let options = FixOptions { tangents, ..FixOptions::DEFAULT };
            let mut fixed = model.clone();
            let (_, welded) = fix_in_place_welded(&mut fixed, &options, None).expect("valid");
            let welded = welded.expect("a weld in model mode");
            let report_options = ReportOptions::from(&options);
            let again = report(&fixed, &report_options).expect("valid");
            let vertices = validate::flatten(&fixed).expect("valid").positions.len();
            let counted = welded.counts_for(vertices, options.weld_tolerance);
            let expected = [
                again.degenerate_triangles,
                again.degenerate_uv_triangles,
                again.mirrored_triangles,
            ];
            assert!(expected.iter().all(|&n| n > 0), "{tangents:?}: {expected:?}");
            assert_eq!(counted, Some(expected), "{tangents:?}");
            let with = report_welded(&fixed, &report_options, Some(&welded)).expect("valid");
            assert_eq!(with, again, "{tangents:?}");
        }
    }

    /// Where the normals are kept and the tangents made against them, the generator's pass
    /// over the triangles counts them, and the counts are the report's.
    #[test]
    fn the_counts_made_beside_kept_normals_are_the_reports() {
        let without_tangents = FixOptions { tangents: TangentMethod::None, ..FixOptions::DEFAULT };
        let with_normals = crate::fix(&tube_with_bad_faces(), &without_tangents).expect("valid");
        assert!(with_normals.objects.iter().all(|o| o.normals.is_some() && o.tangents.is_none()));
        for tangents in [TangentMethod::Mikktspace, TangentMethod::Seamlit] {
            let options = FixOptions { tangents, ..FixOptions::DEFAULT };
            let mut fixed = with_normals.clone();
            let (changes, welded) = fix_in_place_welded(&mut fixed, &options, None).expect("valid");
            assert!(changes.objects.iter().all(|o| o.kept_normals && !o.kept_tangents));
            assert!(fixed.objects.iter().all(|o| o.tangents.is_some()), "{tangents:?}");
            let welded = welded.expect("a weld in model mode");
            let again = report(&fixed, &ReportOptions::from(&options)).expect("valid");
            let vertices = validate::flatten(&fixed).expect("valid").positions.len();
            let expected = [
                again.degenerate_triangles,
                again.degenerate_uv_triangles,
                again.mirrored_triangles,
            ];
            assert!(expected.iter().all(|&n| n > 0), "{tangents:?}: {expected:?}");
            let counted = welded.counts_for(vertices, options.weld_tolerance);
            assert_eq!(counted, Some(expected), "{tangents:?}");
        }
    }

    /// The report of a fixed model with the triangle counts as loaded is the report that
    /// counts them again, in every field, in every mode and with every tangent method; an
    /// `as_loaded` of another model is not used.
    #[test]
    fn the_counts_as_loaded_are_the_fixed_models() {
        let model = tube_with_bad_faces();
        let options = ReportOptions::from(&FixOptions::DEFAULT);
        let as_loaded = report(&model, &options).expect("valid");
        assert!(as_loaded.degenerate_triangles > 0, "{as_loaded:?}");
        assert!(as_loaded.degenerate_uv_triangles > 0 && as_loaded.mirrored_triangles > 0);
        for mode in [Mode::Flat, Mode::Object, Mode::Model] {
            for tangents in [TangentMethod::Mikktspace, TangentMethod::Seamlit, TangentMethod::None]
            {
                let fix_options = FixOptions { mode, tangents, ..FixOptions::DEFAULT };
                let mut fixed = model.clone();
                let (changes, welded) =
                    fix_in_place_welded(&mut fixed, &fix_options, None).expect("ok");
                assert!(changes.vertices_split() > 0, "{mode:?} {tangents:?}: nothing split");
                let again = report(&fixed, &options).expect("valid");
                let given = report_fixed(&fixed, &options, welded.as_ref(), &as_loaded);
                assert_eq!(given.expect("valid"), again, "{mode:?} {tangents:?}");
            }
        }
        // Counts of another model (one triangle fewer, the same positions) or taken at another
        // weld tolerance (the same triangles, more of them degenerate) are counted again.
        let mut fixed = model.clone();
        let (_, welded) =
            fix_in_place_welded(&mut fixed, &FixOptions::DEFAULT, None).expect("valid");
        let again = report(&fixed, &options).expect("valid");
        let mut fewer = model.clone();
        fewer.objects[3].triangles.pop();
        let wide = ReportOptions { weld_tolerance: crate::WeldTolerance::Relative(0.1), ..options };
        for other in [report(&fewer, &options), report(&model, &wide)] {
            let other = other.expect("valid");
            let counts = |r: &SeamReport| {
                [r.degenerate_triangles, r.degenerate_uv_triangles, r.mirrored_triangles]
            };
            assert_ne!(counts(&other), counts(&again), "{other:?}");
            let given = report_fixed(&fixed, &options, welded.as_ref(), &other).expect("valid");
            assert_eq!(given, again);
        }
    }

    /// The fix's weld is not used for another model or another tolerance, and the object
    /// mode's (a weld within each object) is not given.
    #[test]
    fn a_weld_that_does_not_fit_is_not_used() {
        let model = folded_tube();
        let mut fixed = model.clone();
        let (_, welded) =
            fix_in_place_welded(&mut fixed, &FixOptions::DEFAULT, None).expect("valid");
        let welded = welded.expect("a weld in model mode");
        let options = ReportOptions::from(&FixOptions::DEFAULT);
        // The input has fewer vertices than the fixed model: its own weld is made.
        let unfixed = report_welded(&model, &options, Some(&welded)).expect("valid");
        assert_eq!(unfixed, report(&model, &options).expect("valid"));
        let wider =
            ReportOptions { weld_tolerance: crate::WeldTolerance::Relative(0.1), ..options };
        let at_wider = report_welded(&fixed, &wider, Some(&welded)).expect("valid");
        assert_eq!(at_wider, report(&fixed, &wider).expect("valid"));
        let object_mode = FixOptions { mode: Mode::Object, ..FixOptions::DEFAULT };
        let (_, none) = fix_in_place_welded(&mut model.clone(), &object_mode, None).expect("valid");
        assert!(none.is_none());
    }
}
