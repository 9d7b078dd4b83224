//! Hand-built fixtures with exact expected values, and the key properties of `fix`.

mod common;

use glam::{Mat4, Vec2, Vec3, Vec4, Vec4Swizzles};
use seamlit_mesh::{
    FixOptions, MeshError, Mode, Model, NormalPolicy, Object, ReportOptions, TangentMethod,
    Weighting, fix, fix_in_place, reference, report,
};

fn quad(name: &str, corners: [Vec3; 4], uvs: [Vec2; 4]) -> Object {
    Object::new(name, corners.to_vec(), vec![[0, 1, 2], [0, 2, 3]]).with_uvs(uvs.to_vec())
}

/// Two quads in two objects sharing the edge x = 1, folded by about 11 degrees along it.
fn two_quads() -> Model {
    let uv = [Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)];
    let a = quad(
        "a",
        [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ],
        uv,
    );
    let b = quad(
        "b",
        [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, -0.2),
            Vec3::new(2.0, 1.0, -0.2),
            Vec3::new(1.0, 1.0, 0.0),
        ],
        uv,
    );
    Model::new(vec![a, b])
}

fn normals(o: &Object) -> &[Vec3] {
    o.normals.as_deref().expect("normals")
}

fn tangents(o: &Object) -> &[Vec4] {
    o.tangents.as_deref().expect("tangents")
}

#[test]
fn two_quads_share_values_after_model_but_not_after_object() {
    let m = two_quads();
    let fixed = fix(&m, &FixOptions::default()).unwrap();
    let (a, b) = (&fixed.objects[0], &fixed.objects[1]);
    // a's vertices 1 and 2 are b's vertices 0 and 3.
    for (va, vb) in [(1, 0), (2, 3)] {
        assert_eq!(normals(a)[va], normals(b)[vb]);
        assert_eq!(tangents(a)[va], tangents(b)[vb]);
    }
    // Both faces weigh in equally (equal corner angles): the shared normal bisects them.
    let nb = Vec3::new(0.2, 0.0, 1.0).normalize();
    let expected = (Vec3::Z + nb).normalize();
    assert!(normals(a)[1].abs_diff_eq(expected, 1e-6), "{}", normals(a)[1]);
    // Away from the seam, each quad keeps its own flat normal.
    assert_eq!(normals(a)[0], Vec3::Z);
    assert!(normals(b)[1].abs_diff_eq(nb, 1e-6));

    let object = fix(&m, &FixOptions::OBJECT).unwrap();
    let (a, b) = (&object.objects[0], &object.objects[1]);
    assert_eq!(normals(a)[1], Vec3::Z);
    assert!(normals(b)[0].abs_diff_eq(nb, 1e-6));
    assert_ne!(normals(a)[1], normals(b)[0]);
    assert_ne!(tangents(a)[1], tangents(b)[0]);
}

#[test]
fn seam_report_sees_the_seam_and_its_repair() {
    let m = two_quads();
    let opts = ReportOptions::default();
    let object = report(&fix(&m, &FixOptions::OBJECT).unwrap(), &opts).unwrap();
    let model = report(&fix(&m, &FixOptions::default()).unwrap(), &opts).unwrap();
    assert_eq!(object.shared_positions, 2);
    assert_eq!(object.cross_object.edges, 1);
    assert_eq!(object.cross_object.hard_edges, 0);
    // Two faces meet across the shared edge at each end: 2 corner pairs, one per endpoint.
    assert_eq!(object.cross_object.corner_pairs, 2);
    let fold = Vec3::Z.angle_between(Vec3::new(0.2, 0.0, 1.0)).to_degrees();
    let seam = object.cross_object.max_normal_angle_deg.unwrap();
    assert!((seam - fold).abs() < 1e-3, "{seam} vs {fold}");
    assert_eq!(model.cross_object.max_normal_angle_deg, Some(0.0));
    assert_eq!(model.cross_object.max_tangent_angle_deg, Some(0.0));
    assert!(model.max_abs_dot_nt.unwrap() < 1e-6);
    // Unfixed, there are no normals to compare.
    let raw = report(&m, &opts).unwrap();
    assert_eq!(raw.cross_object.max_normal_angle_deg, None);
    assert_eq!(raw.near_miss_positions, 0);
    let json = serde_json::to_value(&model).unwrap();
    for key in ["max_normal_angle_deg", "mean_normal_angle_deg", "max_tangent_angle_deg"] {
        assert!(json["cross_object"][key].is_number(), "{key}");
    }
    for key in [
        "shared_positions",
        "near_miss_positions",
        "degenerate_triangles",
        "degenerate_uv_triangles",
        "mirrored_triangles",
        "max_abs_dot_nt",
    ] {
        assert!(json[key].is_number(), "{key}");
    }
}

