//! Grouping the corners around each welded position into smoothing groups, and averaging
//! their faces' normals and tangents (the paper's section 5.2, with a crease angle).
//!
//! Around a position, faces whose normals are within the crease angle of each other join the
//! same *normal group* (connected components of that relation); a crease angle of 180 degrees
//! or more joins every face at the position, as the paper does. Where the model has smoothing
//! groups ([`crate::Object::smoothing_groups`]), only faces of the same nonzero group are
//! related: a face of group 0 is a normal group of its own (flat). Within a normal group, faces
//! join the same *tangent group* when their UV handedness agrees (unless that split is off)
//! and their tangents are within the tangent angle. Corners of faces whose UVs are degenerate
//! form one more tangent group per normal group, whose tangent is the average over all the
//! normal group's usable faces; they contribute nothing to the others. A tangent group whose
//! members cancel out (a fan around a pole) keeps per-face tangents.
//!
//! Only the positions that need it come here ([`crate::smooth`] settles the others in one
//! pass), with their corners in ascending order, so the sums do not depend on the number of
//! threads.

use glam::{Vec3, Vec4};

use crate::face::{DEGENERATE, DEGENERATE_UV, Face};
use crate::frame::finish;
use crate::index::index;
use crate::weld::union;
use crate::{FixOptions, Model, Object, Weighting};

/// The averaged frame of one group, in model space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Frame {
    pub normal: Vec3,
    pub tangent: Vec4,
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

/// Whether any object of `model` has smoothing groups.
pub(crate) fn has_smoothing_groups(model: &Model) -> bool {
    model.objects.iter().any(|o| o.smoothing_groups.is_some())
}

