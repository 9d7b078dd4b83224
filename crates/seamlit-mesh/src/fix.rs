//! The fix pipeline: validate and flatten, weld, smooth, then write each object back with its
//! vertices split where one position needs several values; under [`NormalPolicy::Auto`] and
//! [`NormalPolicy::Keep`], objects that carry normals keep them and [`crate::repair`] repairs
//! the seams between objects.

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use crate::face::face;
use crate::frame::Linear;
use crate::group::{Frame, Rules};
use crate::index::{index, low_half};
use crate::mikk;
use crate::morph;
use crate::repair::{self, Authored};
use crate::smooth::{self, Smooth, face_frame};
use crate::validate::{self, Flat};
use crate::weld;
use crate::{
    Changes, FixOptions, MeshError, Mode, Model, NormalPolicy, Object, ObjectChanges, TangentMethod,
};

/// Computes seam-free normals and tangents for every object of `model`.
///
/// Returns a copy of the model in which every object has `normals`, and `tangents` where it
/// has UVs (unless `options.tangents` is [`TangentMethod::None`]). Which input normals and
/// tangents are kept is `options.normals`' choice ([`NormalPolicy`]): with
/// [`NormalPolicy::Recompute`] every one is ignored and computed; otherwise objects that carry
/// normals keep them (with [`NormalPolicy::Auto`] in [`Mode::Model`], repaired where objects
/// meet), and the others get them computed. Computed normals are shared by faces only within
/// their smoothing group, where the objects have them ([`Object::smoothing_groups`]). Vertices
/// are split where one position needs several values: at a crease, between smoothing groups,
/// across a change of UV handedness, between tangents further apart than the tangent angle.
/// Split vertices are appended after the object's original vertices, which keep their indices,
/// and recorded in [`Object::split_from`]. Vertices on a boundary between objects get
/// bit-identical normals in model space (up to each object's transform back to its local
/// space) in [`Mode::Model`], unless the policy is [`NormalPolicy::Keep`].
///
/// The result does not depend on the number of threads: every sum runs in a fixed order.
/// Fixing a fixed model changes nothing. [`fix_in_place`] does the same without the copy, and
/// says what it changed.
///
/// # Errors
///
/// A [`MeshError`] naming the object and element for: attribute arrays of the wrong length,
/// indices out of range, a non-finite or singular transform, non-finite positions (after the
/// transform) or UVs, or more than [`crate::MAX_ELEMENTS`] vertices, corners, or both together.
pub fn fix(model: &Model, options: &FixOptions) -> Result<Model, MeshError> {
    let flat = validate::flatten(model)?;
    let authored = Authored::of(model, options);
    let objects = model
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| Object {
            name: o.name.clone(),
            positions: o.positions.clone(),
            uvs: o.uvs.clone(),
            uvs1: o.uvs1.clone(),
            colors: o.colors.clone(),
            // Kept normals are copied; computed objects' vertices that no triangle uses keep
            // their input normal, read from `model` below.
            normals: if authored.normals[i] { o.normals.clone() } else { None },
            tangents: if authored.tangents[i] { o.tangents.clone() } else { None },
            triangles: o.triangles.clone(),
            transform: o.transform,
            material: o.material,
            smoothing_groups: o.smoothing_groups.clone(),
            split_from: o.split_from.clone(),
            skin: o.skin.clone(),
            morph_targets: o.morph_targets.clone(),
        })
        .collect();
    let mut out = Model { objects, v_axis: model.v_axis };
    let (_, weld) = run(&mut out, flat, options, Some(model), &authored)?;
    morph::compute_deltas(&mut out, options, &computed(&authored), weld)?;
    Ok(out)
}

