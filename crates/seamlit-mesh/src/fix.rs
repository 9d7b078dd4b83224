//! The fix pipeline: validate and flatten, weld, per-face frames, group and average, then
//! write each object back with its vertices split where one position needs several values.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use crate::face;
use crate::frame::{Linear, finish};
use crate::group::{self, Frame, Rules};
use crate::validate::{self, Flat};
use crate::weld::{self, Weld};
use crate::{FixOptions, MeshError, Mode, Model, Object, TangentMethod};

/// Computes seam-free normals and tangents for every object of `model`.
///
/// Returns a copy of the model in which every object has `normals`, and `tangents` where it
/// has UVs (unless `options.tangents` is [`TangentMethod::None`]). Input normals and tangents
/// are ignored and replaced. Vertices are split where one position needs several values: at a
/// crease, across a change of UV handedness, between tangents further apart than the tangent
/// angle. Split vertices are appended after the object's original vertices, which keep their
/// indices. Vertices on a boundary between objects get bit-identical values in model space
/// (up to each object's transform back to its local space) in [`Mode::Model`].
///
/// The result does not depend on the number of threads: every sum runs over a position's
/// corners in a fixed order. Fixing a fixed model changes nothing.
///
/// # Errors
///
/// A [`MeshError`] naming the object and element for: attribute arrays of the wrong length,
/// indices out of range, a non-finite or singular transform, non-finite positions (after the
/// transform) or UVs, or more than [`crate::MAX_ELEMENTS`] vertices or corners.
pub fn fix(model: &Model, options: &FixOptions) -> Result<Model, MeshError> {
    let mut flat = validate::flatten(model)?;
    let want_tangents = options.tangents != TangentMethod::None;

    let corner_frame = if options.mode == Mode::Flat {
        let faces = face::faces(&flat, model.v_axis);
        CornerFrames::Flat(
            faces
                .par_iter()
                .map(|f| {
                    let (normal, tangent) = finish(f.normal, f.normal, f.tangent, f.bitangent);
                    Frame { normal, tangent }
                })
                .collect(),
        )
    } else {
        let tolerance = options.weld_tolerance.absolute(diagonal(&flat));
        let weld = weld_for_mode(&flat, tolerance, options.mode);
        weld.snap(&mut flat.positions);
        let faces = face::faces(&flat, model.v_axis);
        let corner_positions: Vec<u32> =
            flat.triangles.as_flattened().par_iter().map(|&v| weld.ids[v as usize]).collect();
        let rules = Rules::new(options, options.tangents == TangentMethod::Seamlit);
        let groups = group::group(&corner_positions, weld.count, &faces, rules);
        CornerFrames::Groups(groups)
    };

    let corner_frames: Option<Vec<Frame>> =
        (options.tangents == TangentMethod::Mikktspace).then(|| {
            let normals: Vec<Vec3> = (0..flat.triangles.len() * 3)
                .into_par_iter()
                .map(|c| corner_frame.get(c).normal)
                .collect();
            let tangents = crate::mikk::tangents(&flat, &normals, model.v_axis);
            normals
                .into_iter()
                .zip(tangents)
                .map(|(normal, tangent)| Frame { normal, tangent })
                .collect()
        });
    let frame_of = |c: usize| match &corner_frames {
        Some(f) => f[c],
        None => corner_frame.get(c),
    };

    let objects = model
        .objects
        .par_iter()
        .enumerate()
        .map(|(o, object)| {
            let tangents = want_tangents && object.uvs.is_some();
            write_object(o, object, &flat, tangents, &frame_of)
        })
        .collect();
    Ok(Model { objects, v_axis: model.v_axis })
}

/// The length of the diagonal of the model-space bounding box.
pub(crate) fn diagonal(flat: &Flat) -> f32 {
    let (lo, hi) = weld::bounds(&flat.positions);
    if lo.x <= hi.x { lo.distance(hi) } else { 0.0 }
}

