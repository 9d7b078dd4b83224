//! One object's output of the fix, built vertex by vertex: a frame per vertex, and a copy of
//! a vertex (with all its attributes, skin and morph targets) wherever one of its corners
//! needs another frame. The writers of `fix` (fix.rs) and of the tangents for kept normals
//! (repair.rs) both fill one.

use glam::{Vec2, Vec3, Vec4};

use crate::Object;
use crate::frame::Linear;
use crate::group::Frame;
use crate::index::index;
use crate::morph::{self, push_copy, push_slack};

/// The frames [`Out::set_each`] moves to local space before it stores them.
const BATCH: usize = 32;

/// One object's output, built vertex by vertex: a frame per vertex, and a copy of a vertex
/// wherever one of its corners needs another frame.
pub(crate) struct Out<'a> {
    positions: &'a mut Vec<Vec3>,
    /// The object's [`Object::split_from`], extended for every copy made here.
    split_from: &'a mut Vec<u32>,
    /// Vertices before this index are the object's input vertices.
    input_count: usize,
    /// The input normals where the object is a copy without them (see [`Out::finish`]).
    input_normals: Option<&'a [Vec3]>,
    /// Whether the object had input normals (its own, or `input_normals`).
    had_normals: bool,
    /// Whether the normals are the object's own, kept: vertices no corner sets keep theirs.
    keep_normals: bool,
    /// Input vertices whose normal was set to other bits than the input's.
    pub(crate) changed: usize,
    pub(crate) uvs: &'a mut Option<Vec<Vec2>>,
    uvs1: &'a mut Option<Vec<Vec2>>,
    colors: &'a mut Option<Vec<Vec4>>,
    skin: &'a mut Vec<crate::Influences>,
    morph_targets: &'a mut Vec<crate::MorphTarget>,
    linear: Option<Linear>,
    /// Whether tangents are written (otherwise they are zero and split nothing).
    tangents_wanted: bool,
    normals: Vec<Vec3>,
    tangents: Vec<Vec4>,
    /// Per vertex: whether its frame is set.
    pub(crate) is_set: Vec<bool>,
    /// Copies of vertex `v` form a chain: `next[v] -> ... -> u32::MAX` (empty until needed).
    next: Vec<u32>,
}

impl<'a> Out<'a> {
    pub(crate) fn new(
        object: &'a mut Object,
        linear: Option<Linear>,
        tangents_wanted: bool,
        input_normals: Option<&'a [Vec3]>,
    ) -> Self {
        // Reuse the input's memory.
        let mut tangents = object.tangents.take().unwrap_or_default();
        tangents.clear();
        tangents.resize(object.positions.len(), Vec4::ZERO);
        Self::over_tangents(object, linear, tangents_wanted, input_normals, tangents)
    }

    /// [`Self::new`] in `tangents`' memory, one entry per vertex of the object (the input
    /// tangents, if any, are dropped): a vertex's entry is [`Self::tangent`] until a corner
    /// sets it, so that what it held (MikkTSpace's fan sums) turns into the tangents in place.
    pub(crate) fn over_tangents(
        object: &'a mut Object,
        linear: Option<Linear>,
        tangents_wanted: bool,
        input_normals: Option<&'a [Vec3]>,
        tangents: Vec<Vec4>,
    ) -> Self {
        let n = object.positions.len();
        assert_eq!(tangents.len(), n, "one tangent a vertex");
        object.tangents = None;
        let had_normals = input_normals.is_some() || object.normals.is_some();
        // Reuse the input's memory. Input normals stay where no triangle overwrites them.
        let mut normals = object.normals.take().unwrap_or_default();
        normals.resize(n, Vec3::ZERO);
        Self {
            input_count: n - object.split_from.len(),
            positions: &mut object.positions,
            split_from: &mut object.split_from,
            input_normals,
            had_normals,
            keep_normals: false,
            changed: 0,
            uvs: &mut object.uvs,
            uvs1: &mut object.uvs1,
            colors: &mut object.colors,
            skin: &mut object.skin,
            morph_targets: &mut object.morph_targets,
            linear,
            tangents_wanted,
            normals,
            tangents,
            is_set: vec![false; n],
            next: Vec::new(),
        }
    }

    /// An output for new tangents of an object whose normals (in local space) stay: frames
    /// are given with [`Self::put_local`], and vertices no corner sets keep their normal.
    pub fn keeping_normals(object: &'a mut Object) -> Self {
        let mut out = Self::new(object, None, true, None);
        out.keep_normals = true;
        out
    }

    /// The normal of vertex `v`: the input one until a corner sets it.
    pub fn normal(&self, v: u32) -> Vec3 {
        self.normals[v as usize]
    }

