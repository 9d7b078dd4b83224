//! What the normal a copy of a shared position carries is: the rule that tells the seams
//! per-object smoothing made from the hard edges and custom normals an artist authored.
//! docs/normals.md explains it with the figures the tolerances were chosen from.
//!
//! At a position that two or more objects share, each object's vertex there (a *copy*) is
//! judged from its own object's faces at that position alone, never from the other objects':
//!
//! - **flat**: its normal is the normal of each of its own faces (flat shading): the copy is
//!   one side of an authored hard edge. Also flat, whatever the geometry says: a copy whose
//!   own faces each carry one normal at all three corners, the copy's, when those faces are
//!   not planar (flat shading of a polygon that is not planar: Blender gives each corner the
//!   polygon's normal, off each triangle's plane by a few degrees; read from the normals and
//!   the index buffer, since the geometry cannot tell it from smoothing);
//! - **smooth**: its normal is its object's smooth normal there, the weighted average of the
//!   object's faces around the position under one of the weightings tools use (corner angle,
//!   area, angle times area, uniform), over the faces of this vertex or of every vertex of the
//!   object there with the same normal (a vertex split by a UV seam): per-object smoothing,
//!   one side of the seam the paper repairs;
//! - **custom**: neither (weighted, edited or transferred normals): the artist's.
//!
//! Where a copy's own faces lie in one plane its normal is both flat and smooth; then its
//! object's shading decides: an object most of whose corners carry their face's normal is
//! faceted (the copy is flat), any other is smooth-shaded (the copy is smooth).
//!
//! **Invariant:** judging reads the model and changes nothing; the judgement of a copy
//! depends only on its own object (`tests/normals.rs`:
//! `faceted_blocks_keep_their_hard_edge`, `smooth_halves_are_repaired`).

use glam::Vec3;

use crate::Weighting;
use crate::face::{DEGENERATE, Face};
use crate::group::weight;

/// What the normal of one copy of a shared position is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// Its object's smooth normal there: one side of a seam.
    Smooth,
    /// Its own faces' normal: one side of an authored hard edge.
    Flat,
    /// Both at once (its faces lie in one plane): its object's shading decides.
    Coplanar,
    /// Neither: custom normals.
    Custom,
}

/// A normal within this angle of its face's normal is that face's normal. Exporters store
/// normals as f32 (float noise: 1e-5 degrees) or, quantised (KHR_mesh_quantization, int8),
/// within half a degree; the smallest facet angle of the low-poly models measured is 11
/// degrees (docs/normals.md).
pub(crate) const FLAT_DEG: f32 = 1.0;

/// A normal within this angle of one of its object's smooth normals there is that normal.
/// Blender's and ufbx's smooth normals, recomputed here from the stored positions, agree
/// within 0.01 degrees; quantised normals within half a degree.
pub(crate) const SMOOTH_DEG: f32 = 1.0;

/// Below this angle two unit vectors differ only by float noise (and by the int8 steps of
/// quantised normals: each step is 0.45 degrees).
const NOISE_DEG: f32 = 0.05;

/// The cosine of [`NOISE_DEG`]: unit vectors whose dot product is at least this are equal but
/// for rounding.
pub(crate) fn noise_cos() -> f32 {
    NOISE_DEG.to_radians().cos()
}

/// Where nothing next to a coplanar copy tells, its object is faceted when fewer than this
/// share of its vertices that two or more faces use join faces that are not coplanar.
pub(crate) const SMOOTH_SHARE: f32 = 0.1;

/// The weightings whose averages count as an object's smooth normal.
const WEIGHTINGS: [Weighting; 4] =
    [Weighting::Angle, Weighting::Area, Weighting::AngleArea, Weighting::Uniform];

/// One corner at a position: which copy it belongs to, its face, which corner of the face it
/// is, and the face's vertices.
pub(crate) struct Corner {
    pub copy: usize,
    pub face: Face,
    pub k: usize,
    /// The face's vertices, in the copy's object.
    pub triangle: [u32; 3],
    /// Whether the face's three vertices carry one normal (within [`NOISE_DEG`]): flat
    /// shading's faces do, smooth shading's do not where the surface bends.
    pub uniform: bool,
}

/// One copy at a position: its object and its unit normal in model space.
pub(crate) struct Copy {
    pub object: usize,
    pub unit: Vec3,
}

