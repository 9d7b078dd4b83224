//! `seamlit fix` of an OBJ with smoothing groups, through the built binary: the groups decide
//! which faces share a normal in the file it writes.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use glam::Vec3;

/// The cube [-1, 1]^3 as six objects (`o` per side, each its own four `v` and one quad), side
/// `i` after `s {group(i)}`.
fn cube_obj(group: impl Fn(usize) -> String) -> String {
    // Per side: its outward normal and two in-plane directions.
    let sides: [(Vec3, Vec3, Vec3); 6] = [
        (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
    ];
    let mut text = String::new();
    for (i, &(n, u, v)) in sides.iter().enumerate() {
        writeln!(text, "o side{i}\ns {}", group(i)).unwrap();
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let p = n + u * a + v * b;
            writeln!(text, "v {} {} {}", p.x, p.y, p.z).unwrap();
        }
        let f = 4 * i + 1;
        writeln!(text, "f {} {} {} {}", f, f + 1, f + 2, f + 3).unwrap();
    }
    text
}

/// The outward normal of side `i` of [`cube_obj`].
const SIDE_NORMALS: [Vec3; 6] = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];

/// Runs `seamlit fix IN -o OUT --crease 180` and reads OUT back.
fn fix(dir: &Path, name: &str, text: &str) -> seamlit_io::Asset {
    let input = dir.join(format!("{name}.obj"));
    let output = dir.join(format!("{name}.fixed.obj"));
    std::fs::write(&input, text).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .args(["fix", input.to_str().unwrap(), "-o", output.to_str().unwrap(), "--crease", "180"])
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{name}: {}", String::from_utf8_lossy(&o.stderr));
    seamlit_io::load(&output, &seamlit_io::LoadOptions::default()).unwrap()
}

#[test]
fn fix_of_an_obj_cube_follows_its_smoothing_groups() {
    let dir = tempfile::tempdir().unwrap();
    for (name, group, blob) in [
        ("one", (&|_| "1".to_owned()) as &dyn Fn(usize) -> String, true),
        ("six", &|i| (i + 1).to_string(), false),
        ("off", &|_| "off".to_owned(), false),
    ] {
        let fixed = fix(dir.path(), name, &cube_obj(group));
        assert_eq!(fixed.model.objects.len(), 6, "{name}");
        for (o, side) in fixed.model.objects.iter().zip(SIDE_NORMALS) {
            let normals = o.normals.as_ref().expect("the written file has vn");
            for &v in o.triangles.as_flattened() {
                let (p, n) = (o.positions[v as usize], normals[v as usize]);
                // One group: every corner the cube's diagonal; else the side's own normal.
                let expected = if blob { p / 3f32.sqrt() } else { side };
                assert!(n.abs_diff_eq(expected, 1e-6), "{name}, {} at {p}: {n}", o.name);
            }
        }
    }
}
