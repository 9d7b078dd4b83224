//! The fix pipeline: validate and flatten, weld, smooth, then write each object back with its
//! vertices split where one position needs several values.

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use crate::face::face;
use crate::frame::Linear;
use crate::group::{Frame, Rules};
use crate::smooth::{self, Smooth, face_frame};
use crate::validate::{self, Flat};
use crate::weld;
use crate::{FixOptions, MeshError, Mode, Model, Object, TangentMethod};

/// Computes seam-free normals and tangents for every object of `model`.
///
/// Returns a copy of the model in which every object has `normals`, and `tangents` where it
/// has UVs (unless `options.tangents` is [`TangentMethod::None`]). Input normals and tangents
/// are ignored and replaced. Faces share a normal only within their smoothing group, where the
/// objects have them ([`Object::smoothing_groups`]). Vertices are split where one position
/// needs several values: at a crease, between smoothing groups, across a change of UV
/// handedness, between tangents further apart than the tangent angle. Split vertices are appended after the object's original vertices, which keep their
/// indices. Vertices on a boundary between objects get bit-identical values in model space
/// (up to each object's transform back to its local space) in [`Mode::Model`].
///
/// The result does not depend on the number of threads: every sum runs in a fixed order.
/// Fixing a fixed model changes nothing. [`fix_in_place`] does the same without the copy.
///
/// # Errors
///
/// A [`MeshError`] naming the object and element for: attribute arrays of the wrong length,
/// indices out of range, a non-finite or singular transform, non-finite positions (after the
/// transform) or UVs, or more than [`crate::MAX_ELEMENTS`] vertices or corners.
pub fn fix(model: &Model, options: &FixOptions) -> Result<Model, MeshError> {
    let flat = validate::flatten(model)?;
    let objects = model
        .objects
        .iter()
        .map(|o| Object {
            name: o.name.clone(),
            positions: o.positions.clone(),
            uvs: o.uvs.clone(),
            colors: o.colors.clone(),
            // Vertices no triangle uses keep their input normal: read from `model` below.
            normals: None,
            tangents: None,
            triangles: o.triangles.clone(),
            transform: o.transform,
            material: o.material,
            smoothing_groups: o.smoothing_groups.clone(),
            split_from: o.split_from.clone(),
        })
        .collect();
    let mut out = Model { objects, v_axis: model.v_axis };
    run(&mut out, flat, options, Some(model));
    Ok(out)
}

/// [`fix`], in place: the model's normals and tangents are replaced (reusing their memory),
/// and split vertices are appended to its objects. On an error the model is unchanged.
///
/// # Errors
///
/// As [`fix`].
pub fn fix_in_place(model: &mut Model, options: &FixOptions) -> Result<(), MeshError> {
    let flat = validate::flatten(model)?;
    run(model, flat, options, None);
    Ok(())
}

