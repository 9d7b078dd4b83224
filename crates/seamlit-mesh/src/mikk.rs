//! MikkTSpace tangents over the whole welded model: in parallel, in time linear in the
//! triangles, with a result that does not depend on the number of threads.
//!
//! The algorithm is Morten S. Mikkelsen's: "Simulation of wrinkled surfaces revisited"
//! (master's thesis, University of Copenhagen, 2008), section 3.2 and appendix, as its
//! reference implementation `mikktspace.c` computes it (the code Blender, Substance, xNormal
//! and glTF's sample models use to bake and read normal maps; `bevy_mikktspace` is a line by
//! line port, and this crate's tests check against it). Its steps, as named below:
//!
//! 1. [`face_tangents`]: per triangle, the first-order tangent `s` and bitangent `t` (the
//!    thesis' equations 18 and 19), normalised, signed by the UV orientation; a triangle with
//!    (near) zero UV area or zero `s` or `t` "groups with any" neighbour and adds nothing; a
//!    triangle two of whose corners share a position is degenerate.
//! 2. A *vertex*, in MikkTSpace's sense, is a (position, normal, UV) triple with exact
//!    equality. The positions are the welded ones: every object's copy of a position is the
//!    same position, so a seam corner of one object and its copy in the next are one vertex
//!    when their normal and UV agree ([`Vertex`]).
//! 3. Around each vertex, triangles that share an edge through it and agree in UV
//!    orientation form a *group* (mikktspace.c's `Build4RuleGroups`); a group with-any
//!    triangle takes the orientation of the group that reaches it first
//!    ([`resolve_orientations`]).
//! 4. A group's tangent is the sum, over its triangles, of `s` projected into the vertex's
//!    tangent plane, normalised, weighted by the triangle's angle at the vertex measured in that
//!    plane (`EvalTspace`); triangles whose projected `s` or `t` point exactly opposite are
//!    split into sub-groups first (mikktspace.c's default angular threshold, 180 degrees).
//! 5. A degenerate triangle's corner takes the tangent of the first healthy corner of its
//!    vertex (`DegenEpilogue`).
//!
//! mikktspace.c finds the groups by sorting every edge of the model and walking each group
//! recursively, triangle by triangle; `bevy_mikktspace` also searches every healthy triangle
//! for each degenerate one, so both grow faster than the model (a 1M-triangle teapot with
//! poles took 3.8 s). Here:
//!
//! - each corner's vertex becomes one 64-bit key ([`keys`]): the first vertex of its position
//!   with the same UV (and, where normals are per vertex, the same normal), and a number that
//!   tells the normals at one position apart; keys are computed in corner order, where memory
//!   is read in sequence, so that the steps after compare integers;
//! - the corners are gathered by position with a sort on the weld's roots, and each
//!   position's groups are found from its corners alone (two triangles share an edge through
//!   a vertex when the next vertex of one is the previous vertex of the other: keys of the
//!   same triangle), with union-find.
//!
//! Positions are independent, so they run in parallel; every sum runs in corner order, so the
//! result does not depend on the number of threads.
//!
//! Where this differs from mikktspace.c (both documented there as its own choices, and
//! outside what a well-formed model hits): an edge shared by more than two triangles joins
//! them all (mikktspace.c pairs them in sort order); and a group-with-any triangle takes the
//! orientation of its first edge-neighbour in triangle order that has one, rather than of the
//! first group its recursive walk reaches.

mod face;
mod keys;
mod plain;
mod position;

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use crate::VAxis;
use keys::{FirstEqual, Keys, first_equal_vertex};
use plain::{Fans, PlainFans, plain_fans};
use position::{ByPosition, resolve_orientations};

