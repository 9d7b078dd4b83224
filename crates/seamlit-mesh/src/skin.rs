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
use crate::{Model, Object};

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
    let mut at_shared: Vec<u64> = roots
        .par_iter()
        .enumerate()
        .filter(|&(_, &r)| shared[r as usize])
        .map(|(v, &r)| (u64::from(r) << 32) | v as u64)
        .collect();
    at_shared.par_sort_unstable();
    let object_of = |v: usize| flat.vertex_start.partition_point(|&s| s as usize <= v) - 1;
    let disagreeing: Vec<(u32, usize, usize)> = at_shared
        .par_chunk_by(|a, b| a >> 32 == b >> 32)
        .filter_map(|run| {
            let vertices: Vec<(usize, Vec<(u32, f32)>)> = run
                .iter()
                .map(|&e| {
                    let v = low_half(e) as usize;
                    let o = object_of(v);
                    (o, influences(&model.objects[o], v - flat.vertex_start[o] as usize))
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
}