/// A unit cube, one object per face (the Cornell box situation), or one object with shared
/// corners.
fn cube(one_object: bool) -> Model {
    let quads: Vec<Object> = common::CUBE_SIDES
        .iter()
        .enumerate()
        .map(|(i, &(n, u, v))| {
            let c = |a: f32, b: f32| n + u * a + v * b;
            quad(
                &format!("side{i}"),
                [c(-1.0, -1.0), c(1.0, -1.0), c(1.0, 1.0), c(-1.0, 1.0)],
                [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y],
            )
        })
        .collect();
    if !one_object {
        return Model::new(quads);
    }
    let mut all = Object::new("cube", Vec::new(), Vec::new());
    let mut uvs = Vec::new();
    for q in quads {
        let base = u32::try_from(all.positions.len()).unwrap();
        all.positions.extend(&q.positions);
        uvs.extend(q.uvs.unwrap());
        all.triangles.extend(q.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    Model::new(vec![all.with_uvs(uvs)])
}

#[test]
fn cube_keeps_hard_edges_at_60_and_is_smooth_at_180() {
    for one_object in [false, true] {
        let m = cube(one_object);
        let hard = fix(&m, &FixOptions::default()).unwrap();
        for o in &hard.objects {
            for (t, tri) in o.triangles.iter().enumerate() {
                let face_n = (o.positions[tri[1] as usize] - o.positions[tri[0] as usize])
                    .cross(o.positions[tri[2] as usize] - o.positions[tri[0] as usize])
                    .normalize();
                for &v in tri {
                    let n = normals(o)[v as usize];
                    // Equal up to the rounding of normalising a weighted sum (1 ulp).
                    assert!(n.abs_diff_eq(face_n, 1e-6), "triangle {t} of {}: {n}", o.name);
                }
            }
        }
        let smooth =
            fix(&m, &FixOptions { crease_angle_deg: 180.0, ..FixOptions::default() }).unwrap();
        for o in &smooth.objects {
            for (p, n) in o.positions.iter().zip(normals(o)) {
                // Every corner of the cube: the diagonal, since the three faces' corner angles
                // are equal (90 degrees each).
                assert!(n.abs_diff_eq(p.normalize(), 1e-6), "{p} -> {n}");
            }
        }
        let r = report(&hard, &ReportOptions::default()).unwrap();
        if !one_object {
            assert_eq!(r.cross_object.edges, 12);
            assert_eq!(r.cross_object.hard_edges, 12);
            assert!((r.cross_object.min_hard_edge_normal_angle_deg.unwrap() - 90.0).abs() < 1e-3);
        }
    }
}

#[test]
fn mirrored_uvs_flip_w_and_are_not_averaged() {
    // A 2 x 1 strip; the right half has u mirrored (u runs back from 1 to 0).
    let p = |x: f32, y: f32| Vec3::new(x, y, 0.0);
    let positions =
        vec![p(0.0, 0.0), p(1.0, 0.0), p(2.0, 0.0), p(0.0, 1.0), p(1.0, 1.0), p(2.0, 1.0)];
    let uvs = vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 0.0),
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(0.0, 1.0),
    ];
    let tris = vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]];
    let m = Model::new(vec![Object::new("strip", positions, tris).with_uvs(uvs)]);
    let fixed = fix(&m, &FixOptions::default()).unwrap();
    let o = &fixed.objects[0];
    // The mirror line's two vertices are split: 6 + 2 vertices.
    assert_eq!(o.positions.len(), 8);
    for (t, tri) in o.triangles.iter().enumerate() {
        let (tangent, w) = if t < 2 { (Vec3::X, 1.0) } else { (Vec3::NEG_X, -1.0) };
        for &v in tri {
            let tv = tangents(o)[v as usize];
            assert!(tv.abs_diff_eq(tangent.extend(w), 1e-6), "triangle {t}, vertex {v}: {tv}");
            // B = cross(N, T) * w is +Y on both sides: the normal map's up agrees.
            let b = normals(o)[v as usize].cross(tv.xyz()) * tv.w;
            assert!(b.abs_diff_eq(Vec3::Y, 1e-6), "{b}");
        }
    }
    let r = report(&fixed, &ReportOptions::default()).unwrap();
    assert_eq!(r.mirrored_triangles, 2);
    // The paper averages across the mirror: the tangent sum cancels, and no vertex is split.
    let paper = fix(&m, &FixOptions::PAPER).unwrap();
    assert_eq!(paper.objects[0].positions.len(), 6);
}