/// The model as MikkTSpace sees it, in model space.
pub(crate) struct Surface<'a, N> {
    /// Per vertex, snapped onto its weld root (equal positions, equal roots).
    pub positions: &'a [Vec3],
    /// Per vertex: its weld root.
    pub roots: &'a [u32],
    /// Per object: its vertices' UVs (`None` for an object without: zero). Per object, as the
    /// model holds them, so that nothing is copied.
    pub uvs: &'a [Option<&'a [Vec2]>],
    /// Per object: its triangles, indexing its own vertices (its first vertex is 0).
    pub triangles: &'a [&'a [[u32; 3]]],
    /// Per object: its first vertex and first triangle, one extra entry at the end (an
    /// object's triangles use its vertices only).
    pub vertex_start: &'a [u32],
    pub triangle_start: &'a [u32],
    /// `normal(corner, vertex)`: the unit normal of corner `triangle * 3 + k` and a key that,
    /// together with `vertex_normals`, tells normals at one position apart: corners of one
    /// position whose normals are bit for bit equal must have equal keys where
    /// `vertex_normals` is `None`.
    pub normal: N,
    /// Where normals are per vertex: those normals (the keys are then 0).
    pub vertex_normals: Option<&'a [Vec3]>,
    /// For glTF (V down) the V coordinate is flipped before MikkTSpace sees it, so that its
    /// bitangent points up the image, as with OBJ's V.
    pub v_axis: VAxis,
    /// Whether the pass over the triangles also counts them as the report does
    /// ([`Tangents::counts`]): it has each triangle's positions and UVs at hand.
    pub count: bool,
}

impl<N> Surface<'_, N> {
    /// How many triangles the model has.
    fn triangle_count(&self) -> usize {
        self.triangle_start.last().map_or(0, |&n| n as usize)
    }

    /// The object triangle `t` belongs to.
    fn object_of_triangle(&self, t: usize) -> usize {
        crate::index::part_of(self.triangle_start, t)
    }

    /// Triangle `t`'s vertices, numbered across the model.
    fn triangle(&self, t: usize) -> [u32; 3] {
        let o = self.object_of_triangle(t);
        let base = self.vertex_start[o];
        self.triangles[o][t - self.triangle_start[o] as usize].map(|v| v + base)
    }

    /// Vertex `v`'s UV (zero in an object without UVs).
    fn uv(&self, v: usize) -> Vec2 {
        let o = crate::index::part_of(self.vertex_start, v);
        self.uvs[o].map_or(Vec2::ZERO, |uvs| uvs[v - self.vertex_start[o] as usize])
    }

    /// Triangle `t`'s vertices (numbered across the model) and their UVs.
    fn corners(&self, t: usize) -> ([u32; 3], [Vec2; 3]) {
        let o = self.object_of_triangle(t);
        let base = self.vertex_start[o];
        let local = self.triangles[o][t - self.triangle_start[o] as usize];
        let uv = self.uvs[o].map_or([Vec2::ZERO; 3], |uvs| local.map(|v| uvs[v as usize]));
        (local.map(|v| v + base), uv)
    }
}

/// MikkTSpace's tangent of every corner of a [`Surface`]: see [`Tangents::fan_of`] and
/// [`Tangents::others`].
pub(crate) fn tangents<N>(surface: &Surface<'_, N>) -> Tangents
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    tangents_with(surface, false)
}

/// [`tangents`], optionally sending every position through the grouping (for tests: both
/// paths must give the same bits).
fn tangents_with<N>(surface: &Surface<'_, N>, all_grouped: bool) -> Tangents
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    let FirstEqual { first, shared } = first_equal_vertex(surface);
    let PlainFans { mut faces, mut plain, fans, counts } = plain_fans(surface, &shared);
    drop(shared);
    if all_grouped {
        plain.fill(false);
    }
    let keys = Keys::of(surface, &first, &plain);
    drop(first);
    let by_position = ByPosition::gather(surface, &plain, &keys);
    resolve_orientations(surface, &keys, &by_position, &mut faces);
    let raw = by_position.evaluate(surface, &keys, &faces);
    drop(keys);
    let mut rest: Vec<(u32, Vec4)> = by_position.corners.iter().copied().zip(raw).collect();
    rest.par_sort_unstable_by_key(|&(c, _)| c);
    Tangents { plain, fans, rest, counts: surface.count.then_some(counts) }
}

