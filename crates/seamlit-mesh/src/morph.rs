//! Morph targets: their normal and tangent deltas, computed the way the base normals were.
//!
//! A morph target moves positions; the renderer adds the target's normal deltas to the base
//! normals (glTF 2.0, "Morph Targets"). Deltas computed object by object would reopen the seam
//! that [`crate::fix`] closed as soon as the face morphs, so they are computed across objects
//! with the base result's decisions:
//!
//! - **the weld** is the base positions' (the same tolerance and [`Mode`]);
//! - **the creases and splits** are the base result's: at one welded position, vertices whose
//!   base normals agree (in model space, within [`SAME_NORMAL`]) are one normal group, and
//!   vertices that also agree on their tangent one tangent group. A split vertex stays split
//!   in every target, and two vertices that share a normal share it in every target.
//!
//! For target `k`, every triangle's face is computed from the displaced positions (`base +
//! delta_k`; objects with fewer targets use their base positions), its normal weighted as
//! [`crate::FixOptions::weighting`] says and added to its corners' normal groups (its tangent to
//! their tangent groups), in triangle order. A group's normal is its sum
//! normalised; a tangent is its sum made orthogonal to that normal, the base handedness kept.
//! The delta is the local-space difference from the base frame (tangents: `xyz` only).
//!
//! A target that does not move any corner of a face leaves that face as it was, so only the
//! groups that hold a corner of a moved face change: every other vertex gets a delta of
//! exactly zero, and only the faces around the changed groups are computed again (a blend
//! shape that moves a face's mouth costs what the mouth costs). The changed groups get the
//! bits a computation over every face would give them (the unit test
//! `sparse_targets_get_the_bits_of_the_dense_computation`).
//!
//! Cost per target: a pass over the triangles and the vertices to find what the target moves,
//! then the faces and vertices of the groups it reaches; the weld and the grouping are done
//! once for all targets.

use glam::{Vec3, Vec4, Vec4Swizzles};
use rayon::prelude::*;

use crate::face::{DEGENERATE, DEGENERATE_UV, face};
use crate::frame::{Linear, orthogonal_tangent};
use crate::group::weight;
use crate::index::{index, low_half};
use crate::validate::{self, Flat, split_at_starts};
use crate::weld::{diagonal, roots_for_mode};
use crate::{FixOptions, Influences, MeshError, Mode, Model, MorphTarget};

/// Two base normals (or tangents) at one welded position belong to one group when their
/// model-space dot product is at least this (about 0.26 degrees): the values of one group
/// differ only by each object's round trip through its transform.
const SAME_NORMAL: f32 = 1.0 - 1e-5;

/// Appends to every per-vertex array of `skin` and `targets` a copy of vertex `v`'s entry:
/// what [`crate::fix`] does for the vertices it splits.
pub(crate) fn copy_vertex(skin: &mut [Influences], targets: &mut [MorphTarget], v: usize) {
    for set in skin {
        push_copy(&mut set.joints, v);
        push_copy(&mut set.weights, v);
    }
    for target in targets {
        push_copy(&mut target.position_deltas, v);
        if let Some(n) = &mut target.normal_deltas {
            push_copy(n, v);
        }
        if let Some(t) = &mut target.tangent_deltas {
            push_copy(t, v);
        }
    }
}

/// Appends `item`, growing a full vector by an eighth rather than doubling it: an object's
/// copies are few beside its vertices (the 1M teapot's 768 among 532,512), and a doubled
/// array of every attribute of every object that splits one vertex would be the fix's peak
/// of memory.
pub(crate) fn push_slack<T>(items: &mut Vec<T>, item: T) {
    if items.len() == items.capacity() {
        items.reserve_exact(items.len() / 8 + 16);
    }
    items.push(item);
}

/// [`push_slack`] of a copy of entry `v`.
pub(crate) fn push_copy<T: Copy>(items: &mut Vec<T>, v: usize) {
    push_slack(items, items[v]);
}

