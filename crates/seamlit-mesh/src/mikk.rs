//! MikkTSpace tangents through `bevy_mikktspace`, for normal maps baked with MikkTSpace.
//!
//! MikkTSpace runs once over the whole model in model space, with the normals seamlit
//! computed, so that vertices shared across objects (equal position, normal and UV) get equal
//! tangents: the seam fix carries over. For glTF (V down) the V coordinate is flipped before
//! MikkTSpace sees it, so that its bitangent points up the image as in the OBJ convention.

use glam::{Vec2, Vec3, Vec4};

use crate::VAxis;

struct Geometry<'a> {
    positions: &'a [Vec3],
    uvs: &'a [Vec2],
    triangles: &'a [[u32; 3]],
    corner_normals: &'a [Vec3],
    v_sign: f32,
    tangents: Vec<Vec4>,
}

impl bevy_mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.triangles.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.triangles[face][vert] as usize].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.corner_normals[face * 3 + vert].to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv: Vec2 = self.uvs[self.triangles[face][vert] as usize];
        [uv.x, uv.y * self.v_sign]
    }

    fn set_tangent(
        &mut self,
        tangent_space: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        if let Some(ts) = tangent_space {
            let t = Vec4::from_array(ts.tangent_encoded());
            if t.is_finite() {
                self.tangents[face * 3 + vert] = t;
            }
        }
    }
}

/// Per-corner MikkTSpace tangents in model space. Corners MikkTSpace leaves unset (degenerate
/// faces) get a vector orthogonal to their normal, w = +1.
pub(crate) fn tangents(
    positions: &[Vec3],
    uvs: &[Vec2],
    triangles: &[[u32; 3]],
    corner_normals: &[Vec3],
    v_axis: VAxis,
) -> Vec<Vec4> {
    let fallback: Vec<Vec4> =
        corner_normals.iter().map(|n| n.any_orthonormal_vector().extend(1.0)).collect();
    let mut geometry = Geometry {
        positions,
        uvs,
        triangles,
        corner_normals,
        v_sign: match v_axis {
            VAxis::Up => 1.0,
            VAxis::Down => -1.0,
        },
        tangents: fallback,
    };
    // The error type has no variants: generation cannot fail.
    if bevy_mikktspace::generate_tangents(&mut geometry).is_err() {
        unreachable!("bevy_mikktspace's error type is uninhabited");
    }
    let mut out = geometry.tangents;
    for (t, n) in out.iter_mut().zip(corner_normals) {
        // MikkTSpace's tangent is orthogonal to the normal it was given, up to rounding.
        let xyz = Vec3::new(t.x, t.y, t.z);
        let xyz = crate::frame::orthogonal_tangent(*n, xyz);
        *t = xyz.extend(if t.w < 0.0 { -1.0 } else { 1.0 });
    }
    out
}
