//! Smoothing across welded positions: one pass over the triangles that settles nearly every
//! position, and the hand-over of the rest to the grouping of [`crate::group`].
//!
//! Inside a smooth, consistently mapped surface, every face around a position belongs to one
//! smoothing group, and the position's frame is the weighted sum of its faces' frames. That
//! sum is built the way fast normal generators build it: each triangle adds its weighted
//! normal, tangent and bitangent to its three vertices (in triangle order, one object per
//! task, so no two tasks touch one vertex); then the sums of the vertices welded into one
//! position are added into the position's *root* (its smallest vertex index) in vertex order.
//! No per-face record and no corner list is kept: memory per vertex is a 12-byte normal sum,
//! a 16-byte normal cone (freed once the positions are settled) and a flag byte, and where the
//! faces' UV frames are used (`--tangents seamlit`) a 24-byte tangent and bitangent sum and a
//! 16-byte tangent cone: the default path (MikkTSpace) does not carry the 40 bytes it never
//! reads.
//!
//! A position takes this shortcut only when the grouping would make one group of it anyway:
//! - where the model has smoothing groups, all its faces are in one nonzero group;
//! - no degenerate triangle touches it, the normal sum does not vanish;
//! - with tangents: some face with usable UVs touches it, and (when mirrored UVs are split)
//!   not faces of both handednesses;
//! - all its faces' normals lie in a cone of half the crease angle, and all its usable faces'
//!   tangents in a cone of half the tangent angle. Two faces in one such cone are within the
//!   angle of each other, so the crease and tangent-angle relations join them all.
//!
//! The cones are found in the same pass: each vertex's cone is centred on its first face's
//! normal (tangent) and widened to take in every later face; where several vertices are welded
//! into one position, the root's cone is widened to take in theirs (the angle between the axes
//! plus the other cone's half-angle). A cone centred on the first face can be up to twice as
//! wide as needed; a position that misses for that reason only takes the slower path.
//!
//! Faces without usable UVs (degenerate UVs, or an object without UVs) add their normal but no
//! tangent: in the grouping they form a tangent group whose tangent is the sum over the usable
//! faces, the same frame. Every other position (a crease, a mirror line, a pole, a degenerate
//! triangle) is *complex*: its corners are gathered, sorted by position, and grouped as in
//! [`crate::group::group_position`], with the faces computed again for just those corners.
//!
//! Without tangents (MikkTSpace makes them, or none are wanted), the faces' UVs are not read:
//! every face counts as one without usable UVs, and the frames' tangents are only a direction
//! across the normal, which nobody reads.
//!
//! Everything is deterministic: sums run in triangle order within an object and in vertex
//! order across a position; each position is settled by one task.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use crate::Model;
use crate::face::{DEGENERATE, DEGENERATE_UV, Face, MIRRORED, NO_UV, add_counts, face, uv_flags};
use crate::frame::{finish, finish_normal};
use crate::group::{self, Frame, Rules, Scratch, weight};
use crate::index::low_half;
use crate::validate::{Flat, split_at_starts};

/// A triangle uses this vertex (per vertex, not merged into the root).
const USED: u8 = 1;
/// A triangle touches the position.
const HAS_FACE: u8 = 2;
/// A degenerate triangle touches the position.
const HAS_DEGENERATE: u8 = 4;
/// A right-handed face with usable UVs touches the position.
const HAS_RIGHT: u8 = 8;
/// A mirrored face with usable UVs touches the position.
const HAS_MIRRORED: u8 = 16;
/// A face of an object with UVs, whose UVs are degenerate, touches the position.
const HAS_BAD_UV: u8 = 32;
/// The position needs the grouping.
const COMPLEX: u8 = 64;
/// The vertex's cone has a tangent axis (per vertex; merged as described in [`merge`]).
const TANGENT_AXIS: u8 = 128;

/// Per vertex where the faces' UV frames are used: the sums of its corners' weighted face
/// tangents and bitangents. At the root of a position that is not complex, after
/// [`finish_positions`], the position's tangent instead, its handedness in `b.x`. (The normal
/// sums are kept apart, in [`Sums::normals`]: without tangents they are all there is.)
#[derive(Clone, Copy, Default)]
struct TangentSlot {
    t: Vec3,
    b: Vec3,
}