/// Sets the normal (and, where the object has tangents, tangent) deltas of every morph
/// target of the objects marked in `computed` (those whose normals `fix` computed), from the
/// fixed `model`'s normals, tangents, triangles and split vertices.
pub(crate) fn compute_deltas(
    model: &mut Model,
    options: &FixOptions,
    computed: &[bool],
    weld: Option<Vec<u32>>,
) -> Result<(), MeshError> {
    let targets = model
        .objects
        .iter()
        .zip(computed)
        .filter(|(_, c)| **c)
        .map(|(o, _)| o.morph_targets.len())
        .max()
        .unwrap_or(0);
    if targets == 0 {
        return Ok(());
    }
    let flat = validate::flatten(model)?;
    let groups = Groups::of(model, &flat, options, weld);
    // Targets are independent (each its own sums): computed side by side, the same bits.
    let deltas: Vec<Vec<Deltas>> = (0..targets)
        .into_par_iter()
        .map(|k| {
            let reach = Reach::of(model, &flat, &groups, k, Scope::Moved);
            target_deltas(model, &flat, &groups, options, &reach, k)
        })
        .collect();
    for (k, per_object) in deltas.into_iter().enumerate() {
        for (o, d) in per_object.into_iter().enumerate() {
            if !computed[o] {
                continue;
            }
            if let Some(target) = model.objects[o].morph_targets.get_mut(k) {
                target.normal_deltas = Some(d.normals);
                target.tangent_deltas = d.tangents;
            }
        }
    }
    Ok(())
}

/// Each vertex's normal group and tangent group, named by their first vertex (model-wide
/// index).
struct Groups {
    normal: Vec<u32>,
    tangent: Vec<u32>,
    /// Per vertex: the base frame in model space (tangent zero where the object has none).
    frames: Vec<(Vec3, Vec4)>,
}

impl Groups {
    /// `weld`: the base fix's roots (see [`roots_after_splits`]), welded again where `None`.
    fn of(model: &Model, flat: &Flat, options: &FixOptions, weld: Option<Vec<u32>>) -> Self {
        let roots: Vec<u32> = if options.mode == Mode::Flat {
            (0..index(flat.positions.len())).collect()
        } else if let Some(roots) = weld {
            roots
        } else {
            let tolerance = options.weld_tolerance.absolute(diagonal(flat));
            roots_for_mode(flat, tolerance, options.mode)
        };
        let frames = base_frames(model, flat);
        // Vertices in order of their root, so that each position's vertices are one run.
        let mut order: Vec<u64> =
            roots.iter().enumerate().map(|(v, &r)| (u64::from(r) << 32) | v as u64).collect();
        order.par_sort_unstable();
        let mut normal: Vec<u32> = (0..index(roots.len())).collect();
        let mut tangent = normal.clone();
        for run in order.chunk_by(|a, b| a >> 32 == b >> 32) {
            for (i, &a) in run.iter().enumerate() {
                let a = low_half(a) as usize;
                let (na, ta) = frames[a];
                // The first earlier vertex with the same normal (and tangent), if any.
                for &b in &run[..i] {
                    let b = low_half(b) as usize;
                    let nb = frames[b].0;
                    if normal[b] as usize == b && na.dot(nb) >= SAME_NORMAL {
                        normal[a] = index(b);
                        break;
                    }
                }
                for &b in &run[..i] {
                    let b = low_half(b) as usize;
                    let tb = frames[b].1;
                    if tangent[b] as usize == b
                        && normal[a] == normal[b]
                        && ta.w == tb.w
                        && ta.xyz().dot(tb.xyz()) >= SAME_NORMAL
                    {
                        tangent[a] = index(b);
                        break;
                    }
                }
            }
        }
        Self { normal, tangent, frames }
    }
}

