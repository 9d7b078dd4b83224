//! Morph targets: the normal and tangent deltas `fix` computes are those of the displaced
//! model, the same on both sides of a seam; skin influences and deltas follow split vertices.

use glam::{Vec2, Vec3, Vec4Swizzles};
use seamlit_mesh::{
    FixOptions, Influences, Model, MorphTarget, NormalPolicy, Object, VAxis, fix, fix_in_place,
};

/// A bump centred on the seam x = 2, y = 1.
fn bulge(p: Vec3) -> Vec3 {
    let d2 = (p.x - 2.0).powi(2) + (p.y - 1.0).powi(2);
    Vec3::new(0.0, 0.0, 0.6 * (-d2).exp())
}

/// A 4 x 4 grid of quads over `[x0, x0 + 2] x [0, 2]`, gently curved (z = 0.05 x^2), with UVs
/// and one morph target: [`bulge`].
fn sheet(name: &str, x0: f32) -> Object {
    let n = 5;
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (x0 + 0.5 * i as f32, 0.5 * j as f32);
            positions.push(Vec3::new(x, y, 0.05 * x * x));
            uvs.push(Vec2::new(x / 4.0, 1.0 - y / 2.0));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let v = j * n + i;
            triangles.push([v, v + 1, v + n + 1]);
            triangles.push([v, v + n + 1, v + n]);
        }
    }
    let deltas = positions.iter().map(|&p| bulge(p)).collect();
    let mut object = Object::new(name, positions, triangles).with_uvs(uvs);
    object.morph_targets = vec![MorphTarget { position_deltas: deltas, ..MorphTarget::default() }];
    object
}

fn model() -> Model {
    Model { objects: vec![sheet("left", 0.0), sheet("right", 2.0)], v_axis: VAxis::Down }
}

/// The model with its first target applied to the positions, and no targets.
fn displaced(model: &Model) -> Model {
    let mut out = model.clone();
    for o in &mut out.objects {
        let target = o.morph_targets.remove(0);
        for (p, d) in o.positions.iter_mut().zip(target.position_deltas) {
            *p += d;
        }
    }
    out
}

fn deltas(o: &Object) -> (&[Vec3], &[Vec3]) {
    let t = &o.morph_targets[0];
    (
        t.normal_deltas.as_deref().expect("normal deltas computed"),
        t.tangent_deltas.as_deref().expect("tangent deltas computed"),
    )
}

#[test]
fn morph_normals_are_those_of_the_displaced_model_and_agree_across_the_seam() {
    let input = model();
    let options = FixOptions { normals: NormalPolicy::Recompute, ..FixOptions::default() };
    let fixed = fix(&input, &options).unwrap();
    let scratch = fix(&displaced(&input), &options).unwrap();
    let mut compared = 0;
    for (o, s) in fixed.objects.iter().zip(&scratch.objects) {
        assert_eq!(o.vertex_count(), s.vertex_count(), "{}: no vertex split", o.name);
        let (dn, dt) = deltas(o);
        let (n, t) = (o.normals.as_ref().unwrap(), o.tangents.as_ref().unwrap());
        let (sn, st) = (s.normals.as_ref().unwrap(), s.tangents.as_ref().unwrap());
        for v in 0..o.vertex_count() {
            let morphed = n[v] + dn[v];
            assert!(morphed.abs_diff_eq(sn[v], 1e-5), "{} v{v}: {morphed} vs {}", o.name, sn[v]);
            let morphed = t[v].xyz() + dt[v];
            assert!(morphed.abs_diff_eq(st[v].xyz(), 1e-5), "{} v{v}: {morphed}", o.name);
            compared += 1;
        }
    }
    assert_eq!(compared, 50);
    // The bulge changes the normals at the seam: the deltas are not zero there.
    let (left, right) = (&fixed.objects[0], &fixed.objects[1]);
    let (mut seam, mut largest) = (0, 0.0f32);
    for (a, pa) in left.positions.iter().enumerate() {
        for (b, pb) in right.positions.iter().enumerate() {
            if pa == pb {
                let na = left.normals.as_ref().unwrap()[a] + deltas(left).0[a];
                let nb = right.normals.as_ref().unwrap()[b] + deltas(right).0[b];
                assert!(na.abs_diff_eq(nb, 1e-5), "seam {pa}: {na} vs {nb}");
                largest = largest.max(deltas(left).0[a].length());
                seam += 1;
            }
        }
    }
    assert_eq!(seam, 5);
    assert!(largest > 0.2, "the bulge tilts the seam's normals: {largest}");
}

#[test]
fn fix_in_place_computes_the_same_deltas() {
    let options = FixOptions::default();
    let copy = fix(&model(), &options).unwrap();
    let mut in_place = model();
    fix_in_place(&mut in_place, &options).unwrap();
    assert_eq!(copy, in_place);
}

#[test]
fn kept_normals_keep_their_targets_as_they_were() {
    let options = FixOptions::default();
    let mut input = model();
    // Authored normals (a fixed model's): `auto` keeps them, and the targets' deltas with them.
    input = fix(&input, &FixOptions { normals: NormalPolicy::Recompute, ..options }).unwrap();
    for o in &mut input.objects {
        o.morph_targets[0].normal_deltas = None;
        o.morph_targets[0].tangent_deltas = None;
    }
    let fixed = fix(&input, &options).unwrap();
    for o in &fixed.objects {
        assert_eq!(o.morph_targets[0].normal_deltas, None, "{}", o.name);
    }
}