#[test]
fn degenerate_triangles_and_uvs_give_no_nan() {
    let positions = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::X * 2.0, // collinear with 0 and 1
        Vec3::new(0.5, 0.5, 1.0),
    ];
    let uvs = vec![Vec2::ZERO, Vec2::ZERO, Vec2::ZERO, Vec2::X, Vec2::new(0.5, 0.5)];
    let tris = vec![[0, 1, 2], [0, 1, 3], [1, 1, 2], [0, 2, 4], [3, 3, 3]];
    let m = Model::new(vec![Object::new("bad", positions, tris).with_uvs(uvs)]);
    for mode in [Mode::Flat, Mode::Object, Mode::Model] {
        for tangents in [TangentMethod::Seamlit, TangentMethod::Mikktspace] {
            for weighting in
                [Weighting::Angle, Weighting::Area, Weighting::AngleArea, Weighting::Uniform]
            {
                let opts = FixOptions { mode, tangents, weighting, ..FixOptions::default() };
                let f = fix(&m, &opts).unwrap();
                let o = &f.objects[0];
                assert!(
                    normals(o).iter().all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-5)
                );
                assert!(self::tangents(o).iter().all(|t| t.is_finite() && t.w.abs() == 1.0));
            }
        }
    }
    let r = report(&m, &ReportOptions::default()).unwrap();
    assert_eq!(r.degenerate_triangles, 3);
    // Of the two triangles with area, [0, 1, 2] has all-zero UVs and [0, 2, 4] collinear ones.
    assert_eq!(r.degenerate_uv_triangles, 2);
    let reference = reference::fix(&m).unwrap();
    assert!(normals(&reference.objects[0]).iter().all(|n| n.is_finite()));
}

#[test]
fn bad_input_is_an_error_naming_object_and_vertex() {
    let mut o = Object::new(
        "broken",
        vec![Vec3::ZERO, Vec3::X, Vec3::new(f32::NAN, 0.0, 0.0)],
        vec![[0, 1, 2]],
    );
    let m = Model::new(vec![cube(true).objects[0].clone(), o.clone()]);
    match fix(&m, &FixOptions::default()) {
        Err(MeshError::NonFinitePosition { object: 1, vertex: 2, ref name, .. }) => {
            assert_eq!(name, "broken");
        }
        other => panic!("{other:?}"),
    }
    let msg = fix(&m, &FixOptions::default()).unwrap_err().to_string();
    assert!(msg.contains("\"broken\"") && msg.contains("vertex 2"), "{msg}");
    o.positions[2] = Vec3::Y;
    o.triangles.push([0, 1, 7]);
    let m = Model::new(vec![o.clone()]);
    assert!(matches!(
        fix(&m, &FixOptions::default()),
        Err(MeshError::IndexOutOfRange { triangle: 1, index: 7, vertex_count: 3, .. })
    ));
    o.triangles.pop();
    o.uvs = Some(vec![Vec2::ZERO]);
    assert!(matches!(
        report(&Model::new(vec![o.clone()]), &ReportOptions::default()),
        Err(MeshError::AttributeLength { attribute: "uvs", expected: 3, actual: 1, .. })
    ));
    o.uvs = None;
    o.transform = Some(Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0)));
    assert!(matches!(
        fix(&Model::new(vec![o]), &FixOptions::default()),
        Err(MeshError::BadTransform { .. })
    ));
}

