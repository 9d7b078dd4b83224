//! `seamlit-bench flip`, which the web page's checks (web/test/run.sh) compare pictures with:
//! a picture is no error from itself, a changed one is, pictures of two sizes are refused, and
//! the side by side is reference | test | error map. (Being an integration test, it also has
//! `cargo test --workspace` build the program that `.ci/run` hands to those checks.)

use std::path::{Path, PathBuf};
use std::process::Command;

use image::{Rgb, RgbImage};

fn folder() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("seamlit-bench-flip");
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    dir
}

/// `seamlit-bench flip ARGS...`: its exit status success, its standard output.
fn flip(args: &[&Path]) -> (bool, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_seamlit-bench"))
        .arg("flip")
        .args(args)
        .output()
        .expect("seamlit-bench runs");
    let text = |b: Vec<u8>| String::from_utf8(b).expect("UTF-8");
    (output.status.success(), text(output.stdout), text(output.stderr))
}

#[test]
fn flip_tells_a_picture_from_a_changed_one() {
    let dir = folder();
    let byte = |v: u32| u8::try_from(v).expect("under 256");
    let gradient = RgbImage::from_fn(32, 16, |x, y| Rgb([byte(x * 8), byte(y * 16), 128]));
    let mut changed = gradient.clone();
    for (x, y) in (8..16).flat_map(|x| (4..12).map(move |y| (x, y))) {
        changed.put_pixel(x, y, Rgb([255, 255, 255]));
    }
    let (a, b, small) = (dir.join("a.png"), dir.join("b.png"), dir.join("small.png"));
    gradient.save(&a).expect("a.png");
    changed.save(&b).expect("b.png");
    RgbImage::new(8, 8).save(&small).expect("small.png");

    let (ok, same, err) = flip(&[&a, &a]);
    assert!(ok, "{err}");
    assert_eq!(same.trim(), "0.0000");

    let sheet = dir.join("side.png");
    let (ok, differ, err) = flip(&[&a, &b, Path::new("--side-by-side"), &sheet]);
    assert!(ok, "{err}");
    let mean: f32 = differ.trim().parse().expect("a number");
    // A white square over an eighth of the picture.
    assert!((0.02..0.5).contains(&mean), "{mean}");
    let sheet = image::open(&sheet).expect("the side by side").to_rgb8();
    assert_eq!(sheet.dimensions(), (96, 16));
    assert_eq!(sheet.get_pixel(32 + 12, 8), &Rgb([255, 255, 255]), "the test picture second");
    assert_ne!(sheet.get_pixel(64 + 12, 8), sheet.get_pixel(64, 0), "the error map third");

    let (ok, _, err) = flip(&[&a, &small]);
    assert!(!ok && err.contains("small.png: 8x8, but"), "{err}");
}
