//! Input checks, and the model flattened into one model-space vertex and triangle list.
//!
//! Everything downstream (weld, faces, grouping, report, reference) works on [`Flat`]: the
//! positions of all objects after their transforms, concatenated, with triangles re-indexed
//! into the concatenation. Validation happens once, here, so that the algorithms can index
//! without checks and never see a NaN.

use glam::{Mat3, Mat4, Vec2, Vec3};
use rayon::prelude::*;

use crate::{MAX_ELEMENTS, MeshError, Model, Object};

/// The model in model space, concatenated.
pub(crate) struct Flat {
    /// Positions after each object's transform.
    pub positions: Vec<Vec3>,
    /// UVs (zero for objects without UVs; see `has_uvs`).
    pub uvs: Vec<Vec2>,
    /// Triangles indexing `positions`.
    pub triangles: Vec<[u32; 3]>,
    /// Per object: first vertex; one extra entry at the end.
    pub vertex_start: Vec<u32>,
    /// Per object: first triangle; one extra entry at the end.
    pub triangle_start: Vec<u32>,
    /// Per object: whether it has UVs.
    pub has_uvs: Vec<bool>,
    /// Per object: linear part of the transform (`None` for the identity).
    pub linear: Vec<Option<Mat3>>,
}

impl Flat {
    /// Per triangle, the object it belongs to.
    pub fn triangle_objects(&self) -> Vec<u32> {
        let mut out = Vec::with_capacity(self.triangles.len());
        for o in 0..self.has_uvs.len() {
            let n = (self.triangle_start[o + 1] - self.triangle_start[o]) as usize;
            out.extend(std::iter::repeat_n(o as u32, n));
        }
        out
    }

    /// Per vertex, the object it belongs to.
    pub fn vertex_objects(&self) -> Vec<u32> {
        let mut out = Vec::with_capacity(self.positions.len());
        for o in 0..self.has_uvs.len() {
            let n = (self.vertex_start[o + 1] - self.vertex_start[o]) as usize;
            out.extend(std::iter::repeat_n(o as u32, n));
        }
        out
    }
}

fn check_lengths(index: usize, object: &Object) -> Result<(), MeshError> {
    let expected = object.positions.len();
    let lens = [
        ("uvs", object.uvs.as_ref().map(Vec::len)),
        ("normals", object.normals.as_ref().map(Vec::len)),
        ("tangents", object.tangents.as_ref().map(Vec::len)),
    ];
    for (attribute, len) in lens {
        if let Some(actual) = len.filter(|&l| l != expected) {
            return Err(MeshError::AttributeLength {
                object: index,
                name: object.name.clone(),
                attribute,
                expected,
                actual,
            });
        }
    }
    Ok(())
}

/// Checks one object: attribute lengths, indices, transform, finite positions and UVs.
pub(crate) fn check_object(index: usize, object: &Object) -> Result<Option<Mat4>, MeshError> {
    check_lengths(index, object)?;
    let vertex_count = object.positions.len();
    if let Some((triangle, &i)) = object
        .triangles
        .iter()
        .enumerate()
        .find_map(|(t, tri)| tri.iter().find(|&&i| i as usize >= vertex_count).map(|i| (t, i)))
    {
        return Err(MeshError::IndexOutOfRange {
            object: index,
            name: object.name.clone(),
            triangle,
            index: i,
            vertex_count,
        });
    }
    let transform = match object.transform {
        Some(m) if m == Mat4::IDENTITY => None,
        Some(m) => {
            let det = Mat3::from_mat4(m).determinant();
            if !m.is_finite() || det == 0.0 || !det.is_finite() {
                return Err(MeshError::BadTransform { object: index, name: object.name.clone() });
            }
            Some(m)
        }
        None => None,
    };
    if let Some(uvs) = &object.uvs
        && let Some((vertex, uv)) = uvs.iter().enumerate().find(|(_, uv)| !uv.is_finite())
    {
        return Err(MeshError::NonFiniteUv {
            object: index,
            name: object.name.clone(),
            vertex,
            value: uv.to_array(),
        });
    }
    Ok(transform)
}