/// The checks scan values in blocks before they search one (validate.rs): a bad index,
/// position or UV far into a large object, past several blocks and not at the start of
/// one, is still named at its own place, and the first of two is the one named.
#[test]
fn bad_input_deep_in_a_large_object_is_named_at_its_place() {
    let n = 20_000u32;
    let positions: Vec<Vec3> = (0..n).map(|i| Vec3::new(i as f32, (i % 7) as f32, 0.0)).collect();
    let triangles: Vec<[u32; 3]> = (0..n - 2).map(|i| [i, i + 1, i + 2]).collect();
    let good = Object::new("large", positions, triangles)
        .with_uvs((0..n).map(|i| Vec2::new(i as f32, 0.5)).collect());
    let first_error = |o: &Object| fix(&Model::new(vec![o.clone()]), &FixOptions::default());

    let mut o = good.clone();
    (o.triangles[12_345][2], o.triangles[15_000][0]) = (n, n + 5);
    assert!(matches!(
        first_error(&o),
        Err(MeshError::IndexOutOfRange { triangle: 12_345, index: 20_000, .. })
    ));
    let mut o = good.clone();
    (o.positions[9_999].z, o.positions[10_001].x) = (f32::INFINITY, f32::NAN);
    assert!(matches!(
        first_error(&o),
        Err(MeshError::NonFinitePosition { vertex: 9_999, value: [_, _, z], .. }) if z == f32::INFINITY
    ));
    let mut o = good;
    o.uvs.as_mut().unwrap()[17_777].y = f32::NAN;
    assert!(matches!(first_error(&o), Err(MeshError::NonFiniteUv { vertex: 17_777, .. })));
}

#[test]
fn transforms_are_applied_before_welding() {
    // The same quad twice, the second placed by a transform so that it continues the first
    // (rotated 20 degrees about the shared edge): welding must happen in model space.
    let uv = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    let local = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let a = quad("a", local, uv);
    let place = Mat4::from_translation(Vec3::X) * Mat4::from_rotation_y(20f32.to_radians());
    let b = quad("b", local, uv).with_transform(place);
    let fixed = fix(&Model::new(vec![a, b]), &FixOptions::default()).unwrap();
    let (fa, fb) = (&fixed.objects[0], &fixed.objects[1]);
    // b's vertex 0 sits on a's vertex 1: equal normals in model space.
    let nb_model = place.transform_vector3(normals(fb)[0]).normalize();
    assert!(normals(fa)[1].abs_diff_eq(nb_model, 1e-6), "{} vs {nb_model}", normals(fa)[1]);
    let r = report(&fixed, &ReportOptions::default()).unwrap();
    assert_eq!(r.shared_positions, 2);
    assert!(r.cross_object.max_normal_angle_deg.unwrap() < 1e-3);
    assert!(r.cross_object.max_tangent_angle_deg.unwrap() < 1e-3);
}

#[test]
fn paper_preset_equals_the_reference() {
    let models = [
        Model::new(vec![common::uv_sphere(8, 12)]),
        common::split(&common::torus(10, 14), &[0, 1, 2, 1, 0, 2, 2], || Vec3::ZERO).0,
        common::teapot(4),
        cube(false),
    ];
    for (i, m) in models.iter().enumerate() {
        let fast = fix(m, &FixOptions::PAPER).unwrap();
        let slow = reference::fix(m).unwrap();
        for (a, b) in fast.objects.iter().zip(&slow.objects) {
            // The paper's semantics split no vertex.
            assert_eq!(a.positions.len(), b.positions.len(), "model {i}");
            for v in 0..a.positions.len() {
                assert!(
                    normals(a)[v].abs_diff_eq(normals(b)[v], 1e-6),
                    "model {i} {} v{v}",
                    a.name
                );
                assert!(
                    tangents(a)[v].abs_diff_eq(tangents(b)[v], 1e-6),
                    "model {i} {} v{v}",
                    a.name
                );
            }
        }
    }
}

