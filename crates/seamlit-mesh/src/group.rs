//! Grouping the corners around each welded position into smoothing groups, and averaging
//! their faces' normals and tangents (the paper's section 5.2, with a crease angle).
//!
//! The corners at one position are gathered from a compressed incidence list (counting sort of
//! corners by position id, so each list is in corner order and the sums do not depend on the
//! number of threads). Around a position, two faces join the same *normal group* when they are
//! edge-adjacent (they share a second welded position, in any object) and their normals are
//! within the crease angle; a crease angle of 180 degrees or more joins every face at the
//! position, as the paper does. Within a normal group, faces join the same *tangent group* when
//! they are edge-adjacent, have the same UV handedness (unless that split is off) and tangents
//! within the tangent angle. Faces whose UVs are degenerate take the tangent of the first
//! usable tangent group of their normal group and contribute nothing to it.

use std::ops::Range;

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use crate::face::{DEGENERATE, DEGENERATE_UV, Face};
use crate::frame::finish;
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
            tangent_cos: cos(options.tangent_angle_deg),
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

struct Scratch {
    normal_parent: Vec<u32>,
    tangent_parent: Vec<u32>,
    /// Per local corner: index into the chunk's frames.
    local_group: Vec<u32>,
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let g = parent[parent[x as usize] as usize];
        parent[x as usize] = g;
        x = g;
    }
    x
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent[hi as usize] = lo;
    }
}

/// Whether faces `fa` and `fb`, both touching position `p`, share an edge through it.
fn share_edge(face_positions: &[[u32; 3]], fa: usize, fb: usize, p: u32) -> bool {
    let a = face_positions[fa];
    let b = face_positions[fb];
    a.iter().any(|&q| q != p && b.contains(&q))
}

