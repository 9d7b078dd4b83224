//! seamlit's MikkTSpace (`TangentMethod::Mikktspace`) against an independent MikkTSpace,
//! `bevy_mikktspace` (a line-by-line port of mikktspace.c), run on the fixed model's own
//! positions, normals and UVs: the same handedness and, within a degree, the same direction on
//! at least 99.9% of the corners. The models have what MikkTSpace must get right: mirrored UV
//! islands, UV seams, creases (vertices split by normal), poles (degenerate triangles).

mod common;

use glam::{Vec2, Vec3, Vec4, Vec4Swizzles};
use seamlit_mesh::{FixOptions, Model, NormalPolicy, Object, TangentMethod, VAxis, fix};

/// One object as bevy_mikktspace sees it: with the positions welded as seamlit welds them
/// (points within 1e-6 of the bounding box's diagonal are one), so that both see the same
/// degenerate triangles at poles whose points differ in the last bits.
struct Reference<'a> {
    object: &'a Object,
    positions: Vec<Vec3>,
    v_sign: f32,
    tangents: Vec<Vec4>,
}

impl bevy_mikktspace::Geometry for Reference<'_> {
    fn num_faces(&self) -> usize {
        self.object.triangles.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.object.triangles[face][vert] as usize].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        let normals = self.object.normals.as_ref().expect("fixed objects have normals");
        normals[self.object.triangles[face][vert] as usize].to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uvs = self.object.uvs.as_ref().expect("the test objects have UVs");
        let uv = uvs[self.object.triangles[face][vert] as usize];
        [uv.x, uv.y * self.v_sign]
    }

    fn set_tangent(
        &mut self,
        tangent_space: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        if let Some(ts) = tangent_space {
            self.tangents[face * 3 + vert] = Vec4::from_array(ts.tangent_encoded());
        }
    }
}

/// bevy_mikktspace's tangent of every corner of `object` (zero where it gives none).
fn reference(object: &Object, v_axis: VAxis) -> Vec<Vec4> {
    let v_sign = match v_axis {
        VAxis::Up => 1.0,
        VAxis::Down => -1.0,
    };
    let positions = welded(&object.positions);
    let tangents = vec![Vec4::ZERO; object.triangles.len() * 3];
    let mut geometry = Reference { object, positions, v_sign, tangents };
    bevy_mikktspace::generate_tangents(&mut geometry).expect("generation cannot fail");
    geometry.tangents
}

/// Every point moved onto the first (lowest-index) point within 1e-6 of the bounding box's
/// diagonal of it: a sweep along x.
fn welded(points: &[Vec3]) -> Vec<Vec3> {
    let (lo, hi) = points.iter().fold((Vec3::MAX, Vec3::MIN), |(l, h), p| (l.min(*p), h.max(*p)));
    let tolerance = 1e-6 * lo.distance(hi);
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| points[a].x.total_cmp(&points[b].x));
    let mut first: Vec<usize> = (0..points.len()).collect();
    for (i, &a) in order.iter().enumerate() {
        for &b in order[i + 1..].iter().take_while(|&&b| points[b].x - points[a].x <= tolerance) {
            if points[a].distance(points[b]) <= tolerance {
                let m = first[a].min(first[b]);
                (first[a], first[b]) = (m, m);
            }
        }
    }
    first.iter().map(|&f| points[first[f]]).collect()
}

/// How the fixed model's tangents compare with the reference, corner by corner.
#[derive(Debug)]
struct Agreement {
    corners: usize,
    same_w: usize,
    within_a_degree: usize,
    worst_degrees: f32,
}

fn agreement(fixed: &Model) -> Agreement {
    let mut a = Agreement { corners: 0, same_w: 0, within_a_degree: 0, worst_degrees: 0.0 };
    for object in &fixed.objects {
        let expected = reference(object, fixed.v_axis);
        let tangents = object.tangents.as_ref().expect("objects with UVs get tangents");
        for (c, e) in expected.iter().enumerate() {
            let got = tangents[object.triangles[c / 3][c % 3] as usize];
            if e.xyz() == Vec3::ZERO {
                // No tangent space from the reference (degenerate): nothing to compare.
                continue;
            }
            a.corners += 1;
            a.same_w += usize::from(got.w == e.w);
            let degrees = got.xyz().angle_between(e.xyz()).to_degrees();
            a.within_a_degree += usize::from(degrees <= 1.0);
            a.worst_degrees = a.worst_degrees.max(degrees);
        }
    }
    a
}

fn assert_agrees(name: &str, model: &Model) {
    let options = FixOptions {
        tangents: TangentMethod::Mikktspace,
        normals: NormalPolicy::Recompute,
        ..FixOptions::default()
    };
    let fixed = fix(model, &options).unwrap();
    let a = agreement(&fixed);
    println!("{name}: {a:?}");
    assert!(a.corners >= 36, "{name}: {a:?}");
    let share = |n: usize| n as f64 / a.corners as f64;
    assert!(share(a.same_w) >= 0.999, "{name}: handedness differs: {a:?}");
    assert!(share(a.within_a_degree) >= 0.999, "{name}: direction differs: {a:?}");
}

