//! Welding: map positions to shared ids, so that vertices of different objects that sit at the
//! same place (within a tolerance) are recognised as one.
//!
//! This is the explicit position remap that seam-free attributes start from
//! (meshoptimizer's `meshopt_generatePositionRemap`, with a tolerance): shared indices stop at
//! object boundaries, positions do not.
//!
//! # Algorithm
//!
//! With a tolerance `tol > 0`, positions are quantised into cubic cells of side
//! `cell >= tol` (64 tolerances, unless the model is so large that 2^20 cells per axis need
//! more). Each position is entered under its own cell and, when it lies within `tol` of a cell
//! face, also under the neighbouring cells across that face (and the edge and corner between
//! two or three such faces). Two positions within `tol` of each other then always share a
//! cell: the second one's own, which the first is within `tol` of. So comparing the positions
//! that share a cell finds every pair; nothing within tolerance is missed because it fell into
//! another cell, and no neighbour lookups are needed. With cells 64 tolerances wide, about
//! one position in ten has a second entry.
//!
//! The entries are `hash(cell) << 32 | index` in one `u64`, sorted in parallel; a run of equal
//! hashes holds the positions of one cell (a rare hash collision merges two cells: more
//! comparisons, never a wrong weld, since every pair is compared by distance). Within a run,
//! copies of one position (the usual content: a vertex of several objects) are compared once.
//! Pairs within tolerance are joined with a union-find whose root is the smallest index, so
//! the ids do not depend on the number of threads. Welding is transitive: a chain of
//! positions each within `tol` of the next becomes one id (with the default tolerance of 1e-6
//! of the bounding-box diagonal, such chains do not occur in real models).
//!
//! With `tol == 0`, the entries are hashes of the positions' bits (with `-0.0 == 0.0`), and
//! positions weld only when their bits are equal.
//!
//! Cost: the sort of about 1.1 n entries, then O(n) (O(k d) for a cell of k
//! positions of which d are distinct: d = 1 for copies of a point).

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use crate::index::{index, low_half};
use crate::validate::Flat;
use crate::{Mode, WeldTolerance};

/// The result of [`weld`]: a shared id per input position. The pipeline works with
/// [`roots`]; this compact form is for the tests.
#[cfg(test)]
#[derive(Clone, Debug, PartialEq, Eq)]
struct Weld {
    /// For each input position, its id in `0..count`. Ids are numbered in order of first
    /// appearance, so the first position gets id 0.
    pub ids: Vec<u32>,
    /// Number of distinct ids.
    pub count: usize,
}

/// A model's weld, handed from one step to the next so that none welds the model again: the
/// weld of a model as loaded ([`crate::report_with_weld`]), which
/// [`crate::fix_in_place_welded`] fixes it with, and the weld a fix smoothed over, for the
/// model it fixed, which [`crate::report_welded`] measures it with.
#[derive(Clone, Debug)]
pub struct Welded {
    /// Per vertex of the model (numbered across its objects), its root: see [`roots`].
    roots: Vec<u32>,
    /// The tolerance it was welded with (absolute from the model's diagonal, which a fix does
    /// not change).
    tolerance: WeldTolerance,
    /// The report's triangle counts (degenerate, degenerate-UV, mirrored) over the positions
    /// snapped to `roots`, where they were counted on the way: a fix keeps every triangle's
    /// positions and UVs, so those of a model are those of the model fixed.
    counts: Option<[usize; 3]>,
}

impl Welded {
    pub(crate) fn new(
        roots: Vec<u32>,
        tolerance: WeldTolerance,
        counts: Option<[usize; 3]>,
    ) -> Self {
        Self { roots, tolerance, counts }
    }

    /// The roots, where they are the weld of a model of `vertices` vertices at `tolerance`: a
    /// weld of another model, or at another tolerance, is not used.
    pub(crate) fn roots_for(&self, vertices: usize, tolerance: WeldTolerance) -> Option<&[u32]> {
        (self.roots.len() == vertices && self.tolerance == tolerance).then_some(&self.roots[..])
    }

    /// The triangle counts, where the roots are [`Self::roots_for`] the model and counted.
    pub(crate) fn counts_for(
        &self,
        vertices: usize,
        tolerance: WeldTolerance,
    ) -> Option<[usize; 3]> {
        self.roots_for(vertices, tolerance).and(self.counts)
    }
}

