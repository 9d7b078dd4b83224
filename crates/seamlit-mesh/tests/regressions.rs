//! Inputs the `fix` fuzz target (fuzz/fuzz_targets/fix.rs) found: `fix` and `report` must
//! return (an error is fine), never panic. The fuzzer's raw input is kept under
//! tests/regressions/ (decode it with the target's `build`); each test here is the model it
//! decodes to, reduced by hand.

use glam::Vec3;
use seamlit_mesh::{FixOptions, Model, Object, ReportOptions, VAxis};

fn fix_and_report_return(model: &Model, options: &FixOptions) {
    use seamlit_mesh::NormalPolicy;
    for normals in [NormalPolicy::Recompute, NormalPolicy::Auto, NormalPolicy::Keep] {
        let options = &options.with_normals(normals);
        let fixed = std::panic::catch_unwind(|| seamlit_mesh::fix(model, options));
        assert!(fixed.is_ok(), "fix panicked on {model:?} with {options:?}");
    }
    let report =
        std::panic::catch_unwind(|| seamlit_mesh::report(model, &ReportOptions::from(options)));
    assert!(report.is_ok(), "report panicked on {model:?} with {options:?}");
}

/// fix-crash-7d43bd6448702756c6df8b9b8058ff42f16e25c3: a position that no triangle uses (the
/// third vertex), after one that does. `group::group` panicked: "index out of bounds: the len
/// is 3 but the index is 3" (group.rs, `incidence.corners[slot]`): `single_group` returned
/// early for a position without corners and left the previous position's groups in
/// `scratch.local_group`, which were appended again.
#[test]
fn a_position_no_triangle_uses_after_one_that_is_used() {
    let model = Model {
        objects: vec![Object::new(
            "o0",
            vec![Vec3::ZERO, Vec3::splat(1e-9), Vec3::X * 100.0],
            vec![[1, 0, 0]],
        )],
        v_axis: VAxis::Down,
    };
    fix_and_report_return(&model, &FixOptions::DEFAULT);
}

/// The same input as the fuzzer decoded it (before reduction).
#[test]
fn fuzz_input_7d43bd64_as_decoded() {
    let mut positions = vec![Vec3::splat(0.5); 10];
    positions[0] = Vec3::splat(6.646_346_4e-33);
    positions[1] = Vec3::new(-26_612_756.0, 0.5, 0.5);
    let mut triangles = vec![[3u32, 3, 3]; 7];
    triangles.push([3, 0, 0]);
    let model =
        Model { objects: vec![Object::new("o0", positions, triangles)], v_axis: VAxis::Down };
    let options = FixOptions {
        weld_tolerance: seamlit_mesh::WeldTolerance::Absolute(-0.0),
        weighting: seamlit_mesh::Weighting::AngleArea,
        crease_angle_deg: f32::NAN,
        tangents: seamlit_mesh::TangentMethod::Mikktspace,
        tangent_angle_deg: -1.0,
        split_mirrored: true,
        mode: seamlit_mesh::Mode::Model,
        normals: seamlit_mesh::NormalPolicy::Recompute,
    };
    fix_and_report_return(&model, &options);
}