/// Per vertex: a cone that holds its faces' normals (or usable tangents). The axis is a unit
/// vector (the first face's); `cos` is the cosine of the cone's half-angle.
#[derive(Clone, Copy)]
struct Cone {
    axis: Vec3,
    cos: f32,
}

impl Default for Cone {
    fn default() -> Self {
        Self { axis: Vec3::ZERO, cos: 1.0 }
    }
}

/// The per-vertex sums and cones of [`accumulate`], [`merge`] and [`finish_positions`]. The
/// tangent arrays are empty where the faces' UV frames are not used ([`Rules::tangents`]).
struct Sums {
    normals: Vec<Vec3>,
    tangents: Vec<TangentSlot>,
    normal_cones: Vec<Cone>,
    tangent_cones: Vec<Cone>,
    flags: Vec<u8>,
}

impl Sums {
    /// Zeroed sums for `n` vertices, filled in parallel: the first touch of fresh memory (a
    /// page fault per 4 KiB) is a good part of the cost at this size.
    fn new(n: usize, tangents: bool) -> Self {
        let t = if tangents { n } else { 0 };
        Self {
            normals: filled(n),
            tangents: filled(t),
            normal_cones: filled(n),
            tangent_cones: filled(t),
            flags: vec![0; n],
        }
    }
}

/// `len` default values, written in parallel.
fn filled<T: Default + Send>(len: usize) -> Vec<T> {
    (0..len).into_par_iter().map(|_| T::default()).collect()
}

/// Widens a cone `(axis, cos)` to take in the cone `(other, other_cos)`: the new half-angle is
/// the larger of the old and the angle between the axes plus the other's half-angle.
fn widen(axis: Vec3, cos: f32, other: Vec3, other_cos: f32) -> f32 {
    let angle = |c: f32| c.clamp(-1.0, 1.0).acos();
    let reach = angle(axis.dot(other)) + angle(other_cos);
    cos.min(reach.min(std::f32::consts::PI).cos())
}

/// The smoothed frames of a model, in model space.
pub(crate) struct Smooth {
    /// Per vertex: its position's root.
    roots: Vec<u32>,
    /// Per vertex; at a root that is not complex, the position's normal.
    normals: Vec<Vec3>,
    /// Per vertex where the faces' UV frames are used (else empty); at a root that is not
    /// complex, the position's tangent and handedness.
    tangents: Vec<TangentSlot>,
    flags: Vec<u8>,
    /// The corners of complex positions, ascending: `corner << 32 | group`.
    pub complex: Vec<u64>,
    /// Per group of a complex position, its frame.
    pub frames: Vec<Frame>,
    /// Where [`smooth`] was asked to count them, the report's triangle counts (degenerate,
    /// degenerate-UV, mirrored; see [`crate::face::count`]) over the snapped positions.
    pub counts: Option<[usize; 3]>,
}

impl Smooth {
    /// Whether a triangle uses vertex `v`.
    pub fn is_used(&self, v: usize) -> bool {
        self.flags[v] & USED != 0
    }

    /// The frame of every corner at vertex `v`, unless `v`'s position is complex.
    pub fn simple_frame(&self, v: usize) -> Option<Frame> {
        let r = self.roots[v] as usize;
        if self.flags[r] & COMPLEX != 0 {
            return None;
        }
        // Without the faces' UV frames, the tangent is nobody's to read (see the module's text).
        let tangent = self.tangents.get(r).map_or(Vec4::ZERO, |s| s.t.extend(s.b.x));
        Some(Frame { normal: self.normals[r], tangent })
    }

    /// The frame of corner `c` (`triangle * 3 + k`, at vertex `v`).
    pub fn corner_frame(&self, c: u32, v: usize) -> Frame {
        self.simple_frame(v).unwrap_or_else(|| {
            let i = self.complex.partition_point(|&e| (e >> 32) < u64::from(c));
            self.frames[low_half(self.complex[i]) as usize]
        })
    }

    /// The normal of corner `c` (at vertex `v`) and a key that tells normals at one position
    /// apart: 0 at a simple position (one normal), else one more than the corner's frame.
    #[inline]
    pub fn corner_normal(&self, c: u32, v: usize) -> (Vec3, u32) {
        let r = self.roots[v] as usize;
        if self.flags[r] & COMPLEX == 0 {
            return (self.normals[r], 0);
        }
        self.complex_corner_normal(c)
    }