#[test]
fn split_vertices_copy_their_influences_and_deltas() {
    // A folded strip: the crease at x = 1 splits its vertices.
    let positions = vec![
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 1.0),
        Vec3::new(2.0, 0.0, 1.0),
        Vec3::new(2.0, 1.0, 1.0),
    ];
    let triangles = vec![[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]];
    let mut object = Object::new("fold", positions, triangles);
    object.skin = vec![Influences {
        joints: (0..6).map(|v| [v, v + 10, 0, 0]).collect(),
        weights: (0..6).map(|v| [0.5, 0.5 - v as f32 / 100.0, 0.0, 0.0]).collect(),
    }];
    object.morph_targets = vec![MorphTarget {
        position_deltas: (0..6).map(|v| Vec3::splat(v as f32)).collect(),
        ..MorphTarget::default()
    }];
    let fixed = fix(&Model::new(vec![object.clone()]), &FixOptions::default()).unwrap();
    let o = &fixed.objects[0];
    assert!(o.vertex_count() > 6, "the crease splits vertices");
    for v in 0..u32::try_from(o.vertex_count()).unwrap() {
        let s = o.source_vertex(v) as usize;
        let v = v as usize;
        assert_eq!(o.skin[0].joints[v], object.skin[0].joints[s]);
        assert_eq!(o.skin[0].weights[v], object.skin[0].weights[s]);
        assert_eq!(o.morph_targets[0].position_deltas[v], Vec3::splat(s as f32));
    }
}

#[test]
fn split_vertices_get_the_deltas_of_their_side_of_the_crease() {
    // Two objects folded at a right angle along x = 1, the crease splitting its vertices;
    // the target tilts the far edge a little.
    let half = |name: &str, far: [Vec3; 2]| {
        let positions = vec![Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), far[1], far[0]];
        let mut o = Object::new(name, positions, vec![[0, 1, 2], [0, 2, 3]]);
        let deltas = (0..4).map(|v| Vec3::new(0.0, 0.0, if v >= 2 { 0.1 } else { 0.0 })).collect();
        o.morph_targets = vec![MorphTarget { position_deltas: deltas, ..MorphTarget::default() }];
        o
    };
    let flat_side = half("flat", [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)]);
    let mut wall = half("wall", [Vec3::new(1.0, 0.0, -1.0), Vec3::new(1.0, 1.0, -1.0)]);
    wall.triangles = vec![[0, 2, 1], [0, 3, 2]];
    // One object holds both sides, so that the crease splits its vertices.
    let mut both = flat_side.clone();
    let offset = u32::try_from(both.vertex_count()).unwrap();
    both.positions.extend(&wall.positions[2..]);
    both.morph_targets[0].position_deltas.extend(&wall.morph_targets[0].position_deltas[2..]);
    let remap = |i: u32| if i < 2 { i } else { i - 2 + offset };
    both.triangles.extend(wall.triangles.iter().map(|t| t.map(remap)));
    let input = Model::new(vec![both]);
    let options = FixOptions { normals: NormalPolicy::Recompute, ..FixOptions::default() };
    let fixed = fix(&input, &options).unwrap();
    let scratch = fix(&displaced(&input), &options).unwrap();
    let (o, s) = (&fixed.objects[0], &scratch.objects[0]);
    assert!(o.vertex_count() > 6, "the crease splits vertices");
    assert_eq!(o.triangles, s.triangles);
    let dn = o.morph_targets[0].normal_deltas.as_ref().unwrap();
    let (normals, expected) = (o.normals.as_ref().unwrap(), s.normals.as_ref().unwrap());
    for (v, (d, e)) in dn.iter().zip(expected).enumerate() {
        let morphed = normals[v] + *d;
        assert!(morphed.abs_diff_eq(*e, 1e-5), "v{v}: {morphed} vs {e}");
    }
}

/// The bits of every object's normal and tangent deltas of target `k`.
fn delta_bits(model: &Model, k: usize) -> Vec<Vec<u32>> {
    let bits = |v: &[Vec3]| v.iter().flat_map(|d| d.to_array()).map(f32::to_bits).collect();
    model
        .objects
        .iter()
        .flat_map(|o| {
            let t = &o.morph_targets[k];
            [bits(t.normal_deltas.as_deref().unwrap()), bits(t.tangent_deltas.as_deref().unwrap())]
        })
        .collect()
}

#[test]
fn each_target_gets_the_bits_it_would_get_alone() {
    // Two targets computed together (one pass over the triangles for both) give each the
    // same bits as a model with that target alone.
    let shear = |p: Vec3| Vec3::new(0.3 * p.y, 0.0, 0.1 * p.x);
    let mut both = model();
    for o in &mut both.objects {
        let deltas = o.positions.iter().map(|&p| shear(p)).collect();
        o.morph_targets.push(MorphTarget { position_deltas: deltas, ..MorphTarget::default() });
    }
    let options = FixOptions::default();
    let together = fix(&both, &options).unwrap();
    for k in 0..2 {
        let mut alone = both.clone();
        for o in &mut alone.objects {
            o.morph_targets = vec![o.morph_targets[k].clone()];
        }
        let alone = fix(&alone, &options).unwrap();
        assert_eq!(delta_bits(&together, k), delta_bits(&alone, 0), "target {k}");
    }
}
