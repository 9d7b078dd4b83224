//! Plain positions: the fans whose tangent is one group's sum, found and summed in one pass
//! per object without the grouping.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::Surface;
use super::face::{ANY, DEGENERATE, ORIENTED, corner_terms, plain_tangent};

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

/// Per root vertex: whether every vertex of its position is *plain*, one MikkTSpace group
/// whose tangent [`plain_fans`] sums in one pass: its corners share one normal (a simple
/// position) and it shares its key with no other vertex; its triangles are healthy (none
/// with-any, none degenerate) and of one orientation; and they close around it (every
/// triangle's next vertex is another's previous one: the sums of their spread keys agree).
/// Such a fan is one group. The rest (boundaries of objects and UV islands, mirror lines,
/// creases, poles) go through the grouping, position by position.
///
/// One case a closed fan does not rule out: two closed fans pinched at one vertex with one
/// UV, two groups for MikkTSpace; they are summed as one here.
pub(super) fn plain_positions<N>(
    surface: &Surface<'_, N>,
    faces: &[u8],
    shared: &[bool],
) -> Vec<bool>
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    let n = surface.roots.len();
    let mut flags = vec![0u8; n];
    let mut fans = vec![0u64; n];
    let parts = split_by_object(surface, &mut flags, &mut fans);
    parts.into_par_iter().for_each(|(o, (flags, fans))| {
        let base = surface.vertex_start[o] as usize;
        let triangles = surface.triangle_start[o] as usize..surface.triangle_start[o + 1] as usize;
        for t in triangles {
            let face = faces[t];
            let bits = if face & (ANY | DEGENERATE) != 0 {
                IRREGULAR
            } else if face & ORIENTED != 0 {
                HAS_ORIENTED
            } else {
                HAS_REVERSED
            };
            let tri = surface.triangles[t];
            for (k, &v) in tri.iter().enumerate() {
                let normal =
                    if (surface.normal)(t * 3 + k, v as usize).1 != 0 { IRREGULAR } else { 0 };
                let v = v as usize - base;
                flags[v] |= bits | normal;
                // Vertices, not keys: a fan closed by vertex is closed by key (at a simple
                // position the corners of one vertex across an edge share a normal group);
                // one closed only through another vertex with the same key is not plain.
                let (next, prev) =
                    (spread(tri[(k + 1) % 3].into()), spread(tri[(k + 2) % 3].into()));
                fans[v] = fans[v].wrapping_add(next).wrapping_sub(prev);
            }
        }
    });
    let mut plain = vec![true; n];
    for v in 0..n {
        let f = flags[v];
        let mixed = f & (HAS_ORIENTED | HAS_REVERSED) == HAS_ORIENTED | HAS_REVERSED;
        if f & IRREGULAR != 0 || mixed || fans[v] != 0 || shared[v] {
            plain[surface.roots[v] as usize] = false;
        }
    }
    plain
}

/// One object's part of two per-vertex arrays, with the object's number.
pub(super) type ObjectPart<'x, A, B> = (usize, (&'x mut [A], &'x mut [B]));

/// `a` and `b` (one entry per vertex) cut into each object's part, numbered.
pub(super) fn split_by_object<'x, N, A, B>(
    surface: &Surface<'_, N>,
    mut a: &'x mut [A],
    mut b: &'x mut [B],
) -> Vec<ObjectPart<'x, A, B>> {
    let mut parts = Vec::with_capacity(surface.vertex_start.len());
    for (o, w) in surface.vertex_start.windows(2).enumerate() {
        let len = (w[1] - w[0]) as usize;
        let (pa, ra) = a.split_at_mut(len);
        let (pb, rb) = b.split_at_mut(len);
        parts.push((o, (pa, pb)));
        (a, b) = (ra, rb);
    }
    parts
}

/// Per vertex at a plain position (see [`plain_positions`]): the tangent of its one group,
/// summed over its corners in triangle order, as [`Position`] sums a group.
pub(super) fn plain_fans<N>(surface: &Surface<'_, N>, plain: &[bool]) -> Vec<Vec4>
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    let n = surface.roots.len();
    let mut sums = vec![Vec4::ZERO; n];
    let mut normals = vec![Vec3::ZERO; n];
    let parts = split_by_object(surface, &mut sums, &mut normals);
    parts.into_par_iter().for_each(|(o, (sums, normals))| {
        let base = surface.vertex_start[o] as usize;
        let triangles = surface.triangle_start[o] as usize..surface.triangle_start[o + 1] as usize;
        for t in triangles {
            let tri = surface.triangles[t];
            let is_plain = tri.map(|v| plain[surface.roots[v as usize] as usize]);
            if is_plain == [false; 3] {
                continue;
            }
            let n: [Vec3; 3] =
                std::array::from_fn(|k| (surface.normal)(t * 3 + k, tri[k] as usize).0);
            let face = plain_tangent(surface, t);
            let terms = corner_terms(surface, &face, t, n);
            let w = if face.is(ORIENTED) { 1.0 } else { -1.0 };
            for k in 0..3 {
                if is_plain[k] {
                    let v = tri[k] as usize - base;
                    let (s, angle) = terms[k];
                    sums[v] += (s * angle).extend(0.0);
                    sums[v].w = w;
                    normals[v] = n[k];
                }
            }
        }
        for (sum, n) in sums.iter_mut().zip(normals.iter()) {
            if sum.w != 0.0 {
                *sum = crate::frame::orthogonal_tangent(*n, sum.truncate()).extend(sum.w);
            }
        }
    });
    sums
}