    /// [`Self::corner_normal`] at a complex position: the corner's group's frame.
    #[cold]
    fn complex_corner_normal(&self, c: u32) -> (Vec3, u32) {
        let i = self.complex.partition_point(|&e| (e >> 32) < u64::from(c));
        let frame = low_half(self.complex[i]);
        (self.frames[frame as usize].normal, frame + 1)
    }

    /// Each vertex's root: the weld the frames were smoothed over.
    pub fn roots(&self) -> &[u32] {
        &self.roots
    }

    /// [`Self::roots`], taken.
    pub fn into_roots(self) -> Vec<u32> {
        self.roots
    }

    /// The range of [`Self::complex`] holding the corners of triangles `triangles`.
    pub fn complex_range(&self, triangles: std::ops::Range<u32>) -> std::ops::Range<usize> {
        let at = |t: u32| self.complex.partition_point(|&e| (e >> 32) < u64::from(t) * 3);
        at(triangles.start)..at(triangles.end)
    }
}

/// Smooths the model. `roots` gives each vertex's position (see [`crate::weld`]); the
/// positions in `flat` must be snapped onto their roots. With `count`, the pass over the
/// triangles also counts them as the report does ([`Smooth::counts`]), reading the UVs for it
/// where the frames do not.
pub(crate) fn smooth(
    model: &Model,
    flat: &Flat,
    roots: Vec<u32>,
    rules: Rules,
    count: bool,
) -> Smooth {
    smooth_with(model, flat, roots, rules, count, false)
}

/// [`smooth`], optionally sending every position through the grouping (for tests: both
/// paths must agree).
fn smooth_with(
    model: &Model,
    flat: &Flat,
    roots: Vec<u32>,
    rules: Rules,
    count: bool,
    all_complex: bool,
) -> Smooth {
    let mut sums = Sums::new(flat.positions.len(), rules.tangents);
    let counts = accumulate(model, flat, rules, count, &mut sums);
    merge(&roots, &mut sums);
    let grouped = group::has_smoothing_groups(model);
    if grouped {
        mark_group_boundaries(model, flat, &roots, &mut sums.flags);
    }
    finish_positions(&roots, &mut sums, rules, all_complex);
    // The cones are done with.
    let Sums { normals, tangents, flags, .. } = sums;
    let (complex, frames) = group_complex(model, flat, &roots, &flags, rules, grouped);
    Smooth { roots, normals, tangents, flags, complex, frames, counts: count.then_some(counts) }
}

/// What a face tells its vertices.
fn face_flags(f: &Face) -> u8 {
    USED | HAS_FACE
        | if f.is(DEGENERATE) {
            HAS_DEGENERATE
        } else if f.is(NO_UV) {
            0
        } else if f.is(DEGENERATE_UV) {
            HAS_BAD_UV
        } else if f.is(MIRRORED) {
            HAS_MIRRORED
        } else {
            HAS_RIGHT
        }
}

/// One object's share of the [`Sums`] (its vertices'), for one task of [`accumulate`].
struct Part<'a> {
    normals: &'a mut [Vec3],
    tangents: &'a mut [TangentSlot],
    normal_cones: &'a mut [Cone],
    tangent_cones: &'a mut [Cone],
    flags: &'a mut [u8],
}

/// `items` cut into each object's part ([`split_at_starts`] at `starts`), or, where `items` is
/// empty (the tangent arrays without tangents), an empty part per object.
fn per_object<'a, T>(items: &'a mut [T], starts: &[u32]) -> std::vec::IntoIter<&'a mut [T]> {
    if items.is_empty() {
        let empty: Vec<&'a mut [T]> = starts.windows(2).map(|_| Default::default()).collect();
        return empty.into_iter();
    }
    split_at_starts(items, starts).into_iter()
}

