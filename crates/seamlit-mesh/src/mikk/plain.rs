//! Plain positions: the fans whose tangent is one group's sum, found and summed in one pass
//! per object without the grouping, with step 1 (each triangle's flags) in the same pass.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::Surface;
use super::face::{ANY, DEGENERATE, ORIENTED, corner_terms, face_flags};

/// What the corners at a vertex tell [`plain_positions`].
pub(super) const HAS_ORIENTED: u8 = 1;
pub(super) const HAS_REVERSED: u8 = 2;
/// With-any or degenerate triangles, or several normals at the position, or another vertex
/// of the position with the same key.
pub(super) const IRREGULAR: u8 = 4;

/// Mixes a key into 64 well-spread bits (splitmix64's finaliser): sums of these tell whether
/// two multisets of keys are equal, but for a 2^-64 chance.
pub(super) fn spread(key: u64) -> u64 {
    let mut z = key.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// What one pass over the triangles gathers per vertex, for [`plain_fans`].
#[derive(Clone, Copy, Default)]
struct Gathered {
    /// The sum of its corners' projected `s` times angle (healthy triangles, in triangle
    /// order) and its triangles' orientation (`w`, as the last one sets it: at a plain
    /// position all agree).
    sum: Vec3,
    w: f32,
    /// Its corners' normal (the last corner's: at a plain position all agree).
    normal: Vec3,
    /// The sum over its corners of the spread next vertex minus the spread previous one:
    /// zero where its triangles close around it.
    closure: u64,
    /// `HAS_ORIENTED`, `HAS_REVERSED`, `IRREGULAR`.
    flags: u8,
}

/// Step 1 and the plain fans, in one pass over each object's triangles.
pub(super) struct PlainFans {
    /// Per triangle: its flags (see [`face_tangent`](super::face::face_tangent)).
    pub(super) faces: Vec<u8>,
    /// Per root vertex: whether its position is plain (see [`plain_fans`]).
    pub(super) plain: Vec<bool>,
    /// Per vertex at a plain position: the tangent of all its corners (zero elsewhere).
    pub(super) fans: Vec<Vec4>,
}

/// Every triangle's flags, and per root vertex whether every vertex of its position is
/// *plain*, one MikkTSpace group whose tangent is summed here in the same pass: its corners
/// share one normal (a simple position) and it shares its key with no other vertex (`shared`);
/// its triangles are healthy (none with-any, none degenerate) and of one orientation; and
/// they close around it (every triangle's next vertex is another's previous one: the sums of
/// their spread keys agree). Such a fan is one group, and its tangent is the sum over its
/// corners in triangle order, as [`Position`](super::position) sums a group. The rest
/// (boundaries of objects and UV islands, mirror lines, creases, poles) go through the
/// grouping, position by position.
///
/// One case a closed fan does not rule out: two closed fans pinched at one vertex with one
/// UV, two groups for MikkTSpace; they are summed as one here.
pub(super) fn plain_fans<N>(surface: &Surface<'_, N>, shared: &[bool]) -> PlainFans
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    let mut faces = vec![0u8; surface.triangles.len()];
    let mut gathered = vec![Gathered::default(); surface.roots.len()];
    let parts = split_by_object(surface, &mut gathered, &mut faces);
    parts
        .into_par_iter()
        .for_each(|(o, (gathered, faces))| gather_object(surface, o, gathered, faces));
    let plain = plain_positions(surface, &gathered, shared);
    let fans = gathered
        .par_iter()
        .zip(surface.roots)
        .map(|(g, &r)| {
            if plain[r as usize] && g.w != 0.0 {
                crate::frame::orthogonal_tangent(g.normal, g.sum).extend(g.w)
            } else {
                Vec4::ZERO
            }
        })
        .collect();
    PlainFans { faces, plain, fans }
}

/// [`plain_fans`]' pass over object `o`'s triangles: their flags into `faces` (the object's
/// part), and what their corners tell into `gathered` (the object's vertices).
fn gather_object<N>(surface: &Surface<'_, N>, o: usize, gathered: &mut [Gathered], faces: &mut [u8])
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    let base = surface.vertex_start[o] as usize;
    let first = surface.triangle_start[o] as usize;
    for (i, flags) in faces.iter_mut().enumerate() {
        let t = first + i;
        let face = face_flags(surface, t);
        *flags = face.flags;
        let bits = if face.is(ANY | DEGENERATE) {
            IRREGULAR
        } else if face.is(ORIENTED) {
            HAS_ORIENTED
        } else {
            HAS_REVERSED
        };
        let tri = surface.triangles[t];
        let normals: [(Vec3, u32); 3] =
            std::array::from_fn(|k| (surface.normal)(t * 3 + k, tri[k] as usize));
        let terms =
            (bits != IRREGULAR).then(|| corner_terms(surface, &face, t, normals.map(|n| n.0)));
        let w = if face.is(ORIENTED) { 1.0 } else { -1.0 };
        // Vertices, not keys: a fan closed by vertex is closed by key (at a simple position
        // the corners of one vertex across an edge share a normal group); one closed only
        // through another vertex with the same key is not plain.
        let spreads = tri.map(|v| spread(v.into()));
        for (k, &v) in tri.iter().enumerate() {
            let g = &mut gathered[v as usize - base];
            g.flags |= bits | if normals[k].1 != 0 { IRREGULAR } else { 0 };
            let (next, prev) = (spreads[(k + 1) % 3], spreads[(k + 2) % 3]);
            g.closure = g.closure.wrapping_add(next).wrapping_sub(prev);
            if let Some(terms) = terms {
                let (s, angle) = terms[k];
                g.sum += s * angle;
                g.w = w;
                g.normal = normals[k].0;
            }
        }
    }
}

/// Per root vertex: whether every vertex of its position is plain, from what
/// [`gather_object`] gathered.
fn plain_positions<N>(
    surface: &Surface<'_, N>,
    gathered: &[Gathered],
    shared: &[bool],
) -> Vec<bool> {
    let not_plain: Vec<u32> = (0..gathered.len())
        .into_par_iter()
        .filter(|&v| {
            let f = gathered[v].flags;
            let mixed = f & (HAS_ORIENTED | HAS_REVERSED) == HAS_ORIENTED | HAS_REVERSED;
            f & IRREGULAR != 0 || mixed || gathered[v].closure != 0 || shared[v]
        })
        .map(|v| surface.roots[v])
        .collect();
    let mut plain = vec![true; gathered.len()];
    for r in not_plain {
        plain[r as usize] = false;
    }
    plain
}

/// One object's part of a per-vertex and a per-triangle array, with the object's number.
pub(super) type ObjectPart<'x, A, B> = (usize, (&'x mut [A], &'x mut [B]));

/// `a` (one entry per vertex) and `b` (one per triangle) cut into each object's part,
/// numbered.
fn split_by_object<'x, N, A, B>(
    surface: &Surface<'_, N>,
    mut a: &'x mut [A],
    mut b: &'x mut [B],
) -> Vec<ObjectPart<'x, A, B>> {
    let mut parts = Vec::with_capacity(surface.vertex_start.len());
    for o in 0..surface.vertex_start.len() - 1 {
        let vertices = (surface.vertex_start[o + 1] - surface.vertex_start[o]) as usize;
        let triangles = (surface.triangle_start[o + 1] - surface.triangle_start[o]) as usize;
        let (pa, ra) = a.split_at_mut(vertices);
        let (pb, rb) = b.split_at_mut(triangles);
        parts.push((o, (pa, pb)));
        (a, b) = (ra, rb);
    }
    parts
}
