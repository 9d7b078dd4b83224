//! Smoothing groups (`Object::smoothing_groups`, OBJ `s N`): faces share a normal only where
//! they are in the same nonzero group, and within the crease angle.

mod common;

use glam::{Vec2, Vec3};
use seamlit_mesh::{FixOptions, MeshError, Model, Object, TangentMethod, fix};

/// The six sides of the cube [-1, 1]^3 as six objects, in this order: +X, -X, +Y, -Y, +Z,
/// -Z; side `i` has its two triangles in smoothing group `groups[i]`. With UVs, the tangents
/// (90 degrees apart at every corner) send every corner through the grouping; without, the
/// cube's corners take the one-pass shortcut unless the groups forbid it: the tests try both.
fn cube(groups: [u32; 6], uvs: bool) -> Model {
    let objects = common::CUBE_SIDES
        .iter()
        .zip(groups)
        .enumerate()
        .map(|(i, (&(n, u, v), group))| {
            let c = |a: f32, b: f32| n + u * a + v * b;
            let side = Object::new(
                format!("side{i}"),
                vec![c(-1.0, -1.0), c(1.0, -1.0), c(1.0, 1.0), c(-1.0, 1.0)],
                vec![[0, 1, 2], [0, 2, 3]],
            )
            .with_smoothing_groups(vec![group; 2]);
            match uvs {
                true => side.with_uvs(vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]),
                false => side,
            }
        })
        .collect();
    Model::new(objects)
}

const SMOOTH: FixOptions = FixOptions { crease_angle_deg: 180.0, ..FixOptions::DEFAULT };

/// The outward normal of side `i` of [`cube`].
const SIDE_NORMALS: [Vec3; 6] = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];

/// Every corner of every triangle of `fixed`'s side `i`, as (position, normal).
fn corners(fixed: &Model, i: usize) -> Vec<(Vec3, Vec3)> {
    let o = &fixed.objects[i];
    let normals = o.normals.as_deref().expect("normals");
    o.triangles
        .as_flattened()
        .iter()
        .map(|&v| (o.positions[v as usize], normals[v as usize]))
        .collect()
}

#[test]
fn one_group_at_180_degrees_is_one_smooth_blob() {
    for uvs in [true, false] {
        let fixed = fix(&cube([1; 6], uvs), &SMOOTH).unwrap();
        for i in 0..6 {
            for (p, n) in corners(&fixed, i) {
                // Three sides meet at each corner with equal (90 degree) corner angles: the
                // diagonal, the same in every object.
                assert!(n.abs_diff_eq(p / 3f32.sqrt(), 1e-6), "uvs {uvs}, side {i} at {p}: {n}");
            }
            assert_eq!(fixed.objects[i].positions.len(), 4, "side {i}: no vertex split");
        }
    }
}

#[test]
fn within_one_group_the_crease_angle_still_applies() {
    // The default crease angle (60 degrees) keeps the cube's 90-degree edges hard.
    for uvs in [true, false] {
        let fixed = fix(&cube([1; 6], uvs), &FixOptions::default()).unwrap();
        for (i, side) in SIDE_NORMALS.iter().enumerate() {
            for (p, n) in corners(&fixed, i) {
                assert!(n.abs_diff_eq(*side, 1e-6), "uvs {uvs}, side {i} at {p}: {n}");
            }
        }
    }
}

#[test]
fn different_groups_or_off_keep_every_edge_hard_even_at_180_degrees() {
    // In the last, the two sides in group 7 are opposite: they share no edge.
    for groups in [[1, 2, 3, 4, 5, 6], [0; 6], [7, 7, 0, 0, 0, 0]] {
        for uvs in [true, false] {
            let fixed = fix(&cube(groups, uvs), &SMOOTH).unwrap();
            for (i, side) in SIDE_NORMALS.iter().enumerate() {
                for (p, n) in corners(&fixed, i) {
                    let at = format!("groups {groups:?}, uvs {uvs}, side {i} at {p}");
                    assert!(n.abs_diff_eq(*side, 1e-6), "{at}: {n}");
                }
            }
        }
    }
}

#[test]
fn two_sides_in_one_group_smooth_across_their_edge_and_a_third_stays_hard() {
    // +X and +Z in group 1, +Y in group 2, the others each in a group of their own.
    let edge = Vec3::new(1.0, 0.0, 1.0).normalize();
    for uvs in [true, false] {
        let fixed = fix(&cube([1, 3, 2, 4, 1, 5], uvs), &SMOOTH).unwrap();
        for (i, side) in SIDE_NORMALS.iter().enumerate() {
            for (p, n) in corners(&fixed, i) {
                // +X and +Z share the bisector on their edge x = z = 1; every other corner
                // has its side's normal.
                let on_edge = (i == 0 || i == 4) && p.x == 1.0 && p.z == 1.0;
                let expected = if on_edge { edge } else { *side };
                assert!(n.abs_diff_eq(expected, 1e-6), "uvs {uvs}, side {i} at {p}: {n}");
            }
        }
    }
}