/// Adds every face's weighted frame to its three vertices, and widens their cones to take in
/// the face; one object per task. With `count`, returns the report's triangle counts (else
/// zeros): the faces are at hand here, a separate pass would gather every triangle again.
fn accumulate(
    model: &Model,
    flat: &Flat,
    rules: Rules,
    count: bool,
    sums: &mut Sums,
) -> [usize; 3] {
    let mut tangents = per_object(&mut sums.tangents, &flat.vertex_start);
    let mut normal_cones = per_object(&mut sums.normal_cones, &flat.vertex_start);
    let mut tangent_cones = per_object(&mut sums.tangent_cones, &flat.vertex_start);
    let mut flags = per_object(&mut sums.flags, &flat.vertex_start);
    let parts: Vec<Part<'_>> = per_object(&mut sums.normals, &flat.vertex_start)
        .map(|normals| Part {
            normals,
            tangents: tangents.next().unwrap_or_default(),
            normal_cones: normal_cones.next().unwrap_or_default(),
            tangent_cones: tangent_cones.next().unwrap_or_default(),
            flags: flags.next().unwrap_or_default(),
        })
        .collect();
    let counted = parts.into_par_iter().enumerate().map(|(o, part)| {
        let positions = &flat.positions[flat.vertex_start[o] as usize..][..part.normals.len()];
        accumulate_object(model, o, positions, part, rules, count)
    });
    counted.reduce(|| [0; 3], add_counts)
}

/// Faces [`accumulate_object`] works out before it adds them to their vertices: the work of
/// one face does not wait on the sums the previous one added to, so the processor overlaps
/// several (as in MikkTSpace's pass over the triangles, `mikk/plain.rs`). One face at a
/// time, the smoothing's pass over the 1M teapot took 30 ms on two threads; 25 so.
const BLOCK: usize = 32;

/// [`accumulate`] of object `o` (whose model-space `positions` are given) into its `part`.
fn accumulate_object(
    model: &Model,
    o: usize,
    positions: &[Vec3],
    mut part: Part<'_>,
    rules: Rules,
    count: bool,
) -> [usize; 3] {
    let object = &model.objects[o];
    // Without tangents the faces' UV frames are never read: not computed.
    let uvs = object.uvs.as_deref().filter(|_| rules.tangents);
    let mut counts = [0; 3];
    let mut faces = [Face::default(); BLOCK];
    for tris in object.triangles.chunks(BLOCK) {
        for (slot, tri) in faces.iter_mut().zip(tris) {
            let p = tri.map(|i| positions[i as usize]);
            let uv = uvs.map(|uvs| tri.map(|i| uvs[i as usize]));
            let face = face(p, uv, model.v_axis);
            if count {
                // `face`'s flags are `face_flags`' where it had the UVs; otherwise only their
                // UV tests are left to make (a degenerate face has none).
                let flags = if face.is(DEGENERATE) || uvs.is_some() || object.uvs.is_none() {
                    face.flags
                } else {
                    let uv = object.uvs.as_deref().map(|uvs| tri.map(|i| uvs[i as usize]));
                    uv_flags(p, face.normal, uv, model.v_axis)
                };
                crate::face::count(&mut counts, flags);
            }
            *slot = face;
        }
        for (face, tri) in faces.iter().zip(tris) {
            add_face(&mut part, face, tri, rules);
        }
    }
    counts
}

/// Adds `face`'s weighted frame to the vertices `tri` of `part`, and widens their cones to
/// take it in.
#[inline(always)]
fn add_face(part: &mut Part<'_>, face: &Face, tri: &[u32; 3], rules: Rules) {
    let bits = face_flags(face);
    let degenerate = face.is(DEGENERATE);
    // Without UVs read, every face is one without usable UVs: no tangent arrays.
    let tangent = rules.tangents && !face.is(DEGENERATE | DEGENERATE_UV);
    for (k, &i) in tri.iter().enumerate() {
        let i = i as usize;
        let w = weight(rules.weighting, face, k);
        part.normals[i] += face.normal * w;
        let flag = &mut part.flags[i];
        if !degenerate {
            let cone = &mut part.normal_cones[i];
            if *flag & HAS_FACE == 0 || cone.axis == Vec3::ZERO {
                cone.axis = face.normal;
            } else {
                cone.cos = cone.cos.min(face.normal.dot(cone.axis));
            }
        }
        if tangent {
            let s = &mut part.tangents[i];
            s.t += face.tangent * w;
            s.b += face.bitangent * w;
            let cone = &mut part.tangent_cones[i];
            if *flag & TANGENT_AXIS == 0 {
                cone.axis = face.tangent;
                *flag |= TANGENT_AXIS;
            } else {
                cone.cos = cone.cos.min(face.tangent.dot(cone.axis));
            }
        }
        *flag |= bits;
    }
}

