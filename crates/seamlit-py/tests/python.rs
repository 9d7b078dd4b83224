//! Runs the Python package's pytest suite (`crates/seamlit-py/tests/*.py`, the Blender
//! add-on's included) against the extension module this `cargo test` just built, so that
//! the README's one test command covers the Python side too.
//!
//! The module is the crate's cdylib in the target folder (`lib_seamlit.so`); it is copied
//! with the package's Python files into a temporary `seamlit/` folder put on `PYTHONPATH`.
//! Needs Python 3 with numpy, pytest, trimesh, bpy (Blender as a module), ray, pyarrow and
//! moto (seamlit.ray's tests): `.ci/run` installs them; the test fails, saying what to
//! install, when they are missing.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The folder cargo puts the workspace's artifacts in (`target/debug`): the test binary
/// lies in its `deps/`.
fn artifacts() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    exe.parent().and_then(Path::parent).expect("target/debug/deps/TEST").to_path_buf()
}

fn python() -> String {
    std::env::var("PYTHON").unwrap_or_else(|_| "python3".to_owned())
}

/// Copies the package's files, its subpackages (`seamlit.ray`) included, skipping caches.
fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap();
        if path.is_dir() {
            if name != "__pycache__" {
                copy_tree(&path, &to.join(name));
            }
        } else {
            std::fs::copy(&path, to.join(name)).unwrap();
        }
    }
}

#[test]
fn the_python_package_and_the_blender_add_on_pass_their_tests() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let artifacts = artifacts();
    // The cdylib this build made lies beside the test binary, in deps/ (cargo copies it up
    // to target/debug only for `cargo build`).
    let deps = artifacts.join("deps");
    let library = ["lib_seamlit.so", "lib_seamlit.dylib", "_seamlit.dll"]
        .iter()
        .map(|name| deps.join(name))
        .find(|p| p.is_file())
        .unwrap_or_else(|| {
            panic!("no lib_seamlit in {}: cargo builds it with the crate", artifacts.display())
        });
    let cli = artifacts.join("seamlit");
    assert!(
        cli.is_file(),
        "{} is missing: the tests compare the package with the command line (cargo build -p seamlit)",
        cli.display()
    );
    let missing = Command::new(python())
        .args(["-c", "import numpy, pytest, trimesh, bpy, ray, pyarrow, moto"])
        .output()
        .expect("python3 is needed for the Python package's tests");
    assert!(
        missing.status.success(),
        "the Python tests need numpy, pytest, trimesh, bpy, ray, pyarrow and moto (pip install numpy pytest trimesh bpy==5.0.1 'ray[data]==2.60.0' 'pyarrow<22' 'pandas<3' 'moto[server]'): {}",
        String::from_utf8_lossy(&missing.stderr)
    );

    let root = tempfile::tempdir().expect("a temporary folder");
    let package = root.path().join("seamlit");
    copy_tree(&crate_dir.join("python/seamlit"), &package);
    let suffix = if cfg!(windows) { "pyd" } else { "so" };
    std::fs::copy(&library, package.join(format!("_seamlit.{suffix}"))).unwrap();

    let status = Command::new(python())
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .arg(crate_dir.join("tests"))
        .env("PYTHONPATH", root.path())
        .env("SEAMLIT_BIN", &cli)
        .env("SEAMLIT_REPO", crate_dir.join("../.."))
        .status()
        .expect("python3 -m pytest");
    assert!(status.success(), "pytest failed (its output is above)");
}
