//! Grouping the corners around each welded position into smoothing groups, and averaging
//! their faces' normals and tangents (the paper's section 5.2, with a crease angle).
//!
//! The corners at one position are gathered from a compressed incidence list (counting sort of
//! corners by position id, so each list is in corner order and the sums do not depend on the
//! number of threads). Around a position, faces whose normals are within the crease angle of
//! each other join the same *normal group* (connected components of that relation); a crease
//! angle of 180 degrees or more joins every face at the position, as the paper does. Within a
//! normal group, faces join the same *tangent group* when their UV handedness agrees (unless
//! that split is off) and their tangents are within the tangent angle. Corners of faces whose
//! UVs are degenerate form one more tangent group per normal group, whose tangent is the
//! average over all the normal group's usable faces; they contribute nothing to the others.
//! A tangent group whose members cancel out (a fan around a pole) keeps per-face tangents.
//!
//! Most positions (inside a smooth, consistently mapped surface) form a single group; a fast
//! path recognises them in one pass: every face within half the crease angle of the first is
//! within the crease angle of every other, so they form one component.
#![expect(
    clippy::needless_range_loop,
    reason = "corners are local indices into several parallel scratch arrays at once"
)]

use std::ops::Range;

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use crate::face::{DEGENERATE, DEGENERATE_UV, Face};
use crate::frame::finish;
use crate::weld::union;
use crate::{FixOptions, Weighting};

/// Corners grouped by position: `corners[offsets[p]..offsets[p + 1]]` are the corners
/// (`triangle * 3 + k`) at position id `p`, in ascending order.
pub(crate) struct Incidence {
    pub offsets: Vec<u32>,
    pub corners: Vec<u32>,
}

impl Incidence {
    pub fn new(corner_positions: &[u32], position_count: usize) -> Self {
        let mut offsets = vec![0u32; position_count + 1];
        for &p in corner_positions {
            offsets[p as usize + 1] += 1;
        }
        for i in 0..position_count {
            offsets[i + 1] += offsets[i];
        }
        let mut next = offsets.clone();
        let mut corners = vec![0u32; corner_positions.len()];
        for (c, &p) in corner_positions.iter().enumerate() {
            let slot = &mut next[p as usize];
            corners[*slot as usize] = c as u32;
            *slot += 1;
        }
        Self { offsets, corners }
    }

    pub fn at(&self, p: usize) -> &[u32] {
        &self.corners[self.offsets[p] as usize..self.offsets[p + 1] as usize]
    }

    pub fn range(&self, positions: Range<usize>) -> Range<usize> {
        self.offsets[positions.start] as usize..self.offsets[positions.end] as usize
    }
}

/// The averaged frame of one group, in model space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Frame {
    pub normal: Vec3,
    pub tangent: Vec4,
}

/// The result: a group per corner and a frame per group.
pub(crate) struct Groups {
    /// Per corner, its group.
    pub corner_group: Vec<u32>,
    /// Per group, its frame.
    pub frames: Vec<Frame>,
}

/// The grouping rules, from [`FixOptions`].
#[derive(Clone, Copy)]
pub(crate) struct Rules {
    pub weighting: Weighting,
    /// Cosine of the crease angle; `None` = no creases.
    pub crease_cos: Option<f32>,
    /// Cosine of the tangent angle; `None` = no limit.
    pub tangent_cos: Option<f32>,
    /// Cosines of half the crease and tangent angles, for the single-group fast path.
    pub crease_half_cos: Option<f32>,
    pub tangent_half_cos: Option<f32>,
    pub split_mirrored: bool,
    /// Whether tangents are averaged at all (otherwise tangent groups = normal groups).
    pub tangents: bool,
}

impl Rules {
    pub fn new(options: &FixOptions, tangents: bool) -> Self {
        let cos = |deg: f32| (deg < 180.0).then(|| deg.max(0.0).to_radians().cos());
        Self {
            weighting: options.weighting,
            crease_cos: cos(options.crease_angle_deg),
            crease_half_cos: cos(options.crease_angle_deg * 0.5),
            tangent_cos: cos(options.tangent_angle_deg),
            tangent_half_cos: cos(options.tangent_angle_deg * 0.5),
            split_mirrored: options.split_mirrored,
            tangents,
        }
    }