/// A UV sphere whose half at x < 0 has its U mirrored (u -> 1 - u), as a symmetric
/// character's two halves share one half of the texture: a mirror seam at x = 0.
fn mirrored_sphere() -> Object {
    let mut sphere = common::uv_sphere(24, 48);
    let positions = sphere.positions.clone();
    let uvs = sphere.uvs.as_mut().unwrap();
    for (uv, p) in uvs.iter_mut().zip(&positions) {
        if p.x < 0.0 {
            uv.x = 1.0 - uv.x;
        }
    }
    sphere
}

/// A box of six faces, each its own UV island turned a quarter more than the last, every
/// other one mirrored: creases (60 degrees) split every corner by normal.
fn island_box() -> Object {
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    let mut triangles = Vec::new();
    let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
    for (f, n) in axes.iter().enumerate() {
        let u = n.any_orthonormal_vector();
        let v = n.cross(u);
        let base = u32::try_from(positions.len()).unwrap();
        let turn = glam::Mat2::from_angle(f as f32 * std::f32::consts::FRAC_PI_2);
        let mirror = if f % 2 == 1 { -1.0 } else { 1.0 };
        for (i, j) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            positions.push(*n + u * (2.0 * i - 1.0) + v * (2.0 * j - 1.0));
            uvs.push(turn * Vec2::new(mirror * i, j));
        }
        triangles.push([base, base + 1, base + 2]);
        triangles.push([base, base + 2, base + 3]);
    }
    Object::new("box", positions, triangles).with_uvs(uvs)
}

#[test]
fn a_mirrored_sphere_agrees_with_mikktspace() {
    assert_agrees("mirrored sphere", &Model::new(vec![mirrored_sphere()]));
}

#[test]
fn a_torus_with_uv_seams_agrees_with_mikktspace() {
    assert_agrees("torus", &Model::new(vec![common::torus(32, 64)]));
}

#[test]
fn a_box_of_turned_and_mirrored_islands_agrees_with_mikktspace() {
    assert_agrees("box", &Model::new(vec![island_box()]));
}

#[test]
fn v_down_as_in_gltf_agrees_with_mikktspace() {
    let mut model = Model::new(vec![mirrored_sphere()]);
    model.v_axis = VAxis::Down;
    assert_agrees("mirrored sphere, V down", &model);
}

#[test]
fn a_torus_whose_triangles_share_no_vertex_agrees_with_mikktspace() {
    // Every corner its own vertex, as some exporters write a mesh: MikkTSpace's vertices are
    // the same (equal position, normal and UV), and so are its tangents.
    let torus = common::torus(32, 64);
    let uvs = torus.uvs.as_ref().unwrap();
    let corners = torus.triangles.as_flattened();
    let positions = corners.iter().map(|&v| torus.positions[v as usize]).collect();
    let triangles =
        (0..u32::try_from(corners.len()).unwrap()).step_by(3).map(|c| [c, c + 1, c + 2]).collect();
    let unshared = Object::new("torus", positions, triangles)
        .with_uvs(corners.iter().map(|&v| uvs[v as usize]).collect());
    assert_agrees("torus, no vertex shared", &Model::new(vec![unshared]));
}

#[test]
fn the_teapot_as_one_object_agrees_with_mikktspace() {
    // The 32 patches merged into one object: poles (degenerate triangles), creases at the
    // spout and handle, and the patches' UV seams.
    let teapot = common::teapot(8);
    let mut one = Object::new("teapot", Vec::new(), Vec::new()).with_uvs(Vec::new());
    for object in &teapot.objects {
        let base = u32::try_from(one.positions.len()).unwrap();
        one.positions.extend(&object.positions);
        one.uvs.as_mut().unwrap().extend(object.uvs.as_ref().unwrap());
        one.triangles.extend(object.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    let mut model = Model::new(vec![one]);
    model.v_axis = teapot.v_axis;
    assert_agrees("teapot", &model);
}

#[test]
fn seamlit_s_own_generator_is_not_mikktspace() {
    // The check above can fail: seamlit's own tangents (smoothed with a tangent angle, split
    // differently) disagree with MikkTSpace on the mirrored sphere.
    let model = Model::new(vec![mirrored_sphere()]);
    let options = FixOptions { normals: NormalPolicy::Recompute, ..FixOptions::default() };
    let a = agreement(&fix(&model, &options).unwrap());
    let share = a.within_a_degree as f64 / a.corners as f64;
    assert!(share < 0.999, "{a:?}");
}