/// The smoothing group of triangle `t` of `object` as a key that faces must share to share a
/// normal: the group number, 0 for none (flat), and for an object without groups one key
/// beyond every number, shared by all such objects.
pub(crate) fn smoothing_key(object: &Object, t: usize) -> u64 {
    object.smoothing_groups.as_ref().map_or(1 << 32, |g| u64::from(g[t]))
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

/// A right-handed usable face (UV mapping not mirrored).
const RIGHT: u8 = 1;
/// A mirrored usable face.
const LEFT: u8 = 2;

/// `tangent` with the handedness of the faces it was summed from, where they agree (`hands`,
/// `RIGHT | LEFT`; they always do where mirrored faces are split off), else the sign of the
/// summed bitangent against the smoothed normal. Across a smoothed hard edge the summed
/// bitangent can point against every face's own. The paper's rules (mirrored faces joined)
/// keep the paper's sign.
fn handed(tangent: Vec4, hands: u8) -> Vec4 {
    match hands {
        RIGHT => tangent.truncate().extend(1.0),
        LEFT => tangent.truncate().extend(-1.0),
        _ => tangent,
    }
}

/// Scratch space of [`group_position`], reused from one position to the next.
#[derive(Default)]
pub(crate) struct Scratch {
    normal_parent: Vec<u32>,
    tangent_parent: Vec<u32>,
    /// Per local corner: its index into `frames` (the output of [`group_position`]).
    pub local_group: Vec<u32>,
    /// Per local corner (as a group root): sums and first usable members.
    n_sum: Vec<Vec3>,
    t_sum: Vec<Vec3>,
    b_sum: Vec<Vec3>,
    w_sum: Vec<f32>,
    /// Per tangent group root (and per normal group root, `group_hands`): the UV
    /// handednesses of its usable faces, `RIGHT | LEFT`.
    hands: Vec<u8>,
    group_hands: Vec<u8>,
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

/// Groups the corners at one position; pushes one frame per tangent group onto `frames` and
/// leaves in `scratch.local_group` each corner's index into `frames`.
///
/// `corners` are the position's corners (`triangle * 3 + k`), ascending; `faces[a]` is the
/// face of `corners[a]`; `groups[a]` its smoothing key ([`smoothing_key`]), or `groups` is
/// empty when the model has no smoothing groups (one group). Faces share a normal group only
/// where they share a nonzero key. Quadratic in the number of corners.
pub(crate) fn group_position(
    corners: &[u32],
    faces: &[Face],
    groups: &[u64],
    rules: Rules,
    s: &mut Scratch,
    frames: &mut Vec<Frame>,
) {
    let at = Position { corners, faces, groups, rules };
    // Faces within the crease angle (and of one smoothing group) form normal groups.
    at.normal_groups(&mut s.normal_parent);
    // Per normal group: the weighted normal sum, a fallback normal, the first usable corner.
    at.normal_sums(s);
    // Within each normal group, faces whose tangents agree form tangent groups.
    at.tangent_groups(s);
    // Per tangent group: the weighted tangent and bitangent sums.
    let position_tb = at.tangent_sums(s);
    // One frame per tangent group, in order of first corner.
    at.emit_frames(s, position_tb, frames);
}

/// The corners at one position and the rules that group them: the input of
/// [`group_position`]'s steps.
struct Position<'a> {
    corners: &'a [u32],
    faces: &'a [Face],
    groups: &'a [u64],
    rules: Rules,
}

impl Position<'_> {
    fn len(&self) -> usize {
        self.corners.len()
    }

    fn face_of(&self, a: usize) -> usize {
        self.corners[a] as usize / 3
    }

    /// Whether local corner `a`'s face has usable UVs (and is not degenerate).
    fn usable(&self, a: usize) -> bool {
        !self.faces[a].is(DEGENERATE_UV | DEGENERATE)
    }

    /// Weight of local corner `a` in its face.
    fn weight(&self, a: usize) -> f32 {
        weight(self.rules.weighting, &self.faces[a], self.corners[a] as usize % 3)
    }

    /// Normal groups into `np` (each corner's root): corners of one face, and faces within the
    /// crease angle that share a nonzero smoothing key.
    fn normal_groups(&self, np: &mut Vec<u32>) {
        let k = self.len();
        np.clear();
        let grouped = !self.groups.is_empty();
        let groups = self.groups;
        let same_group =
            |a: usize, b: usize| !grouped || (groups[a] == groups[b] && groups[a] != 0);
        match self.rules.crease_cos {
            None if !grouped => np.resize(k, 0),
            cos => {
                np.extend(0..index(k));
                for a in 1..k {
                    if self.face_of(a) == self.face_of(a - 1) {
                        union(np, index(a - 1), index(a));
                    }
                }
                for a in 0..k {
                    let fa = &self.faces[a];
                    if fa.is(DEGENERATE) {
                        continue;
                    }
                    for b in a + 1..k {
                        let fb = &self.faces[b];
                        let within = cos.is_none_or(|cos| fa.normal.dot(fb.normal) >= cos);
                        if !fb.is(DEGENERATE) && within && same_group(a, b) {
                            union(np, index(a), index(b));
                        }
                    }
                }
                flatten(np);
            }
        }
    }

    /// Per normal group root: `n_sum`, `fallback` (the first face's normal) and
    /// `first_usable`.
    fn normal_sums(&self, s: &mut Scratch) {
        let k = self.len();
        s.n_sum.clear();
        s.n_sum.resize(k, Vec3::ZERO);
        s.fallback.clear();
        s.fallback.resize(k, Vec3::ZERO);
        s.first_usable.clear();
        s.first_usable.resize(k, u32::MAX);
        for a in 0..k {
            let f = &self.faces[a];
            let g = s.normal_parent[a] as usize;
            s.n_sum[g] += f.normal * self.weight(a);
            if s.fallback[g] == Vec3::ZERO {
                s.fallback[g] = f.normal;
            }
            if s.first_usable[g] == u32::MAX && self.usable(a) {
                s.first_usable[g] = index(a);
            }
        }
    }

    /// Tangent groups into `s.tangent_parent`, within normal groups. Unusable corners
    /// (degenerate UVs) form one group per normal group, whose tangent is the sum over all the
    /// normal group's usable corners: a value that does not depend on the order of the corners
    /// (so not on how the model is cut into objects), and equal to the usable group's where
    /// there is only one.
    fn tangent_groups(&self, s: &mut Scratch) {
        let k = self.len();
        let tp = &mut s.tangent_parent;
        tp.clear();
        if !self.rules.tangents {
            tp.extend_from_slice(&s.normal_parent);
            return;
        }
        tp.extend(0..index(k));
        s.first_unusable.clear();
        s.first_unusable.resize(k, u32::MAX);
        for a in 0..k {
            let g = s.normal_parent[a] as usize;
            if self.usable(a) {
                if self.rules.tangents_unconditional() {
                    union(tp, index(a), s.first_usable[g]);
                }
            } else if s.first_unusable[g] == u32::MAX {
                s.first_unusable[g] = index(a);
            } else {
                union(tp, index(a), s.first_unusable[g]);
            }
        }
        if !self.rules.tangents_unconditional() {
            self.join_tangents(&s.normal_parent, tp);
        }
        flatten(tp);
    }

    /// Joins the usable corners of one face, and usable faces of one normal group whose UV
    /// handedness agrees (where that split is on) and whose tangents are within the angle.
    fn join_tangents(&self, np: &[u32], tp: &mut [u32]) {
        let k = self.len();
        for a in 1..k {
            if self.face_of(a) == self.face_of(a - 1) && self.usable(a) {
                union(tp, index(a - 1), index(a));
            }
        }
        for a in 0..k {
            if !self.usable(a) {
                continue;
            }
            let ta = &self.faces[a];
            for b in a + 1..k {
                if np[a] != np[b] || !self.usable(b) {
                    continue;
                }
                let tb = &self.faces[b];
                let join = (!self.rules.split_mirrored || ta.sign() == tb.sign())
                    && self.rules.tangent_cos.is_none_or(|c| ta.tangent.dot(tb.tangent) >= c);
                if join {
                    union(tp, index(a), index(b));
                }
            }
        }
    }

    /// Sums: per tangent group over its usable corners; per normal group over all its usable
    /// corners (for the unusable group), or over its unusable ones where none is usable.
    /// Degenerate faces never count. Returns the whole position's tangent and bitangent sums.
    fn tangent_sums(&self, s: &mut Scratch) -> (Vec3, Vec3) {
        let k = self.len();
        for v in [&mut s.t_sum, &mut s.b_sum, &mut s.group_t, &mut s.group_b] {
            v.clear();
            v.resize(k, Vec3::ZERO);
        }
        s.w_sum.clear();
        s.w_sum.resize(k, 0.0);
        for v in [&mut s.hands, &mut s.group_hands] {
            v.clear();
            v.resize(k, 0);
        }
        let (mut position_t, mut position_b) = (Vec3::ZERO, Vec3::ZERO);
        if !self.rules.tangents {
            return (position_t, position_b);
        }
        for a in 0..k {
            let f = &self.faces[a];
            if f.is(DEGENERATE) {
                continue;
            }
            let g = s.normal_parent[a] as usize;
            let root = s.tangent_parent[a] as usize;
            if self.usable(a) {
                let w = self.weight(a);
                s.t_sum[root] += f.tangent * w;
                s.b_sum[root] += f.bitangent * w;
                s.w_sum[root] += w;
                let hand = if f.sign() < 0.0 { LEFT } else { RIGHT };
                s.hands[root] |= hand;
                s.group_hands[g] |= hand;
                s.group_t[g] += f.tangent * w;
                s.group_b[g] += f.bitangent * w;
                position_t += f.tangent * w;
                position_b += f.bitangent * w;
            } else if s.first_usable[g] == u32::MAX {
                s.t_sum[root] += f.tangent;
                s.b_sum[root] += f.bitangent;
            }
        }
        for a in 0..k {
            let g = s.normal_parent[a] as usize;
            if s.tangent_parent[a] as usize == a && !self.usable(a) && s.first_usable[g] != u32::MAX
            {
                s.t_sum[a] = s.group_t[g];
                s.b_sum[a] = s.group_b[g];
                s.hands[a] = s.group_hands[g];
            }
        }
        (position_t, position_b)
    }

    /// Pushes one frame per tangent group onto `frames`, in order of first corner, and each
    /// corner's index into `frames` onto `s.local_group`. `position_tb` is the whole position's
    /// tangent and bitangent sums, for groups of degenerate faces only.
    fn emit_frames(&self, s: &mut Scratch, position_tb: (Vec3, Vec3), frames: &mut Vec<Frame>) {
        let k = self.len();
        // Groups whose frames are equal bit for bit share one (a degenerate triangle's group
        // takes the whole position's frame, often another group's): a position's frame
        // indices then name its distinct frames, which MikkTSpace's vertices compare.
        let start = frames.len();
        let mut push = |frame: Frame| {
            let bits = |f: &Frame| {
                (f.normal.to_array().map(f32::to_bits), f.tangent.to_array().map(f32::to_bits))
            };
            let at = frames[start..].iter().position(|f| bits(f) == bits(&frame));
            index(at.map_or_else(
                || {
                    frames.push(frame);
                    frames.len() - 1
                },
                |i| start + i,
            ))
        };
        s.frame_of_root.clear();
        s.frame_of_root.resize(k, u32::MAX);
        s.local_group.clear();
        let mut position_normal: Option<Vec3> = None;
        for a in 0..k {
            let root = s.tangent_parent[a] as usize;
            let g = s.normal_parent[a] as usize;
            // A group whose tangents cancel (a fan around a pole, chained through neighbours
            // each within the tangent angle) has no meaningful average: each corner keeps its
            // face's tangent. The test depends on the group as a set, not on the order of its
            // corners.
            if self.incoherent(s, root) {
                let f = &self.faces[a];
                let (normal, tangent) = finish(s.n_sum[g], s.fallback[g], f.tangent, f.bitangent);
                let tangent = if self.rules.split_mirrored && self.usable(a) {
                    tangent.truncate().extend(f.sign())
                } else {
                    tangent
                };
                s.local_group.push(push(Frame { normal, tangent }));
                continue;
            }
            if s.frame_of_root[root] == u32::MAX {
                let mut n_sum = s.n_sum[g];
                let (mut t_sum, mut b_sum) = (s.t_sum[root], s.b_sum[root]);
                if n_sum == Vec3::ZERO && s.fallback[g] == Vec3::ZERO {
                    // Only degenerate faces in this group: use the whole position's frame.
                    n_sum = *position_normal.get_or_insert_with(|| s.n_sum.iter().sum());
                    (t_sum, b_sum) = position_tb;
                }
                let (normal, tangent) = finish(n_sum, s.fallback[g], t_sum, b_sum);
                let tangent = if self.rules.split_mirrored {
                    handed(tangent, s.hands[root])
                } else {
                    tangent
                };
                s.frame_of_root[root] = push(Frame { normal, tangent });
            }
            s.local_group.push(s.frame_of_root[root]);
        }
    }

    /// Whether the tangent group rooted at `root` cancels out: its summed tangent is shorter
    /// than the tangent angle's cosine times its weight.
    fn incoherent(&self, s: &Scratch, root: usize) -> bool {
        self.rules.tangents
            && s.w_sum[root] > 0.0
            && self.rules.tangent_cos.is_some_and(|c| s.t_sum[root].length() < c * s.w_sum[root])
    }
}