/// The result of [`tangents`].
pub(crate) struct Tangents {
    /// Per root vertex: whether its position is plain (see [`plain_fans`]).
    plain: Vec<bool>,
    /// Per vertex at a plain position: its fan's sum.
    fans: Fans,
    /// The tangent of every corner at the other positions, sorted by corner.
    rest: Vec<(u32, Vec4)>,
    /// Where the [`Surface`] asked for them, the report's triangle counts (degenerate,
    /// degenerate-UV, mirrored; see [`crate::face::count`]) over its positions.
    counts: Option<[usize; 3]>,
}

impl Tangents {
    /// The report's triangle counts, where the [`Surface`] asked for them.
    pub fn counts(&self) -> Option<[usize; 3]> {
        self.counts
    }

    /// Per object, per vertex: the sums [`Self::fan_of`] makes the plain fans' tangents of,
    /// taken. Each array is as long as its object's vertices and as wide as a tangent: it can
    /// become the object's tangents, each vertex's sum read before its tangent is written.
    pub fn take_sums(&mut self) -> Vec<Vec<Vec4>> {
        std::mem::take(&mut self.fans.sums)
    }

    /// The tangent of every corner of vertex `v` (whose root is `root`), where its position
    /// is plain: all its corners have one, made orthogonal to their `normal`, the one the
    /// [`Surface`] gave them; from the vertex's `sum`, one of [`Self::take_sums`]'.
    pub fn fan_of(&self, v: usize, root: usize, normal: Vec3, sum: Vec4) -> Option<Vec4> {
        self.plain[root].then(|| self.fans.tangent_of(v, normal, sum))
    }

    /// Whether the position of root `root` is plain: [`Self::fan_of`] gives its tangents.
    pub fn is_plain(&self, root: usize) -> bool {
        self.plain[root]
    }

    /// The corners in `corners` at positions that are not plain, ascending, with their
    /// tangents.
    pub fn others(&self, corners: std::ops::Range<usize>) -> &[(u32, Vec4)] {
        let at = |c: usize| self.rest.partition_point(|&(e, _)| (e as usize) < c);
        &self.rest[at(corners.start)..at(corners.end)]
    }

    /// The tangent of corner `c` (`triangle * 3 + k`) at a position that is not plain.
    #[cfg(test)]
    fn other(&self, c: usize) -> Vec4 {
        let i = self.rest.partition_point(|&(e, _)| (e as usize) < c);
        debug_assert_eq!(self.rest.get(i).map(|e| e.0 as usize), Some(c), "corner {c} is plain");
        self.rest[i].1
    }