/// Welds across the whole model ([`Mode::Model`]) or within each object ([`Mode::Object`]).
pub(crate) fn weld_for_mode(flat: &Flat, tolerance: f32, mode: Mode) -> Weld {
    if mode == Mode::Model {
        return weld::weld(&flat.positions, tolerance);
    }
    let parts: Vec<Weld> = flat
        .vertex_start
        .par_windows(2)
        .map(|w| weld::weld(&flat.positions[w[0] as usize..w[1] as usize], tolerance))
        .collect();
    let mut ids = Vec::with_capacity(flat.positions.len());
    let mut count = 0;
    for part in parts {
        ids.extend(part.ids.iter().map(|&i| i + count as u32));
        count += part.count;
    }
    Weld { ids, count }
}

/// Where each corner's frame comes from.
enum CornerFrames {
    /// Per face (flat mode).
    Flat(Vec<Frame>),
    /// Per smoothing group.
    Groups(group::Groups),
}

impl CornerFrames {
    fn get(&self, corner: usize) -> Frame {
        match self {
            Self::Flat(faces) => faces[corner / 3],
            Self::Groups(g) => g.frames[g.corner_group[corner] as usize],
        }
    }
}

fn bits(n: Vec3, t: Vec4) -> [u32; 7] {
    [n.x, n.y, n.z, t.x, t.y, t.z, t.w].map(f32::to_bits)
}

/// Writes one object's result: per-corner frames in local space, vertices split where corners
/// of one vertex disagree.
fn write_object(
    o: usize,
    object: &Object,
    flat: &Flat,
    tangents: bool,
    frame_of: &(impl Fn(usize) -> Frame + Sync),
) -> Object {
    let linear = flat.linear[o].map(Linear::new);
    let n = object.positions.len();
    let first_triangle = flat.triangle_start[o] as usize;
    let mut positions = object.positions.clone();
    let mut uvs = object.uvs.clone();
    let mut normals = vec![Vec3::ZERO; n];
    let mut out_tangents = vec![Vec4::ZERO; n];
    let mut set = vec![false; n];
    // Vertices split off vertex v form a chain: next[v] -> ... -> u32::MAX.
    let mut next: Vec<u32> = vec![u32::MAX; n];
    let mut triangles = Vec::with_capacity(object.triangles.len());
    for (t, tri) in object.triangles.iter().enumerate() {
        let mut out = [0u32; 3];
        for (k, &v) in tri.iter().enumerate() {
            let frame = frame_of((first_triangle + t) * 3 + k);
            let (normal, mut tangent) = match &linear {
                Some(l) => l.frame_to_local(frame.normal, frame.tangent),
                None => (frame.normal, frame.tangent),
            };
            if !tangents {
                tangent = Vec4::ZERO;
            }
            let vi = v as usize;
            out[k] = if set[vi] {
                let key = bits(normal, tangent);
                let mut at = vi;
                loop {
                    if bits(normals[at], out_tangents[at]) == key {
                        break at as u32;
                    }
                    if next[at] == u32::MAX {
                        let new = positions.len();
                        positions.push(object.positions[vi]);
                        if let Some(uvs) = &mut uvs {
                            uvs.push(uvs[vi]);
                        }
                        normals.push(normal);
                        out_tangents.push(tangent);
                        next.push(u32::MAX);
                        next[at] = new as u32;
                        break new as u32;
                    }
                    at = next[at] as usize;
                }
            } else {
                set[vi] = true;
                normals[vi] = normal;
                out_tangents[vi] = tangent;
                v
            };
        }
        triangles.push(out);
    }
    // Vertices no triangle uses keep their input normal, or +Z.
    for (i, _) in set.iter().enumerate().filter(|(_, s)| !**s) {
        let input = object.normals.as_ref().and_then(|ns| ns[i].try_normalize());
        let nrm = input.unwrap_or(Vec3::Z);
        normals[i] = nrm;
        out_tangents[i] = nrm.any_orthonormal_vector().extend(1.0);
    }
    Object {
        name: object.name.clone(),
        positions,
        uvs,
        normals: Some(normals),
        tangents: tangents.then_some(out_tangents),
        triangles,
        transform: object.transform,
        material: object.material,
    }
}