/// [`fix`], in place: the model's normals and tangents are replaced where they are computed
/// (reusing their memory), and split vertices are appended to its objects. Returns what
/// changed, object by object. On an error the model is unchanged.
///
/// # Errors
///
/// As [`fix`].
pub fn fix_in_place(model: &mut Model, options: &FixOptions) -> Result<Changes, MeshError> {
    let flat = validate::flatten(model)?;
    let authored = Authored::of(model, options);
    let (changes, weld) = run(model, flat, options, None, &authored)?;
    morph::compute_deltas(model, options, &computed(&authored), weld)?;
    Ok(changes)
}

/// The objects whose normals `fix` computes (the others keep theirs, and their morph
/// targets' deltas).
fn computed(authored: &Authored) -> Vec<bool> {
    authored.normals.iter().map(|&kept| !kept).collect()
}

/// Fixes `model` under the normal policy; `input`, where the model is a copy, is the original
/// (see [`compute`]). Objects marked in `authored` carry their input normals (and tangents
/// where marked), the others none or their input ones, which are replaced.
fn run(
    model: &mut Model,
    flat: Flat,
    options: &FixOptions,
    input: Option<&Model>,
    authored: &Authored,
) -> Result<(Changes, Option<Vec<u32>>), MeshError> {
    let vertices: Vec<usize> = model.objects.iter().map(Object::vertex_count).collect();
    if !authored.any() {
        let (changed, roots) = compute(model, flat, options, input, &authored.normals);
        // The weld, for the morph targets' deltas: the fix made no other change.
        let weld = roots.map(|r| morph::roots_after_splits(&r, &vertices, model));
        return Ok((tally(model, &vertices, &changed, authored), weld));
    }
    // 1. Missing normals (and their tangents), computed as `recompute` computes them; the
    //    objects that keep theirs are left as they are. Vertices may have been split since
    //    the model was flattened: flatten it again.
    let (flat, mut changed) = if authored.all() {
        (flat, vec![0; model.objects.len()])
    } else {
        let (changed, _) = compute(model, flat, options, input, &authored.normals);
        (validate::flatten(model)?, changed)
    };
    let mut flat = flat;
    // 2. Authored tangents that are not kept go (they are computed in step 5).
    for (o, object) in model.objects.iter_mut().enumerate() {
        if authored.normals[o] && !authored.tangents[o] {
            object.tangents = None;
        }
    }
    let wants_tangents = |o: usize| {
        authored.normals[o]
            && !authored.tangents[o]
            && options.tangents != TangentMethod::None
            && model.objects[o].uvs.is_some()
    };
    let tangents_needed: Vec<bool> = (0..model.objects.len()).map(wants_tangents).collect();
    let repairs = options.normals == NormalPolicy::Auto && options.mode == Mode::Model;
    // 3. The weld, where the repair or the tangents need it.
    let roots =
        (options.mode != Mode::Flat && (repairs || tangents_needed.contains(&true))).then(|| {
            let tolerance = options.weld_tolerance.absolute(diagonal(&flat));
            let roots = roots_for_mode(&flat, tolerance, options.mode);
            weld::snap_to_roots(&mut flat.positions, &roots);
            roots
        });
    // 4. The seam-only repair.
    if repairs && let Some(roots) = &roots {
        let repaired = repair::repair_seams(model, &flat, roots, options);
        for (o, n) in repaired.into_iter().enumerate() {
            changed[o] += n;
        }
    }
    // 5. Tangents where kept normals came without them.
    repair::compute_tangents(model, &flat, roots, options, &tangents_needed);
    Ok((tally(model, &vertices, &changed, authored), None))
}

/// The [`Changes`]: `vertices` and `changed` per object, before the fix.
fn tally(model: &Model, vertices: &[usize], changed: &[usize], authored: &Authored) -> Changes {
    let objects = model
        .objects
        .iter()
        .enumerate()
        .map(|(o, object)| ObjectChanges {
            name: object.name.clone(),
            kept_normals: authored.normals[o],
            kept_tangents: authored.tangents[o],
            vertices: vertices[o],
            normals_changed: changed[o].min(vertices[o]),
            vertices_split: object.vertex_count() - vertices[o],
        })
        .collect();
    Changes { objects }
}

