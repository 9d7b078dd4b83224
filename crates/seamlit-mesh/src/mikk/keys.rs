//! Step 2: MikkTSpace's vertices, as one 64-bit key per corner.

use glam::Vec3;
use rayon::prelude::*;

use super::Surface;
use crate::index::index;

/// The bits of `x`, with `-0.0` read as `0.0` (mikktspace.c compares with `==`).
pub(super) fn bits(x: f32) -> u32 {
    (x + 0.0).to_bits()
}

/// Step 2: per corner of every triangle that touches a position that is not plain, its
/// MikkTSpace vertex as a key: equal keys at one position are one vertex
/// (equal position, UV and normal). The high half is the first vertex of the position with
/// the vertex's UV (and normal, where normals are per vertex), the low half the normal's key.
pub(super) struct Keys {
    /// The triangles that touch a position that is not plain, ascending.
    triangles: Vec<u32>,
    /// Three keys per triangle of `triangles`.
    keys: Vec<[u64; 3]>,
}

impl Keys {
    pub(super) fn of<N>(surface: &Surface<'_, N>, first: &[u32], plain: &[bool]) -> Self
    where
        N: Fn(usize, usize) -> (Vec3, u32) + Sync,
    {
        let triangles: Vec<u32> = (0..surface.triangles.len())
            .into_par_iter()
            .filter(|&t| {
                surface.triangles[t].iter().any(|&v| !plain[surface.roots[v as usize] as usize])
            })
            .map(index)
            .collect();
        let keys = triangles
            .par_iter()
            .map(|&t| {
                let (t, tri) = (t as usize, surface.triangles[t as usize]);
                std::array::from_fn(|k| {
                    let normal = (surface.normal)(t * 3 + k, tri[k] as usize).1;
                    (u64::from(first[tri[k] as usize]) << 32) | u64::from(normal)
                })
            })
            .collect();
        Self { triangles, keys }
    }

    /// The keys of the corners of triangle `t`, which touches a position that is not plain.
    pub(super) fn of_triangle(&self, t: usize) -> [u64; 3] {
        let i = self.triangles.partition_point(|&e| (e as usize) < t);
        debug_assert_eq!(self.triangles[i] as usize, t);
        self.keys[i]
    }
}

/// Per vertex: whether another vertex of its position has the same first vertex (see
/// [`first_equal_vertex`]), so that the two may share a MikkTSpace vertex.
pub(super) fn shared(first: &[u32]) -> Vec<bool> {
    let mut shared = vec![false; first.len()];
    for (v, &f) in first.iter().enumerate() {
        if f as usize != v {
            (shared[v], shared[f as usize]) = (true, true);
        }
    }
    shared
}

/// Per vertex: the first vertex of its position with the same UV bits (and normal bits, where
/// normals are per vertex). A counting sort of the vertices by root, then a comparison within
/// each position.
pub(super) fn first_equal_vertex<N>(surface: &Surface<'_, N>) -> Vec<u32> {
    let roots = surface.roots;
    let n = roots.len();
    let mut offsets = vec![0u32; n + 1];
    for &r in roots {
        offsets[r as usize + 1] += 1;
    }
    for r in 0..n {
        offsets[r + 1] += offsets[r];
    }
    let mut next = offsets.clone();
    let mut members = vec![0u32; n];
    for (v, &r) in roots.iter().enumerate() {
        members[next[r as usize] as usize] = index(v);
        next[r as usize] += 1;
    }
    let same = |a: usize, b: usize| {
        let (ua, ub) = (surface.uvs[a], surface.uvs[b]);
        let uv = bits(ua.x) == bits(ub.x) && bits(ua.y) == bits(ub.y);
        uv && surface.vertex_normals.is_none_or(|ns| {
            let (na, nb) = (ns[a], ns[b]);
            bits(na.x) == bits(nb.x) && bits(na.y) == bits(nb.y) && bits(na.z) == bits(nb.z)
        })
    };
    let mut first: Vec<u32> = (0..index(n)).collect();
    for r in 0..n {
        let at = &members[offsets[r] as usize..offsets[r + 1] as usize];
        if at.len() < 2 {
            continue;
        }
        for (i, &v) in at.iter().enumerate() {
            if let Some(&u) = at[..i].iter().find(|&&u| same(u as usize, v as usize)) {
                first[v as usize] = first[u as usize];
            }
        }
    }
    first
}