#[test]
fn objects_without_groups_share_one_group_of_their_own() {
    // +X and +Z without groups, the other four sides in group 1.
    let ungrouped = |i: usize| i == 0 || i == 4;
    for uvs in [true, false] {
        let mut m = cube([1; 6], uvs);
        m.objects[0].smoothing_groups = None;
        m.objects[4].smoothing_groups = None;
        let fixed = fix(&m, &SMOOTH).unwrap();
        for i in 0..6 {
            for (p, n) in corners(&fixed, i) {
                // The sides that meet at p (p . normal = 1) on the same side of the divide,
                // each with a 90-degree corner there: their normals' mean.
                let expected = (0..6)
                    .filter(|&j| ungrouped(j) == ungrouped(i) && p.dot(SIDE_NORMALS[j]) == 1.0)
                    .map(|j| SIDE_NORMALS[j])
                    .sum::<Vec3>()
                    .normalize();
                let at = format!("uvs {uvs}, side {i} at {p}");
                assert!(n.abs_diff_eq(expected, 1e-6), "{at}: {n}, not {expected}");
            }
        }
    }
}

#[test]
fn a_face_in_group_zero_is_flat_inside_a_smooth_object() {
    // A fan of four triangles around (0, 0, 0.5), a low pyramid: smooth, the apex normal is
    // +Z; with one triangle off, that triangle keeps its face normal and the others still
    // share theirs.
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.5),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(0.0, -1.0, 0.0),
    ];
    let triangles = vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]];
    let pyramid = |groups: Vec<u32>| {
        Model::new(vec![
            Object::new("pyramid", positions.clone(), triangles.clone())
                .with_smoothing_groups(groups),
        ])
    };
    let apex_normals = |m: &Model| -> Vec<Vec3> {
        let o = &fix(m, &SMOOTH).unwrap().objects[0];
        o.triangles.iter().map(|t| o.normals.as_ref().unwrap()[t[0] as usize]).collect()
    };
    let smooth = apex_normals(&pyramid(vec![1; 4]));
    assert!(smooth.iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)), "{smooth:?}");
    let one_off = apex_normals(&pyramid(vec![0, 1, 1, 1]));
    // The first face, through (0, 0, 0.5), (1, 0, 0), (0, 1, 0): normal (0.5, 0.5, 1) / |..|.
    assert!(one_off[0].abs_diff_eq(Vec3::new(0.5, 0.5, 1.0).normalize(), 1e-6), "{one_off:?}");
    assert_eq!(one_off[1], one_off[2]);
    assert_eq!(one_off[2], one_off[3]);
    assert!(!one_off[1].abs_diff_eq(one_off[0], 1e-3), "{one_off:?}");
}

#[test]
fn objects_without_groups_give_todays_bits() {
    // No groups at all and every triangle in one group give the same frames (`fix` keeps
    // the groups it was given).
    let (m, _) = common::split(&common::torus(12, 16), &[0, 1, 2, 1, 0, 2, 2], || Vec3::ZERO);
    let mut grouped = m.clone();
    for o in &mut grouped.objects {
        o.smoothing_groups = Some(vec![9; o.triangles.len()]);
    }
    for opts in [FixOptions::default(), SMOOTH] {
        let mut a = fix(&m, &opts).unwrap();
        let b = fix(&grouped, &opts).unwrap();
        for o in &mut a.objects {
            o.smoothing_groups = Some(vec![9; o.triangles.len()]);
        }
        assert_eq!(a, b, "{opts:?}");
    }
}

#[test]
fn one_thread_and_many_give_the_same_bits_with_groups() {
    // Big enough for many parallel chunks of complex positions (over 4096 corners).
    let (mut m, _) = common::split(&common::torus(120, 160), &[0, 1, 2, 3, 1, 2], || Vec3::ZERO);
    for (i, o) in m.objects.iter_mut().enumerate() {
        // Bands of groups 0 to 3, different in each object.
        let groups =
            (0..o.triangles.len()).map(|t| u32::try_from((t / 97 + i) % 4).unwrap()).collect();
        o.smoothing_groups = Some(groups);
    }
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let four = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap();
    for opts in [
        FixOptions::default(),
        SMOOTH,
        FixOptions { tangents: TangentMethod::Mikktspace, ..FixOptions::default() },
    ] {
        let a = one.install(|| fix(&m, &opts)).unwrap();
        let b = four.install(|| fix(&m, &opts)).unwrap();
        assert_eq!(a, b, "{opts:?}");
        // The groups split vertices: there is something to be deterministic about.
        assert!(a.vertex_count() > m.vertex_count(), "{opts:?}");
    }
}

#[test]
fn groups_of_the_wrong_length_are_an_error_naming_the_object() {
    let mut m = cube([1; 6], true);
    m.objects[3].smoothing_groups = Some(vec![1; 3]);
    match fix(&m, &FixOptions::default()) {
        Err(MeshError::SmoothingGroupsLength { object: 3, ref name, expected: 2, actual: 3 }) => {
            assert_eq!(name, "side3");
        }
        other => panic!("{other:?}"),
    }
}
