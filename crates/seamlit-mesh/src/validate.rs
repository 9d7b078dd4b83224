//! Input checks, and the model's positions flattened into one model-space list.
//!
//! Everything downstream (weld, faces, smoothing, report, reference) works on [`Flat`]: the
//! positions of all objects after their transforms, concatenated, so that vertex `v` of the
//! model is `vertex_start[o] + i`. Validation happens once, here, so that the algorithms can
//! index without checks and never see a NaN.

use glam::{Mat3, Mat4, Vec2, Vec3};
use rayon::prelude::*;

use crate::index::index;
use crate::{MAX_ELEMENTS, MeshError, Model, Object};

/// The model's positions in model space, concatenated, and where each object starts.
///
/// UVs and triangles stay in the [`Model`]; `triangles` and `uvs` build concatenated copies for
/// the few users that want them (the reference, MikkTSpace).
pub(crate) struct Flat {
    /// Positions after each object's transform.
    pub positions: Vec<Vec3>,
    /// Per object: first vertex; one extra entry at the end.
    pub vertex_start: Vec<u32>,
    /// Per object: first triangle; one extra entry at the end.
    pub triangle_start: Vec<u32>,
    /// Per object: linear part of the transform (`None` for the identity).
    pub linear: Vec<Option<Mat3>>,
}

impl Flat {
    /// The object that triangle `t` (an index into the concatenation) belongs to.
    pub fn object_of_triangle(&self, t: usize) -> usize {
        crate::index::part_of(&self.triangle_start, t)
    }

    /// The three model-space positions and (if the object has them) UVs of triangle `t` of
    /// object `o`, and its vertices as indices into the concatenation.
    pub fn corners(&self, model: &Model, o: usize, t: usize) -> Corners {
        let object = &model.objects[o];
        let tri = object.triangles[t];
        let base = self.vertex_start[o];
        let vertices = tri.map(|i| base + i);
        Corners {
            vertices,
            positions: vertices.map(|v| self.positions[v as usize]),
            uvs: object.uvs.as_ref().map(|uv| tri.map(|i| uv[i as usize])),
        }
    }

    /// The corners (`triangle * 3 + k`, into the concatenation) whose vertex's weld root
    /// (see [`crate::weld`]) passes `keep`, as `root << 32 | corner`, sorted: grouped by
    /// position, ascending corners within.
    ///
    /// The callers keep few positions (shared, complex): whether each vertex is kept is
    /// settled first, once per vertex, so that the pass over the corners reads one byte for
    /// each (not its root, then the root's entry), and skips objects with no vertex kept.
    pub fn corners_at(
        &self,
        model: &Model,
        roots: &[u32],
        keep: impl Fn(u32) -> bool + Sync,
    ) -> Vec<u64> {
        let kept: Vec<bool> = roots.par_iter().map(|&r| keep(r)).collect();
        let mut entries: Vec<u64> = model
            .objects
            .par_iter()
            .enumerate()
            .flat_map_iter(|(o, object)| {
                let base = self.vertex_start[o] as usize;
                let kept = &kept[base..self.vertex_start[o + 1] as usize];
                let first = u64::from(self.triangle_start[o]) * 3;
                let mut out = Vec::new();
                if !kept.contains(&true) {
                    return out;
                }
                for (c, &i) in object.triangles.as_flattened().iter().enumerate() {
                    if kept[i as usize] {
                        let root = roots[base + i as usize];
                        out.push((u64::from(root) << 32) | (first + c as u64));
                    }
                }
                out
            })
            .collect();
        entries.par_sort_unstable();
        entries
    }

    /// Per root (see [`crate::weld`]; index by root): whether vertices of two or more objects
    /// are welded to it. A vertex's root is the smallest index of its set, so a root below
    /// the first vertex of the vertex's own object belongs to an earlier object.
    pub fn shared_positions(&self, roots: &[u32]) -> Vec<bool> {
        // The roots of earlier objects' vertices, found in parallel (few: a seam's), then set.
        let earlier: Vec<u32> = self
            .vertex_start
            .par_windows(2)
            .flat_map_iter(|w| roots[w[0] as usize..w[1] as usize].iter().filter(|&&r| r < w[0]))
            .copied()
            .collect();
        let mut shared = vec![false; roots.len()];
        for r in earlier {
            shared[r as usize] = true;
        }
        shared
    }

