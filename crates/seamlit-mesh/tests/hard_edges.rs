//! The default repair tells the seams that smoothing each object alone made from the hard
//! edges and custom normals the artist authored (docs/normals.md, "What a shared position
//! is"). Fixtures built here with their normals worked out here: per-object smooth normals as
//! tools compute them (area-weighted sums of face normals), flat normals as faceted exports
//! carry them, custom normals as a weighted-normal modifier leaves them.

mod common;

use glam::{Vec3, Vec3Swizzles};
use seamlit_mesh::{
    FixOptions, Model, NormalPolicy, Object, ReportOptions, SharedNormals, TangentMethod,
    fix_in_place, report,
};

const AUTO: FixOptions = FixOptions { tangents: TangentMethod::None, ..FixOptions::DEFAULT };
const SMOOTH_SHARED: FixOptions = AUTO.with_normals(NormalPolicy::SmoothShared);
const KEEP: FixOptions = AUTO.with_normals(NormalPolicy::Keep);

fn bits(o: &Object) -> Vec<[u32; 3]> {
    o.normals.as_ref().expect("normals").iter().map(|n| n.to_array().map(f32::to_bits)).collect()
}

/// Every vertex's normal: the area-weighted sum of the object's faces around its position
/// (Blender's and most exporters' smooth shading before weighting by angle; vertices split
/// by a UV seam get the same normal). Vertices no triangle uses are dropped.
fn smooth_per_object(o: &mut Object) {
    let key = |p: Vec3| p.to_array().map(|x| (x + 0.0).to_bits());
    let mut sums = std::collections::HashMap::new();
    for t in &o.triangles {
        let p = t.map(|i| o.positions[i as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        for q in p {
            *sums.entry(key(q)).or_insert(Vec3::ZERO) += n;
        }
    }
    let mut used: Vec<u32> = o.triangles.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    let new_index = |i: u32| u32::try_from(used.binary_search(&i).expect("used")).expect("small");
    o.triangles = o.triangles.iter().map(|t| t.map(new_index)).collect();
    o.positions = used.iter().map(|&i| o.positions[i as usize]).collect();
    o.normals = Some(o.positions.iter().map(|&p| sums[&key(p)].normalize()).collect());
    o.uvs = None;
}

/// Each triangle gets its own three vertices carrying its face normal: flat shading as a
/// faceted export writes it.
fn facet(o: &Object) -> Object {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut triangles = Vec::new();
    for t in &o.triangles {
        let p = t.map(|i| o.positions[i as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let base = u32::try_from(positions.len()).expect("small");
        positions.extend(p);
        normals.extend([n; 3]);
        triangles.push([base, base + 1, base + 2]);
    }
    let mut out = Object::new(o.name.clone(), positions, triangles);
    out.normals = Some(normals);
    out
}

/// A UV sphere split at the equator into two objects, each smoothed on its own: the seam the
/// paper is about. Returns the model and the equator's (object, vertex) copies.
fn smooth_halves() -> Model {
    let sphere = common::uv_sphere(8, 12);
    // Ring r of the sphere's grid is the vertices r * 13 .. r * 13 + 13; rows 0..4 are the top.
    let half = |name: &str, top: bool| {
        let tris: Vec<[u32; 3]> = sphere
            .triangles
            .iter()
            .copied()
            .filter(|t| {
                let ring = t.iter().map(|&i| i / 13).min().expect("three");
                (ring < 4) == top
            })
            .collect();
        let mut o = Object::new(name, sphere.positions.clone(), tris);
        smooth_per_object(&mut o);
        o
    };
    Model::new(vec![half("top", true), half("bottom", false)])
}

fn seam_angle(m: &Model) -> f32 {
    report(m, &ReportOptions::default())
        .expect("valid")
        .cross_object
        .max_normal_angle_deg
        .expect("a smooth cross-object edge")
}

#[test]
fn smooth_halves_are_repaired() {
    let input = smooth_halves();
    assert!(seam_angle(&input) > 10.0, "the fixture has a seam: {}", seam_angle(&input));
    let mut fixed = input.clone();
    let changes = fix_in_place(&mut fixed, &AUTO).expect("valid");
    assert_eq!(format!("{:.2}", seam_angle(&fixed)), "0.00");
    // The equator's 12 positions (13 vertices: the UV seam's column twice).
    let expected = SharedNormals { repaired: 12, ..SharedNormals::default() };
    assert_eq!(changes.shared, expected);
    // The equator's normals are horizontal (the halves mirror each other).
    let top = &fixed.objects[0];
    for (p, n) in top.positions.iter().zip(top.normals.as_ref().expect("normals")) {
        if p.y.abs() < 1e-6 {
            assert!(n.y.abs() < 1e-5 && n.is_normalized(), "{p}: {n}");
        }
    }
}

/// Two faceted blocks whose top faces meet along the edge x = 0 at 30 degrees: block `a` is
/// flat on top, block `b`'s top slopes down; each has a front face at a hard 90 degrees.
fn faceted_blocks() -> Model {
    let slope = 30_f32.to_radians();
    let (dx, dy) = (slope.cos(), -slope.sin());
    let a = Object::new(
        "a",
        vec![
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3], [4, 5, 1], [4, 1, 0]],
    );
    let b = Object::new(
        "b",
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(dx, dy, 0.0),
            Vec3::new(dx, dy, -1.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(dx, -1.0, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3], [4, 5, 1], [4, 1, 0]],
    );
    Model::new(vec![facet(&a), facet(&b)])
}

#[test]
fn faceted_blocks_keep_their_hard_edge() {
    let input = faceted_blocks();
    let mut fixed = input.clone();
    let changes = fix_in_place(&mut fixed, &AUTO).expect("valid");
    for (out, inp) in fixed.objects.iter().zip(&input.objects) {
        assert_eq!(bits(out), bits(inp), "{}: every normal as authored", out.name);
    }
    // (0,0,0) and (0,0,-1) on the top edge, (0,-1,0) at the front's foot.
    assert_eq!(changes.shared, SharedNormals { hard_edges: 2, agreeing: 1, ..Default::default() });
    assert_eq!(changes.normals_changed(), 0);

    // The rule of before (every shared position within the crease averaged) softens it.
    let mut old = input.clone();
    let changes = fix_in_place(&mut old, &SMOOTH_SHARED).expect("valid");
    // (The fronts' copies, coplanar, differ in their last bits: averaged too.)
    assert!(changes.normals_changed() > 0 && changes.shared.repaired == 3, "{changes:?}");
}

/// A cylinder split lengthwise into two objects, each smoothed on its own: where the halves
/// meet, each copy's faces lie in one plane (one facet column), so the copy's normal is its
/// face's normal and its object's smooth normal at once; the objects are smooth-shaded, so it
/// is a seam.
#[test]
fn a_seam_between_coplanar_facets_of_smooth_objects_is_repaired() {
    let segments = 12_u32;
    let ring = |y: f32| {
        (0..=segments).map(move |s| {
            let a = std::f32::consts::TAU * s as f32 / segments as f32;
            Vec3::new(a.cos(), y, -a.sin())
        })
    };
    let positions: Vec<Vec3> = ring(0.0).chain(ring(1.0)).chain(ring(2.0)).collect();
    let half = |name: &str, columns: std::ops::Range<u32>| {
        let w = segments + 1;
        let tris = (0..2)
            .flat_map(|r| columns.clone().map(move |c| (r, c)))
            .flat_map(|(r, c)| {
                let (a, b) = (r * w + c, (r + 1) * w + c);
                [[a, a + 1, b + 1], [a, b + 1, b]]
            })
            .collect();
        let mut o = Object::new(name, positions.clone(), tris);
        smooth_per_object(&mut o);
        o
    };
    let input = Model::new(vec![half("left", 0..6), half("right", 6..12)]);
    let mut fixed = input.clone();
    let changes = fix_in_place(&mut fixed, &AUTO).expect("valid");
    // Two seams (columns 0/12 and 6), three rings each.
    assert_eq!(changes.shared, SharedNormals { repaired: 6, ..Default::default() });
    // Column 6 is at angle pi: the repaired normal there is radial, -X.
    let left = &fixed.objects[0];
    for (p, n) in left.positions.iter().zip(left.normals.as_ref().expect("normals")) {
        if p.x < -0.999 {
            assert!(n.xz().abs_diff_eq(glam::Vec2::new(-1.0, 0.0), 1e-5), "{p}: {n}");
        }
    }
}

/// Custom normals (a weighted-normal modifier on a hard-surface model: each vertex leans
/// toward its largest face) stay as authored, seams included.
#[test]
fn custom_normals_are_kept() {
    let mut model = smooth_halves();
    for o in &mut model.objects {
        let normals = o.normals.as_mut().expect("normals");
        for n in normals.iter_mut() {
            *n = (*n + Vec3::new(0.2, 0.1, -0.15)).normalize();
        }
    }
    let mut fixed = model.clone();
    let changes = fix_in_place(&mut fixed, &AUTO).expect("valid");
    for (out, inp) in fixed.objects.iter().zip(&model.objects) {
        assert_eq!(bits(out), bits(inp), "{}", out.name);
    }
    assert_eq!(changes.shared, SharedNormals { custom: 12, ..Default::default() });
}

/// A smooth object meeting a faceted one: one side is not per-object smoothing, so nothing
/// is averaged.
#[test]
fn a_smooth_side_against_a_flat_side_is_kept() {
    let mut model = smooth_halves();
    model.objects[1] = facet(&model.objects[1]);
    let mut fixed = model.clone();
    let changes = fix_in_place(&mut fixed, &AUTO).expect("valid");
    for (out, inp) in fixed.objects.iter().zip(&model.objects) {
        assert_eq!(bits(out), bits(inp), "{}", out.name);
    }
    assert_eq!(changes.shared.repaired, 0);
    assert_eq!(changes.shared.hard_edges, 12);
    // Keep agrees.
    let mut kept = model.clone();
    fix_in_place(&mut kept, &KEEP).expect("valid");
    assert_eq!(kept, fixed);
}

/// A heightfield of quads that are not planar (each corner raised or lowered a little, as a
/// low-poly sculpt leaves them), split into two objects along a column of edges, and
/// flat-shaded per quad as Blender exports a flat-shaded mesh: every corner of a quad carries
/// the quad's normal (Newell's: the cross product of its diagonals), which lies off each of
/// its two triangles' planes by a few degrees. `quantise`: the normals stored as int8, as
/// KHR_mesh_quantization writes them.
fn non_planar_facets(quantise: bool) -> Model {
    let height = |i: u32, j: u32| {
        let h = (i * 7 + j * 13) % 5;
        0.12 * h as f32 + 0.05 * (i % 2) as f32
    };
    let corner = |i: u32, j: u32| Vec3::new(i as f32, height(i, j), -(j as f32));
    let object = |name: &str, columns: std::ops::Range<u32>| {
        let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
        for i in columns {
            for j in 0..3 {
                let p = [corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)];
                let mut n = (p[2] - p[0]).cross(p[3] - p[1]).normalize();
                if quantise {
                    n = (n * 127.0).round() / 127.0;
                }
                let base = u32::try_from(positions.len()).expect("small");
                positions.extend(p);
                normals.extend([n; 4]);
                triangles.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
            }
        }
        let mut o = Object::new(name, positions, triangles);
        o.normals = Some(normals);
        o
    };
    Model::new(vec![object("left", 0..2), object("right", 2..4)])
}

#[test]
fn flat_shaded_quads_that_are_not_planar_keep_their_facets() {
    for quantise in [false, true] {
        let input = non_planar_facets(quantise);
        // The fixture's facets are not planar: corners lie off their triangles' planes.
        let off = input.objects[0]
            .triangles
            .iter()
            .map(|t| {
                let p = t.map(|i| input.objects[0].positions[i as usize]);
                let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
                let n = input.objects[0].normals.as_ref().expect("normals")[t[0] as usize];
                face.angle_between(n.normalize()).to_degrees()
            })
            .fold(0.0_f32, f32::max);
        assert!(off > 3.0, "the quads are not planar: {off} degrees");
        let mut fixed = input.clone();
        let changes = fix_in_place(&mut fixed, &AUTO).expect("valid");
        for (out, inp) in fixed.objects.iter().zip(&input.objects) {
            assert_eq!(bits(out), bits(inp), "{}: every facet as authored ({quantise})", out.name);
        }
        assert_eq!(changes.normals_changed(), 0, "{changes:?}");
        assert_eq!(changes.shared.repaired, 0, "{:?}", changes.shared);
    }
}
