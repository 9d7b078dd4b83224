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
//! `cell >= tol`. Two positions within `tol` of each other lie in the same cell or in cells
//! adjacent along the axes on which at least one of them is within `tol` of a cell face, so
//! each position is compared with the positions of its own cell and, only when it is that close
//! to a face, with those of the neighbouring cells on that side. Nothing within tolerance is
//! missed because it fell into another cell. The cells are found by sorting `(cell, index)`
//! pairs (in parallel), which is deterministic; pairs within tolerance are joined with a
//! union-find whose representative is the smallest index, so the ids do not depend on the
//! number of threads. Welding is transitive: a chain of positions each within `tol` of the
//! next becomes one id (with the default tolerance of 1e-6 of the bounding-box diagonal, such
//! chains do not occur in real models).
//!
//! With `tol == 0`, positions weld only when their bits are equal, with `-0.0 == 0.0`.
//!
//! Expected cost: O(n log n) for the sort of n positions (a radix-like parallel sort in
//! practice), O(n) for the rest.

use glam::Vec3;
use rayon::prelude::*;

/// The result of [`weld`]: a shared id per input position.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Weld {
    /// For each input position, its id in `0..count`. Ids are numbered in order of first
    /// appearance, so the first position gets id 0.
    pub ids: Vec<u32>,
    /// Number of distinct ids.
    pub count: usize,
}

impl Weld {
    /// For each id, the index of its first input position (its representative).
    #[must_use]
    pub fn representatives(&self) -> Vec<u32> {
        let mut reps = vec![u32::MAX; self.count];
        for (i, &id) in self.ids.iter().enumerate() {
            let r = &mut reps[id as usize];
            if *r == u32::MAX {
                *r = i as u32;
            }
        }
        reps
    }

    /// Moves every position onto its id's representative (its first position), so that
    /// geometry computed afterwards sees welded positions as one point: a sliver between two
    /// positions closer than the tolerance becomes a degenerate triangle, not a face with a
    /// random normal.
    pub fn snap(&self, positions: &mut [Vec3]) {
        let reps = self.representatives();
        for (i, &id) in self.ids.iter().enumerate() {
            // The representative is the smallest index of its id, already final here.
            positions[i] = positions[reps[id as usize] as usize];
        }
    }

    /// Number of ids whose positions are not all bit-equal (with `-0.0 == 0.0`): welds that
    /// only the tolerance made.
    #[must_use]
    pub fn near_misses(&self, positions: &[Vec3]) -> usize {
        let reps = self.representatives();
        let mut flagged = vec![false; self.count];
        for (i, &id) in self.ids.iter().enumerate() {
            let r = reps[id as usize] as usize;
            if exact_key(positions[i]) != exact_key(positions[r]) {
                flagged[id as usize] = true;
            }
        }
        flagged.iter().filter(|&&f| f).count()
    }
}