/// Adds the sums of every vertex into its root, in vertex order, and widens the root's cones
/// to take in the vertex's.
fn merge(roots: &[u32], sums: &mut Sums) {
    let with_tangents = !sums.tangents.is_empty();
    for (v, &r) in roots.iter().enumerate() {
        let r = r as usize;
        if r == v {
            continue;
        }
        let n = sums.normals[v];
        sums.normals[r] += n;
        let (bits, root_bits) = (sums.flags[v], sums.flags[r]);
        let c = sums.normal_cones[v];
        let rc = &mut sums.normal_cones[r];
        if c.axis != Vec3::ZERO {
            if rc.axis == Vec3::ZERO {
                *rc = c;
            } else {
                rc.cos = widen(rc.axis, rc.cos, c.axis, c.cos);
            }
        }
        if with_tangents {
            let s = sums.tangents[v];
            let root = &mut sums.tangents[r];
            root.t += s.t;
            root.b += s.b;
            if bits & TANGENT_AXIS != 0 {
                let c = sums.tangent_cones[v];
                let rc = &mut sums.tangent_cones[r];
                if root_bits & TANGENT_AXIS == 0 {
                    *rc = c;
                } else {
                    rc.cos = widen(rc.axis, rc.cos, c.axis, c.cos);
                }
            }
        }
        sums.flags[r] |= bits & !USED;
    }
}

/// Per vertex in [`mark_group_boundaries`]: no face seen yet.
const NO_GROUP_YET: u64 = u64::MAX;
/// Per vertex in [`mark_group_boundaries`]: faces of more than one group, or of group 0.
const MIXED_GROUPS: u64 = u64::MAX - 1;

/// What a vertex's faces so far (`seen`) and one more face or vertex (`next`) say together.
fn join_groups(seen: u64, next: u64) -> u64 {
    match (seen, next) {
        (NO_GROUP_YET, g) | (g, NO_GROUP_YET) => g,
        (a, b) if a == b => a,
        _ => MIXED_GROUPS,
    }
}

/// Flags complex every position whose faces are not all in one nonzero smoothing group (see
/// [`crate::Object::smoothing_groups`]): only the grouping keeps such faces apart. Runs only
/// for models with smoothing groups; a vertex's group is found per object (one task each),
/// then merged into its root in vertex order.
fn mark_group_boundaries(model: &Model, flat: &Flat, roots: &[u32], flags: &mut [u8]) {
    let parts: Vec<Vec<u64>> = model
        .objects
        .par_iter()
        .map(|object| {
            let mut seen = vec![NO_GROUP_YET; object.positions.len()];
            for (t, tri) in object.triangles.iter().enumerate() {
                let g = match group::smoothing_key(object, t) {
                    0 => MIXED_GROUPS,
                    g => g,
                };
                for &i in tri {
                    seen[i as usize] = join_groups(seen[i as usize], g);
                }
            }
            seen
        })
        .collect();
    let mut seen = parts.concat();
    debug_assert_eq!(seen.len(), flat.positions.len());
    for v in 0..roots.len() {
        let r = roots[v] as usize;
        if r != v {
            seen[r] = join_groups(seen[r], seen[v]);
        }
    }
    flags.par_iter_mut().zip(&seen).for_each(|(f, &g)| {
        if g == MIXED_GROUPS {
            *f |= COMPLEX;
        }
    });
}

