//! Steps 3 to 5, position by position: the groups of corners around each vertex, their
//! orientations, and their tangents.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::Surface;
use super::face::{ANY, DEGENERATE, FaceTangent, ORIENTED, corner_terms, face_tangent};
use super::keys::Keys;
use crate::index::{index, low_half};
use crate::weld::union;

/// Corner `c`'s triangle (whose first-order frame is `f`) in the tangent plane of the vertex
/// normal `n`: its `s` and `t` projected and normalised, and its angle at the vertex between
/// its edges projected (mikktspace.c's `EvalTspace`).
pub(super) fn frame<N>(surface: &Surface<'_, N>, f: &FaceTangent, c: usize, n: Vec3) -> Projected {
    let (s, angle) = corner_terms(surface, f, surface.triangle(c / 3), [n; 3])[c % 3];
    Projected { s, t: (f.t - n * n.dot(f.t)).normalize_or_zero(), angle }
}

/// The corners of the positions that are not plain, sorted by position (weld root), in corner
/// order within each.
pub(super) struct ByPosition {
    /// The roots of the positions that are not plain, ascending.
    roots: Vec<u32>,
    /// Per entry `i` of `roots`: its corners are `corners[offsets[i]..offsets[i + 1]]` (one
    /// extra entry at the end).
    offsets: Vec<u32>,
    pub(super) corners: Vec<u32>,
}

