//! OBJ smoothing groups (`s N`, `s off`, `s 0`): read per triangle, written back, and used by
//! `fix`. Every expected value is written out by hand from the fixture's text.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::Vec3;
use seamlit_io::{InvalidAsset, IoError, LoadOptions, SaveOptions};
use seamlit_mesh::{FixOptions, fix};

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn load(dir: &Path, name: &str, text: &str) -> seamlit_io::Asset {
    seamlit_io::load(&write(dir, name, text), &LoadOptions::default()).unwrap()
}

fn groups(asset: &seamlit_io::Asset) -> Vec<Option<Vec<u32>>> {
    asset.model.objects.iter().map(|o| o.smoothing_groups.clone()).collect()
}

/// Six corners of a convex hexagon-ish fan in z = 0; faces below use them.
const VERTICES: &str = "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 2 0\nv -1 1 0\n";

#[test]
fn groups_are_read_per_triangle_and_a_polygon_shares_its_group() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "{VERTICES}o first\n\
         f 1 2 3\n\
         s 1\n\
         f 1 3 4\n\
         f 1 2 3 4\n\
         s off\n\
         f 1 4 5\n\
         s 2 # a comment after the number\n\
         f 1 2 3 4 5\n\
         o second\n\
         f 1 5 6\n\
         s 0\n\
         f 1 2 3\n\
         s 4294967295\n\
         f 1 3 4\n"
    );
    let asset = load(dir.path(), "groups.obj", &text);
    // Before the first `s`: 0; the quad's two and the pentagon's three triangles share their
    // polygon's group; `s` carries over `o`.
    assert_eq!(groups(&asset), [Some(vec![0, 1, 1, 1, 0, 2, 2, 2]), Some(vec![2, 0, u32::MAX])],);
}

#[test]
fn a_file_without_s_has_no_groups() {
    let dir = tempfile::tempdir().unwrap();
    let asset = load(dir.path(), "plain.obj", &format!("{VERTICES}o a\nf 1 2 3\no b\nf 1 3 4\n"));
    assert_eq!(groups(&asset), [None, None]);
}

#[test]
fn a_bad_group_is_a_syntax_error_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    for (bad, line) in [("s smooth", 7), ("s -1", 7), ("s", 7), ("s 4294967296", 7)] {
        let path = write(dir.path(), "bad.obj", &format!("{VERTICES}{bad}\nf 1 2 3\n"));
        let err = seamlit_io::load(&path, &LoadOptions::default()).unwrap_err();
        assert!(matches!(err, IoError::Syntax { line: l, .. } if l == line), "{bad}: {err}");
        assert!(err.to_string().contains("`s`"), "{bad}: {err}");
    }
}

#[test]
fn groups_carry_across_the_parser_s_blocks() {
    // Over 2 MiB of text, so the parser reads several blocks: `s 3` in the first block,
    // `s off` then `s 5` far into a later one, and faces on both sides of every cut.
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from(VERTICES);
    text.push_str("s 3\n");
    let faces = 120_000;
    for k in 0..faces {
        if k == 80_000 {
            text.push_str("s off\ns 5\n");
        }
        text.push_str("f 1 2 3\n");
        // Padding that makes the file long without adding faces.
        writeln!(text, "# {k:040}").unwrap();
    }
    assert!(text.len() > 2 << 20, "{}", text.len());
    let asset = load(dir.path(), "long.obj", &text);
    let got = asset.model.objects[0].smoothing_groups.as_ref().unwrap();
    let mut expected = vec![3; 80_000];
    expected.resize(faces, 5);
    assert!(
        *got == expected,
        "first difference at {:?}",
        got.iter().zip(&expected).position(|(a, b)| a != b)
    );
}

#[test]
fn groups_survive_an_obj_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("{VERTICES}f 1 2 3\ns 1\nf 1 3 4\ns off\nf 1 4 5\ns 7\nf 1 5 6\n");
    let asset = load(dir.path(), "in.obj", &text);
    let out = dir.path().join("out.obj");
    seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap();
    let back = seamlit_io::load(&out, &LoadOptions::default()).unwrap();
    assert_eq!(groups(&back), [Some(vec![0, 1, 0, 7])]);
}

#[test]
fn objects_without_groups_are_written_in_a_group_of_their_own() {
    let dir = tempfile::tempdir().unwrap();
    let triangle =
        || seamlit_mesh::Object::new("t", vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]);
    let objects = vec![
        triangle().with_smoothing_groups(vec![3]),
        triangle(),
        triangle().with_smoothing_groups(vec![0]),
        triangle(),
    ];
    let mut asset = seamlit_io::Asset {
        model: seamlit_mesh::Model::new(objects),
        ..seamlit_io::Asset::default()
    };
    let out = dir.path().join("out.obj");
    seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap();
    let back = seamlit_io::load(&out, &LoadOptions::default()).unwrap();
    // One above the largest group used (3), shared by both objects without groups.
    let expected = [Some(vec![3]), Some(vec![4]), Some(vec![0]), Some(vec![4])];
    assert_eq!(groups(&back), expected);

    // A wrong length is refused, naming the object, and nothing is written.
    asset.model.objects[1].smoothing_groups = Some(vec![1, 1]);
    let out = dir.path().join("bad.obj");
    let err = seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            IoError::InvalidAsset {
                kind: InvalidAsset::SmoothingGroups { groups: 2, triangles: 1 },
                ..
            }
        ),
        "{err}"
    );
    assert!(!out.exists());
}

/// The cube [-1, 1]^3 as six objects (`o` per side, each its own four `v`), side `i` in
/// smoothing group `group(i)` (as written after `s`).
fn cube_obj(group: impl Fn(usize) -> &'static str) -> String {
    // Per side: its outward normal's axis and sign, and two in-plane directions.
    let sides: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
        ([1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
        ([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        ([0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    ];
    let mut text = String::new();
    for (i, (n, u, v)) in sides.iter().enumerate() {
        writeln!(text, "o side{i}\ns {}", group(i)).unwrap();
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let p: Vec<f32> = (0..3).map(|k| n[k] + u[k] * a + v[k] * b).collect();
            writeln!(text, "v {} {} {}", p[0], p[1], p[2]).unwrap();
        }
        let f = 4 * i + 1;
        writeln!(text, "f {} {} {} {}", f, f + 1, f + 2, f + 3).unwrap();
    }
    text
}

#[test]
fn fix_of_an_obj_cube_follows_its_groups() {
    let dir = tempfile::tempdir().unwrap();
    let smooth = FixOptions { crease_angle_deg: 180.0, ..FixOptions::default() };
    let names = ["1", "2", "3", "4", "5", "6"];
    for (name, group, blob) in [
        ("one.obj", (&|_| "1") as &dyn Fn(usize) -> &'static str, true),
        ("six.obj", &|i| names[i], false),
        ("off.obj", &|_| "off", false),
    ] {
        let asset = load(dir.path(), name, &cube_obj(group));
        let fixed = fix(&asset.model, &smooth).unwrap();
        for o in &fixed.objects {
            let normals = o.normals.as_ref().unwrap();
            // The side's own normal: the mean of its four input corners (splits come after).
            let side = (o.positions[..4].iter().sum::<Vec3>() / 4.0).normalize();
            for &v in o.triangles.as_flattened() {
                let (p, n) = (o.positions[v as usize], normals[v as usize]);
                // One group: every corner the cube's diagonal; else the side's normal.
                let expected = if blob { p / 3f32.sqrt() } else { side };
                assert!(n.abs_diff_eq(expected, 1e-6), "{name}, {} at {p}: {n}", o.name);
            }
        }
    }
}
