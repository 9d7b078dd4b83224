//! Step 2: MikkTSpace's vertices, as one 64-bit key per corner.

use glam::Vec3;
use rayon::prelude::*;

use super::Surface;
use crate::index::{index, low_half};

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
    pub(super) fn of<N>(surface: &Surface<'_, N>, first: &Firsts, plain: &[bool]) -> Self
    where
        N: Fn(usize, usize) -> (Vec3, u32) + Sync,
    {
        let triangles: Vec<u32> = (0..surface.triangles.len())
            .into_par_iter()
            .flat_map(|o| {
                let (base, first) = (surface.vertex_start[o], surface.triangle_start[o]);
                surface.triangles[o].par_iter().enumerate().filter_map(move |(i, tri)| {
                    let not_plain = |&v: &u32| !plain[surface.roots[(v + base) as usize] as usize];
                    tri.iter().any(not_plain).then_some(first + index(i))
                })
            })
            .collect();
        let keys = triangles
            .par_iter()
            .map(|&t| {
                let (t, tri) = (t as usize, surface.triangle(t as usize));
                std::array::from_fn(|k| {
                    let normal = (surface.normal)(t * 3 + k, tri[k] as usize).1;
                    (u64::from(first.of(tri[k])) << 32) | u64::from(normal)
                })
            })
            .collect();
        Self { triangles, keys }
    }

    /// The triangles that touch a position that is not plain, ascending.
    pub(super) fn triangles(&self) -> &[u32] {
        &self.triangles
    }

    /// The keys of the corners of triangle `t`, which touches a position that is not plain.
    pub(super) fn of_triangle(&self, t: usize) -> [u64; 3] {
        let i = self.triangles.partition_point(|&e| (e as usize) < t);
        debug_assert_eq!(self.triangles[i] as usize, t);
        self.keys[i]
    }
}

/// Per vertex: the first vertex of its position with the same UV bits (and normal bits, where
/// normals are per vertex), and whether another vertex of its position has the same first
/// vertex, so that the two may share a MikkTSpace vertex.
pub(super) struct FirstEqual {
    pub(super) first: Firsts,
    pub(super) shared: Vec<bool>,
}

/// The first vertex of each vertex's position with its UV (see [`FirstEqual`]).
pub(super) enum Firsts {
    /// Where few vertices have another first (the usual model, its vertices shared by its
    /// triangles): those vertices with their first, ascending by vertex. At a million
    /// triangles an array of every vertex was 2 MB at the fix's peak.
    Few(Vec<(u32, u32)>),
    /// Where many do (a model whose triangles share no vertex: every position's vertices but
    /// one), every vertex's first: searching the pairs for every corner was slower, and the
    /// pairs larger than the array.
    Every(Vec<u32>),
}

/// Above this share of the vertices (one in [`FEW`]) having another first, [`Firsts`] keeps
/// every vertex's.
const FEW: usize = 16;

impl Firsts {
    /// `others`: the vertices of `n` whose first is another vertex, with that vertex.
    fn new(n: usize, mut others: Vec<(u32, u32)>) -> Self {
        if others.len() > n / FEW {
            let mut every: Vec<u32> = (0..index(n)).into_par_iter().collect();
            for (v, first) in others {
                every[v as usize] = first;
            }
            return Self::Every(every);
        }
        others.par_sort_unstable();
        Self::Few(others)
    }

    /// The first vertex of `v`'s position with its UV: `v` itself unless it is another.
    pub(super) fn of(&self, v: u32) -> u32 {
        match self {
            Self::Few(others) => match others.binary_search_by_key(&v, |&(w, _)| w) {
                Ok(i) => others[i].1,
                Err(_) => v,
            },
            Self::Every(every) => every[v as usize],
        }
    }
}

/// [`FirstEqual`]: only positions of several vertices are compared, found among the vertices
/// welded to a root other than themselves (sorted by root, then vertex); a vertex alone at
/// its position is its own first.
pub(super) fn first_equal_vertex<N: Sync>(surface: &Surface<'_, N>) -> FirstEqual {
    let roots = surface.roots;
    let n = roots.len();
    let mut welded: Vec<u64> = roots
        .par_iter()
        .enumerate()
        .filter(|&(v, &r)| r as usize != v)
        .map(|(v, &r)| (u64::from(r) << 32) | v as u64)
        .collect();
    welded.par_sort_unstable();
    let same = |a: usize, b: usize| {
        let (ua, ub) = (surface.uv(a), surface.uv(b));
        let uv = bits(ua.x) == bits(ub.x) && bits(ua.y) == bits(ub.y);
        uv && surface.vertex_normals.is_none_or(|ns| {
            let (na, nb) = (ns[a], ns[b]);
            bits(na.x) == bits(nb.x) && bits(na.y) == bits(nb.y) && bits(na.z) == bits(nb.z)
        })
    };
    let mut others = Vec::new();
    let mut shared = vec![false; n];
    // The position's vertices, and the first of each as found so far.
    let (mut at, mut firsts) = (Vec::new(), Vec::new());
    for run in welded.chunk_by(|a, b| a >> 32 == b >> 32) {
        // The position's vertices, ascending: its root (its own root) and the others.
        let root = (run[0] >> 32) as u32;
        debug_assert_eq!(roots[root as usize], root, "a weld root is its own root");
        at.clear();
        at.push(root);
        at.extend(run.iter().map(|&e| low_half(e)));
        at.sort_unstable();
        firsts.clear();
        firsts.extend_from_slice(&at);
        for (i, &v) in at.iter().enumerate() {
            if let Some(j) = at[..i].iter().position(|&u| same(u as usize, v as usize)) {
                let f = firsts[j];
                firsts[i] = f;
                others.push((v, f));
                (shared[v as usize], shared[f as usize]) = (true, true);
            }
        }
    }
    FirstEqual { first: Firsts::new(n, others), shared }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both forms give each vertex of the pairs its first and every other vertex itself; the
    /// pairs are kept where they are few, every vertex's first where they are many.
    #[test]
    fn firsts_few_and_every_answer_alike() {
        let n = 64;
        let few = vec![(40, 3), (9, 3), (5, 2)];
        let many: Vec<(u32, u32)> = (1..index(n)).map(|v| (v, v - 1)).collect();
        for pairs in [few, many] {
            let firsts = Firsts::new(n, pairs.clone());
            let every = matches!(firsts, Firsts::Every(_));
            assert_eq!(every, pairs.len() > n / FEW, "{} pairs of {n}", pairs.len());
            for v in 0..index(n) {
                let first = pairs.iter().find(|&&(w, _)| w == v).map_or(v, |&(_, f)| f);
                assert_eq!(firsts.of(v), first, "vertex {v}");
            }
        }
    }
}
