//! The report measured with a fix's weld and counts: the same report as measuring afresh.

use glam::{Mat4, Quat, Vec2, Vec3};

use super::*;
use crate::{FixOptions, Mode, Object, TangentMethod, fix_in_place_welded};

/// A cylinder standing on a ring (a 90-degree fold between them inside the first object: a
/// crease), with the U of its last quarter of columns mirrored, cut into three objects by
/// rows; each object has its own copy of the rows it shares, and the middle one has a
/// transform (its positions put back through the inverse, so they round differently:
/// welded by the tolerance).
fn folded_tube() -> Model {
    let (columns, rows) = (16u32, 12u32);
    let point = |i: u32, j: u32| {
        let a = i as f32 / columns as f32 * std::f32::consts::TAU;
        let (r, y) =
            if j <= 2 { (0.5 + j as f32 * 0.25, 0.0) } else { (1.0, (j - 2) as f32 * 0.3) };
        let u = if i > columns * 3 / 4 {
            1.5 - i as f32 / columns as f32
        } else {
            i as f32 / columns as f32
        };
        (Vec3::new(r * a.cos(), y, r * a.sin()), Vec2::new(u, j as f32 / rows as f32))
    };
    let transform =
        Mat4::from_rotation_translation(Quat::from_rotation_y(0.7), Vec3::new(0.3, -0.2, 0.1));
    let part = |name: &str, band: std::ops::Range<u32>, moved: bool| {
        let (mut positions, mut uvs, mut triangles) = (vec![], vec![], vec![]);
        for j in band.clone() {
            for i in 0..=columns {
                let (p, uv) = point(i % columns, j);
                positions.push(if moved { transform.inverse().transform_point3(p) } else { p });
                uvs.push(uv);
            }
        }
        let w = columns + 1;
        for j in 0..band.end - band.start - 1 {
            for i in 0..columns {
                let a = j * w + i;
                triangles.push([a, a + w, a + w + 1]);
                triangles.push([a, a + w + 1, a + 1]);
            }
        }
        let object = Object::new(name, positions, triangles).with_uvs(uvs);
        if moved { object.with_transform(transform) } else { object }
    };
    Model::new(vec![
        part("ring", 0..5, false),
        part("middle", 4..9, true),
        part("top", 8..rows, false),
    ])
}

/// The report of a fixed model with the fix's weld is the report that welds it again, in
/// every field; and the fix's weld is the one used (it fits the fixed model).
#[test]
fn the_fixs_weld_gives_the_same_report() {
    let model = folded_tube();
    for tangents in [TangentMethod::Mikktspace, TangentMethod::Seamlit, TangentMethod::None] {
        let options = FixOptions { tangents, ..FixOptions::DEFAULT };
        let mut fixed = model.clone();
        let (changes, welded) = fix_in_place_welded(&mut fixed, &options, None).expect("valid");
        // Vertices were split at the crease and at the mirror line: the renumbering is
        // exercised, as is the weld across objects and transforms.
        assert!(changes.vertices_split() > 0, "{tangents:?}: nothing split");
        let welded = welded.expect("a weld in model mode");
        let report_options = ReportOptions::from(&options);
        let again = report(&fixed, &report_options).expect("valid");
        assert!(again.shared_positions > 0 && again.near_miss_positions > 0, "{again:?}");
        let flat = validate::flatten(&fixed).expect("valid");
        assert!(welded.roots_for(flat.positions.len(), options.weld_tolerance).is_some());
        let with = report_welded(&fixed, &report_options, Some(&welded)).expect("valid");
        assert_eq!(with, again, "{tangents:?}");
    }
}

/// The folded tube and a fourth object with a degenerate triangle (three points on a line)
/// and one whose UVs collapse to a point, so that every count is above zero.
fn tube_with_bad_faces() -> Model {
    let mut model = folded_tube();
    let positions =
        vec![Vec3::new(3.0, 0.0, 0.0), Vec3::new(4.0, 0.0, 0.0), Vec3::new(5.0, 0.0, 0.0)];
    let positions = [positions, vec![Vec3::new(3.0, 1.0, 0.0)]].concat();
    let uvs = vec![Vec2::ZERO, Vec2::X, Vec2::new(2.0, 0.0), Vec2::X];
    let object = Object::new("bad", positions, vec![[0, 1, 2], [0, 1, 3], [1, 3, 0]]);
    model.objects.push(object.with_uvs(uvs));
    model
}