/// Moves every position onto its root's (see [`roots`]), so that geometry computed afterwards
/// sees welded positions as one point: a sliver between two positions closer than the
/// tolerance becomes a degenerate triangle, not a face with a random normal.
///
/// Few positions move (none where the weld is exact): they are found in parallel, then
/// moved.
pub(crate) fn snap_to_roots(positions: &mut [Vec3], roots: &[u32]) {
    let bits = |p: Vec3| p.to_array().map(f32::to_bits);
    let moved = off_their_roots(roots, |v, r| bits(positions[v]) != bits(positions[r]));
    for (v, r) in moved {
        // The root is the smallest index of its set, its own root: not moved.
        positions[v as usize] = positions[r as usize];
    }
}

/// Per root (see [`roots`]): whether the positions welded to it are not all bit-equal to it
/// (with `-0.0 == 0.0`), i.e. whether the tolerance alone made that weld. Index by root.
pub(crate) fn near_misses(positions: &[Vec3], roots: &[u32]) -> Vec<bool> {
    let mut flagged = vec![false; roots.len()];
    for (_, r) in off_their_roots(roots, |v, r| !same_bits(positions[v], positions[r])) {
        flagged[r as usize] = true;
    }
    flagged
}

/// The vertices `v` welded to another vertex `r` (their root) for which `differs(v, r)`, with
/// their roots, found in parallel: one pass over the vertices on every core, where the
/// callers then visit only the few it finds.
fn off_their_roots(
    roots: &[u32],
    differs: impl Fn(usize, usize) -> bool + Sync,
) -> Vec<(u32, u32)> {
    roots
        .par_iter()
        .enumerate()
        .filter(|&(v, &r)| r as usize != v && differs(v, r as usize))
        .map(|(v, &r)| (index(v), r))
        .collect()
}

/// Whether two positions have equal bits (with `-0.0 == 0.0`).
fn same_bits(a: Vec3, b: Vec3) -> bool {
    exact_key(a) == exact_key(b)
}