/// The fix's weld `roots`, taken before it split vertices (when objects had `counts`
/// vertices), for the vertices of the fixed `model`: a copy's root is its source's, and each
/// root is renumbered into the new layout.
pub(crate) fn roots_after_splits(roots: &[u32], counts: &[usize], model: &Model) -> Vec<u32> {
    let mut old_start = Vec::with_capacity(counts.len() + 1);
    let mut new_start = Vec::with_capacity(counts.len() + 1);
    let (mut a, mut b) = (0usize, 0usize);
    for (count, object) in counts.iter().zip(&model.objects) {
        old_start.push(a);
        new_start.push(b);
        a += count;
        b += object.vertex_count();
    }
    old_start.push(a);
    new_start.push(b);
    let starts: Vec<u32> = new_start.iter().map(|&s| index(s)).collect();
    let renumber = |r: u32| {
        let o = old_start.partition_point(|&s| s <= r as usize) - 1;
        index(new_start[o] + r as usize - old_start[o])
    };
    let mut out = vec![0; b];
    split_at_starts(&mut out, &starts).into_par_iter().enumerate().for_each(|(o, part)| {
        let object = &model.objects[o];
        // Most roots lie in the vertex's own object: moved by the object's shift.
        let (start, end) = (old_start[o], old_start[o + 1]);
        let shift = |r: u32| index(new_start[o] + r as usize - start);
        for (v, root) in (0..).zip(part.iter_mut()) {
            // A copy of a copy points at the first input vertex: the same position.
            let r = roots[start + object.source_vertex(v) as usize];
            *root = if (start..end).contains(&(r as usize)) { shift(r) } else { renumber(r) };
        }
    });
    out
}

/// Every vertex's fixed normal and tangent in model space.
fn base_frames(model: &Model, flat: &Flat) -> Vec<(Vec3, Vec4)> {
    model
        .objects
        .par_iter()
        .enumerate()
        .flat_map_iter(|(o, object)| {
            let linear = flat.linear[o].map(Linear::new);
            let normals = object.normals.as_deref().unwrap_or_default();
            let tangents = object.tangents.as_deref();
            (0..object.vertex_count()).map(move |v| {
                let n = normals.get(v).copied().unwrap_or(Vec3::Z);
                let t = tangents.map_or(Vec4::ZERO, |t| t[v]);
                match &linear {
                    Some(l) if t != Vec4::ZERO => l.frame_to_model(n, t),
                    Some(l) => (l.normal_to_model(n), Vec4::ZERO),
                    None => (n, t),
                }
            })
        })
        .collect()
}

/// Which vertices a target's deltas are computed for.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Scope {
    /// Those whose normal group holds a corner of a face that the target moves; the others
    /// get a delta of exactly zero.
    Moved,
    /// Every vertex (the dense computation, kept as the tests' oracle).
    All,
}

/// Per vertex (model-wide index): whether its deltas are computed for one target.
struct Reach {
    needed: Vec<bool>,
}

impl Reach {
    /// The vertices of the normal groups that hold a corner of a face target `k` moves (a
    /// face moves when a corner's position delta is not zero). A tangent group lies inside
    /// one normal group, so these are also every vertex of the tangent groups it reaches.
    fn of(model: &Model, flat: &Flat, groups: &Groups, k: usize, scope: Scope) -> Self {
        let n = flat.positions.len();
        if scope == Scope::All {
            return Self { needed: vec![true; n] };
        }
        // 1. The corners of the moved faces, object by object.
        let mut touched = vec![false; n];
        split_by_object(&mut touched, model).into_par_iter().zip(&model.objects).for_each(
            |(touched, object)| {
                let Some(deltas) = object.morph_targets.get(k).map(|t| &t.position_deltas) else {
                    return;
                };
                for tri in &object.triangles {
                    if tri.iter().any(|&i| deltas[i as usize] != Vec3::ZERO) {
                        tri.iter().for_each(|&i| touched[i as usize] = true);
                    }
                }
            },
        );
        // 2. Their normal groups (named by their first vertex, which comes first), then every
        //    member of those groups.
        let mut needed = vec![false; n];
        for v in (0..n).filter(|&v| touched[v]) {
            needed[groups.normal[v] as usize] = true;
        }
        for v in 0..n {
            needed[v] = needed[groups.normal[v] as usize];
        }
        Self { needed }
    }
}

/// `values` (one per vertex of the model, in object order) cut into one slice per object.
fn split_by_object<'a, T>(values: &'a mut [T], model: &Model) -> Vec<&'a mut [T]> {
    let mut parts = Vec::with_capacity(model.objects.len());
    let mut rest = values;
    for object in &model.objects {
        let (part, tail) = rest.split_at_mut(object.vertex_count());
        parts.push(part);
        rest = tail;
    }
    parts
}