/// The folded tube with authored normals: every object's ("all"), and all but the first
/// object's ("partly"; the first as made, its vertices not yet split, so the others' move
/// when they are). The normals are each object's own: seams where the objects meet, for
/// the repair.
fn tubes_with_normals() -> [(&'static str, Model); 2] {
    let mut authored = folded_tube();
    let per_object = FixOptions { mode: Mode::Object, ..FixOptions::DEFAULT };
    fix_in_place_welded(&mut authored, &per_object, None).expect("valid");
    for object in &mut authored.objects {
        object.tangents = None;
        object.split_from.clear();
    }
    let mut partly = authored.clone();
    partly.objects[0] = folded_tube().objects.swap_remove(0);
    [("all", authored), ("partly", partly)]
}

/// With authored normals (every object's, or all but one's), where the fix repairs seams
/// and makes tangents instead of smoothing, its weld still gives the report that welds the
/// fixed model again.
#[test]
fn the_weld_of_a_fix_that_keeps_normals_gives_the_same_report() {
    for (name, model) in tubes_with_normals() {
        let mut fixed = model.clone();
        let options = FixOptions::DEFAULT;
        let (changes, welded) = fix_in_place_welded(&mut fixed, &options, None).expect("valid");
        assert!(changes.objects.iter().any(|o| o.kept_normals), "{name}");
        // Where one object's normals are computed, its vertices split at the mirror line
        // after the weld: the renumbering is exercised.
        assert!(name == "all" || changes.vertices_split() > 0, "{name}: nothing split");
        let welded = welded.unwrap_or_else(|| panic!("{name}: no weld"));
        let report_options = ReportOptions::from(&options);
        let again = report(&fixed, &report_options).expect("valid");
        assert!(again.shared_positions > 0 && again.mirrored_triangles > 0, "{again:?}");
        let with = report_welded(&fixed, &report_options, Some(&welded)).expect("valid");
        assert_eq!(with, again, "{name}");
    }
}

/// The weld and counts of the report as loaded, handed to the fix, give the same fixed
/// model and the same report of it, with every object's normals computed, all kept, and
/// all but the first object's kept; and the fix uses them (its weld carries the counts as
/// loaded, which it would not count with them given).
#[test]
fn the_weld_as_loaded_fixes_as_a_fresh_weld() {
    let [all, partly] = tubes_with_normals();
    for (name, model) in [("computed", tube_with_bad_faces()), all, partly] {
        let options = FixOptions::DEFAULT;
        let report_options = ReportOptions::from(&options);
        let (as_loaded, loaded) = report_with_weld(&model, &report_options).expect("valid");
        assert_eq!(as_loaded, report(&model, &report_options).expect("valid"), "{name}");
        let (mut fresh, mut given) = (model.clone(), model.clone());
        let (changes, welded) = fix_in_place_welded(&mut fresh, &options, None).expect("ok");
        let (changes_given, welded_given) =
            fix_in_place_welded(&mut given, &options, Some(&loaded)).expect("ok");
        assert_eq!(given, fresh, "{name}");
        assert_eq!(changes_given, changes, "{name}");
        let welded_given = welded_given.expect("a weld in model mode");
        let counts = [
            as_loaded.degenerate_triangles,
            as_loaded.degenerate_uv_triangles,
            as_loaded.mirrored_triangles,
        ];
        let vertices = validate::flatten(&given).expect("valid").positions.len();
        assert_eq!(welded_given.counts_for(vertices, options.weld_tolerance), Some(counts));
        let with = report_welded(&given, &report_options, Some(&welded_given));
        let again = report_welded(&fresh, &report_options, welded.as_ref());
        assert_eq!(with.expect("valid"), again.expect("valid"), "{name}");
    }
    // What is given is what is used: counts it would not make, roots it would not weld.
    let model = tube_with_bad_faces();
    let tolerance = FixOptions::DEFAULT.weld_tolerance;
    let vertices = model.vertex_count();
    let (_, loaded) = report_with_weld(&model, &ReportOptions::default()).expect("valid");
    let roots = loaded.roots_for(vertices, tolerance).expect("the model's").to_vec();
    let odd = Welded::new(roots, tolerance, Some([7, 8, 9]));
    let mut fixed = model.clone();
    let (_, welded) =
        fix_in_place_welded(&mut fixed, &FixOptions::DEFAULT, Some(&odd)).expect("valid");
    let fixed_vertices = validate::flatten(&fixed).expect("valid").positions.len();
    let counts = welded.expect("a weld").counts_for(fixed_vertices, tolerance);
    assert_eq!(counts, Some([7, 8, 9]));
    let apart =
        Welded::new((0..u32::try_from(vertices).expect("small")).collect(), tolerance, None);
    let (mut fresh, mut unwelded) = (model.clone(), model.clone());
    fix_in_place_welded(&mut fresh, &FixOptions::DEFAULT, None).expect("valid");
    fix_in_place_welded(&mut unwelded, &FixOptions::DEFAULT, Some(&apart)).expect("valid");
    assert_ne!(unwelded, fresh);
}

/// The triangle counts a fix makes on its way (in the smoothing's pass, with or without
/// the faces' UV frames) are the report's, and the report of the fixed model takes them.
#[test]
fn the_fixs_counts_are_the_reports() {
    let model = tube_with_bad_faces();
    for tangents in [TangentMethod::Mikktspace, TangentMethod::Seamlit, TangentMethod::None] {
        let options = FixOptions { tangents, ..FixOptions::DEFAULT };
        let mut fixed = model.clone();
        let (_, welded) = fix_in_place_welded(&mut fixed, &options, None).expect("valid");
        let welded = welded.expect("a weld in model mode");
        let report_options = ReportOptions::from(&options);
        let again = report(&fixed, &report_options).expect("valid");
        let vertices = validate::flatten(&fixed).expect("valid").positions.len();
        let counted = welded.counts_for(vertices, options.weld_tolerance);
        let expected =
            [again.degenerate_triangles, again.degenerate_uv_triangles, again.mirrored_triangles];
        assert!(expected.iter().all(|&n| n > 0), "{tangents:?}: {expected:?}");
        assert_eq!(counted, Some(expected), "{tangents:?}");
        let with = report_welded(&fixed, &report_options, Some(&welded)).expect("valid");
        assert_eq!(with, again, "{tangents:?}");
    }
}

/// Where the normals are kept and the tangents made against them, the generator's pass
/// over the triangles counts them, and the counts are the report's.
#[test]
fn the_counts_made_beside_kept_normals_are_the_reports() {
    let without_tangents = FixOptions { tangents: TangentMethod::None, ..FixOptions::DEFAULT };
    let with_normals = crate::fix(&tube_with_bad_faces(), &without_tangents).expect("valid");
    assert!(with_normals.objects.iter().all(|o| o.normals.is_some() && o.tangents.is_none()));
    for tangents in [TangentMethod::Mikktspace, TangentMethod::Seamlit] {
        let options = FixOptions { tangents, ..FixOptions::DEFAULT };
        let mut fixed = with_normals.clone();
        let (changes, welded) = fix_in_place_welded(&mut fixed, &options, None).expect("valid");
        assert!(changes.objects.iter().all(|o| o.kept_normals && !o.kept_tangents));
        assert!(fixed.objects.iter().all(|o| o.tangents.is_some()), "{tangents:?}");
        let welded = welded.expect("a weld in model mode");
        let again = report(&fixed, &ReportOptions::from(&options)).expect("valid");
        let vertices = validate::flatten(&fixed).expect("valid").positions.len();
        let expected =
            [again.degenerate_triangles, again.degenerate_uv_triangles, again.mirrored_triangles];
        assert!(expected.iter().all(|&n| n > 0), "{tangents:?}: {expected:?}");
        let counted = welded.counts_for(vertices, options.weld_tolerance);
        assert_eq!(counted, Some(expected), "{tangents:?}");
    }
}

/// The report of a fixed model with the triangle counts as loaded is the report that
/// counts them again, in every field, in every mode and with every tangent method; an
/// `as_loaded` of another model is not used.
#[test]
fn the_counts_as_loaded_are_the_fixed_models() {
    let model = tube_with_bad_faces();
    let options = ReportOptions::from(&FixOptions::DEFAULT);
    let as_loaded = report(&model, &options).expect("valid");
    assert!(as_loaded.degenerate_triangles > 0, "{as_loaded:?}");
    assert!(as_loaded.degenerate_uv_triangles > 0 && as_loaded.mirrored_triangles > 0);
    for mode in [Mode::Flat, Mode::Object, Mode::Model] {
        for tangents in [TangentMethod::Mikktspace, TangentMethod::Seamlit, TangentMethod::None] {
            let fix_options = FixOptions { mode, tangents, ..FixOptions::DEFAULT };
            let mut fixed = model.clone();
            let (changes, welded) =
                fix_in_place_welded(&mut fixed, &fix_options, None).expect("ok");
            assert!(changes.vertices_split() > 0, "{mode:?} {tangents:?}: nothing split");
            let again = report(&fixed, &options).expect("valid");
            let given = report_fixed(&fixed, &options, welded.as_ref(), &as_loaded);
            assert_eq!(given.expect("valid"), again, "{mode:?} {tangents:?}");
        }
    }
    // Counts of another model (one triangle fewer, the same positions) or taken at another
    // weld tolerance (the same triangles, more of them degenerate) are counted again.
    let mut fixed = model.clone();
    let (_, welded) = fix_in_place_welded(&mut fixed, &FixOptions::DEFAULT, None).expect("valid");
    let again = report(&fixed, &options).expect("valid");
    let mut fewer = model.clone();
    fewer.objects[3].triangles.pop();
    let wide = ReportOptions { weld_tolerance: crate::WeldTolerance::Relative(0.1), ..options };
    for other in [report(&fewer, &options), report(&model, &wide)] {
        let other = other.expect("valid");
        let counts = |r: &SeamReport| {
            [r.degenerate_triangles, r.degenerate_uv_triangles, r.mirrored_triangles]
        };
        assert_ne!(counts(&other), counts(&again), "{other:?}");
        let given = report_fixed(&fixed, &options, welded.as_ref(), &other).expect("valid");
        assert_eq!(given, again);
    }
}

/// The report before a fix, completed with what that fix counted, is the report as
/// loaded, and the fixed model's report with it is the one that measures it afresh: with
/// every object's normals computed, all kept and some kept, in every mode, with every
/// tangent method.
#[test]
fn the_report_before_a_fix_completed_by_it_is_the_report() {
    let [all, partly] = tubes_with_normals();
    for (name, model) in [("computed", tube_with_bad_faces()), all, partly] {
        for mode in [Mode::Flat, Mode::Object, Mode::Model] {
            for tangents in [TangentMethod::Mikktspace, TangentMethod::Seamlit, TangentMethod::None]
            {
                let options = FixOptions { mode, tangents, ..FixOptions::DEFAULT };
                let report_options = ReportOptions::from(&options);
                let (before, loaded) = report_before_fix(&model, &report_options).expect("valid");
                let mut fixed = model.clone();
                let (_, welded) =
                    fix_in_place_welded(&mut fixed, &options, Some(&loaded)).expect("ok");
                let (as_loaded, after) =
                    before.with_fixed(&fixed, &report_options, welded.as_ref()).expect("ok");
                let case = format!("{name} {mode:?} {tangents:?}");
                let expected = report(&model, &report_options).expect("valid");
                let counts = [
                    expected.degenerate_triangles,
                    expected.degenerate_uv_triangles,
                    expected.mirrored_triangles,
                ];
                assert!(counts.iter().any(|&n| n > 0), "{case}: nothing to count");
                assert_eq!(as_loaded, expected, "{case}");
                assert_eq!(after, report(&fixed, &report_options).expect("valid"), "{case}");
            }
        }
    }
}

/// The fix's weld is not used for another model or another tolerance, and the object
/// mode's (a weld within each object) is not given.
#[test]
fn a_weld_that_does_not_fit_is_not_used() {
    let model = folded_tube();
    let mut fixed = model.clone();
    let (_, welded) = fix_in_place_welded(&mut fixed, &FixOptions::DEFAULT, None).expect("valid");
    let welded = welded.expect("a weld in model mode");
    let options = ReportOptions::from(&FixOptions::DEFAULT);
    // The input has fewer vertices than the fixed model: its own weld is made.
    let unfixed = report_welded(&model, &options, Some(&welded)).expect("valid");
    assert_eq!(unfixed, report(&model, &options).expect("valid"));
    let wider = ReportOptions { weld_tolerance: crate::WeldTolerance::Relative(0.1), ..options };
    let at_wider = report_welded(&fixed, &wider, Some(&welded)).expect("valid");
    assert_eq!(at_wider, report(&fixed, &wider).expect("valid"));
    let object_mode = FixOptions { mode: Mode::Object, ..FixOptions::DEFAULT };
    let (_, none) = fix_in_place_welded(&mut model.clone(), &object_mode, None).expect("valid");
    assert!(none.is_none());
}
