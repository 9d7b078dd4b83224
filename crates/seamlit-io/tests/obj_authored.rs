//! OBJ files as their authors wrote them: concave polygons. Every fixture is made here, with expected values computed
//! independently of the loader.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::{DQuat, DVec2, DVec3};
use seamlit_io::LoadOptions;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A star of 33 points (66 corners, every other one reflex) in the plane z = 0.
fn star() -> Vec<DVec2> {
    (0..66)
        .map(|k| {
            let angle = f64::from(k) * std::f64::consts::TAU / 66.0;
            let radius = if k % 2 == 0 { 1.0 } else { 0.45 };
            DVec2::new(angle.cos(), angle.sin()) * radius
        })
        .collect()
}

#[test]
fn a_concave_66_gon_is_ear_clipped_facing_its_normal_with_its_area() {
    let star = star();
    // The polygon's area by the shoelace formula, in its own plane.
    let area = (0..66).map(|i| star[i].perp_dot(star[(i + 1) % 66])).sum::<f64>() / 2.0;
    assert!(area > 0.5, "counter-clockwise, {area}");
    // Placed on a tilted plane away from the origin.
    let rotation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let offset = DVec3::new(5.0, -2.0, 1.0);
    let normal = (rotation * DVec3::Z).as_vec3();
    let mut text = String::from("o star\n");
    for p in &star {
        let q = (rotation * p.extend(0.0) + offset).as_vec3();
        writeln!(text, "v {} {} {}", q.x, q.y, q.z).unwrap();
    }
    text.push('f');
    for k in 1..=66 {
        write!(text, " {k}").unwrap();
    }
    text.push('\n');
    let dir = tempfile::tempdir().unwrap();
    let asset =
        seamlit_io::load(&write(dir.path(), "star.obj", &text), &LoadOptions::default()).unwrap();
    let object = &asset.model.objects[0];
    let p = &object.positions;
    let twice_area = |t: [u32; 3]| {
        let [a, b, c] = t.map(|i| p[i as usize]);
        (b - a).cross(c - a)
    };
    // The fixture is one a fan gets wrong: some fan triangles face backwards.
    let fan_backwards = (1..65)
        .filter(|&k| {
            let [a, b, c] = [0, k, k + 1].map(|i| (rotation * star[i].extend(0.0)).as_vec3());
            (b - a).cross(c - a).dot(normal) < 0.0
        })
        .count();
    assert!(fan_backwards > 10, "{fan_backwards}");

    assert_eq!(object.triangles.len(), 64);
    let mut total = 0.0f64;
    for &t in &object.triangles {
        let n = twice_area(t);
        assert!(n.dot(normal) > 0.0, "{t:?} faces away from the polygon's normal");
        total += f64::from(n.length()) / 2.0;
    }
    assert!((total - area).abs() < 1e-5 * area, "{total} vs {area}");
}

#[test]
fn convex_polygons_keep_the_fan() {
    // A regular octagon and a square, as exporters write n-gons: the fan, exactly.
    let mut text = String::new();
    for k in 0..8 {
        let a = k as f32 * std::f32::consts::TAU / 8.0;
        writeln!(text, "v {} {} 0.5", a.cos(), a.sin()).unwrap();
    }
    text.push_str("f 1 2 3 4 5 6 7 8\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 9 10 11 12\n");
    let dir = tempfile::tempdir().unwrap();
    let asset =
        seamlit_io::load(&write(dir.path(), "convex.obj", &text), &LoadOptions::default()).unwrap();
    let fan: Vec<[u32; 3]> =
        (1..7).map(|k| [0, k, k + 1]).chain([[8, 9, 10], [8, 10, 11]]).collect();
    assert_eq!(asset.model.objects[0].triangles, fan);
}

#[test]
fn a_self_intersecting_polygon_keeps_its_fan() {
    // A bow tie has no right triangulation: what tobj gives stays.
    let text = "v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n";
    let dir = tempfile::tempdir().unwrap();
    let asset =
        seamlit_io::load(&write(dir.path(), "bow.obj", text), &LoadOptions::default()).unwrap();
    assert_eq!(asset.model.objects[0].triangles, [[0, 1, 2], [0, 2, 3]]);
}
