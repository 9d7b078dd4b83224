//! Helpers shared by the integration tests: model paths, an independent OBJ counter, an
//! independent glTF reader (`gltf.rs`), structure-aware mutations of glTF documents
//! (`mutate.rs`) and the Khronos glTF Validator.

#![allow(dead_code, reason = "each test binary uses a different subset")]

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::process::Command;

use seamlit_mesh::Model;

pub mod gltf;
pub mod mutate;

/// `i`, an index or count a test file holds (JSON numbers are `u64`), as a `usize`.
pub fn usize_of(i: u64) -> usize {
    usize::try_from(i).expect("an index that fits usize")
}

/// `x`, a float a test file holds (JSON numbers are `f64`), rounded to `f32` as the loader
/// rounds it.
#[expect(clippy::cast_possible_truncation, reason = "rounding to f32 is the point")]
pub fn f32_of(x: f64) -> f32 {
    x as f32
}

/// A file under assets/models (the small test models kept in the repository).
pub fn model(relative: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/models/")).join(relative)
}

/// What an OBJ file holds, counted with plain string handling (not the loader): per object
/// (a run of faces after an `o` or `g` line), its name, its triangle count (a face of n
/// corners is n - 2 triangles) and the bit patterns of the positions its faces use.
pub struct ObjCount {
    pub objects: Vec<(String, usize, HashSet<[u32; 3]>)>,
}

impl ObjCount {
    pub fn of_text(text: &str) -> Self {
        let mut positions: Vec<[u32; 3]> = Vec::new();
        let mut objects: Vec<(String, usize, HashSet<[u32; 3]>)> = Vec::new();
        let mut name = "unnamed_object".to_owned();
        let mut open = false; // whether the current name already has an entry
        for line in text.lines() {
            let line = line.trim();
            if let Some(rest) = line.strip_prefix("v ") {
                let v: Vec<f32> =
                    rest.split_whitespace().take(3).map(|t| t.parse().unwrap()).collect();
                positions.push([v[0].to_bits(), v[1].to_bits(), v[2].to_bits()]);
            } else if let Some(rest) = line.strip_prefix("o ").or_else(|| line.strip_prefix("g ")) {
                name = rest.trim().to_owned();
                open = false;
            } else if let Some(rest) = line.strip_prefix("f ") {
                if !open {
                    objects.push((name.clone(), 0, HashSet::new()));
                    open = true;
                }
                let corners: Vec<&str> = rest.split_whitespace().collect();
                let entry = objects.last_mut().unwrap();
                entry.1 += corners.len() - 2;
                for c in corners {
                    let i: i64 = c.split('/').next().unwrap().parse().unwrap();
                    let i = if i < 0 { positions.len() as i64 + i } else { i - 1 };
                    entry.2.insert(positions[usize::try_from(i).unwrap()]);
                }
            }
        }
        Self { objects }
    }

    pub fn of_file(relative: &str) -> Self {
        Self::of_text(&std::fs::read_to_string(model(relative)).unwrap())
    }

    /// Distinct positions used by two or more objects.
    pub fn shared_positions(&self) -> usize {
        shared(self.objects.iter().map(|(_, _, p)| p.clone()))
    }
}

/// Distinct positions (bit patterns, model space) that appear in two or more objects.
pub fn shared_positions(model: &Model) -> usize {
    shared(model.objects.iter().map(|o| {
        let m = o.model_transform();
        o.positions.iter().map(|&p| m.transform_point3(p).to_array().map(f32::to_bits)).collect()
    }))
}

fn shared(sets: impl Iterator<Item = HashSet<[u32; 3]>>) -> usize {
    let mut users: HashMap<[u32; 3], usize> = HashMap::new();
    for set in sets {
        for p in set {
            *users.entry(p).or_default() += 1;
        }
    }
    users.values().filter(|&&n| n >= 2).count()
}

/// Runs tests/validate.cjs (the Khronos glTF Validator, npm package `gltf-validator`, which
/// `.ci/run` installs into .ci/node) and returns (errors, the whole report line).
///
/// Panics (fails the test) when node or the validator is missing: run `.ci/run`, or
/// `npm install --prefix .ci/node gltf-validator` once.
pub fn validate(file: &Path) -> (u64, String) {
    validate_many(&[file.to_path_buf()]).pop().expect("one report for one file")
}

/// Runs the Khronos glTF Validator on many files with one node start-up: per file, in order,
/// the number of errors and the report line (as [`validate`]).
pub fn validate_many(files: &[PathBuf]) -> Vec<(u64, String)> {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/validate.cjs");
    let output = Command::new("node")
        .arg(script)
        .args(files)
        .output()
        .expect("node is needed for the glTF validator test (Debian package nodejs)");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "the glTF validator did not run (install it: npm install --prefix .ci/node gltf-validator): {}{}",
        stdout,
        String::from_utf8_lossy(&output.stderr)
    );
    let reports: Vec<(u64, String)> = stdout
        .lines()
        .map(|line| {
            let report: serde_json::Value = serde_json::from_str(line).expect("validator report");
            (report["errors"].as_u64().expect("error count"), line.to_owned())
        })
        .collect();
    assert_eq!(reports.len(), files.len(), "one report per file: {stdout}");
    reports
}

/// Loads `input`, fixes it in place with the default options, saves it as `output` (the
/// format from its extension); returns the save's warnings.
pub fn fix_and_save(input: &Path, output: &Path) -> Vec<String> {
    let mut asset = seamlit_io::load(input, &seamlit_io::LoadOptions::GEOMETRY).unwrap();
    seamlit_mesh::fix_in_place(&mut asset.model, &seamlit_mesh::FixOptions::default()).unwrap();
    seamlit_io::save(&asset, output, &seamlit_io::SaveOptions::default()).unwrap().warnings
}

/// Asserts that the Khronos glTF Validator reports no error in `path`.
pub fn assert_valid(path: &Path) {
    let (errors, report) = validate(path);
    assert_eq!(errors, 0, "{}: {report}", path.display());
}

/// Runs tests/usd/pxr_check.py `command` with Pixar's USD (PyPI usd-core, through `python3`
/// or `$PYTHON`) on `inputs`, then the path of the JSON it writes, then `extra`; returns that
/// JSON.
pub fn pxr_check<S: AsRef<std::ffi::OsStr> + std::fmt::Debug>(
    command: &str,
    inputs: &[S],
    extra: &[&str],
) -> serde_json::Value {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/usd/pxr_check.py");
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".to_owned());
    let out = tempfile::NamedTempFile::new().unwrap();
    let output = Command::new(python)
        .arg(script)
        .arg(command)
        .args(inputs)
        .arg(out.path())
        .args(extra)
        .output()
        .expect("python3 with usd-core (pip install usd-core) is needed for the USD tests");
    assert!(
        output.status.success(),
        "pxr_check.py {command} {inputs:?} {extra:?} failed (is usd-core installed? pip install usd-core):\n{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(out.path()).unwrap()).unwrap()
}
