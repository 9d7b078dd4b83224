//! Triangulating OBJ polygons (faces of more than three corners): a fan where the polygon is
//! convex, ear clipping on its best-fit plane where it is not.
//!
//! The parser fans every face, `(a, b, c), (a, c, d), ...`, as tobj does: right for a convex
//! polygon, but a fan over a concave one overlaps itself, with triangles facing backwards and
//! an area larger than the polygon's. Once the positions are known, each polygon is checked:
//!
//! 1. its normal by Newell's method (M. E. Newell, as given by Sutherland, Sproull and
//!    Schumacker, "A characterization of ten hidden-surface algorithms", 1974): the
//!    best-fit plane's normal, right for non-planar polygons too;
//! 2. convex when every corner turns the same way about that normal (a cross product and a
//!    dot product per corner): the fan stays, the common case, at that cost only;
//! 3. otherwise the polygon is projected onto the plane and ear-clipped (the `earcutr` crate,
//!    Mapbox's earcut), each triangle turned to face the polygon's normal.
//!
//! Earcut drops corners that repeat their neighbour or lie on a straight edge (a T-junction
//! vertex of a floor plan); they are put back, each splitting the triangle on its edge, so
//! that every corner stays in the mesh and a polygon still gives `n - 2` triangles. The
//! ear-clipped triangles replace the fan only when their areas add up to the polygon's: a
//! self-intersecting polygon, which has no right triangulation, keeps its fan. Polygons of
//! more than [`MOST_CORNERS`] corners keep theirs too: ear clipping is quadratic in the worst
//! case, and a hostile file must not make loading take hours.

use glam::{DVec2, DVec3, Vec3};

/// The largest polygon that is ear-clipped.
pub const MOST_CORNERS: usize = 1024;

/// Triangulates again the polygons that are not convex. `triangles` holds every polygon as a
/// fan; `polygons` gives, ascending, each polygon's first triangle in `triangles` and its
/// number of corners; `positions` are the vertices the triangles index.
///
/// Returns the polygons whose fan was replaced: their first triangle and their corners (the
/// vertices, in the order the face gives them), so that a writer can find each corner among
/// the new triangles (the OBJ pass-through, `passthrough.rs`). A polygon that keeps its fan is
/// not listed: its corner `0` is its first triangle's corner 0, corner `k` (`0 < k < n - 1`)
/// triangle `k - 1`'s corner 1, and corner `n - 1` the last triangle's corner 2.
pub fn triangulate(
    triangles: &mut [[u32; 3]],
    positions: &[Vec3],
    polygons: impl Iterator<Item = (usize, usize)>,
) -> Vec<(usize, Vec<u32>)> {
    let mut clipped_polygons = Vec::new();
    let mut corners = Vec::new();
    for (first, n) in polygons {
        let fan = &mut triangles[first..first + n - 2];
        corners.clear();
        corners.extend_from_slice(&fan[0][..2]);
        corners.extend(fan.iter().map(|t| t[2]));
        if let Some(clipped) = ear_clip(&corners, positions) {
            fan.copy_from_slice(&clipped);
            clipped_polygons.push((first, corners.clone()));
        }
    }
    clipped_polygons
}

/// The ear-clipped triangles of a polygon (`corners` index `positions`), `n - 2` of them, or
/// `None` where its fan stays: convex, degenerate, self-intersecting, too large, or where
/// earcut gives up or drops a corner that cannot be put back.
fn ear_clip(corners: &[u32], positions: &[Vec3]) -> Option<Vec<[u32; 3]>> {
    let n = corners.len();
    if n > MOST_CORNERS {
        return None;
    }
    // The convex case, nearly every polygon, allocates nothing.
    let point = |i: usize| positions[corners[i % n] as usize].as_dvec3();
    let normal = newell_normal(n, point).try_normalize()?;
    if is_convex(n, point, normal) {
        return None;
    }
    let points: Vec<DVec3> = (0..n).map(point).collect();
    // A right-handed basis of the plane: counter-clockwise about the normal is
    // counter-clockwise in (u, v).
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let flat: Vec<DVec2> = points
        .iter()
        .map(|&p| DVec2::new((p - points[0]).dot(u), (p - points[0]).dot(v)))
        .collect();
    // Earcut drops corners that repeat the one before or lie on the line through their
    // neighbours: they are left out here, and put back below.
    let kept = on_turns(&flat);
    let coordinates: Vec<f64> = kept.iter().flat_map(|&k| [flat[k].x, flat[k].y]).collect();
    let indices = earcutr::earcut(&coordinates, &[], 2).ok()?;
    if kept.len() < 3 || indices.len() != 3 * (kept.len() - 2) {
        return None;
    }
    let twice_area = |[a, b, c]: [usize; 3]| (flat[b] - flat[a]).perp_dot(flat[c] - flat[a]);
    let mut triangles = Vec::with_capacity(n - 2);
    for t in indices.as_chunks::<3>().0 {
        let [a, b, c] = [kept[t[0]], kept[t[1]], kept[t[2]]];
        // Counter-clockwise about the normal, as the polygon.
        triangles.push(if twice_area([a, b, c]) < 0.0 { [a, c, b] } else { [a, b, c] });
    }
    put_back(&mut triangles, &kept, n)?;
    let covered: f64 = triangles.iter().map(|&t| twice_area(t).abs()).sum();
    let polygon = shoelace(&flat);
    let whole = (covered - polygon).abs() <= 1e-9 * polygon.max(f64::MIN_POSITIVE);
    whole.then(|| triangles.iter().map(|t| t.map(|k| corners[k])).collect())
}