    /// Whether every corner at a position joins one tangent group (the paper).
    fn tangents_unconditional(&self) -> bool {
        self.tangent_cos.is_none() && !self.split_mirrored
    }
}

/// Weight of corner `k` of face `f`.
pub(crate) fn weight(weighting: Weighting, f: &Face, k: usize) -> f32 {
    if f.is(DEGENERATE) {
        return 0.0;
    }
    match weighting {
        Weighting::Angle => f.angles[k],
        Weighting::Area => f.area2,
        Weighting::AngleArea => f.angles[k] * f.area2,
        Weighting::Uniform => 1.0,
    }
}

/// Positions handled per parallel task.
const CHUNK: usize = 4096;

#[derive(Default)]
struct Scratch {
    normal_parent: Vec<u32>,
    tangent_parent: Vec<u32>,
    /// Per local corner: index into the chunk's frames.
    local_group: Vec<u32>,
    /// Per local corner (as a group root): sums and first usable members.
    n_sum: Vec<Vec3>,
    t_sum: Vec<Vec3>,
    b_sum: Vec<Vec3>,
    w_sum: Vec<f32>,
    group_t: Vec<Vec3>,
    group_b: Vec<Vec3>,
    first_unusable: Vec<u32>,
    fallback: Vec<Vec3>,
    first_usable: Vec<u32>,
    frame_of_root: Vec<u32>,
}

/// Points every entry at its root.
fn flatten(parent: &mut [u32]) {
    for a in 0..parent.len() {
        // Roots are the smallest members, so `parent[a] <= a` and one pass suffices.
        parent[a] = parent[parent[a] as usize];
    }
}

/// Groups the corners at every position and averages their frames.
///
/// `corner_positions[c]` is the position id of corner `c` (`triangle * 3 + k`).
pub(crate) fn group(
    corner_positions: &[u32],
    position_count: usize,
    faces: &[Face],
    rules: Rules,
) -> Groups {
    let incidence = Incidence::new(corner_positions, position_count);
    let chunks: Vec<Range<usize>> =
        (0..position_count).step_by(CHUNK).map(|s| s..(s + CHUNK).min(position_count)).collect();
    let parts: Vec<(Vec<u32>, Vec<Frame>)> = chunks
        .into_par_iter()
        .map_init(Scratch::default, |scratch, positions| {
            let slots = incidence.range(positions.clone());
            let mut groups = Vec::with_capacity(slots.len());
            let mut frames = Vec::with_capacity(positions.len() + positions.len() / 8);
            for p in positions {
                let corners = incidence.at(p);
                group_position(corners, faces, rules, scratch, &mut frames);
                groups.extend_from_slice(&scratch.local_group);
            }
            (groups, frames)
        })
        .collect();

    let mut corner_group = vec![0u32; corner_positions.len()];
    let mut frames = Vec::with_capacity(position_count + position_count / 8);
    let mut slot = 0usize;
    for (groups, chunk_frames) in parts {
        let base = frames.len() as u32;
        for g in groups {
            corner_group[incidence.corners[slot] as usize] = base + g;
            slot += 1;
        }
        frames.extend(chunk_frames);
    }
    Groups { corner_group, frames }
}

