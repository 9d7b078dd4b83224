//! End-to-end tests of every subcommand through the built binary: success, bad arguments and
//! bad files (exit status 2, one line naming the file and the problem, no output left).
//!
//! One test binary, a module per group of commands; the helpers they share are here.

mod files;
mod fix;
mod render;
mod usage;
mod view;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn seamlit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the binary runs")
}

fn models() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models")
}

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(name).display().to_string()
}

fn teapot() -> String {
    models().join("newell_teaset/teapot").display().to_string()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The lines of stderr that are ours (drivers print their own noise, e.g. about
/// XDG_RUNTIME_DIR).
fn errors(o: &Output) -> Vec<String> {
    String::from_utf8_lossy(&o.stderr)
        .lines()
        .filter(|l| l.starts_with("error: ") && !l.contains("XDG_RUNTIME_DIR"))
        .map(str::to_owned)
        .collect()
}

/// Exit status 2, exactly one error line, and that line contains every one of `needles`.
fn assert_bad_input(o: &Output, needles: &[&str]) {
    assert_eq!(
        o.status.code(),
        Some(2),
        "stdout: {}\nstderr: {}",
        stdout(o),
        String::from_utf8_lossy(&o.stderr)
    );
    let errors = errors(o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    for n in needles {
        assert!(errors[0].contains(n), "{:?} lacks {n:?}", errors[0]);
    }
    assert!(!String::from_utf8_lossy(&o.stderr).contains("panicked"));
}

/// Files in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

/// Pixels that differ clearly from the top-left (background) pixel.
fn foreground_fraction(img: &image::RgbaImage, x0: u32) -> f64 {
    let bg = img.get_pixel(img.width() - 1, img.height() - 1).0;
    let mut count = 0u64;
    let mut total = 0u64;
    for (x, _, p) in img.enumerate_pixels() {
        if x < x0 {
            continue;
        }
        total += 1;
        let d: i32 = (0..3).map(|k| (i32::from(p.0[k]) - i32::from(bg[k])).abs()).sum();
        if d > 30 {
            count += 1;
        }
    }
    count as f64 / total.max(1) as f64
}
