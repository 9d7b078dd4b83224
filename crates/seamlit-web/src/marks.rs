//! Marks on the model where shared positions carry different normals: the seams to see.

use glam::{Mat3, Vec3};
use seamlit_mesh::{MeshError, Model, Object, WeldTolerance, shared_copies};

/// Normals further apart than this (degrees) at one shared position are a seam: the seam
/// report's threshold for a normal break (`cross_object.normal_breaks`).
pub const BREAK_DEG: f32 = 1.0;

/// The positions (model space) that two or more objects share, welded as the seam report
/// welds them (`tolerance`), where two of the copies' normals differ by more than
/// [`BREAK_DEG`]. Copies of objects without normals are not compared.
///
/// # Errors
///
/// The model's validation errors (as `seamlit_mesh::fix`).
pub fn seam_points(model: &Model, tolerance: WeldTolerance) -> Result<Vec<Vec3>, MeshError> {
    let cos_break = BREAK_DEG.to_radians().cos();
    let world_normal = |o: u32, v: u32| -> Option<Vec3> {
        let object = &model.objects[o as usize];
        let n = *object.normals.as_ref()?.get(v as usize)?;
        let n = match object.transform {
            Some(m) => Mat3::from_mat4(m).inverse().transpose() * n,
            None => n,
        };
        n.try_normalize()
    };
    let mut points = Vec::new();
    for copies in shared_copies(model, tolerance)? {
        let normals: Vec<Vec3> = copies.iter().filter_map(|&(o, v)| world_normal(o, v)).collect();
        let broken = normals
            .iter()
            .enumerate()
            .any(|(i, a)| normals[i + 1..].iter().any(|b| a.dot(*b) < cos_break));
        if broken {
            let (o, v) = copies[0];
            let object = &model.objects[o as usize];
            let p = object.positions[v as usize];
            points.push(object.transform.map_or(p, |m| m.transform_point3(p)));
        }
    }
    Ok(points)
}

/// One object of small octahedra, `size` across, centred on `points` (with normals, so that
/// it draws without a fix): the marks drawn over the model.
#[must_use]
pub fn markers(points: &[Vec3], size: f32) -> Object {
    const DIRS: [Vec3; 6] = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];
    const FACES: [[u32; 3]; 8] =
        [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
    let r = size * 0.5;
    let mut positions = Vec::with_capacity(points.len() * 6);
    let mut normals = Vec::with_capacity(points.len() * 6);
    let mut triangles = Vec::with_capacity(points.len() * 8);
    for (i, p) in points.iter().enumerate() {
        let base = u32::try_from(i * 6).unwrap_or(u32::MAX);
        positions.extend(DIRS.iter().map(|d| *p + *d * r));
        normals.extend(DIRS);
        triangles.extend(FACES.iter().map(|f| f.map(|k| base + k)));
    }
    let mut object = Object::new("seam marks", positions, triangles);
    object.normals = Some(normals);
    object
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two quads meeting at the edge x = 1; `bend` tilts the second one's normals.
    fn two_quads(bend: Vec3) -> Model {
        let quad = |x: f32, n: Vec3| {
            let p = [0.0, 1.0].map(|dx| [0.0, 1.0].map(|z| Vec3::new(x + dx, 0.0, z)));
            let mut o = Object::new(
                format!("q{x}"),
                vec![p[0][0], p[1][0], p[1][1], p[0][1]],
                vec![[0, 2, 1], [0, 3, 2]],
            );
            o.normals = Some(vec![n; 4]);
            o
        };
        Model::new(vec![quad(0.0, Vec3::Y), quad(1.0, bend.normalize())])
    }

    #[test]
    fn the_shared_edge_is_marked_where_the_normals_differ() {
        let tolerance = WeldTolerance::default();
        let bent = seam_points(&two_quads(Vec3::new(0.2, 1.0, 0.0)), tolerance).unwrap();
        let mut xz: Vec<(f32, f32)> = bent.iter().map(|p| (p.x, p.z)).collect();
        xz.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(xz, [(1.0, 0.0), (1.0, 1.0)]);
        // Half a degree apart: under the report's threshold.
        let slight = Vec3::new(0.5f32.to_radians().tan(), 1.0, 0.0);
        assert!(seam_points(&two_quads(slight), tolerance).unwrap().is_empty());
        assert!(seam_points(&two_quads(Vec3::Y), tolerance).unwrap().is_empty());
    }

    #[test]
    fn each_mark_is_an_octahedron_around_its_point() {
        let m = markers(&[Vec3::ZERO, Vec3::ONE], 2.0);
        assert_eq!((m.positions.len(), m.triangles.len()), (12, 16));
        assert_eq!(m.positions[6], Vec3::new(2.0, 1.0, 1.0));
        assert!(m.triangles.iter().flatten().all(|&i| i < 12));
    }
}