/// Judges every copy at one position (see the module docs), from the copies and all their
/// corners there. Coplanar copies are left [`Kind::Coplanar`] for the object to decide.
pub(crate) fn judge(copies: &[Copy], corners: &[Corner]) -> Vec<Kind> {
    let equal_cos = noise_cos();
    // Per copy, the copies of its object that carry the same normal (one vertex split by UVs).
    let same = |a: usize, b: usize| {
        copies[b].object == copies[a].object && copies[b].unit.dot(copies[a].unit) >= equal_cos
    };
    (0..copies.len())
        .map(|a| {
            let unit = copies[a].unit;
            // One pass: the farthest own face, and each weighting's sums over the copy's own
            // faces and over those of the copies with the same normal.
            let (mut flat, mut faces, mut uniform) = (0.0_f32, 0, true);
            let (mut own, mut split) = ([Vec3::ZERO; 4], [Vec3::ZERO; 4]);
            for c in corners.iter().filter(|c| same(a, c.copy)) {
                let weighted = WEIGHTINGS.map(|w| c.face.normal * weight(w, &c.face, c.k));
                for (sum, w) in split.iter_mut().zip(weighted) {
                    *sum += w;
                }
                if c.copy == a {
                    for (sum, w) in own.iter_mut().zip(weighted) {
                        *sum += w;
                    }
                    if !c.face.is(DEGENERATE) {
                        flat = flat.max(angle(unit, c.face.normal));
                        faces += 1;
                        uniform &= c.uniform;
                    }
                }
            }
            if faces == 0 {
                return Kind::Custom;
            }
            // One normal at every corner of faces that are not planar: flat shading of
            // polygons that are not planar, which the angles below would take for smoothing.
            if uniform && flat > FLAT_DEG.to_radians() {
                return Kind::Flat;
            }
            let smooth = own
                .iter()
                .chain(&split)
                .filter_map(|n| n.try_normalize())
                .map(|n| angle(unit, n))
                .fold(f32::INFINITY, f32::min);
            kind(flat, smooth)
        })
        .collect()
}

/// Whether the vertices of `triangle` carry one normal in `normals` (within [`NOISE_DEG`]).
pub(crate) fn uniform(normals: &[Vec3], triangle: [u32; 3]) -> bool {
    let [a, b, c] = triangle.map(|v| normals[v as usize].normalize_or_zero());
    let cos = noise_cos();
    a != Vec3::ZERO && a.dot(b) >= cos && a.dot(c) >= cos
}

/// The kind from the angles (radians) between a copy's normal and its farthest face
/// (`flat`) and its nearest smooth normal (`smooth`).
fn kind(flat: f32, smooth: f32) -> Kind {
    let (flat_ok, smooth_ok) = (flat <= FLAT_DEG.to_radians(), smooth <= SMOOTH_DEG.to_radians());
    match (flat_ok, smooth_ok) {
        // A smooth normal that is clearly nearer than any face's: the faces are not coplanar.
        (true, true) if flat > NOISE_DEG.to_radians() && 2.0 * smooth < flat => Kind::Smooth,
        (true, true) => Kind::Coplanar,
        (false, true) => Kind::Smooth,
        (true, false) => Kind::Flat,
        (false, false) => Kind::Custom,
    }
}

/// The angle between two unit vectors, radians: atan2 of sine and cosine, exact near 0.
fn angle(a: Vec3, b: Vec3) -> f32 {
    a.cross(b).length().atan2(a.dot(b))
}

/// How the faces that use one vertex of an object lie.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Joins {
    /// No face, or one.
    Few,
    /// Two or more, all in one plane.
    Coplanar,
    /// Two or more, not in one plane: the vertex is shared across a curve (smooth shading).
    Curved,
}

/// How some of an object's vertices join its faces: what decides a coplanar copy (see the
/// module docs). It reads the index buffer, not the normals: quantised normals do not blur
/// it, and a densely tessellated smooth object, whose normals lie within a fraction of a
/// degree of its faces', is not mistaken for a faceted one. Only the vertices asked about
/// are worked out (the other vertices of coplanar copies' faces: a few per seam position);
/// the object as a whole only where those tell nothing.
pub(crate) struct Shading {
    /// The vertices asked about, ascending, and how each joins its faces.
    joins: Vec<(u32, Joins)>,
    /// Whether the object as a whole is faceted: fewer than [`SMOOTH_SHARE`] of the vertices
    /// that two or more faces use are curved (worked out only where asked).
    faceted: bool,
}