    /// The tangent entry of vertex `v`: what the memory held (see [`Self::over_tangents`])
    /// until a corner sets it.
    pub fn tangent(&self, v: u32) -> Vec4 {
        self.tangents[v as usize]
    }

    /// A model-space frame in the object's local space.
    fn local(&self, f: Frame) -> (Vec3, Vec4) {
        let (n, t) = match &self.linear {
            Some(l) => l.frame_to_local(f.normal, f.tangent),
            None => (f.normal, f.tangent),
        };
        (n, self.wanted(t))
    }

    /// `tangent`, or zero where tangents are not written.
    fn wanted(&self, tangent: Vec4) -> Vec4 {
        if self.tangents_wanted { tangent } else { Vec4::ZERO }
    }

    /// Sets the frame of every vertex `v` (which no corner has set yet) to which
    /// `frame_of(self, v)` gives one, [`BATCH`] at a time: a batch's frames are moved to local
    /// space before any is stored, four at once ([`Linear::frames_to_local`]), so that the
    /// processor works on several (each a long chain of dependent roots and divisions) rather
    /// than one after the other behind the stores and counts of the last. `frame_of` sees the
    /// entries of `v` as they were: a batch stores only its own vertices.
    pub(crate) fn set_each(&mut self, frame_of: impl Fn(&Self, usize) -> Option<Frame>) {
        let none = Frame { normal: Vec3::ZERO, tangent: Vec4::ZERO };
        let mut batch = [(0usize, none); BATCH];
        let mut len = 0;
        for v in 0..self.is_set.len() {
            if let Some(f) = frame_of(self, v) {
                batch[len] = (v, f);
                len += 1;
                if len == BATCH {
                    self.set_batch(&batch);
                    len = 0;
                }
            }
        }
        self.set_batch(&batch[..len]);
    }

    /// [`Self::set_each`]'s batch: with a transform, four frames at a time, the rest one by
    /// one.
    fn set_batch(&mut self, batch: &[(usize, Frame)]) {
        let mut local = [(Vec3::ZERO, Vec4::ZERO); BATCH];
        let mut done = 0;
        if let Some(l) = &self.linear {
            let (quads, _) = batch.as_chunks::<4>();
            for (out, quad) in local.as_chunks_mut::<4>().0.iter_mut().zip(quads) {
                let frames =
                    l.frames_to_local(quad.map(|(_, f)| f.normal), quad.map(|(_, f)| f.tangent));
                *out = frames.map(|(n, t)| (n, self.wanted(t)));
            }
            done = quads.len() * 4;
        }
        for (out, &(_, f)) in local[done..].iter_mut().zip(&batch[done..]) {
            *out = self.local(f);
        }
        for (&(v, _), &(n, t)) in batch.iter().zip(&local) {
            self.set_local(v, n, t);
        }
    }

    /// Sets the frame of vertex `v`, in local space.
    fn set_local(&mut self, v: usize, normal: Vec3, tangent: Vec4) {
        let input = self.input_normals.map_or(self.normals[v], |ns| ns[v]);
        self.changed += usize::from(!self.had_normals || vec3_bits(input) != vec3_bits(normal));
        (self.normals[v], self.tangents[v]) = (normal, tangent);
        self.is_set[v] = true;
    }

    /// Gives a corner at vertex `v` the frame `f`: returns `v`, or the copy of `v` that has
    /// this frame (made if none has).
    pub(crate) fn put(&mut self, v: u32, f: Frame) -> u32 {
        let (normal, tangent) = self.local(f);
        self.put_local(v, normal, tangent)
    }

    /// [`Self::put`] in local space.
    pub fn put_local(&mut self, v: u32, normal: Vec3, tangent: Vec4) -> u32 {
        let vi = v as usize;
        if !self.is_set[vi] {
            self.set_local(vi, normal, tangent);
            return v;
        }
        let key = bits(normal, tangent);
        if self.next.is_empty() {
            self.next = vec![u32::MAX; self.is_set.len()];
        }
        let mut at = vi;
        loop {
            if bits(self.normals[at], self.tangents[at]) == key {
                return index(at);
            }
            if self.next[at] == u32::MAX {
                let new = self.positions.len();
                push_copy(self.positions, vi);
                let source = match vi.checked_sub(self.input_count) {
                    Some(k) => self.split_from[k],
                    None => v,
                };
                push_slack(self.split_from, source);
                if let Some(uvs) = self.uvs {
                    push_copy(uvs, vi);
                }
                if let Some(uvs1) = self.uvs1 {
                    push_copy(uvs1, vi);
                }
                if let Some(colors) = self.colors {
                    push_copy(colors, vi);
                }
                morph::copy_vertex(self.skin, self.morph_targets, vi);
                push_slack(&mut self.normals, normal);
                push_slack(&mut self.tangents, tangent);
                push_slack(&mut self.is_set, true);
                push_slack(&mut self.next, u32::MAX);
                // At most one new vertex per corner: see crate::index.
                let new = index(new);
                self.next[at] = new;
                return new;
            }
            at = self.next[at] as usize;
        }
    }