/// Groups the corners at every position and averages their frames.
///
/// `corner_positions[c]` is the position id of corner `c`; `face_positions[f]` the position ids
/// of face `f`'s corners.
pub(crate) fn group(
    corner_positions: &[u32],
    face_positions: &[[u32; 3]],
    position_count: usize,
    faces: &[Face],
    rules: Rules,
) -> Groups {
    let incidence = Incidence::new(corner_positions, position_count);
    let chunks: Vec<Range<usize>> =
        (0..position_count).step_by(CHUNK).map(|s| s..(s + CHUNK).min(position_count)).collect();
    let parts: Vec<(Vec<u32>, Vec<Frame>)> = chunks
        .into_par_iter()
        .map_init(
            || Scratch {
                normal_parent: Vec::new(),
                tangent_parent: Vec::new(),
                local_group: Vec::new(),
            },
            |scratch, positions| {
                let slots = incidence.range(positions.clone());
                let mut groups = Vec::with_capacity(slots.len());
                let mut frames = Vec::with_capacity(positions.len() + positions.len() / 8);
                for p in positions {
                    let corners = incidence.at(p);
                    group_position(
                        p as u32,
                        corners,
                        face_positions,
                        faces,
                        rules,
                        scratch,
                        &mut frames,
                    );
                    groups.extend_from_slice(&scratch.local_group);
                }
                (groups, frames)
            },
        )
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
fn group_position(
    p: u32,
    corners: &[u32],
    face_positions: &[[u32; 3]],
    faces: &[Face],
    rules: Rules,
    scratch: &mut Scratch,
    frames: &mut Vec<Frame>,
) {
    let k = corners.len();
    let face_of = |i: usize| corners[i] as usize / 3;
    let np = &mut scratch.normal_parent;
    np.clear();
    np.extend(0..k as u32);

    // Normal groups.
    match rules.crease_cos {
        None => np.iter_mut().for_each(|x| *x = 0),
        Some(cos) => {
            for a in 0..k {
                let fa = face_of(a);
                let na = &faces[fa];
                for b in a + 1..k {
                    let fb = face_of(b);
                    let nb = &faces[fb];
                    let join = fa == fb
                        || (!na.is(DEGENERATE)
                            && !nb.is(DEGENERATE)
                            && na.normal.dot(nb.normal) >= cos
                            && share_edge(face_positions, fa, fb, p));
                    if join {
                        union(np, a as u32, b as u32);
                    }
                }
            }
            for a in 0..k {
                np[a] = find(np, a as u32);
            }
        }
    }

    // Tangent groups, within normal groups.
    let tp = &mut scratch.tangent_parent;
    tp.clear();
    if !rules.tangents {
        tp.extend_from_slice(np);
    } else {
        tp.extend(0..k as u32);
        let unconditional = rules.tangents_unconditional() && rules.crease_cos.is_none();
        let usable = |i: usize| !faces[face_of(i)].is(DEGENERATE_UV | DEGENERATE);
        for a in 0..k {
            if !usable(a) {
                continue;
            }
            let fa = face_of(a);
            let ta = &faces[fa];
            for b in a + 1..k {
                if np[a] != np[b] || !usable(b) {
                    continue;
                }
                let fb = face_of(b);
                let tb = &faces[fb];
                let join = unconditional
                    || fa == fb
                    || ((!rules.split_mirrored || ta.sign() == tb.sign())
                        && rules.tangent_cos.is_none_or(|c| ta.tangent.dot(tb.tangent) >= c)
                        && (rules.tangents_unconditional()
                            || share_edge(face_positions, fa, fb, p)));
                if join {
                    union(tp, a as u32, b as u32);
                }
            }
        }
        // Unusable corners join the first usable tangent group of their normal group, or, if
        // there is none, the first unusable corner of it.
        for a in 0..k {
            if usable(a) {
                continue;
            }
            let target = (0..k)
                .find(|&b| np[b] == np[a] && usable(b))
                .or_else(|| (0..k).find(|&b| np[b] == np[a]))
                .unwrap_or(a);
            union(tp, a as u32, target as u32);
        }
        for a in 0..k {
            tp[a] = find(tp, a as u32);
        }
    }

    // One frame per tangent group.
    let lg = &mut scratch.local_group;
    lg.clear();
    lg.resize(k, u32::MAX);
    let mut position_normal: Option<Vec3> = None;
    for a in 0..k {
        let root = tp[a] as usize;
        if lg[root] != u32::MAX {
            lg[a] = lg[root];
            continue;
        }
        // A new tangent group rooted at `root` (== a, the smallest member).
        let ng = np[a];
        let mut n_sum = Vec3::ZERO;
        let (mut t_sum, mut b_sum) = (Vec3::ZERO, Vec3::ZERO);
        let (mut t_any, mut b_any) = (Vec3::ZERO, Vec3::ZERO);
        let mut fallback = Vec3::ZERO;
        for b in 0..k {
            if np[b] != ng {
                continue;
            }
            let c = corners[b] as usize;
            let f = &faces[c / 3];
            let w = weight(rules.weighting, f, c % 3);
            n_sum += f.normal * w;
            if fallback == Vec3::ZERO {
                fallback = f.normal;
            }
            if tp[b] as usize == root {
                if f.is(DEGENERATE) {
                    // No area: no say in the tangent either.
                } else if f.is(DEGENERATE_UV) {
                    t_any += f.tangent;
                    b_any += f.bitangent;
                } else {
                    t_sum += f.tangent * w;
                    b_sum += f.bitangent * w;
                }
            }
        }
        if n_sum == Vec3::ZERO && fallback == Vec3::ZERO {
            // Only degenerate faces in this group: use the whole position's normal.
            let pn = *position_normal.get_or_insert_with(|| {
                corners
                    .iter()
                    .map(|&c| {
                        let f = &faces[c as usize / 3];
                        f.normal * weight(rules.weighting, f, c as usize % 3)
                    })
                    .sum()
            });
            n_sum = pn;
        }
        if t_sum == Vec3::ZERO && b_sum == Vec3::ZERO {
            t_sum = t_any;
            b_sum = b_any;
        }
        let (normal, tangent) = finish(n_sum, fallback, t_sum, b_sum);
        lg[a] = frames.len() as u32;
        frames.push(Frame { normal, tangent });
    }
}
