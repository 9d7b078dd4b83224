//! The skin part of the seam report: welded positions where objects disagree on their skin
//! influences.
//!
//! Objects welded at a position in their bind pose stay together when the character moves
//! only if the joints move that position the same way in every object. Where one object's
//! vertex follows the arm and the other's the shoulder, the seam opens into a gap as soon as
//! the arm bends, whatever its normals. Influences are compared as a weight per joint node
//! (the joints of every set, weights of the same joint added, absent = 0): two vertices agree
//! when every joint's weight is within 1/255 (weights are often stored as normalised bytes).

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::index::low_half;
use crate::validate::Flat;
use crate::{Influences, Model, Object};

/// Two weights of one joint closer than this are equal: one step of a normalised byte, and
/// a little for the rounding of the sums.
const SAME_WEIGHT: f32 = 1.0 / 255.0 + 1e-6;

/// Welded positions shared by objects that disagree on their skin influences.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SkinSeams {
    /// Welded positions used by two or more objects whose vertices there have different skin
    /// influences (an object without a skin has none): a gap when the model is posed.
    pub positions: usize,
    /// The first such position (lowest welded index), with two of the objects that disagree.
    pub example: Option<SkinSeamExample>,
}

/// One welded position where objects' skin influences differ.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SkinSeamExample {
    /// The position in model space (bind pose for skinned objects).
    pub position: [f32; 3],
    /// The names of two objects whose vertices there disagree.
    pub objects: [String; 2],
}

/// Counts the shared welded positions whose objects disagree on influences. `roots` and
/// `shared` are the report's weld; nothing is done for a model without skins.
pub(crate) fn skin_seams(model: &Model, flat: &Flat, roots: &[u32], shared: &[bool]) -> SkinSeams {
    if model.objects.iter().all(|o| o.skin.is_empty()) {
        return SkinSeams::default();
    }
    let at_shared = at_shared_positions(roots, shared);
    let disagreeing: Vec<(u32, usize, usize)> = at_shared
        .par_chunk_by(|a, b| a >> 32 == b >> 32)
        .filter_map(|run| {
            let vertices: Vec<(usize, Vec<(u32, f32)>)> = run
                .iter()
                .map(|&e| {
                    let (o, v) = copy_of(flat, e);
                    (o, influences(&model.objects[o], v))
                })
                .collect();
            for (i, (oa, a)) in vertices.iter().enumerate() {
                for (ob, b) in &vertices[i + 1..] {
                    if oa != ob && !same(a, b) {
                        return Some(((run[0] >> 32) as u32, *oa, *ob));
                    }
                }
            }
            None
        })
        .collect();
    SkinSeams {
        positions: disagreeing.len(),
        example: disagreeing.first().map(|&(root, a, b)| SkinSeamExample {
            position: flat.positions[root as usize].to_array(),
            objects: [a, b].map(|o| model.objects[o].name.clone()),
        }),
    }
}

/// Every vertex at a shared welded position as `root << 32 | vertex`, sorted: the copies of
/// one position are one run (equal high halves), in vertex order, the positions in the order
/// of their roots. `roots` and `shared` are the report's weld.
fn at_shared_positions(roots: &[u32], shared: &[bool]) -> Vec<u64> {
    let mut at_shared: Vec<u64> = roots
        .par_iter()
        .enumerate()
        .filter(|&(_, &r)| shared[r as usize])
        .map(|(v, &r)| (u64::from(r) << 32) | v as u64)
        .collect();
    at_shared.par_sort_unstable();
    at_shared
}

/// An entry of [`at_shared_positions`] as (object, vertex within the object).
fn copy_of(flat: &Flat, entry: u64) -> (usize, usize) {
    let v = low_half(entry) as usize;
    let o = crate::index::part_of(&flat.vertex_start, v);
    (o, v - flat.vertex_start[o] as usize)
}

/// Vertex `v`'s weight per joint node, sorted by joint, weights of one joint added, zero
/// weights left out.
fn influences(object: &Object, v: usize) -> Vec<(u32, f32)> {
    let mut out: Vec<(u32, f32)> = object.skin.iter().flat_map(|set| set.of(v)).collect();
    out.sort_by_key(|&(j, _)| j);
    out.dedup_by(|next, kept| {
        let same = next.0 == kept.0;
        if same {
            kept.1 += next.1;
        }
        same
    });
    out
}