impl ByPosition {
    /// The corners at positions that are not `plain`, sorted by their vertex's root, found
    /// among the corners of the triangles that touch such a position (`keys`).
    pub(super) fn gather<N>(surface: &Surface<'_, N>, plain: &[bool], keys: &Keys) -> Self
    where
        N: Sync,
    {
        let roots = surface.roots;
        let mut entries: Vec<u64> = keys
            .triangles()
            .par_iter()
            .flat_map_iter(|&t| {
                let tri = surface.triangle(t as usize);
                (0..3).filter_map(move |k| {
                    let r = roots[tri[k] as usize];
                    let corner = u64::from(t) * 3 + k as u64;
                    (!plain[r as usize]).then_some((u64::from(r) << 32) | corner)
                })
            })
            .collect();
        entries.par_sort_unstable();
        let mut offsets: Vec<u32> = (0..entries.len())
            .filter(|&i| i == 0 || entries[i] >> 32 != entries[i - 1] >> 32)
            .map(index)
            .collect();
        let roots = offsets.iter().map(|&i| (entries[i as usize] >> 32) as u32).collect();
        offsets.push(index(entries.len()));
        Self { roots, offsets, corners: entries.into_iter().map(low_half).collect() }
    }

    /// The corners at root `r`, a position that is not plain.
    fn at(&self, r: u32) -> &[u32] {
        let i = self.roots.partition_point(|&e| e < r);
        debug_assert_eq!(self.roots.get(i), Some(&r), "position {r} is not plain");
        &self.corners[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Steps 3 to 5 for every position, in parallel: each corner's tangent, in the order of
    /// `corners`.
    pub(super) fn evaluate<N>(
        &self,
        surface: &Surface<'_, N>,
        keys: &Keys,
        faces: &[u8],
    ) -> Vec<Vec4>
    where
        N: Fn(usize, usize) -> (Vec3, u32) + Sync,
    {
        let mut raw = vec![Vec4::ZERO; self.corners.len()];
        // Blocks of positions, cut where a position ends, about this many corners each: many
        // more blocks than threads. At 16,384 the 1M teapot's few blocks left one of two
        // threads with three quarters of the work.
        const BLOCK: usize = 1 << 11;
        let positions = self.offsets.len() - 1;
        let mut blocks = Vec::new();
        let mut rest: &mut [Vec4] = &mut raw;
        let mut start = 0;
        while start < positions {
            let mut end = start + 1;
            while end < positions && (self.offsets[end] - self.offsets[start]) as usize <= BLOCK {
                end += 1;
            }
            let len = (self.offsets[end] - self.offsets[start]) as usize;
            let (block, tail) = rest.split_at_mut(len);
            blocks.push((start..end, block));
            rest = tail;
            start = end;
        }
        blocks.into_par_iter().for_each_init(Scratch::default, |scratch, (range, out)| {
            let base = self.offsets[range.start] as usize;
            for i in range {
                let (lo, hi) = (self.offsets[i] as usize, self.offsets[i + 1] as usize);
                let at = Position { surface, keys, faces, corners: &self.corners[lo..hi] };
                at.evaluate(scratch, &mut out[lo - base..hi - base]);
            }
        });
        raw
    }
}

/// Scratch space for one position, reused from one to the next.
#[derive(Default)]
pub(super) struct Scratch {
    /// Per local corner: its key, and the keys of the vertices after and before it in its
    /// triangle.
    key: Vec<u64>,
    next: Vec<u64>,
    prev: Vec<u64>,
    /// Local corners sorted by key (then corner).
    order: Vec<u32>,
    /// The healthy corners of one vertex (local indices), in corner order.
    members: Vec<u32>,
    /// Union-find over `members`.
    parent: Vec<u32>,
    /// `members` sorted by their previous vertex's key.
    by_prev: Vec<u32>,
    /// `members`' indices sorted by group.
    by_group: Vec<u32>,
    /// One group's local corners, in corner order.
    group: Vec<u32>,
    /// Per corner of `group`: its triangle seen from the vertex (`None`: a with-any one).
    frames: Vec<Option<Projected>>,
    /// Sub-groups of one group: their member lists and results.
    sub_members: Vec<Vec<u32>>,
    sub_result: Vec<Vec4>,
}

/// The corners at one position.
pub(super) struct Position<'a, 'b, N> {
    surface: &'a Surface<'b, N>,
    keys: &'a Keys,
    /// Per triangle: its flags.
    faces: &'a [u8],
    /// Global corner indices, ascending.
    corners: &'a [u32],
}

impl<N> Position<'_, '_, N>
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    /// The flags of local corner `a`'s triangle.
    fn flags(&self, a: usize) -> u8 {
        self.faces[self.corners[a] as usize / 3]
    }

    /// Writes the tangent of every corner at this position into `out` (aligned with
    /// `self.corners`).
    fn evaluate(&self, s: &mut Scratch, out: &mut [Vec4]) {
        let k = self.corners.len();
        s.key.clear();
        s.next.clear();
        s.prev.clear();
        for &c in self.corners {
            let c = c as usize;
            let k = c % 3;
            let keys = self.keys.of_triangle(c / 3);
            s.key.push(keys[k]);
            s.next.push(keys[(k + 1) % 3]);
            s.prev.push(keys[(k + 2) % 3]);
        }
        s.order.clear();
        s.order.extend(0..index(k));
        if k > 1 {
            let key = &s.key;
            s.order.sort_unstable_by_key(|&a| (key[a as usize], a));
        }
        let mut i = 0;
        while i < k {
            let key = s.key[s.order[i] as usize];
            let mut j = i + 1;
            while j < k && s.key[s.order[j] as usize] == key {
                j += 1;
            }
            self.one_vertex(s, i..j, out);
            i = j;
        }
    }

    /// Steps 3 to 5 for the corners `s.order[range]`, which share one vertex.
    fn one_vertex(&self, s: &mut Scratch, range: std::ops::Range<usize>, out: &mut [Vec4]) {
        // Healthy corners only take part in the groups.
        s.members.clear();
        let order = &s.order[range.clone()];
        s.members
            .extend(order.iter().copied().filter(|&a| !self.flags(a as usize) & DEGENERATE != 0));
        let n = self.normal_of(s.order[range.start] as usize);
        // Corners no group reaches get a direction across the normal, w = +1.
        let none = n.any_orthonormal_vector().extend(1.0);
        for &a in order {
            out[a as usize] = none;
        }
        if !s.members.is_empty() {
            self.groups(s);
            self.group_tangents(s, n, out);
        }
        // Step 5: a degenerate triangle's corner copies the first healthy corner's result.
        let first_healthy = s.members.first().map(|&a| out[a as usize]);
        for &a in &s.order[range] {
            if self.flags(a as usize) & DEGENERATE != 0 {
                out[a as usize] = first_healthy.unwrap_or(none);
            }
        }
    }

    /// Step 3: union-find over `s.members` (into `s.parent`, every entry its root): two
    /// triangles join where they share an edge through the vertex and agree in orientation.
    fn groups(&self, s: &mut Scratch) {
        let m = s.members.len();
        s.parent.clear();
        s.parent.extend(0..index(m));
        if m == 1 {
            return;
        }
        let members = &s.members;
        s.by_prev.clear();
        s.by_prev.extend(0..index(m));
        let prev = |b: u32| s.prev[members[b as usize] as usize];
        s.by_prev.sort_unstable_by_key(|&b| (prev(b), b));
        for a in 0..m {
            let next = s.next[members[a] as usize];
            let from = s.by_prev.partition_point(|&b| prev(b) < next);
            for &b in s.by_prev[from..].iter().take_while(|&&b| prev(b) == next) {
                let (fa, fb) =
                    (self.flags(members[a] as usize), self.flags(members[b as usize] as usize));
                if (fa ^ fb) & ORIENTED == 0 {
                    union(&mut s.parent, index(a), b);
                }
            }
        }
        for a in 0..m {
            s.parent[a] = s.parent[s.parent[a] as usize];
        }
    }

    /// Step 4: each group's tangent, written for its members (`n` is the vertex's normal);
    /// corners of groups made only of with-any triangles keep what they have.
    fn group_tangents(&self, s: &mut Scratch, n: Vec3, out: &mut [Vec4]) {
        let m = s.members.len();
        // The members by group (root), in corner order within each.
        s.by_group.clear();
        s.by_group.extend(0..index(m));
        if m > 1 {
            s.by_group.sort_unstable_by_key(|&a| (s.parent[a as usize], a));
        }
        let mut i = 0;
        while i < m {
            let root = s.parent[s.by_group[i] as usize];
            let mut j = i + 1;
            while j < m && s.parent[s.by_group[j] as usize] == root {
                j += 1;
            }
            s.group.clear();
            s.group.extend(s.by_group[i..j].iter().map(|&a| s.members[a as usize]));
            self.one_group(s, n, out);
            i = j;
        }
    }

    /// Step 4 for the local corners `s.group`, one group.
    fn one_group(&self, s: &mut Scratch, n: Vec3, out: &mut [Vec4]) {
        let Some(&seed) = s.group.iter().find(|&&a| self.flags(a as usize) & ANY == 0) else {
            return;
        };
        let w = if self.flags(seed as usize) & ORIENTED != 0 { 1.0 } else { -1.0 };
        let finish = |sum: Vec3| crate::frame::orthogonal_tangent(n, sum).extend(w);
        s.frames.clear();
        for &a in &s.group {
            let a = a as usize;
            s.frames.push(if self.flags(a) & ANY != 0 { None } else { Some(self.frame(a, n)) });
        }
        if !splits(&s.frames) {
            let tangent = finish(s.frames.iter().flatten().map(|f| f.s * f.angle).sum());
            for &a in &s.group {
                out[a as usize] = tangent;
            }
            return;
        }
        // mikktspace.c's sub-groups: each member's set of similar members (with-any triangles
        // are similar to all) names its sub-group; equal sets share one result.
        s.sub_members.clear();
        s.sub_result.clear();
        for (i, &a) in s.group.iter().enumerate() {
            let similar: Vec<u32> = (0..s.group.len())
                .filter(|&j| similar(s.frames[i], s.frames[j]))
                .map(index)
                .collect();
            let l = s.sub_members.iter().position(|g| *g == similar).unwrap_or_else(|| {
                let sum: Vec3 = similar
                    .iter()
                    .filter_map(|&j| s.frames[j as usize])
                    .map(|f| f.s * f.angle)
                    .sum();
                s.sub_members.push(similar);
                s.sub_result.push(finish(sum));
                s.sub_members.len() - 1
            });
            out[a as usize] = s.sub_result[l];
        }
    }

    /// The normal of local corner `a`.
    fn normal_of(&self, a: usize) -> Vec3 {
        let c = self.corners[a] as usize;
        (self.surface.normal)(c, self.surface.triangle(c / 3)[c % 3] as usize).0
    }

    /// Local corner `a`'s triangle seen from the vertex: see [`frame`].
    fn frame(&self, a: usize, n: Vec3) -> Projected {
        let c = self.corners[a] as usize;
        frame(self.surface, &face_tangent(self.surface, c / 3), c, n)
    }
}

/// One healthy triangle of a group, seen from the vertex: see [`Position::frame`].
#[derive(Clone, Copy, Debug)]
pub(super) struct Projected {
    s: Vec3,
    t: Vec3,
    angle: f32,
}

/// Whether members `a` and `b` of a group are similar at mikktspace.c's default threshold
/// (180 degrees: a cosine above -1); with-any triangles (`None`) are similar to all.
pub(super) fn similar(a: Option<Projected>, b: Option<Projected>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => a.s.dot(b.s) > -1.0 && a.t.dot(b.t) > -1.0,
        _ => true,
    }
}

/// Whether a group needs sub-groups: two of its members are not similar.
pub(super) fn splits(frames: &[Option<Projected>]) -> bool {
    frames.iter().enumerate().any(|(i, &a)| frames[i + 1..].iter().any(|&b| !similar(a, b)))
}

/// Step 3's one order dependency: a with-any triangle takes an orientation from a neighbour.
/// In triangle order, each takes that of its first edge-neighbour (in corner order around
/// each of its vertices) that is healthy or already resolved; one without keeps its own.
pub(super) fn resolve_orientations<N>(
    surface: &Surface<'_, N>,
    keys: &Keys,
    by_position: &ByPosition,
    faces: &mut [u8],
) {
    let is = |flags: u8, flag: u8| flags & flag != 0;
    let any: Vec<usize> = (0..faces.len())
        .into_par_iter()
        .filter(|&f| is(faces[f], ANY) && !is(faces[f], DEGENERATE))
        .collect();
    let mut resolved = vec![false; faces.len()];
    for f in any {
        let mut found = None;
        let own = keys.of_triangle(f);
        'corners: for k in 0..3 {
            let (next, prev) = (own[(k + 1) % 3], own[(k + 2) % 3]);
            let r = surface.roots[surface.triangle(f)[k] as usize];
            for &b in by_position.at(r) {
                let (g, kb) = (b as usize / 3, b as usize % 3);
                let fb = faces[g];
                if g == f || is(fb, DEGENERATE) || (is(fb, ANY) && !resolved[g]) {
                    continue;
                }
                let theirs = keys.of_triangle(g);
                if theirs[kb] != own[k] {
                    continue;
                }
                if theirs[(kb + 2) % 3] == next || theirs[(kb + 1) % 3] == prev {
                    found = Some(fb & ORIENTED);
                    break 'corners;
                }
            }
        }
        if let Some(oriented) = found {
            faces[f] = (faces[f] & !ORIENTED) | oriented;
        }
        resolved[f] = true;
    }
}
