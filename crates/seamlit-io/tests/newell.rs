//! Newell patch files: object and triangle counts, shared boundary positions and orientation,
//! with expectations computed from the file text or by hand, not by the loader.

use std::collections::{HashMap, HashSet};
use std::path::PathBuf;

use seamlit_io::{IoError, LoadOptions, Syntax, newell};

fn teaset(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/models/newell_teaset/"))
        .join(name)
}

/// The file's control points and the 16 one-based indices per patch, read with plain string
/// handling (independent of the loader).
fn read_by_hand(name: &str) -> (Vec<[f32; 3]>, Vec<Vec<usize>>) {
    let text = std::fs::read_to_string(teaset(name)).unwrap();
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    let patch_count: usize = lines[0].trim().parse().unwrap();
    let patches: Vec<Vec<usize>> = lines[1..=patch_count]
        .iter()
        .map(|l| l.split(',').map(|t| t.trim().parse().unwrap()).collect())
        .collect();
    let point_count: usize = lines[patch_count + 1].trim().parse().unwrap();
    let points: Vec<[f32; 3]> = lines[patch_count + 2..patch_count + 2 + point_count]
        .iter()
        .map(|l| {
            let v: Vec<f32> = l.split(',').map(|t| t.trim().parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    (points, patches)
}

#[test]
fn teaset_objects_and_triangles() {
    // Patch counts from the first line of each file, and from SOURCES.md: 32, 26, 16.
    for (name, patches) in [("teapot", 32), ("teacup", 26), ("teaspoon", 16)] {
        for n in [1, 4, 16] {
            let asset =
                seamlit_io::load(&teaset(name), &LoadOptions::default().with_tessellation(n))
                    .unwrap();
            let model = &asset.model;
            assert_eq!(model.objects.len(), patches, "{name}");
            for object in &model.objects {
                assert_eq!(object.triangle_count(), 2 * (n * n) as usize, "{name} {}", object.name);
                assert_eq!(object.vertex_count(), ((n + 1) * (n + 1)) as usize);
                assert!(object.positions.iter().all(|p| p.is_finite()));
                let uvs = object.uvs.as_ref().unwrap();
                assert!(
                    uvs.iter().all(|t| (0.0..=1.0).contains(&t.x) && (0.0..=1.0).contains(&t.y))
                );
            }
            assert_eq!(asset.model.v_axis, seamlit_mesh::VAxis::Up);
        }
    }
}

#[test]
fn patch_corners_are_the_control_points_and_shared_between_objects() {
    // A patch passes through its four corner control points (indices 1, 4, 13, 16 of the 16).
    // Corner points used by two or more patches must appear, bit for bit, in two or more
    // objects of the tessellated model.
    for name in ["teapot", "teacup", "teaspoon"] {
        let (points, patches) = read_by_hand(name);
        let mut users: HashMap<[u32; 3], HashSet<usize>> = HashMap::new();
        for (i, patch) in patches.iter().enumerate() {
            for k in [0, 3, 12, 15] {
                users.entry(points[patch[k] - 1].map(f32::to_bits)).or_default().insert(i);
            }
        }
        let expected: HashSet<[u32; 3]> =
            users.iter().filter(|(_, u)| u.len() >= 2).map(|(p, _)| *p).collect();
        assert!(!expected.is_empty());

        let asset =
            seamlit_io::load(&teaset(name), &LoadOptions::default().with_tessellation(8)).unwrap();
        let mut holders: HashMap<[u32; 3], HashSet<usize>> = HashMap::new();
        for (i, object) in asset.model.objects.iter().enumerate() {
            for p in &object.positions {
                holders.entry(p.to_array().map(f32::to_bits)).or_default().insert(i);
            }
        }
        for p in &expected {
            assert!(
                holders.get(p).is_some_and(|h| h.len() >= 2),
                "{name}: corner {p:?} not shared"
            );
        }
    }
}

#[test]
fn pole_patches_collapse_to_one_position() {
    // Teapot patch 29 (one-based, a lid patch) repeats control point 270 four times: its
    // whole first row collapses to that point. At 8 x 8 the first row of 9 vertices must be
    // one position exactly, the control point itself (0, 0, 3.15 in the file).
    let asset =
        newell::load(&teaset("teapot"), &LoadOptions::default().with_tessellation(8)).unwrap();
    let object = asset
        .model
        .objects
        .iter()
        .find(|o| o.positions[..9].iter().all(|p| *p == o.positions[0]))
        .unwrap();
    assert_eq!(object.positions[0].to_array(), [0.0, 0.0, 3.15]);
    let pole_objects = asset
        .model
        .objects
        .iter()
        .filter(|o| o.positions[..9].iter().all(|p| *p == o.positions[0]))
        .count();
    // Counted from the file: the patches whose first four indices are equal.
    let (_, patches) = read_by_hand("teapot");
    let by_hand = patches.iter().filter(|p| p[0] == p[1] && p[1] == p[2] && p[2] == p[3]).count();
    assert_eq!(pole_objects, by_hand);
}

#[test]
fn body_faces_point_outward() {
    // Teapot patches 5..12 (one-based) are the body, a surface of revolution about z: the
    // front face of each triangle must point away from the axis.
    let asset =
        newell::load(&teaset("teapot"), &LoadOptions::default().with_tessellation(8)).unwrap();
    for object in &asset.model.objects[4..12] {
        let p = &object.positions;
        for t in &object.triangles {
            let [a, b, c] = t.map(|i| p[i as usize]);
            let normal = (b - a).cross(c - a);
            if normal.length() < 1e-6 {
                continue;
            }
            let centre = (a + b + c) / 3.0;
            let radial = glam::Vec3::new(centre.x, centre.y, 0.0);
            assert!(normal.dot(radial) > 0.0, "{}: triangle {t:?} faces inward", object.name);
        }
    }
}

#[test]
fn malformed_patch_files_get_precise_errors() {
    let good_patch = "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16";
    let points: String = (0..16).map(|i| format!("{},{},0\n", i % 4, i / 4)).collect();
    // A huge declared patch count: refused before anything is allocated for it.
    let err =
        newell::parse(&format!("4000000000\n{good_patch}\n16\n{points}"), "huge", 4).unwrap_err();
    assert!(
        matches!(err, IoError::BadCount { line: 1, declared: 4_000_000_000, what: "patches", .. }),
        "{err}"
    );
    // A huge point count.
    let err =
        newell::parse(&format!("1\n{good_patch}\n999999999999\n{points}"), "huge", 4).unwrap_err();
    assert!(matches!(err, IoError::BadCount { line: 3, what: "points", .. }), "{err}");
    // An index past the point count, on line 2.
    let bad = good_patch.replace("16", "17");
    let err = newell::parse(&format!("1\n{bad}\n16\n{points}"), "range", 4).unwrap_err();
    assert!(
        matches!(err, IoError::ReferenceOutOfRange { line: 2, index: 17, count: 16, .. }),
        "{err}"
    );
    // A NaN coordinate on line 5.
    let nan_points = points.replacen("1,0,0", "1,nan,0", 1);
    let err = newell::parse(&format!("1\n{good_patch}\n16\n{nan_points}"), "nan", 4).unwrap_err();
    assert!(matches!(err, IoError::NotFinite { line: 5, .. }), "{err}");
    // Fifteen indices.
    let err = newell::parse(&format!("1\n1,2,3\n16\n{points}"), "short", 4).unwrap_err();
    let fifteen = Syntax::TooFewValues { expected: 16, what: "control-point indices", found: 3 };
    assert!(matches!(&err, IoError::Syntax { line: 2, kind, .. } if *kind == fifteen), "{err}");
    assert_eq!(err.to_string(), "short:2: expected 16 control-point indices, found 3");
    // Truncated point list.
    let err = newell::parse(&format!("1\n{good_patch}\n16\n0,0,0\n"), "cut", 4).unwrap_err();
    assert!(matches!(err, IoError::BadCount { line: 3, remaining: 1, .. }), "{err}");
    let message = "cut:3: declares 16 points, but the file holds only 1 more non-empty lines";
    assert_eq!(err.to_string(), message);
}
