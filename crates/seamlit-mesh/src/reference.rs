//! The paper's algorithm, literally: a test oracle and the benchmark's baseline, never the
//! production path.
//!
//! P. Mileff, "Per-pixel lighting for multi-object models" (2024), section 5.2: for every
//! vertex of every object, scan every face of every object; if one of the face's corners has
//! exactly the vertex's position, add the face's unit normal, tangent and bitangent. Then
//! normalise the normal (the listing's erratum: it normalises the tangent instead),
//! re-orthogonalise the tangent (section 5.3) and take the handedness from the bitangent
//! (section 5.4). That is O(V x F) (its figures: BENCHMARKS.md, "Fixing").
//!
//! Where the listing would divide by zero or normalise a zero vector, this implementation uses
//! the same guards as the fast path (see the `face` module): degenerate triangles contribute
//! nothing, and degenerate-UV triangles contribute a tangent only where no face at the
//! position has usable UVs. With those rules, [`crate::fix`] with [`crate::FixOptions::PAPER`]
//! gives the same result up to floating-point rounding.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use crate::face::{DEGENERATE, DEGENERATE_UV, Face};
use crate::frame::{Linear, finish};
use crate::validate::Flat;
use crate::{MeshError, Model, Object, validate};

/// Computes normals and tangents with the paper's brute-force algorithm, in model space, one
/// value per input vertex (no vertex is split). Objects without UVs get no tangents.
///
/// # Errors
///
/// The same input checks as [`crate::fix`].
pub fn fix(model: &Model) -> Result<Model, MeshError> {
    let flat = validate::flatten(model)?;
    let faces = faces(model, &flat);
    let triangles = flat.triangles(model);
    let objects = model
        .objects
        .iter()
        .enumerate()
        .map(|(o, object)| {
            let start = flat.vertex_start[o] as usize;
            let linear = flat.linear[o].map(Linear::new);
            let mut normals = Vec::with_capacity(object.positions.len());
            let mut tangents = Vec::with_capacity(object.positions.len());
            for i in 0..object.positions.len() {
                let (n, t) = vertex_frame(flat.positions[start + i], &flat, &triangles, &faces);
                let (n, t) = match &linear {
                    Some(l) => l.frame_to_local(n, t),
                    None => (n, t),
                };
                normals.push(n);
                tangents.push(t);
            }
            Object {
                normals: Some(normals),
                tangents: object.uvs.is_some().then_some(tangents),
                ..object.clone()
            }
        })
        .collect();
    Ok(Model { objects, v_axis: model.v_axis })
}

fn vertex_frame(vertex: Vec3, flat: &Flat, triangles: &[[u32; 3]], faces: &[Face]) -> (Vec3, Vec4) {
    let (mut n, mut t, mut b) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    let (mut t_any, mut b_any) = (Vec3::ZERO, Vec3::ZERO);
    let mut fallback = Vec3::ZERO;
    for (tri, face) in triangles.iter().zip(faces) {
        // `==` on floats: -0.0 == 0.0, as the weld's exact mode.
        if !tri.iter().any(|&v| flat.positions[v as usize] == vertex) || face.is(DEGENERATE) {
            continue;
        }
        n += face.normal;
        if fallback == Vec3::ZERO {
            fallback = face.normal;
        }
        if face.is(DEGENERATE_UV) {
            t_any += face.tangent;
            b_any += face.bitangent;
        } else {
            t += face.tangent;
            b += face.bitangent;
        }
    }
    if t == Vec3::ZERO && b == Vec3::ZERO {
        (t, b) = (t_any, b_any);
    }
    finish(n, fallback, t, b)
}

/// Computes every face of the model, in parallel.
fn faces(model: &Model, flat: &Flat) -> Vec<Face> {
    (0..flat.triangle_start.last().map_or(0, |&n| n as usize))
        .into_par_iter()
        .map(|t| {
            let o = flat.object_of_triangle(t);
            let c = flat.corners(model, o, t - flat.triangle_start[o] as usize);
            crate::face::face(c.positions, c.uvs, model.v_axis)
        })
        .collect()
}