/// The bits of a position with `-0.0` mapped to `0.0`.
fn exact_key(p: Vec3) -> [u32; 3] {
    // Adding 0.0 turns -0.0 into +0.0 and leaves every other value unchanged.
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

fn pack_exact(p: Vec3) -> u128 {
    let [x, y, z] = exact_key(p);
    (u128::from(x) << 64) | (u128::from(y) << 32) | u128::from(z)
}

/// Welds `positions` with an absolute `tolerance` (`0.0`: exact bits).
///
/// All positions must be finite (the fix pipeline checks this first). A negative or NaN
/// tolerance is treated as `0.0`.
#[must_use]
pub fn weld(positions: &[Vec3], tolerance: f32) -> Weld {
    let n = positions.len();
    if n == 0 {
        return Weld { ids: Vec::new(), count: 0 };
    }
    let parent = if tolerance > 0.0 && tolerance.is_finite() {
        weld_tolerant(positions, tolerance)
    } else {
        weld_exact(positions)
    };
    compact(parent)
}

/// Numbers the union-find roots in order of first appearance. `parent[i] <= i`, and roots are
/// their own parents, so one forward pass suffices.
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

fn weld_exact(positions: &[Vec3]) -> Vec<u32> {
    let mut keyed: Vec<(u128, u32)> =
        positions.par_iter().enumerate().map(|(i, &p)| (pack_exact(p), i as u32)).collect();
    keyed.par_sort_unstable();
    let mut parent: Vec<u32> = (0..positions.len() as u32).collect();
    for run in keyed.chunk_by(|a, b| a.0 == b.0) {
        let root = run[0].1; // smallest index: the pairs are sorted by index within a key
        for &(_, i) in &run[1..] {
            parent[i as usize] = root;
        }
    }
    parent
}

/// Cells are at least this many tolerances wide: few positions lie near a cell face, so few
/// need a neighbour check, while a cell still holds about one position of a real mesh.
const CELL_TOLERANCES: f32 = 16.0;
/// Cell coordinates use 21 bits per axis.
const AXIS_CELLS: f32 = (1u32 << 20) as f32;

struct Grid {
    origin: Vec3,
    inv_cell: f32,
    cell: f32,
}

impl Grid {
    fn cell_of(&self, p: Vec3) -> [u32; 3] {
        let c = ((p - self.origin) * self.inv_cell).floor();
        [c.x as u32, c.y as u32, c.z as u32]
    }

    fn key(c: [u32; 3]) -> u64 {
        (u64::from(c[0]) << 42) | (u64::from(c[1]) << 21) | u64::from(c[2])
    }
}

/// The axis-aligned bounds of `positions` (`min > max` for none), in parallel.
pub(crate) fn bounds(positions: &[Vec3]) -> (Vec3, Vec3) {
    let empty = || (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    positions
        .par_iter()
        .fold(empty, |(lo, hi), &p| (lo.min(p), hi.max(p)))
        .reduce(empty, |(a, b), (c, d)| (a.min(c), b.max(d)))
}

fn weld_tolerant(positions: &[Vec3], tol: f32) -> Vec<u32> {
    let (min, max) = bounds(positions);
    let extent = (max - min).max_element();
    // Cells at least `tol` wide, and few enough per axis to fit 21 bits (one cell of margin).
    let cell = (tol * CELL_TOLERANCES).max(extent / (AXIS_CELLS - 2.0)).max(f32::MIN_POSITIVE);
    let grid = Grid { origin: min - Vec3::splat(cell), inv_cell: 1.0 / cell, cell };

    let mut keyed: Vec<(u64, u32)> = positions
        .par_iter()
        .enumerate()
        .map(|(i, &p)| (Grid::key(grid.cell_of(p)), i as u32))
        .collect();
    keyed.par_sort_unstable();

    // Pairs within tolerance, found in parallel over chunks of the sorted list.
    let tol2 = tol * tol;
    // A little more than `tol`, so that rounding in the cell arithmetic never hides a pair.
    let reach = tol * 1.01;
    let cell_range = |key: u64| -> &[(u64, u32)] {
        let start = keyed.partition_point(|e| e.0 < key);
        let end = start + keyed[start..].partition_point(|e| e.0 == key);
        &keyed[start..end]
    };
    let pairs: Vec<(u32, u32)> = keyed
        .par_chunk_by(|a, b| a.0 == b.0)
        .flat_map_iter(|run| {
            let mut out = Vec::new();
            for (k, &(_, i)) in run.iter().enumerate() {
                let p = positions[i as usize];
                for &(_, j) in &run[k + 1..] {
                    if positions[j as usize].distance_squared(p) <= tol2 {
                        out.push((i, j));
                    }
                }
                // Neighbour cells, only on the sides where p is within tol of the cell face.
                let c = grid.cell_of(p);
                let local = (p - grid.origin) * grid.inv_cell - Vec3::from(c.map(|v| v as f32));
                let near = |f: f32| -> [i32; 2] {
                    let lo = if f * grid.cell <= reach { -1 } else { 0 };
                    let hi = if (1.0 - f) * grid.cell <= reach { 1 } else { 0 };
                    [lo, hi]
                };
                let [xl, xh] = near(local.x);
                let [yl, yh] = near(local.y);
                let [zl, zh] = near(local.z);
                if xl == 0 && xh == 0 && yl == 0 && yh == 0 && zl == 0 && zh == 0 {
                    continue;
                }
                for dx in xl..=xh {
                    for dy in yl..=yh {
                        for dz in zl..=zh {
                            if dx == 0 && dy == 0 && dz == 0 {
                                continue;
                            }
                            let nc = [
                                c[0].wrapping_add_signed(dx),
                                c[1].wrapping_add_signed(dy),
                                c[2].wrapping_add_signed(dz),
                            ];
                            let key = Grid::key(nc);
                            // Each unordered pair of cells is visited from the smaller key.
                            if key < Grid::key(c) {
                                continue;
                            }
                            for &(_, j) in cell_range(key) {
                                if positions[j as usize].distance_squared(p) <= tol2 {
                                    out.push((i, j));
                                }
                            }
                        }
                    }
                }
            }
            out
        })
        .collect();

    let mut parent: Vec<u32> = (0..positions.len() as u32).collect();
    for (a, b) in pairs {
        union(&mut parent, a, b);
    }
    // Flatten so that every entry points at its root (the smallest index of its set).
    for i in 0..parent.len() {
        let p = parent[i];
        parent[i] = parent[p as usize];
    }
    parent
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

#[cfg(test)]
mod tests {
    use super::*;

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
        assert_eq!(w.near_misses(&p), 0);
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
        assert_eq!(w.near_misses(&p), 200);
    }

    #[test]
    fn tolerant_weld_keeps_apart_what_is_farther_than_tolerance() {
        let p = [Vec3::ZERO, Vec3::new(0.0011, 0.0, 0.0), Vec3::new(0.0, 0.0009, 0.0)];
        let w = weld(&p, 1e-3);
        assert_eq!(w.ids, vec![0, 1, 0]);
    }
}