/// Whether every joint's weight (0 where absent) is within [`SAME_WEIGHT`] in `a` and `b`
/// (both sorted by joint).
fn same(a: &[(u32, f32)], b: &[(u32, f32)]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        let (wa, wb) = match (a.get(i), b.get(j)) {
            (Some(x), Some(y)) if x.0 == y.0 => {
                (i, j) = (i + 1, j + 1);
                (x.1, y.1)
            }
            (Some(x), y) if y.is_none_or(|y| x.0 < y.0) => {
                i += 1;
                (x.1, 0.0)
            }
            (_, Some(y)) => {
                j += 1;
                (0.0, y.1)
            }
            _ => unreachable!("the loop runs while one side has entries"),
        };
        if (wa - wb).abs() > SAME_WEIGHT {
            return false;
        }
    }
    true
}

/// What [`match_skin_seams`] changed.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SkinMatch {
    /// Welded positions whose skinned objects disagreed and now agree.
    pub positions: usize,
    /// Vertices given new influences.
    pub vertices: usize,
    /// Per object: whether its influences changed (so a writer writes them anew).
    pub objects: Vec<bool>,
}

/// Gives every copy of a welded position the same skin influences, where the skinned
/// objects that share it disagree (as [`SkinSeams`] counts them): a seam that stays closed in
/// every pose, since every copy then follows the same joints by the same weights.
///
/// The influences are merged in joint-node space: each object's weight per joint there (the
/// mean over its vertices at the position, which are split copies of one another or
/// nearly), averaged over the objects; the largest `4 x sets` kept (sets: the most any of
/// them has; objects with fewer get zero-weight sets added) and renormalised to sum 1; lanes
/// in order of weight. Objects without a skin are left out. Nothing else changes.
///
/// `copies` are the model's shared positions as [`shared_copies`] gives them (for a model
/// that `fix` has split since, those of its input vertices: the split copies follow their
/// sources' influences already); entries past an object's vertices are skipped.
pub fn match_skin_seams(model: &mut Model, copies: &[Vec<(u32, u32)>]) -> SkinMatch {
    let mut out = SkinMatch { objects: vec![false; model.objects.len()], ..SkinMatch::default() };
    if model.objects.iter().all(|o| o.skin.is_empty()) {
        return out;
    }
    let objects = &model.objects;
    // Per disagreeing position: its vertices (object, vertex) and their merged influences.
    type Merged = (Vec<(usize, usize)>, Vec<(u32, f32)>, usize);
    let merged: Vec<Merged> = copies
        .par_iter()
        .filter_map(|group| {
            let vertices: Vec<(usize, usize)> = group
                .iter()
                .map(|&(o, v)| (o as usize, v as usize))
                .filter(|&(o, v)| {
                    objects.get(o).is_some_and(|o| !o.skin.is_empty() && v < o.positions.len())
                })
                .collect();
            let each: Vec<(usize, Vec<(u32, f32)>)> =
                vertices.iter().map(|&(o, v)| (o, influences(&objects[o], v))).collect();
            let disagree = each
                .iter()
                .enumerate()
                .any(|(i, (oa, a))| each[i + 1..].iter().any(|(ob, b)| oa != ob && !same(a, b)));
            if !disagree {
                return None;
            }
            let sets = vertices.iter().map(|&(o, _)| objects[o].skin.len()).max().unwrap_or(1);
            Some((vertices, merge(&each, 4 * sets), sets))
        })
        .collect();
    for (vertices, joints, sets) in merged {
        out.positions += 1;
        for (o, v) in vertices {
            let object = &mut model.objects[o];
            let count = object.positions.len();
            while object.skin.len() < sets {
                object.skin.push(Influences {
                    joints: vec![[0; 4]; count],
                    weights: vec![[0.0; 4]; count],
                });
            }
            for (s, set) in object.skin.iter_mut().enumerate() {
                for lane in 0..4 {
                    let (joint, weight) = joints.get(4 * s + lane).copied().unwrap_or((0, 0.0));
                    set.joints[v][lane] = joint;
                    set.weights[v][lane] = weight;
                }
            }
            out.vertices += 1;
            out.objects[o] = true;
        }
    }
    out
}