/// Groups the corners at one position; pushes one frame per tangent group onto `frames` and
/// leaves in `scratch.local_group` each corner's frame index (chunk-local).
///
/// Quadratic in the number of corners where the fast path does not apply.
#[inline(never)]
fn group_position(
    corners: &[u32],
    faces: &[Face],
    rules: Rules,
    s: &mut Scratch,
    frames: &mut Vec<Frame>,
) {
    let k = corners.len();
    let face_of = |a: usize| corners[a] as usize / 3;
    let usable = |a: usize| !faces[face_of(a)].is(DEGENERATE_UV | DEGENERATE);

    if single_group(corners, faces, rules, s, frames) {
        return;
    }

    // Normal groups.
    let np = &mut s.normal_parent;
    np.clear();
    match rules.crease_cos {
        None => np.resize(k, 0),
        Some(cos) => {
            np.extend(0..k as u32);
            for a in 1..k {
                if face_of(a) == face_of(a - 1) {
                    union(np, a as u32 - 1, a as u32);
                }
            }
            for a in 0..k {
                let fa = &faces[face_of(a)];
                if fa.is(DEGENERATE) {
                    continue;
                }
                for b in a + 1..k {
                    let fb = &faces[face_of(b)];
                    if !fb.is(DEGENERATE) && fa.normal.dot(fb.normal) >= cos {
                        union(np, a as u32, b as u32);
                    }
                }
            }
            flatten(np);
        }
    }

    // Per normal group: the weighted normal sum, a fallback normal, the first usable corner.
    s.n_sum.clear();
    s.n_sum.resize(k, Vec3::ZERO);
    s.fallback.clear();
    s.fallback.resize(k, Vec3::ZERO);
    s.first_usable.clear();
    s.first_usable.resize(k, u32::MAX);
    for a in 0..k {
        let c = corners[a] as usize;
        let f = &faces[c / 3];
        let g = np[a] as usize;
        s.n_sum[g] += f.normal * weight(rules.weighting, f, c % 3);
        if s.fallback[g] == Vec3::ZERO {
            s.fallback[g] = f.normal;
        }
        if s.first_usable[g] == u32::MAX && usable(a) {
            s.first_usable[g] = a as u32;
        }
    }

    // Tangent groups, within normal groups. Unusable corners (degenerate UVs) form one group
    // per normal group, whose tangent is the sum over all the normal group's usable corners:
    // a value that does not depend on the order of the corners (so not on how the model is
    // cut into objects), and equal to the usable group's where there is only one.
    let tp = &mut s.tangent_parent;
    tp.clear();
    if !rules.tangents {
        tp.extend_from_slice(np);
    } else {
        tp.extend(0..k as u32);
        s.first_unusable.clear();
        s.first_unusable.resize(k, u32::MAX);
        for a in 0..k {
            let g = np[a] as usize;
            if usable(a) {
                if rules.tangents_unconditional() {
                    union(tp, a as u32, s.first_usable[g]);
                }
            } else if s.first_unusable[g] == u32::MAX {
                s.first_unusable[g] = a as u32;
            } else {
                union(tp, a as u32, s.first_unusable[g]);
            }
        }
        if !rules.tangents_unconditional() {
            for a in 1..k {
                if face_of(a) == face_of(a - 1) && usable(a) {
                    union(tp, a as u32 - 1, a as u32);
                }
            }
            for a in 0..k {
                if !usable(a) {
                    continue;
                }
                let ta = &faces[face_of(a)];
                for b in a + 1..k {
                    if np[a] != np[b] || !usable(b) {
                        continue;
                    }
                    let tb = &faces[face_of(b)];
                    let join = (!rules.split_mirrored || ta.sign() == tb.sign())
                        && rules.tangent_cos.is_none_or(|c| ta.tangent.dot(tb.tangent) >= c);
                    if join {
                        union(tp, a as u32, b as u32);
                    }
                }
            }
        }
        flatten(tp);
    }

    // Sums: per tangent group over its usable corners; per normal group over all its usable
    // corners (for the unusable group), or over its unusable ones where none is usable.
    // Degenerate faces never count.
    for v in [&mut s.t_sum, &mut s.b_sum, &mut s.group_t, &mut s.group_b] {
        v.clear();
        v.resize(k, Vec3::ZERO);
    }
    s.w_sum.clear();
    s.w_sum.resize(k, 0.0);
    let (mut position_t, mut position_b) = (Vec3::ZERO, Vec3::ZERO);
    if rules.tangents {
        for a in 0..k {
            let c = corners[a] as usize;
            let f = &faces[c / 3];
            if f.is(DEGENERATE) {
                continue;
            }
            let g = np[a] as usize;
            if usable(a) {
                let w = weight(rules.weighting, f, c % 3);
                let root = tp[a] as usize;
                s.t_sum[root] += f.tangent * w;
                s.b_sum[root] += f.bitangent * w;
                s.w_sum[root] += w;
                s.group_t[g] += f.tangent * w;
                s.group_b[g] += f.bitangent * w;
                position_t += f.tangent * w;
                position_b += f.bitangent * w;
            } else if s.first_usable[g] == u32::MAX {
                let root = tp[a] as usize;
                s.t_sum[root] += f.tangent;
                s.b_sum[root] += f.bitangent;
            }
        }
        for a in 0..k {
            let g = np[a] as usize;
            if tp[a] as usize == a && !usable(a) && s.first_usable[g] != u32::MAX {
                s.t_sum[a] = s.group_t[g];
                s.b_sum[a] = s.group_b[g];
            }
        }
    }

    // One frame per tangent group, in order of first corner.
    s.frame_of_root.clear();
    s.frame_of_root.resize(k, u32::MAX);
    s.local_group.clear();
    let mut position_normal: Option<Vec3> = None;
    for a in 0..k {
        let root = s.tangent_parent[a] as usize;
        // A group whose tangents cancel (a fan around a pole, chained through neighbours each
        // within the tangent angle) has no meaningful average: each corner keeps its face's
        // tangent. The test depends on the group as a set, not on the order of its corners.
        let incoherent = rules.tangents
            && s.w_sum[root] > 0.0
            && rules.tangent_cos.is_some_and(|c| s.t_sum[root].length() < c * s.w_sum[root]);
        if incoherent {
            let c = corners[a] as usize;
            let f = &faces[c / 3];
            let g = s.normal_parent[a] as usize;
            let (normal, tangent) = finish(s.n_sum[g], s.fallback[g], f.tangent, f.bitangent);
            s.local_group.push(frames.len() as u32);
            frames.push(Frame { normal, tangent });
            continue;
        }
        if s.frame_of_root[root] == u32::MAX {
            let g = s.normal_parent[a] as usize;
            let mut n_sum = s.n_sum[g];
            let (mut t_sum, mut b_sum) = (s.t_sum[root], s.b_sum[root]);
            if n_sum == Vec3::ZERO && s.fallback[g] == Vec3::ZERO {
                // Only degenerate faces in this group: use the whole position's frame.
                n_sum = *position_normal.get_or_insert_with(|| s.n_sum.iter().sum());
                (t_sum, b_sum) = (position_t, position_b);
            }
            let (normal, tangent) = finish(n_sum, s.fallback[g], t_sum, b_sum);
            s.frame_of_root[root] = frames.len() as u32;
            frames.push(Frame { normal, tangent });
        }
        s.local_group.push(s.frame_of_root[root]);
    }
}