    /// The tangent of corner `c` (`triangle * 3 + k`) at vertex `v` whose root is `root` and
    /// whose normal is `normal`: MikkTSpace's, made orthogonal to the corner's normal (it
    /// is, up to rounding), `w` the handedness. A corner MikkTSpace leaves without a tangent
    /// space (a degenerate triangle whose vertex has no healthy one) gets a direction across
    /// its normal, `w = +1`.
    #[cfg(test)]
    fn get(&self, c: usize, v: usize, root: usize, normal: Vec3) -> Vec4 {
        let (mut o, mut i) = (0, v);
        while i >= self.fans.sums[o].len() {
            (i, o) = (i - self.fans.sums[o].len(), o + 1);
        }
        self.fan_of(v, root, normal, self.fans.sums[o][i]).unwrap_or_else(|| self.other(c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::index::index;

    /// A wavy grid of `n` x `n` quads whose right half has mirrored U, in one object, with
    /// per-vertex normals (the grid's up, tilted by the waves).
    fn wavy(n: u32) -> (Vec<Vec3>, Vec<Vec2>, Vec<[u32; 3]>, Vec<Vec3>) {
        let (mut p, mut uv, mut normals, mut tris) = (vec![], vec![], vec![], vec![]);
        for j in 0..=n {
            for i in 0..=n {
                let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
                let y = (x * 7.0).sin() * 0.1 + (z * 5.0).cos() * 0.1;
                p.push(Vec3::new(x, y, z));
                let u = if x > 0.5 { 1.0 - x } else { x };
                uv.push(Vec2::new(u, z));
                normals.push(
                    Vec3::new(-(x * 7.0).cos() * 0.7, 1.0, (z * 5.0).sin() * 0.5).normalize(),
                );
            }
        }
        let w = n + 1;
        for j in 0..n {
            for i in 0..n {
                let a = j * w + i;
                tris.push([a, a + w, a + w + 1]);
                tris.push([a, a + w + 1, a + 1]);
            }
        }
        (p, uv, tris, normals)
    }

    /// The tangent of every corner of one object, by the plain fans where they apply and by
    /// the grouping for every position.
    fn both_paths(
        positions: &[Vec3],
        uvs: &[Vec2],
        triangles: &[[u32; 3]],
        normals: &[Vec3],
    ) -> (Tangents, Tangents) {
        let roots: Vec<u32> = (0..index(positions.len())).collect();
        let (vertex_start, triangle_start) =
            ([0, index(positions.len())], [0, index(triangles.len())]);
        let surface = Surface {
            positions,
            roots: &roots,
            uvs: &[Some(uvs)],
            triangles: &[triangles],
            vertex_start: &vertex_start,
            triangle_start: &triangle_start,
            normal: |_, v: usize| (normals[v], 0),
            vertex_normals: Some(normals),
            v_axis: VAxis::Up,
            count: false,
        };
        (tangents_with(&surface, false), tangents_with(&surface, true))
    }

    /// Two triangles that meet only at vertex 0, with one UV there: two fans, each open, of
    /// one orientation, whose tangents point along x and along y. MikkTSpace makes two groups
    /// of the vertex's corners (no edge joins them); summed as one fan, both corners would get
    /// the diagonal.
    #[test]
    fn a_vertex_pinched_between_two_fans_is_two_groups() {
        let positions = [
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(-1.0, -1.0, 0.0),
        ];
        let uvs = [
            Vec2::new(0.5, 0.5),
            Vec2::new(1.0, 0.5),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.5, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        let triangles = [[0, 1, 2], [0, 3, 4]];
        let normals = [Vec3::Z; 5];
        let (fast, grouped) = both_paths(&positions, &uvs, &triangles, &normals);
        for (c, &v) in triangles.as_flattened().iter().enumerate() {
            let v = v as usize;
            let (a, b) = (fast.get(c, v, v, Vec3::Z), grouped.get(c, v, v, Vec3::Z));
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits),
                "corner {c}"
            );
        }
        // Each of vertex 0's corners has its own triangle's tangent.
        let (t0, t3) = (grouped.get(0, 0, 0, Vec3::Z), grouped.get(3, 0, 0, Vec3::Z));
        assert!(t0.abs_diff_eq(Vec4::new(1.0, 0.0, 0.0, 1.0), 1e-6), "{t0}");
        assert!(t3.abs_diff_eq(Vec4::new(0.0, 1.0, 0.0, 1.0), 1e-6), "{t3}");
    }

    #[test]
    fn plain_fans_give_the_bits_of_the_grouping() {
        let (positions, uvs, triangles, normals) = wavy(24);
        let (fast, grouped) = both_paths(&positions, &uvs, &triangles, &normals);
        let plain = fast.plain.iter().filter(|&&p| p).count();
        assert!(plain > positions.len() / 2, "{plain} plain positions");
        for (c, &v) in triangles.as_flattened().iter().enumerate() {
            let (v, n) = (v as usize, normals[v as usize]);
            let (a, b) = (fast.get(c, v, v, n), grouped.get(c, v, v, n));
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits),
                "corner {c}"
            );
        }
    }
}