/// Turns the sums at every root into the position's frame, or flags the position complex.
fn finish_positions(roots: &[u32], sums: &mut Sums, rules: Rules, all_complex: bool) {
    let Sums { normals, tangents, normal_cones, tangent_cones, flags } = sums;
    let usable = HAS_RIGHT | HAS_MIRRORED;
    let crease = rules.crease_half_cos.unwrap_or(-1.0);
    let tangent_cone = rules.tangent_half_cos.filter(|_| rules.tangents).unwrap_or(-1.0);
    let settle = |v: usize, n: &mut Vec3, t: Option<&mut TangentSlot>, f: &mut u8| {
        // Already complex: faces of several smoothing groups (see `mark_group_boundaries`).
        if roots[v] as usize != v || *f & (HAS_FACE | COMPLEX) != HAS_FACE {
            return;
        }
        let uv_faces = *f & (usable | HAS_BAD_UV) != 0;
        let complex = all_complex
            || *f & HAS_DEGENERATE != 0
            || *n == Vec3::ZERO
            || normal_cones[v].cos < crease
            || (rules.tangents
                && uv_faces
                && (*f & usable == 0
                    || (rules.split_mirrored && *f & usable == usable)
                    || tangent_cones[v].cos < tangent_cone));
        if complex {
            *f |= COMPLEX;
            return;
        }
        let Some(t) = t else {
            // Nobody reads the tangent (see the module's text): only the normal.
            *n = finish_normal(*n, Vec3::ZERO);
            return;
        };
        let (normal, tangent) = finish(*n, Vec3::ZERO, t.t, t.b);
        // Where mirrored faces are split off, the handedness is the faces' own, not the sign
        // of the summed bitangent against the smoothed normal: across a smoothed hard edge
        // those can disagree. The paper's rules (no split) keep the paper's sign.
        let w = match *f & usable {
            HAS_RIGHT if rules.split_mirrored => 1.0,
            HAS_MIRRORED if rules.split_mirrored => -1.0,
            _ => tangent.w,
        };
        *n = normal;
        *t = TangentSlot { t: tangent.truncate(), b: Vec3::new(w, 0.0, 0.0) };
    };
    if tangents.is_empty() {
        let each = normals.par_iter_mut().zip(flags.par_iter_mut()).enumerate();
        each.for_each(|(v, (n, f))| settle(v, n, None, f));
    } else {
        let each = normals.par_iter_mut().zip(tangents.par_iter_mut()).zip(flags.par_iter_mut());
        each.enumerate().for_each(|(v, ((n, t), f))| settle(v, n, Some(t), f));
    }
}

/// Corners of complex positions handled per parallel task (about).
const BATCH: usize = 4096;

/// Groups the corners of every complex position. Returns them ascending, each with its group
/// (`corner << 32 | group`), and the groups' frames.
fn group_complex(
    model: &Model,
    flat: &Flat,
    roots: &[u32],
    flags: &[u8],
    rules: Rules,
    grouped: bool,
) -> (Vec<u64>, Vec<Frame>) {
    let mut entries = flat.corners_at(model, roots, |r| flags[r as usize] & COMPLEX != 0);
    if entries.is_empty() {
        return (entries, Vec::new());
    }

    // Batches of whole positions.
    let mut batches = Vec::new();
    let mut start = 0;
    while start < entries.len() {
        let mut end = (start + BATCH).min(entries.len());
        while end < entries.len() && entries[end] >> 32 == entries[end - 1] >> 32 {
            end += 1;
        }
        batches.push(start..end);
        start = end;
    }
    let parts: Vec<(Vec<u32>, Vec<Frame>)> = batches
        .into_par_iter()
        .map_init(
            || (Scratch::default(), Vec::new(), Vec::new(), Vec::new()),
            |(scratch, corners, faces, keys), range| {
                let mut groups = Vec::with_capacity(range.len());
                let mut frames = Vec::new();
                for run in entries[range].chunk_by(|a, b| a >> 32 == b >> 32) {
                    corners.clear();
                    corners.extend(run.iter().map(|&e| low_half(e)));
                    faces.clear();
                    keys.clear();
                    for &c in corners.iter() {
                        let t = c as usize / 3;
                        let o = flat.object_of_triangle(t);
                        let local = t - flat.triangle_start[o] as usize;
                        let c = flat.corners(model, o, local);
                        let uvs = c.uvs.filter(|_| rules.tangents);
                        faces.push(face(c.positions, uvs, model.v_axis));
                        if grouped {
                            keys.push(group::smoothing_key(&model.objects[o], local));
                        }
                    }
                    group::group_position(corners, faces, keys, rules, scratch, &mut frames);
                    groups.extend_from_slice(&scratch.local_group);
                }
                (groups, frames)
            },
        )
        .collect();

    let mut frames = Vec::new();
    let mut i = 0;
    for (groups, part_frames) in parts {
        let base = frames.len() as u64;
        for g in groups {
            let corner = entries[i] & 0xFFFF_FFFF;
            entries[i] = (corner << 32) | (base + u64::from(g));
            i += 1;
        }
        frames.extend(part_frames);
    }
    entries.par_sort_unstable();
    (entries, frames)
}