/// Per group (indexed by its first vertex): the weighted sums of the normals (normal groups)
/// and tangents (tangent groups) of target `k`'s faces. Each object adds its faces into its
/// own vertices in parallel (triangle order); the vertices are then added into their groups
/// in vertex order, so the bits do not depend on the thread count. Only the faces with a
/// corner in `reach` are computed, and only the groups in `reach` summed: a vertex's sum still
/// takes every face around it, in triangle order, so those groups get the dense bits.
fn group_sums(
    model: &Model,
    flat: &Flat,
    groups: &Groups,
    options: &FixOptions,
    reach: &Reach,
    k: usize,
) -> (Vec<Vec3>, Vec<Vec3>) {
    let n = flat.positions.len();
    let mut sums = vec![(Vec3::ZERO, Vec3::ZERO); n];
    let parts = split_by_object(&mut sums, model);
    parts.into_par_iter().zip(&model.objects).enumerate().for_each(|(o, (sums, object))| {
        let needed = &reach.needed[flat.vertex_start[o] as usize..][..object.vertex_count()];
        let deltas = object.morph_targets.get(k).map(|t| t.position_deltas.as_slice());
        let transform = object.transform.map(|_| object.model_transform());
        let displaced = |i: u32| {
            let i = i as usize;
            let p = object.positions[i] + deltas.map_or(Vec3::ZERO, |d| d[i]);
            transform.map_or(p, |m| m.transform_point3(p))
        };
        let uvs = object.uvs.as_deref();
        for tri in object.triangles.iter().filter(|t| t.iter().any(|&i| needed[i as usize])) {
            let f =
                face(tri.map(displaced), uvs.map(|uv| tri.map(|i| uv[i as usize])), model.v_axis);
            let tangent = !f.is(DEGENERATE | DEGENERATE_UV);
            for (c, &i) in tri.iter().enumerate() {
                let w = weight(options.weighting, &f, c);
                let s = &mut sums[i as usize];
                s.0 += f.normal * w;
                if tangent {
                    s.1 += f.tangent * w;
                }
            }
        }
    });
    // A group's first vertex comes before its other vertices: add each into it in order.
    let (mut n_sum, mut t_sum): (Vec<Vec3>, Vec<Vec3>) = sums.into_iter().unzip();
    for v in (0..n).filter(|&v| reach.needed[v]) {
        let (gn, gt) = (groups.normal[v] as usize, groups.tangent[v] as usize);
        if gn != v {
            n_sum[gn] = n_sum[gn] + n_sum[v];
        }
        if gt != v {
            t_sum[gt] = t_sum[gt] + t_sum[v];
        }
    }
    (n_sum, t_sum)
}

/// One object's deltas for one target, local space.
struct Deltas {
    normals: Vec<Vec3>,
    tangents: Option<Vec<Vec3>>,
}