#[test]
fn fixing_twice_changes_nothing() {
    let models = [
        common::teapot(6),
        common::split(&common::uv_sphere(10, 16), &[0, 1, 1, 2], || Vec3::ZERO).0,
        cube(false),
    ];
    for m in &models {
        let presets =
            [FixOptions::default(), FixOptions::OBJECT, FixOptions::FLAT, FixOptions::PAPER];
        let recompute = presets.map(|o| o.with_normals(NormalPolicy::Recompute));
        for opts in presets.into_iter().chain(recompute) {
            let once = fix(m, &opts).unwrap();
            let twice = fix(&once, &opts).unwrap();
            assert_eq!(once, twice, "{opts:?}");
        }
    }
}

#[test]
fn one_thread_and_many_give_the_same_bits() {
    // Big enough for many parallel chunks (over 4096 positions).
    let (m, _) = common::split(&common::torus(120, 160), &[0, 1, 2, 3, 1, 2], || Vec3::ZERO);
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let four = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap();
    for opts in [
        FixOptions::default(),
        FixOptions { tangents: TangentMethod::Mikktspace, ..FixOptions::default() },
        FixOptions::default().with_normals(NormalPolicy::Recompute),
    ] {
        let a = one.install(|| fix(&m, &opts)).unwrap();
        let b = four.install(|| fix(&m, &opts)).unwrap();
        assert_eq!(a, b);
        let ra = one.install(|| report(&a, &ReportOptions::default())).unwrap();
        let rb = four.install(|| report(&b, &ReportOptions::default())).unwrap();
        assert_eq!(ra, rb);
    }
}

#[test]
fn teapot_seams_close_in_model_mode() {
    let m = common::teapot(8);
    let opts = ReportOptions::default();
    let raw = report(&m, &opts).unwrap();
    assert_eq!(raw.objects, 32);
    assert_eq!(raw.triangles, 32 * 8 * 8 * 2);
    let object = report(&fix(&m, &FixOptions::OBJECT).unwrap(), &opts).unwrap();
    let model = report(&fix(&m, &FixOptions::default()).unwrap(), &opts).unwrap();
    let before = object.cross_object.max_normal_angle_deg.unwrap();
    let after = model.cross_object.max_normal_angle_deg.unwrap();
    assert!(before > 1.0, "object mode leaves seams: {before}");
    assert!(after < 1e-3, "model mode closes them: {after}");
    assert_eq!(model.cross_object.normal_breaks, 0);
}

#[test]
fn a_vertex_no_triangle_uses_keeps_its_input_normal() {
    // Vertex 3 is used by no triangle; its input normal (0, 3, 4) becomes (0, 0.6, 0.8).
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::splat(5.0)];
    let mut object = Object::new("with a stray vertex", positions, vec![[0, 1, 2]]);
    object.normals = Some(vec![Vec3::X, Vec3::X, Vec3::X, Vec3::new(0.0, 3.0, 4.0)]);
    let model = Model::new(vec![object]);

    // Recompute: the input normals are replaced by the faces' (auto would keep them all).
    let recompute = FixOptions::DEFAULT.with_normals(NormalPolicy::Recompute);
    let copied = fix(&model, &recompute).expect("valid");
    let mut in_place = model.clone();
    fix_in_place(&mut in_place, &recompute).expect("valid");
    for fixed in [&copied, &in_place] {
        let n = normals(&fixed.objects[0]);
        assert_eq!(&n[..3], &[Vec3::Z; 3], "the triangle's own normal");
        assert_eq!(n[3], Vec3::new(0.0, 0.6, 0.8));
    }
    // Without input normals, +Z.
    let mut bare = model.clone();
    bare.objects[0].normals = None;
    assert_eq!(normals(&fix(&bare, &FixOptions::DEFAULT).expect("valid").objects[0])[3], Vec3::Z);
}