impl Shading {
    /// How the vertices `asked` (ascending, no repeats) of an object with `vertices` vertices
    /// and `triangles` join its faces (`normal`: a triangle's unit normal, zero where it is
    /// degenerate); and, with `whole`, whether the whole object is faceted.
    pub fn of(
        triangles: &[[u32; 3]],
        normal: impl Fn(usize) -> Vec3,
        asked: &[u32],
        vertices: usize,
        whole: bool,
    ) -> Self {
        let mut wanted = vec![false; vertices];
        if whole {
            wanted.fill(true);
        } else {
            asked.iter().for_each(|&v| wanted[v as usize] = true);
        }
        let slot = |v: u32| if whole { Some(v as usize) } else { asked.binary_search(&v).ok() };
        let n = if whole { vertices } else { asked.len() };
        let (mut first, mut joins) = (vec![Vec3::ZERO; n], vec![Joins::Few; n]);
        let cos = noise_cos();
        for (t, triangle) in triangles.iter().enumerate() {
            if !triangle.iter().any(|&v| wanted[v as usize]) {
                continue;
            }
            let normal = normal(t);
            if normal == Vec3::ZERO {
                continue;
            }
            for i in triangle.iter().filter_map(|&v| wanted[v as usize].then(|| slot(v)).flatten())
            {
                if first[i] == Vec3::ZERO {
                    first[i] = normal;
                } else if joins[i] != Joins::Curved {
                    let flat = first[i].dot(normal) >= cos;
                    joins[i] = if flat { Joins::Coplanar } else { Joins::Curved };
                }
            }
        }
        let faceted = whole && {
            let shared = joins.iter().filter(|&&j| j != Joins::Few).count();
            let curved = joins.iter().filter(|&&j| j == Joins::Curved).count();
            #[expect(clippy::cast_precision_loss, reason = "a share")]
            let few = (curved as f32) < SMOOTH_SHARE * shared as f32;
            few || shared == 0
        };
        let joins = if whole {
            asked.iter().map(|&v| (v, joins[v as usize])).collect()
        } else {
            asked.iter().copied().zip(joins).collect()
        };
        Self { joins, faceted }
    }

    /// How the vertices in `known` join their faces, from all their faces' unit normals
    /// (zero for a degenerate face) each: what the corners at shared positions tell.
    pub fn known(known: Vec<(u32, Vec<Vec3>)>) -> Self {
        let cos = noise_cos();
        let mut joins: Vec<(u32, Joins)> = known
            .into_iter()
            .map(|(v, normals)| {
                let mut faces = normals.into_iter().filter(|&n| n != Vec3::ZERO);
                let joins = match faces.next() {
                    None => Joins::Few,
                    Some(first) => faces.fold(Joins::Few, |j, n| match j {
                        Joins::Curved => Joins::Curved,
                        _ if first.dot(n) >= cos => Joins::Coplanar,
                        _ => Joins::Curved,
                    }),
                };
                (v, joins)
            })
            .collect();
        joins.sort_unstable_by_key(|&(v, _)| v);
        joins.dedup_by_key(|&mut (v, _)| v);
        Self { joins, faceted: false }
    }

    /// These joins, and `other`'s for the vertices these do not know.
    pub fn or(mut self, other: Self) -> Self {
        let known = |v: u32| self.joins.binary_search_by_key(&v, |&(u, _)| u).is_ok();
        let more: Vec<(u32, Joins)> = other.joins.into_iter().filter(|&(v, _)| !known(v)).collect();
        self.joins.extend(more);
        self.joins.sort_unstable_by_key(|&(v, _)| v);
        self
    }

    /// How vertex `v` (one asked about) joins its faces.
    fn joins(&self, v: u32) -> Joins {
        self.joins.binary_search_by_key(&v, |&(u, _)| u).map_or(Joins::Few, |i| self.joins[i].1)
    }

    /// Whether the other vertices of a coplanar copy's faces (`fan`, all asked about) tell
    /// anything: `Some(true)` where one joins faces across a curve (smooth shading runs up to
    /// the copy: the facet column of a cylinder cut lengthwise), `Some(false)` where none does
    /// but one joins coplanar faces (the copy's facet has vertices of its own: flat shading),
    /// `None` where all join one face or none (a lone triangle).
    pub fn near(&self, fan: impl Iterator<Item = u32> + Clone) -> Option<bool> {
        let any = |j: Joins| fan.clone().any(|v| self.joins(v) == j);
        if any(Joins::Curved) {
            Some(true)
        } else if any(Joins::Coplanar) {
            Some(false)
        } else {
            None
        }
    }

    /// Whether a coplanar copy is smooth: [`Self::near`], else the object's shading as a
    /// whole (where it was worked out).
    pub fn smooth_at(&self, fan: impl Iterator<Item = u32> + Clone) -> bool {
        self.near(fan).unwrap_or(!self.faceted)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_normal_between_its_faces_is_smooth_and_on_one_face_flat() {
        let deg = f32::to_radians;
        assert_eq!(kind(deg(15.0), deg(0.001)), Kind::Smooth);
        assert_eq!(kind(deg(0.3), deg(0.001)), Kind::Smooth, "a dense smooth mesh");
        assert_eq!(kind(deg(0.0001), deg(0.0001)), Kind::Coplanar);
        assert_eq!(kind(deg(0.4), deg(0.4)), Kind::Coplanar, "quantised, one plane");
        assert_eq!(kind(deg(0.0001), deg(15.0)), Kind::Flat);
        assert_eq!(kind(deg(10.0), deg(5.0)), Kind::Custom);
    }
}