/// The fast path: if every corner's face is usable and within half the crease angle (and its
/// tangent within half the tangent angle, with the same handedness) of the first corner's,
/// all corners form one normal group and one tangent group. Pushes its frame and returns
/// `true`; returns `false`, having changed nothing, when the general path is needed.
fn single_group(
    corners: &[u32],
    faces: &[Face],
    rules: Rules,
    s: &mut Scratch,
    frames: &mut Vec<Frame>,
) -> bool {
    let Some(&c0) = corners.first() else {
        // A position no triangle uses: no groups (not the previous position's, left over).
        s.local_group.clear();
        return true;
    };
    let f0 = &faces[c0 as usize / 3];
    let unusable = DEGENERATE | if rules.tangents { DEGENERATE_UV } else { 0 };
    let (mut n_sum, mut t_sum, mut b_sum) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    for &c in corners {
        let c = c as usize;
        let f = &faces[c / 3];
        if f.is(unusable)
            || rules.crease_half_cos.is_some_and(|h| f.normal.dot(f0.normal) < h)
            || (rules.tangents
                && ((rules.split_mirrored && f.sign() != f0.sign())
                    || rules.tangent_half_cos.is_some_and(|h| f.tangent.dot(f0.tangent) < h)))
        {
            return false;
        }
        let w = weight(rules.weighting, f, c % 3);
        n_sum += f.normal * w;
        t_sum += f.tangent * w;
        b_sum += f.bitangent * w;
    }
    let (normal, tangent) = finish(n_sum, f0.normal, t_sum, b_sum);
    s.local_group.clear();
    s.local_group.resize(corners.len(), frames.len() as u32);
    frames.push(Frame { normal, tangent });
    true
}