/// Validates the model and flattens it into model space.
///
/// # Errors
/// Any [`MeshError`] about a bad object: attribute lengths, indices, transforms, non-finite
/// positions (after the transform) or UVs, or a model too large for 32-bit indices.
pub(crate) fn flatten(model: &Model) -> Result<Flat, MeshError> {
    let vertices = model.vertex_count();
    let corners = model.triangle_count().saturating_mul(3);
    if vertices > MAX_ELEMENTS {
        return Err(MeshError::TooLarge { what: "vertices", count: vertices, max: MAX_ELEMENTS });
    }
    if corners > MAX_ELEMENTS {
        return Err(MeshError::TooLarge {
            what: "triangle corners",
            count: corners,
            max: MAX_ELEMENTS,
        });
    }
    let transforms = model
        .objects
        .par_iter()
        .enumerate()
        .map(|(i, o)| check_object(i, o))
        .collect::<Result<Vec<_>, _>>()?;

    let mut vertex_start = Vec::with_capacity(model.objects.len() + 1);
    let mut triangle_start = Vec::with_capacity(model.objects.len() + 1);
    let (mut v, mut t) = (0u32, 0u32);
    for o in &model.objects {
        vertex_start.push(v);
        triangle_start.push(t);
        v += o.positions.len() as u32;
        t += o.triangles.len() as u32;
    }
    vertex_start.push(v);
    triangle_start.push(t);

    let mut positions = vec![Vec3::ZERO; vertices];
    let mut uvs = vec![Vec2::ZERO; vertices];
    let mut triangles = vec![[0u32; 3]; corners / 3];
    // Split the output arrays at object boundaries so objects fill them in parallel.
    let mut pos_parts = Vec::with_capacity(model.objects.len());
    let mut uv_parts = Vec::with_capacity(model.objects.len());
    let mut tri_parts = Vec::with_capacity(model.objects.len());
    {
        let (mut p, mut u, mut tr) = (&mut positions[..], &mut uvs[..], &mut triangles[..]);
        for o in &model.objects {
            let (a, rest) = p.split_at_mut(o.positions.len());
            pos_parts.push(a);
            p = rest;
            let (a, rest) = u.split_at_mut(o.positions.len());
            uv_parts.push(a);
            u = rest;
            let (a, rest) = tr.split_at_mut(o.triangles.len());
            tri_parts.push(a);
            tr = rest;
        }
    }
    pos_parts.into_par_iter().zip(uv_parts).zip(tri_parts).enumerate().try_for_each(
        |(i, ((pos, uv), tri))| {
            let object = &model.objects[i];
            match transforms[i] {
                Some(m) => {
                    for (dst, &src) in pos.iter_mut().zip(&object.positions) {
                        *dst = m.transform_point3(src);
                    }
                }
                None => pos.copy_from_slice(&object.positions),
            }
            if let Some((vertex, p)) = pos.iter().enumerate().find(|(_, p)| !p.is_finite()) {
                return Err(MeshError::NonFinitePosition {
                    object: i,
                    name: object.name.clone(),
                    vertex,
                    value: p.to_array(),
                });
            }
            if let Some(src) = &object.uvs {
                uv.copy_from_slice(src);
            }
            let base = vertex_start[i];
            for (dst, src) in tri.iter_mut().zip(&object.triangles) {
                *dst = src.map(|k| k + base);
            }
            Ok(())
        },
    )?;

    Ok(Flat {
        positions,
        uvs,
        triangles,
        vertex_start,
        triangle_start,
        has_uvs: model.objects.iter().map(|o| o.uvs.is_some()).collect(),
        linear: transforms.iter().map(|m| m.map(Mat3::from_mat4)).collect(),
    })
}