/// The deltas of target `k` for every object (empty for objects without vertices): zero
/// outside `reach`.
fn target_deltas(
    model: &Model,
    flat: &Flat,
    groups: &Groups,
    options: &FixOptions,
    reach: &Reach,
    k: usize,
) -> Vec<Deltas> {
    let (n_sum, t_sum) = group_sums(model, flat, groups, options, reach, k);
    model
        .objects
        .par_iter()
        .enumerate()
        .map(|(o, object)| {
            let base = flat.vertex_start[o] as usize;
            let linear = flat.linear[o].map(Linear::new);
            let normals = object.normals.as_deref().unwrap_or_default();
            let mut dn = Vec::with_capacity(object.vertex_count());
            let mut dt = object.tangents.as_ref().map(|_| Vec::with_capacity(dn.capacity()));
            for v in 0..object.vertex_count() {
                if !reach.needed[base + v] {
                    dn.push(Vec3::ZERO);
                    if let Some(dt) = &mut dt {
                        dt.push(Vec3::ZERO);
                    }
                    continue;
                }
                let (n0, t0) = groups.frames[base + v];
                let nk = n_sum[groups.normal[base + v] as usize].try_normalize().unwrap_or(n0);
                let tk = t_sum[groups.tangent[base + v] as usize];
                let tk = if tk == Vec3::ZERO { t0.xyz() } else { tk };
                let frame = orthogonal_tangent(nk, tk).extend(if t0.w < 0.0 { -1.0 } else { 1.0 });
                let (local_n, local_t) = match &linear {
                    Some(l) => l.frame_to_local(nk, frame),
                    None => (nk, frame),
                };
                let base_n = normals.get(v).copied().unwrap_or(Vec3::Z);
                dn.push(local_n - base_n);
                if let (Some(dt), Some(tangents)) = (&mut dt, &object.tangents) {
                    dt.push(local_t.xyz() - tangents[v].xyz());
                }
            }
            Deltas { normals: dn, tangents: dt }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec2};

    use super::*;
    use crate::{Object, VAxis, fix};

    /// An 8 x 8 grid of quads over `[x0, x0 + 2] x [0, 2]` with a 70-degree ridge at
    /// `x0 + 1` (a crease that splits vertices), UVs, and one target: a bump of radius 0.6
    /// around the seam point (2, 1), exactly zero outside it.
    fn sheet(name: &str, x0: f32) -> Object {
        let n = 9;
        let (mut positions, mut uvs, mut deltas) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (x0 + 0.25 * i as f32, 0.25 * j as f32);
                let ridge = 2.75 * (x - x0 - 1.0).max(0.0);
                positions.push(Vec3::new(x, y, 0.05 * x * x + ridge));
                uvs.push(Vec2::new(x / 4.0, 1.0 - y / 2.0));
                let r2 = (x - 2.0).powi(2) + (y - 1.0).powi(2);
                deltas.push(if r2 < 0.36 { Vec3::Z * 0.3 * (1.0 - r2 / 0.36) } else { Vec3::ZERO });
            }
        }
        let mut triangles = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let v = j * n + i;
                triangles.push([v, v + 1, v + n + 1]);
                triangles.push([v, v + n + 1, v + n]);
            }
        }
        let mut object = Object::new(name, positions, triangles).with_uvs(uvs);
        object.morph_targets =
            vec![MorphTarget { position_deltas: deltas, ..MorphTarget::default() }];
        object
    }

    #[test]
    fn sparse_targets_get_the_bits_of_the_dense_computation() {
        let options = FixOptions::default();
        let mut right = sheet("right", 2.0);
        // A transform that moves the object and back: its deltas go through model space.
        right.positions.iter_mut().for_each(|p| *p -= Vec3::X);
        right.transform = Some(Mat4::from_translation(Vec3::X));
        let input = Model { objects: vec![sheet("left", 0.0), right], v_axis: VAxis::Down };
        let model = fix(&input, &options).unwrap();
        let flat = validate::flatten(&model).unwrap();
        let groups = Groups::of(&model, &flat, &options, None);
        let deltas = |scope| {
            let reach = Reach::of(&model, &flat, &groups, 0, scope);
            (target_deltas(&model, &flat, &groups, &options, &reach, 0), reach)
        };
        let ((sparse, reach), (dense, _)) = (deltas(Scope::Moved), deltas(Scope::All));
        let (mut computed, mut zero, mut unmoved) = (0, 0, 0);
        for (o, object) in model.objects.iter().enumerate() {
            let (s, d) = (&sparse[o], &dense[o]);
            let (st, dt) = (s.tangents.as_ref().unwrap(), d.tangents.as_ref().unwrap());
            for v in 0..object.vertex_count() {
                if reach.needed[flat.vertex_start[o] as usize + v] {
                    assert_eq!(
                        s.normals[v].to_array().map(f32::to_bits),
                        d.normals[v].to_array().map(f32::to_bits),
                        "{o} v{v}"
                    );
                    assert_eq!(
                        st[v].to_array().map(f32::to_bits),
                        dt[v].to_array().map(f32::to_bits),
                        "{o} v{v}"
                    );
                    computed += 1;
                    let source = object.source_vertex(index(v)) as usize;
                    if object.morph_targets[0].position_deltas[source] == Vec3::ZERO {
                        unmoved += 1;
                    }
                } else {
                    assert_eq!((s.normals[v], st[v]), (Vec3::ZERO, Vec3::ZERO), "{o} v{v}");
                    // What the dense computation gives there is rounding only.
                    assert!(d.normals[v].length() < 1e-5, "{o} v{v}: {}", d.normals[v]);
                    zero += 1;
                }
            }
        }
        // Both objects are reached (across the seam), and beyond the moved vertices.
        assert!(computed > 20 && zero > 100 && unmoved > 10, "{computed} {zero} {unmoved}");
    }
}