/// A cube of 8 shared corners in one object: each corner meets three faces at 90 degrees, so
/// the 60 degree crease splits it into three vertices, and `split_from` says which input
/// vertex each copy duplicates.
#[test]
fn split_vertices_record_the_input_vertex_they_copy() {
    let cube = common::shared_corner_cube();
    let positions = cube.positions.clone();
    // Distinct UVs per input vertex, so a copy's UV tells its source too.
    let uvs = (0..8).map(|i| Vec2::new(i as f32, 0.5)).collect();
    let model = Model::new(vec![cube.with_uvs(uvs)]);
    let fixed = fix(&model, &FixOptions::default()).unwrap();
    let o = &fixed.objects[0];
    assert_eq!(o.input_vertex_count(), 8);
    assert_eq!(o.vertex_count(), 24, "each corner split into one vertex per face");
    assert_eq!(o.split_from.len(), 16);
    for v in 0..u32::try_from(o.vertex_count()).unwrap() {
        let source = o.source_vertex(v);
        assert!(source < 8);
        assert_eq!(o.positions[v as usize], positions[source as usize], "vertex {v}");
        assert_eq!(o.uvs.as_ref().unwrap()[v as usize].x, source as f32, "vertex {v}");
    }
    // Every input vertex was copied twice.
    for source in 0..8 {
        assert_eq!(o.split_from.iter().filter(|&&s| s == source).count(), 2, "vertex {source}");
    }
    // A second fix splits nothing more and keeps the record pointing at the first input.
    let again = fix(&fixed, &FixOptions::default()).unwrap();
    assert_eq!(again.objects[0].split_from, o.split_from);
    // A split_from that names a copy, or is longer than the vertices, is refused.
    let mut bad = fixed.clone();
    bad.objects[0].split_from[0] = 20;
    assert!(matches!(fix(&bad, &FixOptions::default()), Err(MeshError::BadSplitFrom { .. })));
    bad.objects[0].split_from = vec![0; 30];
    assert!(matches!(fix(&bad, &FixOptions::default()), Err(MeshError::BadSplitFrom { .. })));
}

/// Vertex colours and second texture coordinates follow their vertex through the splits, in
/// `fix` and `fix_in_place`, in every mode, and a wrong length is refused.
#[test]
fn split_vertices_keep_their_colour_and_second_uvs() {
    let colors: Vec<Vec4> = (0..8).map(|i| Vec4::new(i as f32 / 8.0, 0.25, 1.0, 0.5)).collect();
    let uvs1: Vec<Vec2> =
        (0..8).map(|i| Vec2::new(i as f32 / 8.0, 1.0 - i as f32 / 16.0)).collect();
    let mut object = common::shared_corner_cube();
    object.colors = Some(colors.clone());
    object.uvs1 = Some(uvs1.clone());
    let model = Model::new(vec![object]);
    for mode in [Mode::Flat, Mode::Object, Mode::Model] {
        let options = FixOptions::default().with_mode(mode);
        let fixed = fix(&model, &options).unwrap();
        let mut in_place = model.clone();
        fix_in_place(&mut in_place, &options).unwrap();
        for o in [&fixed.objects[0], &in_place.objects[0]] {
            assert_eq!(o.vertex_count(), 24, "{mode:?}: each corner split");
            let got = o.colors.as_ref().expect("colours kept");
            assert_eq!(got.len(), 24);
            let got_uvs1 = o.uvs1.as_ref().expect("second uvs kept");
            assert_eq!(got_uvs1.len(), 24);
            for v in 0..24 {
                assert_eq!(got[v as usize], colors[o.source_vertex(v) as usize], "{mode:?} {v}");
                assert_eq!(got_uvs1[v as usize], uvs1[o.source_vertex(v) as usize], "{mode:?} {v}");
            }
        }
    }
    let mut bad = model.clone();
    bad.objects[0].colors.as_mut().unwrap().pop();
    assert!(matches!(
        fix(&bad, &FixOptions::default()),
        Err(MeshError::AttributeLength { attribute: "colors", expected: 8, actual: 7, .. })
    ));
    let mut bad = model.clone();
    bad.objects[0].uvs1.as_mut().unwrap().pop();
    assert!(matches!(
        fix(&bad, &FixOptions::default()),
        Err(MeshError::AttributeLength { attribute: "uvs1", expected: 8, actual: 7, .. })
    ));
}