/// The bits of a position with `-0.0` mapped to `0.0`.
fn exact_key(p: Vec3) -> [u32; 3] {
    // Adding 0.0 turns -0.0 into +0.0 and leaves every other value unchanged.
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// Welds `positions` with an absolute `tolerance` (`0.0`: exact bits).
///
/// All positions must be finite (the fix pipeline checks this first). A negative or NaN
/// tolerance is treated as `0.0`.
#[cfg(test)]
#[must_use]
fn weld(positions: &[Vec3], tolerance: f32) -> Weld {
    compact(roots(positions, tolerance))
}

/// For each position, the smallest index of its weld set: the form the pipeline works with
/// (a position's *root* doubles as its id, and the root's slot in per-vertex arrays holds what
/// belongs to the whole position). See [`weld`].
pub(crate) fn roots(positions: &[Vec3], tolerance: f32) -> Vec<u32> {
    if tolerance > 0.0 && tolerance.is_finite() {
        weld_tolerant(positions, tolerance)
    } else {
        weld_exact(positions)
    }
}

/// Numbers the union-find roots in order of first appearance. `parent[i] <= i`, and roots are
/// their own parents, so one forward pass suffices.
#[cfg(test)]
fn compact(mut parent: Vec<u32>) -> Weld {
    let mut count = 0u32;
    for i in 0..parent.len() {
        let p = parent[i] as usize;
        if p == i {
            parent[i] = count;
            count += 1;
        } else {
            // `p < i`: already renumbered, and its root's id was written there.
            parent[i] = parent[p];
        }
    }
    Weld { ids: parent, count: count as usize }
}

/// A 32-bit hash of a 64-bit key (Fibonacci hashing). Equal keys give equal hashes; the few
/// unequal keys that collide only cost a comparison.
fn hash(key: u64) -> u64 {
    key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 32
}

/// How two positions relate.
#[derive(PartialEq)]
enum Relation {
    Apart,
    /// Within the tolerance.
    Near,
    /// Bit-equal (with `-0.0 == 0.0`).
    Identical,
}

/// Sorts `entries` (`hash << 32 | index`) and joins, within every run of equal hashes, the
/// indices that are [`Relation::Near`] or [`Relation::Identical`]. Returns the union-find
/// forest, flattened: every entry is the smallest index of its set.
fn join_runs(
    n: usize,
    mut entries: Vec<u64>,
    relate: impl Fn(u32, u32) -> Relation + Sync,
) -> Vec<u32> {
    // In place and in parallel; by hash, then index (the whole `u64`), so the order does not
    // depend on the threads. (A radix sort was no faster here and needs a second buffer.)
    entries.par_sort_unstable();
    let pairs: Vec<(u32, u32)> = entries
        .par_chunk_by(|a, b| a >> 32 == b >> 32)
        .filter(|run| run.len() > 1)
        .flat_map_iter(|run| {
            let mut out = Vec::new();
            // A position bit-equal to an earlier one (the usual case: copies of a boundary
            // vertex) is joined to it and compared no further: it has the same neighbours. So
            // a run of k copies of one point costs O(k), not O(k^2).
            let mut distinct: Vec<u32> = Vec::new();
            for &e in run {
                let i = low_half(e);
                let mut copy = false;
                for &j in &distinct {
                    match relate(j, i) {
                        Relation::Apart => {}
                        Relation::Near => out.push((j, i)),
                        Relation::Identical => {
                            out.push((j, i));
                            copy = true;
                            break;
                        }
                    }
                }
                if !copy {
                    distinct.push(i);
                }
            }
            out
        })
        .collect();
    let mut parent: Vec<u32> = (0..index(n)).collect();
    for (a, b) in pairs {
        union(&mut parent, a, b);
    }
    // Every entry points at its root: `parent[i] <= i`, so one forward pass suffices.
    for i in 0..parent.len() {
        parent[i] = parent[parent[i] as usize];
    }
    parent
}

fn weld_exact(positions: &[Vec3]) -> Vec<u32> {
    let entries: Vec<u64> = positions
        .par_iter()
        .enumerate()
        .map(|(i, &p)| {
            let [x, y, z] = exact_key(p).map(u64::from);
            (hash(((x << 32) | y).wrapping_mul(0xD6E8_FEB8_6659_FD93) ^ z) << 32) | i as u64
        })
        .collect();
    join_runs(positions.len(), entries, |i, j| {
        if exact_key(positions[i as usize]) == exact_key(positions[j as usize]) {
            Relation::Identical
        } else {
            Relation::Apart
        }
    })
}

/// Cells are at least this many tolerances wide: few positions lie within a tolerance of a
/// cell face (about 3% per axis), while a cell of a real mesh still holds about one position.
const CELL_TOLERANCES: f32 = 64.0;
/// Positions a task of [`weld_tolerant`] enters.
const ENTRY_CHUNK: usize = 1 << 13;
/// Cell coordinates use 21 bits per axis.
const AXIS_CELLS: f32 = (1u32 << 20) as f32;

/// The bounds of `positions` (`min > max` for none), in parallel. The positions are finite
/// (the pipeline checks them first): in SSE lanes, four running bounds a chunk, so that no
/// `min` waits on the one before it. (Folded one position at a time with `f32::min`, which
/// handles NaN, each pass over the 1M teapot's positions took a few milliseconds.)
pub(crate) fn bounds(positions: &[Vec3]) -> (Vec3, Vec3) {
    let empty = || (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
    let (lo, hi) = positions
        .par_chunks(1 << 14)
        .map(|chunk| {
            let (mut lo, mut hi) = ([Vec3A::INFINITY; 4], [Vec3A::NEG_INFINITY; 4]);
            let (quads, rest) = chunk.as_chunks::<4>();
            for &p in rest {
                lo[0] = lo[0].min(p.into());
                hi[0] = hi[0].max(p.into());
            }
            for quad in quads {
                for k in 0..4 {
                    lo[k] = lo[k].min(quad[k].into());
                    hi[k] = hi[k].max(quad[k].into());
                }
            }
            (lo[0].min(lo[1]).min(lo[2].min(lo[3])), hi[0].max(hi[1]).max(hi[2].max(hi[3])))
        })
        .reduce(empty, |(a, b), (c, d)| (a.min(c), b.max(d)));
    (lo.into(), hi.into())
}

/// The cells [`weld_tolerant`] enters positions under: cubes at least [`CELL_TOLERANCES`]
/// tolerances wide, from a cell below the positions' minimum.
struct Grid {
    origin: Vec3,
    inv_cell: f32,
    /// A little more than the tolerance, in cells, so rounding in the cell arithmetic never
    /// hides a pair.
    reach: f32,
}

impl Grid {
    fn new(positions: &[Vec3], tol: f32) -> Self {
        let (min, max) = bounds(positions);
        let extent = (max - min).max_element();
        // Cells at least `tol` wide, and few enough per axis to fit 21 bits (one cell of
        // margin).
        let cell = (tol * CELL_TOLERANCES).max(extent / (AXIS_CELLS - 2.0)).max(f32::MIN_POSITIVE);
        let inv_cell = 1.0 / cell;
        Self { origin: min - Vec3::splat(cell), inv_cell, reach: tol * 1.01 * inv_cell }
    }

    /// The cell of `p`, and per axis the side (-1, 1) of the cell's face within the
    /// tolerance of `p`, or 0.
    fn cell(&self, p: Vec3) -> ([u32; 3], [i32; 3]) {
        // Non-negative (the origin is a cell below the minimum): `as` truncates = floor.
        let f = (p - self.origin) * self.inv_cell;
        #[expect(
            clippy::cast_possible_truncation,
            reason = "in 0..AXIS_CELLS: `cell` is at least extent / (AXIS_CELLS - 2), above"
        )]
        let c = [f.x as u32, f.y as u32, f.z as u32];
        let local = f - Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
        let side = |l: f32| -> i32 {
            if l <= self.reach {
                -1
            } else if 1.0 - l <= self.reach {
                1
            } else {
                0
            }
        };
        (c, [side(local.x), side(local.y), side(local.z)])
    }

    /// Every position's entries (`hash of the cell << 32 | index`): under its own cell and
    /// the cells across the faces (edges, corners) it lies near. Where a cell holds about one
    /// position, all but a few positions are entered once: each position's own cell is
    /// written in place, in parallel (collecting up to eight entries a position through
    /// rayon's lists took as long as the sort); the few cells across are gathered apart and
    /// appended. The sort orders the entries whatever their order.
    fn entries(&self, positions: &[Vec3]) -> Vec<u64> {
        let key =
            |c: [u32; 3]| hash((u64::from(c[0]) << 42) | (u64::from(c[1]) << 21) | u64::from(c[2]));
        let mut entries = vec![0u64; positions.len()];
        let across: Vec<u64> = entries
            .par_chunks_mut(ENTRY_CHUNK)
            .zip(positions.par_chunks(ENTRY_CHUNK))
            .enumerate()
            .flat_map_iter(|(k, (entries, positions))| {
                let mut across = Vec::new();
                for (j, (entry, &p)) in entries.iter_mut().zip(positions).enumerate() {
                    let i = (k * ENTRY_CHUNK + j) as u64;
                    let (c, s) = self.cell(p);
                    *entry = (key(c) << 32) | i;
                    if s == [0; 3] {
                        continue;
                    }
                    // Every combination of the near sides (up to 7 more cells).
                    for mask in 1..8u32 {
                        if (0..3).any(|a| mask & (1 << a) != 0 && s[a] == 0) {
                            continue;
                        }
                        let nc: [u32; 3] = std::array::from_fn(|a| {
                            if mask & (1 << a) != 0 { c[a].wrapping_add_signed(s[a]) } else { c[a] }
                        });
                        across.push((key(nc) << 32) | i);
                    }
                }
                across
            })
            .collect();
        // Exactly: a `Vec`'s doubling would make this block, freed after the weld, twice the
        // entries, and glibc's malloc, which then serves blocks up to the largest freed one
        // from its heap instead of fresh pages, kept 2 to 4 MB more of the fix's later arrays
        // resident.
        entries.reserve_exact(across.len());
        entries.extend(across);
        entries
    }
}