/// The frame of a face on its own (flat shading).
pub(crate) fn face_frame(f: &Face) -> Frame {
    let (normal, tangent) = finish(f.normal, f.normal, f.tangent, f.bitangent);
    Frame { normal, tangent }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;
    use crate::{FixOptions, Object, validate, weld};

    /// A wavy sheet with a sharp fold (a crease), mirrored UVs on its last quarter, and a
    /// degenerate-UV strip, cut into two objects along a row (duplicated vertices).
    fn sheet() -> Model {
        let (nx, ny) = (24u32, 12u32);
        let vertex = |i: u32, j: u32| {
            let x = i as f32 * 0.25;
            let fold = (x - 3.0).abs() * 1.6;
            let p = Vec3::new(x, j as f32 * 0.25, 0.3 * (x * 1.3 + j as f32 * 0.4).sin() + fold);
            let u = if i <= 18 { x } else { 9.0 - x };
            let v = if j == 3 { 0.75 } else { j as f32 * 0.25 };
            (p, Vec2::new(u, v))
        };
        let part = |rows: std::ops::Range<u32>| {
            let (mut positions, mut uvs, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
            let h = rows.end - rows.start;
            for j in rows.clone() {
                for i in 0..=nx {
                    let (p, uv) = vertex(i, j);
                    positions.push(p);
                    uvs.push(uv);
                }
            }
            for j in 0..h - 1 {
                for i in 0..nx {
                    let a = j * (nx + 1) + i;
                    let (b, c, d) = (a + 1, a + nx + 1, a + nx + 2);
                    triangles.push([a, b, d]);
                    triangles.push([a, d, c]);
                }
            }
            Object::new(format!("rows {rows:?}"), positions, triangles).with_uvs(uvs)
        };
        Model::new(vec![part(0..7), part(6..ny)])
    }

    /// [`sheet`] with smoothing groups in bands of columns (1, 2, then 0 = off), numbered
    /// alike in both objects.
    fn grouped_sheet() -> Model {
        let mut model = sheet();
        for object in &mut model.objects {
            // Two triangles per grid cell, 24 cells per row.
            let groups = (0..object.triangles.len())
                .map(|t| match (t / 2) % 24 {
                    0..10 => 1,
                    10..20 => 2,
                    _ => 0,
                })
                .collect();
            object.smoothing_groups = Some(groups);
        }
        model
    }

    #[test]
    fn the_shortcut_and_the_grouping_agree() {
        for model in [sheet(), grouped_sheet()] {
            shortcut_and_grouping_agree_on(&model);
        }
    }

    fn shortcut_and_grouping_agree_on(model: &Model) {
        let model = model.clone();
        // Without tangents, only the normal cones decide; with them, the tangent cones too.
        for (options, tangents) in
            [(FixOptions::DEFAULT, true), (FixOptions::DEFAULT, false), (FixOptions::PAPER, true)]
        {
            let mut flat = validate::flatten(&model).expect("valid");
            let tolerance = options.weld_tolerance.absolute(weld::diagonal(&flat));
            let roots = weld::roots(&flat.positions, tolerance);
            weld::snap_to_roots(&mut flat.positions, &roots);
            let rules = Rules::new(&options, tangents);
            let fast = smooth_with(&model, &flat, roots.clone(), rules, false, false);
            let slow = smooth_with(&model, &flat, roots, rules, false, true);
            // The sheet has both kinds of positions, so both paths run.
            let corners = model.triangle_count() * 3;
            assert!(!fast.complex.is_empty() && fast.complex.len() < corners / 2);
            assert_eq!(slow.complex.len(), corners);
            let mut c = 0;
            for (o, object) in model.objects.iter().enumerate() {
                for &i in object.triangles.as_flattened() {
                    let v = (flat.vertex_start[o] + i) as usize;
                    let (a, b) = (fast.corner_frame(c, v), slow.corner_frame(c, v));
                    assert!(a.normal.abs_diff_eq(b.normal, 1e-5), "corner {c}: {a:?} {b:?}");
                    // Without tangents, the frames' tangents are left to chance.
                    let t_ok = !tangents || a.tangent.abs_diff_eq(b.tangent, 1e-5);
                    assert!(t_ok, "corner {c}: {a:?} {b:?}");
                    c += 1;
                }
            }
        }
    }
}