    /// Vertices no triangle uses keep their input normal (normalised, or +Z; as it is where
    /// the normals are kept); then the result goes into the object.
    pub fn finish(mut self, normals: &mut Option<Vec<Vec3>>, tangents: &mut Option<Vec<Vec4>>) {
        for v in 0..self.is_set.len() {
            if !self.is_set[v] {
                let input = self.input_normals.map_or(self.normals[v], |ns| ns[v]);
                let n = input.try_normalize().unwrap_or(Vec3::Z);
                if !self.keep_normals {
                    self.changed +=
                        usize::from(!self.had_normals || vec3_bits(input) != vec3_bits(n));
                    self.normals[v] = n;
                }
                self.tangents[v] = n.any_orthonormal_vector().extend(1.0);
            }
        }
        *normals = Some(self.normals);
        *tangents = self.tangents_wanted.then_some(self.tangents);
    }
}

fn bits(n: Vec3, t: Vec4) -> [u32; 7] {
    [n.x, n.y, n.z, t.x, t.y, t.z, t.w].map(f32::to_bits)
}

fn vec3_bits(n: Vec3) -> [u32; 3] {
    n.to_array().map(f32::to_bits)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Influences, MorphTarget};

    /// Copies grow an object's arrays by an eighth, not twice over: the 1M teapot's fix
    /// splits a few vertices in most of its objects, and a doubled array of every attribute
    /// of each was 6 MiB of its peak.
    #[test]
    fn copies_leave_little_slack() {
        let n = 1000;
        let mut object =
            Object::new("o", vec![Vec3::X; n], vec![[0, 1, 2]]).with_uvs(vec![Vec2::ONE; n]);
        object.uvs1 = Some(vec![Vec2::ZERO; n]);
        object.colors = Some(vec![Vec4::ONE; n]);
        object.skin =
            vec![Influences { joints: vec![[0; 4]; n], weights: vec![[1.0, 0.0, 0.0, 0.0]; n] }];
        object.morph_targets = vec![MorphTarget {
            name: "m".into(),
            position_deltas: vec![Vec3::Y; n],
            normal_deltas: Some(vec![Vec3::Z; n]),
            tangent_deltas: Some(vec![Vec3::Z; n]),
        }];
        let frame = |x: f32| Frame { normal: Vec3::new(x, 1.0, 0.0).normalize(), tangent: Vec4::X };
        let mut out = Out::new(&mut object, None, true, None);
        out.set_each(|_, _| Some(frame(0.0)));
        for v in 0..5 {
            assert_eq!(out.put(v, frame(1.0)) as usize, n + v as usize, "a copy of vertex {v}");
        }
        let (mut normals, mut tangents) = (None, None);
        out.finish(&mut normals, &mut tangents);
        (object.normals, object.tangents) = (normals, tangents);
        let slack = |what: &str, len: usize, capacity: usize| {
            assert_eq!(len, n + 5, "{what}");
            assert!(capacity <= len + len / 8 + 16, "{what}: {capacity} for {len}");
        };
        let o = &object;
        slack("positions", o.positions.len(), o.positions.capacity());
        let uvs = o.uvs.as_ref().unwrap();
        slack("uvs", uvs.len(), uvs.capacity());
        let uvs1 = o.uvs1.as_ref().unwrap();
        slack("uvs1", uvs1.len(), uvs1.capacity());
        let colors = o.colors.as_ref().unwrap();
        slack("colors", colors.len(), colors.capacity());
        let normals = o.normals.as_ref().unwrap();
        slack("normals", normals.len(), normals.capacity());
        let tangents = o.tangents.as_ref().unwrap();
        slack("tangents", tangents.len(), tangents.capacity());
        slack("joints", o.skin[0].joints.len(), o.skin[0].joints.capacity());
        slack("weights", o.skin[0].weights.len(), o.skin[0].weights.capacity());
        let target = &o.morph_targets[0];
        slack("position deltas", target.position_deltas.len(), target.position_deltas.capacity());
        let normal_deltas = target.normal_deltas.as_ref().unwrap();
        slack("normal deltas", normal_deltas.len(), normal_deltas.capacity());
        let tangent_deltas = target.tangent_deltas.as_ref().unwrap();
        slack("tangent deltas", tangent_deltas.len(), tangent_deltas.capacity());
        assert_eq!(o.split_from, [0, 1, 2, 3, 4]);
    }
}