/// The copies of each welded position that two or more objects share, as the seam report
/// welds them: per position (in the order of its lowest vertex), its vertices as
/// `(object, vertex)`. What a pose pulls apart when the copies move differently.
///
/// # Errors
///
/// The input checks of [`crate::fix`] (indices, lengths, transforms, finite positions).
pub fn shared_copies(
    model: &Model,
    tolerance: crate::WeldTolerance,
) -> Result<Vec<Vec<(u32, u32)>>, crate::MeshError> {
    let flat = crate::validate::flatten(model)?;
    let tolerance = tolerance.absolute(crate::weld::diagonal(&flat));
    let roots = crate::weld::roots(&flat.positions, tolerance);
    let shared = flat.shared_positions(&roots);
    let at_shared = at_shared_positions(&roots, &shared);
    Ok(at_shared
        .chunk_by(|a, b| a >> 32 == b >> 32)
        .map(|run| {
            run.iter()
                .map(|&e| {
                    let (o, v) = copy_of(&flat, e);
                    // Both fit u32: the model's vertex count does (validate).
                    #[expect(clippy::cast_possible_truncation, reason = "checked by validate")]
                    (o as u32, v as u32)
                })
                .collect()
        })
        .collect())
}

/// The influences of several objects' vertices at one position merged: per object the mean
/// weight per joint over its vertices, then the mean over the objects; the `keep` largest
/// (ties: the lower joint first), renormalised to sum 1.
fn merge(each: &[(usize, Vec<(u32, f32)>)], keep: usize) -> Vec<(u32, f32)> {
    /// An object, how many of its vertices are at the position, their weights per joint.
    type PerObject = (usize, usize, Vec<(u32, f32)>);
    let mut per_object: Vec<PerObject> = Vec::new();
    for (o, influences) in each {
        let entry = match per_object.iter_mut().position(|(x, _, _)| x == o) {
            Some(i) => &mut per_object[i],
            None => {
                per_object.push((*o, 0, Vec::new()));
                per_object.last_mut().expect("just pushed")
            }
        };
        entry.1 += 1;
        for &(j, w) in influences {
            match entry.2.iter_mut().find(|(k, _)| *k == j) {
                Some(slot) => slot.1 += w,
                None => entry.2.push((j, w)),
            }
        }
    }
    let mut total: Vec<(u32, f32)> = Vec::new();
    for (_, count, weights) in &per_object {
        for &(j, w) in weights {
            let w = w / *count as f32 / per_object.len() as f32;
            match total.iter_mut().find(|(k, _)| *k == j) {
                Some(slot) => slot.1 += w,
                None => total.push((j, w)),
            }
        }
    }
    total.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    total.truncate(keep);
    let sum: f32 = total.iter().map(|&(_, w)| w).sum();
    if sum > 0.0 {
        for (_, w) in &mut total {
            *w /= sum;
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_within_a_byte_step_agree_and_a_missing_joint_counts_as_zero() {
        assert!(same(&[(1, 0.5), (2, 0.5)], &[(1, 0.5 + 0.5 / 255.0), (2, 0.5)]));
        assert!(!same(&[(1, 0.5), (2, 0.5)], &[(1, 0.5 + 2.0 / 255.0), (2, 0.5)]));
        assert!(same(&[(1, 1.0)], &[(1, 1.0), (7, 0.5 / 255.0)]));
        assert!(!same(&[(1, 1.0)], &[(2, 1.0)]));
        assert!(!same(&[], &[(2, 1.0)]));
        assert!(same(&[], &[]));
    }

    #[test]
    fn merging_averages_per_object_keeps_the_largest_and_sums_to_one() {
        // Object 0 has two vertices there (a split copy), object 1 one.
        let each =
            vec![(0, vec![(1, 0.5), (2, 0.5)]), (0, vec![(1, 0.5), (2, 0.5)]), (1, vec![(2, 1.0)])];
        let merged = merge(&each, 4);
        assert_eq!(merged, vec![(2, 0.75), (1, 0.25)]);
        let five: Vec<(u32, f32)> = (0..5).map(|j| (j, 0.1 + 0.01 * j as f32)).collect();
        let kept = merge(&[(0, five)], 4);
        assert_eq!(kept.iter().map(|&(j, _)| j).collect::<Vec<_>>(), [4, 3, 2, 1]);
        assert!((kept.iter().map(|&(_, w)| w).sum::<f32>() - 1.0).abs() < 1e-6);
    }
}