/// Every position is entered under its own cell and, when it lies within the tolerance of a
/// cell face, under the neighbouring cells across that face (and edge and corner). Two
/// positions `p`, `q` within the tolerance then share at least one cell: `q`'s own, since `p`
/// is within the tolerance of it. So comparing within cells finds every pair, and no cell
/// lookups are needed.
fn weld_tolerant(positions: &[Vec3], tol: f32) -> Vec<u32> {
    let entries = Grid::new(positions, tol).entries(positions);
    let tol2 = tol * tol;
    join_runs(positions.len(), entries, |i, j| {
        let (p, q) = (positions[i as usize], positions[j as usize]);
        if exact_key(p) == exact_key(q) {
            Relation::Identical
        } else if p.distance_squared(q) <= tol2 {
            Relation::Near
        } else {
            Relation::Apart
        }
    })
}

/// The root of `x`'s set in a union-find forest, halving paths on the way.
pub(crate) fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let grand = parent[parent[x as usize] as usize];
        parent[x as usize] = grand;
        x = grand;
    }
    x
}

/// Joins the sets of `a` and `b`; the smaller root becomes the root, so each root is the
/// smallest index of its set.
pub(crate) fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent[hi as usize] = lo;
    }
}

/// The length of the diagonal of the model-space bounding box.
pub(crate) fn diagonal(flat: &Flat) -> f32 {
    let (lo, hi) = bounds(&flat.positions);
    if lo.x <= hi.x { lo.distance(hi) } else { 0.0 }
}