/// The corners of a polygon that earcut keeps (its `filterPoints`, with the same arithmetic):
/// all but those that equal the next one or lie exactly on the line through their
/// neighbours, removed one at a time until none is left.
fn on_turns(flat: &[DVec2]) -> Vec<usize> {
    let mut kept: Vec<usize> = (0..flat.len()).collect();
    let mut at = 0;
    let mut unchanged = 0;
    while kept.len() > 2 && unchanged < kept.len() {
        let m = kept.len();
        let [p, q, r] = [(at + m - 1) % m, at, (at + 1) % m].map(|i| flat[kept[i]]);
        let turn = (q.y - p.y) * (r.x - q.x) - (q.x - p.x) * (r.y - q.y);
        if q == r || turn == 0.0 {
            kept.remove(at);
            at = (at + m - 2) % (m - 1);
            unchanged = 0;
        } else {
            at = (at + 1) % m;
            unchanged += 1;
        }
    }
    kept
}

/// Puts the corners that `kept` leaves out back into `triangles` (counter-clockwise, on
/// the `n` corners of the polygon): each lies on the boundary edge between its nearest
/// corners already in, and splits the one triangle on that edge in two. `None` where that
/// edge is in no triangle (ear clipping went wrong).
fn put_back(triangles: &mut Vec<[usize; 3]>, kept: &[usize], n: usize) -> Option<()> {
    let mut placed = vec![false; n];
    for &k in kept {
        placed[k] = true;
    }
    for d in 0..n {
        if placed[d] {
            continue;
        }
        let a = (1..n).map(|s| (d + n - s) % n).find(|&i| placed[i])?;
        let b = (1..n).map(|s| (d + s) % n).find(|&i| placed[i])?;
        let (t, k) = triangles.iter().enumerate().find_map(|(t, tri)| {
            (0..3).find(|&k| tri[k] == a && tri[(k + 1) % 3] == b).map(|k| (t, k))
        })?;
        let c = triangles[t][(k + 2) % 3];
        triangles[t] = [a, d, c];
        triangles.push([d, b, c]);
        placed[d] = true;
    }
    Some(())
}

/// Newell's normal: twice the area times the unit normal of a planar polygon, the normal of
/// the best-fit plane otherwise.
/// `point(i)` is corner `i` of `n` (taken modulo `n`).
fn newell_normal(n: usize, point: impl Fn(usize) -> DVec3) -> DVec3 {
    let origin = point(0);
    (0..n).map(|i| (point(i) - origin).cross(point(i + 1) - origin)).sum()
}

/// Whether every corner turns left about `normal` (corners on a straight line count as
/// turning either way). `point(i)` is corner `i` of `n` (taken modulo `n`).
fn is_convex(n: usize, point: impl Fn(usize) -> DVec3, normal: DVec3) -> bool {
    (0..n).all(|i| {
        let (before, at, after) = (point(i + n - 1), point(i), point(i + 1));
        let (e1, e2) = (at - before, after - at);
        e1.cross(e2).dot(normal) >= -1e-9 * e1.length() * e2.length()
    })
}

/// Twice the signed area of a polygon in the plane (the shoelace formula).
fn shoelace(points: &[DVec2]) -> f64 {
    let n = points.len();
    (0..n).map(|i| points[i].perp_dot(points[(i + 1) % n])).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_convex_polygon_keeps_its_fan() {
        let hexagon: Vec<Vec3> = (0..6)
            .map(|k| {
                let a = k as f32 * std::f32::consts::TAU / 6.0;
                Vec3::new(a.cos(), 0.3, a.sin())
            })
            .collect();
        let fan = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]];
        let mut triangles = fan;
        triangulate(&mut triangles, &hexagon, [(0, 6)].into_iter());
        assert_eq!(triangles, fan);
    }

    #[test]
    fn corners_on_straight_edges_are_kept() {
        // An L whose corner 0 cannot see corner 2 (the fan fails), with a repeated corner and a
        // corner in the middle of its bottom edge: ear clipping drops both, and each goes back
        // in by splitting the triangle on its edge.
        let l = [
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
        ];
        let mut triangles: Vec<[u32; 3]> = (1..7).map(|k| [0, k, k + 1]).collect();
        triangulate(&mut triangles, &l, [(0, 8)].into_iter());
        let mut used: Vec<u32> = triangles.as_flattened().to_vec();
        used.sort_unstable();
        used.dedup();
        assert_eq!(used, (0..8).collect::<Vec<u32>>(), "{triangles:?}");
        let mut area = 0.0;
        for t in &triangles {
            let [a, b, c] = t.map(|i| l[i as usize]);
            let z = (b - a).cross(c - a).z;
            assert!(z >= 0.0, "{t:?} faces backwards");
            area += z / 2.0;
        }
        assert_eq!(area, 3.0, "{triangles:?}");
    }

    #[test]
    fn a_dart_is_clipped_through_its_reflex_corner() {
        // Corner 3 is reflex: the fan's diagonal 0-2 runs outside the polygon, and the fan's
        // second triangle faces backwards.
        let dart = [
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.3, 1.0, 0.0),
        ];
        let mut triangles = [[0, 1, 2], [0, 2, 3]];
        triangulate(&mut triangles, &dart, [(0, 4)].into_iter());
        let mut sets = triangles.map(|mut t| {
            t.sort_unstable();
            t
        });
        sets.sort_unstable();
        assert_eq!(sets, [[0, 1, 3], [1, 2, 3]]);
        for t in triangles {
            let [a, b, c] = t.map(|i| dart[i as usize]);
            assert!((b - a).cross(c - a).z > 0.0, "{t:?} faces backwards");
        }
    }
}