    /// Every triangle, indexing the concatenated positions (for the paper's listing).
    #[cfg(feature = "reference")]
    pub fn triangles(&self, model: &Model) -> Vec<[u32; 3]> {
        let mut out = vec![[0; 3]; *self.triangle_start.last().unwrap_or(&0) as usize];
        let parts = split_at_starts(&mut out, &self.triangle_start);
        parts.into_par_iter().zip(&model.objects).enumerate().for_each(|(o, (out, object))| {
            let base = self.vertex_start[o];
            for (out, t) in out.iter_mut().zip(&object.triangles) {
                *out = t.map(|i| i + base);
            }
        });
        out
    }
}

/// `values` cut at `starts` (each object's first entry, one extra entry at the end).
pub(crate) fn split_at_starts<'a, T>(mut values: &'a mut [T], starts: &[u32]) -> Vec<&'a mut [T]> {
    let mut parts = Vec::with_capacity(starts.len());
    for w in starts.windows(2) {
        let (part, rest) = values.split_at_mut((w[1] - w[0]) as usize);
        parts.push(part);
        values = rest;
    }
    parts
}

/// One triangle, gathered: see [`Flat::corners`].
pub(crate) struct Corners {
    pub vertices: [u32; 3],
    pub positions: [Vec3; 3],
    pub uvs: Option<[Vec2; 3]>,
}

fn check_lengths(index: usize, object: &Object) -> Result<(), MeshError> {
    let expected = object.positions.len();
    let lens = [
        ("uvs", object.uvs.as_ref().map(Vec::len)),
        ("uvs1", object.uvs1.as_ref().map(Vec::len)),
        ("normals", object.normals.as_ref().map(Vec::len)),
        ("tangents", object.tangents.as_ref().map(Vec::len)),
        ("colors", object.colors.as_ref().map(Vec::len)),
    ];
    let skin = object.skin.iter().flat_map(|set| {
        [("skin joints", Some(set.joints.len())), ("skin weights", Some(set.weights.len()))]
    });
    let targets = object.morph_targets.iter().flat_map(|target| {
        [
            ("morph target position deltas", Some(target.position_deltas.len())),
            ("morph target normal deltas", target.normal_deltas.as_ref().map(Vec::len)),
            ("morph target tangent deltas", target.tangent_deltas.as_ref().map(Vec::len)),
        ]
    });
    for (attribute, len) in lens.into_iter().chain(skin).chain(targets) {
        if let Some(actual) = len.filter(|&l| l != expected) {
            return Err(MeshError::AttributeLength {
                object: index,
                name: object.name.clone(),
                attribute,
                expected,
                actual,
            });
        }
    }
    if let Some(groups) = &object.smoothing_groups
        && groups.len() != object.triangles.len()
    {
        return Err(MeshError::SmoothingGroupsLength {
            object: index,
            name: object.name.clone(),
            expected: object.triangles.len(),
            actual: groups.len(),
        });
    }
    let Some(input_vertices) = expected.checked_sub(object.split_from.len()) else {
        return Err(MeshError::BadSplitFrom {
            object: index,
            name: object.name.clone(),
            entry: usize::MAX,
            value: u32::try_from(object.split_from.len()).unwrap_or(u32::MAX),
            input_vertices: 0,
        });
    };
    if let Some((entry, &value)) =
        object.split_from.iter().enumerate().find(|&(_, &v)| v as usize >= input_vertices)
    {
        return Err(MeshError::BadSplitFrom {
            object: index,
            name: object.name.clone(),
            entry,
            value,
            input_vertices,
        });
    }
    Ok(())
}

/// Checks one object: attribute lengths, indices, transform, finite positions and UVs.
pub(crate) fn check_object(index: usize, object: &Object) -> Result<Option<Mat4>, MeshError> {
    check_lengths(index, object)?;
    let vertex_count = object.positions.len();
    if let Some((corner, i)) = first_out_of_range(object.triangles.as_flattened(), vertex_count) {
        return Err(MeshError::IndexOutOfRange {
            object: index,
            name: object.name.clone(),
            triangle: corner / 3,
            index: i,
            vertex_count,
        });
    }
    let transform = match object.transform {
        Some(m) if m == Mat4::IDENTITY => None,
        Some(m) => {
            let det = Mat3::from_mat4(m).determinant();
            if !m.is_finite() || det == 0.0 || !det.is_finite() {
                return Err(MeshError::BadTransform { object: index, name: object.name.clone() });
            }
            Some(m)
        }
        None => None,
    };
    if let Some(uvs) = &object.uvs
        && let Some(vertex) = first_not_finite(bytemuck::cast_slice(uvs))
    {
        let (vertex, uv) = (vertex / 2, uvs[vertex / 2]);
        return Err(MeshError::NonFiniteUv {
            object: index,
            name: object.name.clone(),
            vertex,
            value: uv.to_array(),
        });
    }
    Ok(transform)
}