/// Fixes `model`; `input`, where the model is a copy, is the original (for the normals of
/// vertices no triangle uses).
fn run(model: &mut Model, mut flat: Flat, options: &FixOptions, input: Option<&Model>) {
    let input_normals = |o: usize| input.and_then(|m| m.objects[o].normals.as_deref());
    let want_tangents = options.tangents != TangentMethod::None;
    let tangents_of = |object: &Object| want_tangents && object.uvs.is_some();
    if options.mode == Mode::Flat {
        // Flat shading: each corner takes its face's frame.
        let v_axis = model.v_axis;
        let flat = &flat;
        model.objects.par_iter_mut().enumerate().for_each(|(o, object)| {
            let tangents = tangents_of(object);
            write_corners(o, object, flat, tangents, input_normals(o), |_, p, uv| {
                [face_frame(&face(p, uv, v_axis)); 3]
            });
        });
        return;
    }

    let tolerance = options.weld_tolerance.absolute(diagonal(&flat));
    let roots = roots_for_mode(&flat, tolerance, options.mode);
    weld::snap_to_roots(&mut flat.positions, &roots);
    let rules = Rules::new(options, options.tangents == TangentMethod::Seamlit);
    let smooth = smooth::smooth(model, &flat, roots, rules);
    let flat = &flat;

    if options.tangents == TangentMethod::Mikktspace {
        let triangles = flat.triangles(model);
        let normals: Vec<Vec3> = triangles
            .as_flattened()
            .par_iter()
            .enumerate()
            .map(|(c, &v)| smooth.corner_frame(c as u32, v as usize).normal)
            .collect();
        let uvs = flat.uvs(model);
        let tangents =
            crate::mikk::tangents(&flat.positions, &uvs, &triangles, &normals, model.v_axis);
        drop((triangles, uvs));
        model.objects.par_iter_mut().enumerate().for_each(|(o, object)| {
            let tangents_wanted = tangents_of(object);
            let first = flat.triangle_start[o] as usize * 3;
            write_corners(o, object, flat, tangents_wanted, input_normals(o), |t, _, _| {
                let c = first + t * 3;
                std::array::from_fn(|k| Frame { normal: normals[c + k], tangent: tangents[c + k] })
            });
        });
        return;
    }

    let smooth = &smooth;
    model.objects.par_iter_mut().enumerate().for_each(|(o, object)| {
        let tangents = tangents_of(object);
        write_smooth(o, object, flat, smooth, tangents, input_normals(o));
    });
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
struct Out<'a> {
    positions: &'a mut Vec<Vec3>,
    /// The object's [`Object::split_from`], extended for every copy made here.
    split_from: &'a mut Vec<u32>,
    /// Vertices before this index are the object's input vertices.
    input_count: usize,
    /// The input normals where the object is a copy without them (see [`Out::finish`]).
    input_normals: Option<&'a [Vec3]>,
    uvs: &'a mut Option<Vec<Vec2>>,
    colors: &'a mut Option<Vec<Vec4>>,
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
            uvs: &mut object.uvs,
            colors: &mut object.colors,
            linear,
            tangents_wanted,
            normals,
            tangents,
            is_set: vec![false; n],
            next: Vec::new(),
        }
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
        (self.normals[v], self.tangents[v]) = self.local(f);
        self.is_set[v] = true;
    }

    /// Gives a corner at vertex `v` the frame `f`: returns `v`, or the copy of `v` that has
    /// this frame (made if none has).
    fn put(&mut self, v: u32, f: Frame) -> u32 {
        let vi = v as usize;
        if !self.is_set[vi] {
            self.set(vi, f);
            return v;
        }
        let (normal, tangent) = self.local(f);
        let key = bits(normal, tangent);
        if self.next.is_empty() {
            self.next = vec![u32::MAX; self.is_set.len()];
        }
        let mut at = vi;
        loop {
            if bits(self.normals[at], self.tangents[at]) == key {
                return at as u32;
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
                if let Some(colors) = self.colors {
                    colors.push(colors[vi]);
                }
                self.normals.push(normal);
                self.tangents.push(tangent);
                self.is_set.push(true);
                self.next.push(u32::MAX);
                self.next[at] = new as u32;
                return new as u32;
            }
            at = self.next[at] as usize;
        }
    }

    /// Vertices no triangle uses keep their input normal, or +Z; then the result goes into
    /// the object.
    fn finish(mut self, normals: &mut Option<Vec<Vec3>>, tangents: &mut Option<Vec<Vec4>>) {
        for v in 0..self.is_set.len() {
            if !self.is_set[v] {
                let input = self.input_normals.map_or(self.normals[v], |ns| ns[v]);
                let n = input.try_normalize().unwrap_or(Vec3::Z);
                self.normals[v] = n;
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

/// Writes one object corner by corner, `frames(t, positions, uvs)` giving the model-space
/// frames of triangle `t`'s corners (from its model-space positions and UVs). `input_normals`:
/// see [`Out`].
fn write_corners(
    o: usize,
    object: &mut Object,
    flat: &Flat,
    tangents: bool,
    input_normals: Option<&[Vec3]>,
    frames: impl Fn(usize, [Vec3; 3], Option<[Vec2; 3]>) -> [Frame; 3],
) {
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
    out.finish(&mut normals, &mut out_tangents);
    (object.normals, object.tangents, object.triangles) = (normals, out_tangents, triangles);
}

/// Writes one object from the smoothed frames: every vertex at a simple position takes its
/// position's frame; the corners of complex positions are placed one by one, in corner order.
fn write_smooth(
    o: usize,
    object: &mut Object,
    flat: &Flat,
    smooth: &Smooth,
    tangents: bool,
    input_normals: Option<&[Vec3]>,
) {
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
        *corner = out.put(*corner, smooth.frames[e as u32 as usize]);
    }
    out.finish(&mut normals, &mut out_tangents);
    (object.normals, object.tangents, object.triangles) = (normals, out_tangents, triangles);
}