/// Computes the normals and tangents of every object not marked in `skip` (objects marked
/// are not written), from the faces of all objects: the paper's way, and the whole fix under
/// [`NormalPolicy::Recompute`]. `input`, where the model is a copy, is the original (for the
/// normals of vertices no triangle uses). Returns, per object, how many of its vertices'
/// normals are not the input ones, and each vertex's weld root (where it welded).
fn compute(
    model: &mut Model,
    mut flat: Flat,
    options: &FixOptions,
    input: Option<&Model>,
    skip: &[bool],
) -> (Vec<usize>, Option<Vec<u32>>) {
    let want_tangents = options.tangents != TangentMethod::None;
    if options.mode == Mode::Flat {
        // Flat shading: each corner takes its face's frame.
        let v_axis = model.v_axis;
        let flat = &flat;
        let changed =
            write_objects(model, skip, want_tangents, input, |o, object, tangents, input| {
                write_corners(o, object, flat, tangents, input, |_, p, uv| {
                    [face_frame(&face(p, uv, v_axis)); 3]
                })
            });
        return (changed, None);
    }

    let tolerance = options.weld_tolerance.absolute(diagonal(&flat));
    let roots = roots_for_mode(&flat, tolerance, options.mode);
    weld::snap_to_roots(&mut flat.positions, &roots);
    let rules = Rules::new(options, options.tangents == TangentMethod::Seamlit);
    let smooth = smooth::smooth(model, &flat, roots, rules);
    let flat = &flat;

    if options.tangents == TangentMethod::Mikktspace {
        let triangles = flat.triangles(model);
        let uvs = flat.uvs(model);
        let smooth = &smooth;
        let surface = mikk::Surface {
            positions: &flat.positions,
            roots: smooth.roots(),
            uvs: &uvs,
            triangles: &triangles,
            vertex_start: &flat.vertex_start,
            triangle_start: &flat.triangle_start,
            normal: |c: usize, v: usize| smooth.corner_normal(index(c), v),
            vertex_normals: None,
            v_axis: model.v_axis,
        };
        let tangents = mikk::tangents(&surface);
        drop((uvs, triangles));
        let tangents = &tangents;
        let changed =
            write_objects(model, skip, want_tangents, input, |o, object, wanted, input| {
                write_mikk(o, object, flat, smooth, tangents, wanted, input)
            });
        return (changed, Some(smooth.roots().to_vec()));
    }

    let changed = {
        let smooth = &smooth;
        write_objects(model, skip, want_tangents, input, |o, object, tangents, input| {
            write_smooth(o, object, flat, smooth, tangents, input)
        })
    };
    (changed, Some(smooth.into_roots()))
}

/// Writes every object not marked in `skip` with `write(o, object, tangents wanted, input
/// normals)`, in parallel; returns each one's count of changed normals (0 for those skipped).
fn write_objects(
    model: &mut Model,
    skip: &[bool],
    want_tangents: bool,
    input: Option<&Model>,
    write: impl Fn(usize, &mut Object, bool, Option<&[Vec3]>) -> usize + Sync,
) -> Vec<usize> {
    model
        .objects
        .par_iter_mut()
        .enumerate()
        .map(|(o, object)| {
            if skip[o] {
                return 0;
            }
            let tangents = want_tangents && object.uvs.is_some();
            write(o, object, tangents, input.and_then(|m| m.objects[o].normals.as_deref()))
        })
        .collect()
}

/// The length of the diagonal of the model-space bounding box.
pub(crate) fn diagonal(flat: &Flat) -> f32 {
    let (lo, hi) = weld::bounds(&flat.positions);
    if lo.x <= hi.x { lo.distance(hi) } else { 0.0 }
}