/// Each vertex's root (see [`roots`]), welding across the whole model ([`Mode::Model`])
/// or within each object ([`Mode::Object`]).
pub(crate) fn roots_for_mode(flat: &Flat, tolerance: f32, mode: Mode) -> Vec<u32> {
    if mode == Mode::Model {
        return roots(&flat.positions, tolerance);
    }
    let parts: Vec<Vec<u32>> = flat
        .vertex_start
        .par_windows(2)
        .map(|w| {
            let mut part = roots(&flat.positions[w[0] as usize..w[1] as usize], tolerance);
            part.iter_mut().for_each(|r| *r += w[0]);
            part
        })
        .collect();
    parts.concat()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Numbers in [0, 1] from Marsaglia's xorshift32, the same on every run.
    fn xorshift(mut seed: u32) -> impl FnMut() -> f32 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32
        }
    }

    /// The lanes' bounds are those of one position at a time, for every length around a
    /// chunk's (the remainders of four and of a chunk) and for none.
    #[test]
    fn bounds_in_lanes_are_the_positions_bounds() {
        let mut unit = xorshift(0x2545_f491);
        let mut next = move || (unit() - 0.5) * 200.0;
        let positions: Vec<Vec3> =
            (0..(1 << 14) + 7).map(|_| Vec3::new(next(), next(), next())).collect();
        for n in [0, 1, 3, 4, 5, 8, 1 << 14, (1 << 14) + 1, (1 << 14) + 7] {
            let some = &positions[..n];
            let one_by_one = some.iter().fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), p| {
                    let (l, h) = (lo.to_array(), hi.to_array());
                    let q = p.to_array();
                    let lo = Vec3::from_array(std::array::from_fn(|k| {
                        if q[k] < l[k] { q[k] } else { l[k] }
                    }));
                    let hi = Vec3::from_array(std::array::from_fn(|k| {
                        if q[k] > h[k] { q[k] } else { h[k] }
                    }));
                    (lo, hi)
                },
            );
            assert_eq!(bounds(some), one_by_one, "{n} positions");
        }
        // The extreme position in the last of four lanes, and in the remainder.
        let mut quad = vec![Vec3::ZERO; 9];
        quad[3] = Vec3::new(-5.0, 6.0, -7.0);
        quad[8] = Vec3::new(9.0, -9.0, 9.0);
        assert_eq!(bounds(&quad), (Vec3::new(-5.0, -9.0, -7.0), Vec3::new(9.0, 6.0, 9.0)));
    }

    #[test]
    fn exact_weld_joins_equal_bits_and_signed_zero() {
        let p = [
            Vec3::new(0.0, 1.0, 2.0),
            Vec3::new(-0.0, 1.0, 2.0),
            Vec3::new(0.0, 1.0, 2.000_001),
            Vec3::new(0.0, 1.0, 2.0),
        ];
        let w = weld(&p, 0.0);
        assert_eq!(w.ids, vec![0, 0, 1, 0]);
        assert_eq!(w.count, 2);
        let misses = near_misses(&p, &roots(&p, 0.0));
        assert_eq!(misses.iter().filter(|&&m| m).count(), 0);
    }

    /// Snapping leaves every position with its root's bits, signed zeros included (the weld
    /// joins -0.0 and 0.0, a near miss counts them equal, snapping does not), and moves
    /// nothing else; the near misses are the roots of the positions the tolerance joined.
    #[test]
    fn snapping_gives_every_position_its_roots_bits() {
        let p = vec![
            Vec3::new(0.0, 1.0, 2.0),
            Vec3::new(-0.0, 1.0, 2.0),
            Vec3::new(5.0, 5.0, 5.0),
            Vec3::new(0.0, 1.0, 2.000_001),
            Vec3::new(5.0, 5.0, 5.000_001),
            Vec3::new(9.0, 9.0, 9.0),
        ];
        let roots = roots(&p, 1e-4);
        assert_eq!(roots, vec![0, 0, 2, 0, 2, 5]);
        let misses = near_misses(&p, &roots);
        assert_eq!(misses, vec![true, false, true, false, false, false]);
        let mut snapped = p.clone();
        snap_to_roots(&mut snapped, &roots);
        let bits = |p: Vec3| p.to_array().map(f32::to_bits);
        for (v, &r) in roots.iter().enumerate() {
            assert_eq!(bits(snapped[v]), bits(p[r as usize]), "vertex {v}");
        }
    }

    #[test]
    fn tolerant_weld_finds_pairs_across_cell_faces() {
        // Pairs straddling every kind of cell boundary: the second point of each pair is
        // within tolerance of the first but, for some grid origin, in a neighbouring cell.
        let tol = 1e-3;
        let mut p = Vec::new();
        for k in 0..200 {
            let base = Vec3::new(k as f32 * 0.0173, (k % 7) as f32 * 0.031, (k % 3) as f32);
            p.push(base);
            let d = Vec3::new(0.55, -0.45, 0.3).normalize() * tol * 0.9;
            p.push(base + d);
        }
        let w = weld(&p, tol);
        assert_eq!(w.count, 200);
        for k in 0..200 {
            assert_eq!(w.ids[2 * k], w.ids[2 * k + 1], "pair {k}");
        }
        let misses = near_misses(&p, &roots(&p, tol));
        assert_eq!(misses.iter().filter(|&&m| m).count(), 200);
    }

    /// The tolerant weld joins exactly what comparing every pair joins (transitively), on
    /// clusters of points a few cells wide, many of whose pairs straddle a cell's face, edge
    /// or corner: found only through the cells across ([`weld_tolerant`]'s second entries).
    #[test]
    fn tolerant_weld_joins_what_every_pair_compared_joins() {
        let tol = 1e-3;
        let mut next = xorshift(0x9e37_79b9);
        let mut p = Vec::new();
        while p.len() < 1500 {
            let centre = Vec3::new(next(), next(), next()) * 0.2;
            for _ in 0..3 {
                let d = Vec3::new(next(), next(), next()) * 2.0 - Vec3::ONE;
                p.push(centre + d * tol * 0.8);
            }
        }
        let mut parent: Vec<u32> = (0..index(p.len())).collect();
        for i in 0..p.len() {
            for j in 0..i {
                if p[i].distance_squared(p[j]) <= tol * tol {
                    union(&mut parent, index(j), index(i));
                }
            }
        }
        let every_pair: Vec<u32> = (0..p.len()).map(|i| find(&mut parent, index(i))).collect();
        let joined = (0..p.len()).filter(|&i| every_pair[i] as usize != i).count();
        assert!(joined > 500, "clusters of three: {joined} joined");
        assert_eq!(roots(&p, tol), every_pair);
    }

    #[test]
    fn tolerant_weld_keeps_apart_what_is_farther_than_tolerance() {
        let p = [Vec3::ZERO, Vec3::new(0.0011, 0.0, 0.0), Vec3::new(0.0, 0.0009, 0.0)];
        let w = weld(&p, 1e-3);
        assert_eq!(w.ids, vec![0, 1, 0]);
    }
}