/// Values a check scans without a branch, before it looks for the first bad one in them:
/// a search that stops at the first bad value compares one value at a time, a scan that
/// does not stop compares several in one instruction (the checks run over every index and
/// position of the model, twice in a default `fix`: its own and its report's).
const SCAN: usize = 4096;

/// The first of `indices` (with its place) that is not below `count`.
fn first_out_of_range(indices: &[u32], count: usize) -> Option<(usize, u32)> {
    // No `u32` reaches a count past `u32::MAX`.
    let count = u32::try_from(count).ok()?;
    indices.chunks(SCAN).enumerate().find_map(|(k, chunk)| {
        let any = chunk.iter().fold(false, |any, &i| any | (i >= count));
        let at = any.then(|| chunk.iter().position(|&i| i >= count))??;
        Some((k * SCAN + at, chunk[at]))
    })
}

/// The place of the first of `values` that is not finite (NaN or infinite).
fn first_not_finite(values: &[f32]) -> Option<usize> {
    // All exponent bits set: infinite or NaN.
    let bad = |x: f32| x.to_bits() & 0x7F80_0000 == 0x7F80_0000;
    values.chunks(SCAN).enumerate().find_map(|(k, chunk)| {
        let any = chunk.iter().fold(false, |any, &x| any | bad(x));
        any.then(|| chunk.iter().position(|&x| bad(x)))?.map(|at| k * SCAN + at)
    })
}

/// Validates the model and flattens it into model space.
///
/// # Errors
/// Any [`MeshError`] about a bad object: attribute lengths, indices, transforms, non-finite
/// positions (after the transform) or UVs, or a model too large for 32-bit indices.
pub(crate) fn flatten(model: &Model) -> Result<Flat, MeshError> {
    let vertices = model.vertex_count();
    let corners = model.triangle_count().saturating_mul(3);
    if vertices > MAX_ELEMENTS {
        return Err(MeshError::TooLarge { what: "vertices", count: vertices, max: MAX_ELEMENTS });
    }
    if corners > MAX_ELEMENTS {
        return Err(MeshError::TooLarge {
            what: "triangle corners",
            count: corners,
            max: MAX_ELEMENTS,
        });
    }
    // `fix` adds at most one vertex per corner, and those vertices need 32-bit indices too.
    if vertices + corners > MAX_ELEMENTS {
        return Err(MeshError::TooLarge {
            what: "vertices plus triangle corners",
            count: vertices + corners,
            max: MAX_ELEMENTS,
        });
    }
    let transforms = model
        .objects
        .par_iter()
        .enumerate()
        .map(|(i, o)| check_object(i, o))
        .collect::<Result<Vec<_>, _>>()?;

    let mut vertex_start = Vec::with_capacity(model.objects.len() + 1);
    let mut triangle_start = Vec::with_capacity(model.objects.len() + 1);
    let (mut v, mut t) = (0u32, 0u32);
    for o in &model.objects {
        vertex_start.push(v);
        triangle_start.push(t);
        v += index(o.positions.len());
        t += index(o.triangles.len());
    }
    vertex_start.push(v);
    triangle_start.push(t);

    let mut positions = vec![Vec3::ZERO; vertices];
    // Split the output at object boundaries so objects fill it in parallel.
    let mut parts = Vec::with_capacity(model.objects.len());
    let mut rest = &mut positions[..];
    for o in &model.objects {
        let (part, tail) = rest.split_at_mut(o.positions.len());
        parts.push(part);
        rest = tail;
    }
    parts.into_par_iter().enumerate().try_for_each(|(i, pos)| {
        let object = &model.objects[i];
        match transforms[i] {
            Some(m) => {
                for (dst, &src) in pos.iter_mut().zip(&object.positions) {
                    *dst = m.transform_point3(src);
                }
            }
            None => pos.copy_from_slice(&object.positions),
        }
        match first_not_finite(bytemuck::cast_slice(pos)) {
            Some(x) => Err(MeshError::NonFinitePosition {
                object: i,
                name: object.name.clone(),
                vertex: x / 3,
                value: pos[x / 3].to_array(),
            }),
            None => Ok(()),
        }
    })?;

    Ok(Flat {
        positions,
        vertex_start,
        triangle_start,
        linear: transforms.iter().map(|m| m.map(Mat3::from_mat4)).collect(),
    })
}