/// Each vertex's root (see [`weld::roots`]), welding across the whole model ([`Mode::Model`])
/// or within each object ([`Mode::Object`]).
pub(crate) fn roots_for_mode(flat: &Flat, tolerance: f32, mode: Mode) -> Vec<u32> {
    if mode == Mode::Model {
        return weld::roots(&flat.positions, tolerance);
    }
    let parts: Vec<Vec<u32>> = flat
        .vertex_start
        .par_windows(2)
        .map(|w| {
            let mut roots = weld::roots(&flat.positions[w[0] as usize..w[1] as usize], tolerance);
            roots.iter_mut().for_each(|r| *r += w[0]);
            roots
        })
        .collect();
    parts.concat()
}

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
    changed: usize,
    uvs: &'a mut Option<Vec<Vec2>>,
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
    is_set: Vec<bool>,
    /// Copies of vertex `v` form a chain: `next[v] -> ... -> u32::MAX` (empty until needed).
    next: Vec<u32>,
}

impl<'a> Out<'a> {
    fn new(
        object: &'a mut Object,
        linear: Option<Linear>,
        tangents_wanted: bool,
        input_normals: Option<&'a [Vec3]>,
    ) -> Self {
        let n = object.positions.len();
        let had_normals = input_normals.is_some() || object.normals.is_some();
        // Reuse the input's memory. Input normals stay where no triangle overwrites them.
        let mut normals = object.normals.take().unwrap_or_default();
        normals.resize(n, Vec3::ZERO);
        let mut tangents = object.tangents.take().unwrap_or_default();
        tangents.clear();
        tangents.resize(n, Vec4::ZERO);
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

    /// A model-space frame in the object's local space.
    fn local(&self, f: Frame) -> (Vec3, Vec4) {
        let (n, t) = match &self.linear {
            Some(l) => l.frame_to_local(f.normal, f.tangent),
            None => (f.normal, f.tangent),
        };
        (n, if self.tangents_wanted { t } else { Vec4::ZERO })
    }

    /// Sets the frame of vertex `v`, which no corner has set yet.
    fn set(&mut self, v: usize, f: Frame) {
        let (n, t) = self.local(f);
        self.set_local(v, n, t);
    }

    /// [`Self::set`] in local space.
    fn set_local(&mut self, v: usize, normal: Vec3, tangent: Vec4) {
        let input = self.input_normals.map_or(self.normals[v], |ns| ns[v]);
        self.changed += usize::from(!self.had_normals || vec3_bits(input) != vec3_bits(normal));
        (self.normals[v], self.tangents[v]) = (normal, tangent);
        self.is_set[v] = true;
    }

    /// Gives a corner at vertex `v` the frame `f`: returns `v`, or the copy of `v` that has
    /// this frame (made if none has).
    fn put(&mut self, v: u32, f: Frame) -> u32 {
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
                self.positions.push(self.positions[vi]);
                let source = match vi.checked_sub(self.input_count) {
                    Some(k) => self.split_from[k],
                    None => v,
                };
                self.split_from.push(source);
                if let Some(uvs) = self.uvs {
                    uvs.push(uvs[vi]);
                }
                if let Some(uvs1) = self.uvs1 {
                    uvs1.push(uvs1[vi]);
                }
                if let Some(colors) = self.colors {
                    colors.push(colors[vi]);
                }
                morph::copy_vertex(self.skin, self.morph_targets, vi);
                self.normals.push(normal);
                self.tangents.push(tangent);
                self.is_set.push(true);
                self.next.push(u32::MAX);
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

/// Writes one object corner by corner, `frames(t, positions, uvs)` giving the model-space
/// frames of triangle `t`'s corners (from its model-space positions and UVs). `input_normals`:
/// see [`Out`]. Returns how many input vertices' normals changed.
fn write_corners(
    o: usize,
    object: &mut Object,
    flat: &Flat,
    tangents: bool,
    input_normals: Option<&[Vec3]>,
    frames: impl Fn(usize, [Vec3; 3], Option<[Vec2; 3]>) -> [Frame; 3],
) -> usize {
    let base = flat.vertex_start[o];
    let mut triangles = std::mem::take(&mut object.triangles);
    let (mut normals, mut out_tangents) = (None, None);
    let mut out = Out::new(object, flat.linear[o].map(Linear::new), tangents, input_normals);
    for (t, tri) in triangles.iter_mut().enumerate() {
        let p = tri.map(|i| flat.positions[(base + i) as usize]);
        let uv = out.uvs.as_ref().map(|uvs| tri.map(|i| uvs[i as usize]));
        let f = frames(t, p, uv);
        for k in 0..3 {
            tri[k] = out.put(tri[k], f[k]);
        }
    }
    let changed = out.changed;
    out.finish(&mut normals, &mut out_tangents);
    (object.normals, object.tangents, object.triangles) = (normals, out_tangents, triangles);
    changed
}

/// Writes one object from the smoothed normals and MikkTSpace's tangents: every vertex at a
/// plain position takes its one frame; the corners of other positions are placed one by one,
/// in corner order. Returns how many input vertices' normals changed.
fn write_mikk(
    o: usize,
    object: &mut Object,
    flat: &Flat,
    smooth: &Smooth,
    tangents: &mikk::Tangents,
    tangents_wanted: bool,
    input_normals: Option<&[Vec3]>,
) -> usize {
    let base = flat.vertex_start[o] as usize;
    let first = flat.triangle_start[o] as usize * 3;
    let others = tangents.others(first..flat.triangle_start[o + 1] as usize * 3);
    let mut triangles = std::mem::take(&mut object.triangles);
    let (mut normals, mut out_tangents) = (None, None);
    let linear = flat.linear[o].map(Linear::new);
    let mut out = Out::new(object, linear, tangents_wanted, input_normals);
    for v in 0..out.is_set.len() {
        let g = base + v;
        if smooth.is_used(g)
            && let Some(tangent) = tangents.fan(g, smooth.roots()[g] as usize)
            && let Some(frame) = smooth.simple_frame(g)
        {
            out.set(v, Frame { normal: frame.normal, tangent });
        }
    }
    for &(c, tangent) in others {
        let local = c as usize - first;
        let corner = &mut triangles[local / 3][local % 3];
        let normal = smooth.corner_normal(c, base + *corner as usize).0;
        *corner = out.put(*corner, Frame { normal, tangent });
    }
    let changed = out.changed;
    out.finish(&mut normals, &mut out_tangents);
    (object.normals, object.tangents, object.triangles) = (normals, out_tangents, triangles);
    changed
}

/// Writes one object from the smoothed frames: every vertex at a simple position takes its
/// position's frame; the corners of complex positions are placed one by one, in corner order.
/// Returns how many input vertices' normals changed.
fn write_smooth(
    o: usize,
    object: &mut Object,
    flat: &Flat,
    smooth: &Smooth,
    tangents: bool,
    input_normals: Option<&[Vec3]>,
) -> usize {
    let base = flat.vertex_start[o] as usize;
    let first = flat.triangle_start[o];
    let complex = &smooth.complex[smooth.complex_range(first..flat.triangle_start[o + 1])];
    let mut triangles = std::mem::take(&mut object.triangles);
    let (mut normals, mut out_tangents) = (None, None);
    let mut out = Out::new(object, flat.linear[o].map(Linear::new), tangents, input_normals);
    for v in 0..out.is_set.len() {
        if smooth.is_used(base + v)
            && let Some(f) = smooth.simple_frame(base + v)
        {
            out.set(v, f);
        }
    }
    for &e in complex {
        let c = (e >> 32) as usize - first as usize * 3;
        let corner = &mut triangles[c / 3][c % 3];
        *corner = out.put(*corner, smooth.frames[low_half(e) as usize]);
    }
    let changed = out.changed;
    out.finish(&mut normals, &mut out_tangents);
    (object.normals, object.tangents, object.triangles) = (normals, out_tangents, triangles);
    changed
}
