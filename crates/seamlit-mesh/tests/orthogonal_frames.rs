//! Every output tangent is orthogonal to its normal (|N.T| < 1e-5), whatever the UVs:
//! degenerate, repeated, mirrored or folded back, in every mode and with both tangent
//! methods, with and without a non-uniform transform.

mod common;

use glam::{Mat4, Quat, Vec2, Vec3, Vec4Swizzles};
use proptest::prelude::*;
use seamlit_mesh::{FixOptions, Mode, Model, Object, TangentMethod, fix};

/// UVs drawn from a few values, so that triangles repeat them (zero UV area), line them up,
/// mirror and fold them back.
const UV_CHOICES: [Vec2; 6] =
    [Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE, Vec2::new(0.5, 0.5), Vec2::new(2.0, 2.0)];

/// A grid of `rows` x `cols` quads whose vertices are at height 0 or `relief` (so that
/// ridges and valleys are symmetric, and faces' tangents can cancel exactly across them),
/// with UVs from [`UV_CHOICES`], turned by `turn` radians about a skew axis (so that no
/// coordinate is exact and cancelling sums leave rounding noise); heights and UVs from `seed`.
fn sheet(rows: u32, cols: u32, relief: f32, turn: f32, seed: u64) -> Object {
    let rotation = Quat::from_axis_angle(Vec3::new(3.0, -1.0, 2.0).normalize(), turn);
    let mut state = seed | 1;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    for r in 0..=rows {
        for c in 0..=cols {
            let height = (next() % 2) as f32 * relief;
            positions.push(rotation * Vec3::new(c as f32, r as f32, height));
            uvs.push(UV_CHOICES[usize::try_from(next() % UV_CHOICES.len() as u64).unwrap()]);
        }
    }
    Object::new("sheet", positions, common::grid_triangles(rows, cols)).with_uvs(uvs)
}

/// The largest |N.T| of a fixed model, over every vertex of every object.
fn worst_dot(model: &Model) -> f32 {
    let mut worst = 0.0f32;
    for object in &model.objects {
        let (Some(normals), Some(tangents)) = (&object.normals, &object.tangents) else {
            continue;
        };
        for (n, t) in normals.iter().zip(tangents) {
            assert!(n.is_finite() && t.is_finite(), "{n} {t}");
            assert!((n.length() - 1.0).abs() < 1e-5 && (t.xyz().length() - 1.0).abs() < 1e-5);
            worst = worst.max(n.dot(t.xyz()).abs());
        }
    }
    worst
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn tangents_are_orthogonal_to_normals_whatever_the_uvs(
        rows in 1u32..7,
        cols in 1u32..7,
        relief in prop::sample::select(vec![0.0f32, 0.2, 1.0, 4.0]),
        turn in 0.0f32..3.0,
        seed in any::<u64>(),
        objects in 1usize..4,
        cut in prop::collection::vec(0usize..8, 1..12),
        mode in prop::sample::select(vec![Mode::Flat, Mode::Object, Mode::Model]),
        tangents in prop::sample::select(vec![TangentMethod::Seamlit, TangentMethod::Mikktspace]),
        crease in prop::sample::select(vec![30.0f32, 60.0, 180.0]),
        tangent_angle in prop::sample::select(vec![45.0f32, 180.0]),
        split_mirrored in any::<bool>(),
        stretched in any::<bool>(),
    ) {
        let whole = sheet(rows, cols, relief, turn, seed);
        let assignment: Vec<usize> = cut.iter().map(|c| c % objects).collect();
        let (mut model, _) = common::split(&whole, &assignment, || Vec3::ZERO);
        if stretched {
            let m = Mat4::from_scale_rotation_translation(
                Vec3::new(1.0, 7.0, 0.1),
                Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.9),
                Vec3::new(3.0, -1.0, 2.0),
            );
            for object in &mut model.objects {
                object.transform = Some(m);
            }
        }
        let options = FixOptions {
            mode,
            tangents,
            crease_angle_deg: crease,
            tangent_angle_deg: tangent_angle,
            split_mirrored,
            ..FixOptions::default()
        };
        let fixed = fix(&model, &options).unwrap();
        let worst = worst_dot(&fixed);
        prop_assert!(worst < 1e-5, "max |N.T| = {worst}");
    }
}
