//! What every writer checks of an object before writing a byte of it (attribute lengths,
//! indices in range, finite positions), and the unit normals and tangents that the glTF
//! validator requires of an output.

use std::path::Path;

use glam::{Vec3, Vec4};
use seamlit_mesh::Object;

use crate::error::{InvalidAsset, IoError};

/// Attribute arrays must match the vertex count and indices must be in range.
///
/// # Errors
///
/// [`IoError::InvalidAsset`] naming the object and what is wrong.
pub fn check_object(object: &Object, path: &Path) -> Result<(), IoError> {
    let n = object.positions.len();
    let invalid = |kind: InvalidAsset| IoError::InvalidAsset {
        path: path.to_path_buf(),
        object: object.name.clone(),
        kind,
    };
    let lengths = [
        ("uvs", object.uvs.as_ref().map(Vec::len)),
        ("uvs1", object.uvs1.as_ref().map(Vec::len)),
        ("normals", object.normals.as_ref().map(Vec::len)),
        ("tangents", object.tangents.as_ref().map(Vec::len)),
        ("colors", object.colors.as_ref().map(Vec::len)),
    ];
    let skin = object.skin.iter().flat_map(|set| {
        [("skin joints", Some(set.joints.len())), ("skin weights", Some(set.weights.len()))]
    });
    let morph = object.morph_targets.iter().flat_map(|target| {
        [
            ("morph position deltas", Some(target.position_deltas.len())),
            ("morph normal deltas", target.normal_deltas.as_ref().map(Vec::len)),
            ("morph tangent deltas", target.tangent_deltas.as_ref().map(Vec::len)),
        ]
    });
    for (attribute, len) in lengths.into_iter().chain(skin).chain(morph) {
        if let Some(count) = len.filter(|&len| len != n) {
            return Err(invalid(InvalidAsset::AttributeLength { attribute, count, positions: n }));
        }
    }
    if let Some(groups) = object.smoothing_groups.as_ref().map(Vec::len) {
        let triangles = object.triangles.len();
        if groups != triangles {
            return Err(invalid(InvalidAsset::SmoothingGroups { groups, triangles }));
        }
    }
    if n >= u32::MAX as usize {
        return Err(invalid(InvalidAsset::TooManyVertices { vertices: n }));
    }
    if let Some(t) = object.triangles.iter().find(|t| t.iter().any(|&i| i as usize >= n)) {
        return Err(invalid(InvalidAsset::IndexOutOfRange { triangle: *t, vertices: n }));
    }
    if !object.positions.iter().all(|p| p.is_finite()) {
        return Err(invalid(InvalidAsset::NotFinite));
    }
    Ok(())
}

/// A normal for the validator: unit length (only non-unit ones are touched).
pub fn unit_normal(n: Vec3) -> Vec3 {
    if (n.length_squared() - 1.0).abs() <= 1e-5 { n } else { n.try_normalize().unwrap_or(Vec3::Z) }
}

/// A tangent for the validator: unit xyz, w exactly +-1.
pub fn unit_tangent(t: Vec4) -> Vec4 {
    let xyz = t.truncate();
    let xyz = if (xyz.length_squared() - 1.0).abs() <= 1e-5 {
        xyz
    } else {
        xyz.try_normalize().unwrap_or(Vec3::X)
    };
    xyz.extend(if t.w < 0.0 { -1.0 } else { 1.0 })
}
