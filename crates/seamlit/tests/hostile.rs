//! Hostile files through the binary: every input of seamlit-io's regression corpus (made by
//! hand or found by the fuzz targets in fuzz/) gives exit status 0 or 2 and, when it fails,
//! exactly one error line naming the file, never a panic; a folder run reports each bad file
//! and carries on, also past a panic (a bug) in one file; outputs never write through a
//! symlink; a write failure is exit status 1.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn seamlit(args: &[&str]) -> Output {
    seamlit_with(args, &[])
}

fn seamlit_with(args: &[&str], env: &[(&str, &str)]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .envs(env.iter().copied())
        .output()
        .expect("the binary runs")
}

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../seamlit-io/tests/regressions")
}

/// The regression inputs (files only; their side files live in subfolders).
fn inputs() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(corpus())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    assert!(files.len() >= 20, "the corpus is missing: {files:?}");
    files
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn error_lines(o: &Output) -> Vec<String> {
    stderr(o).lines().filter(|l| l.starts_with("error: ")).map(str::to_owned).collect()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

const GOOD: &str = "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

#[test]
fn inspect_and_fix_of_every_regression_input_fail_cleanly_or_succeed() {
    let out = tempfile::tempdir().unwrap();
    let mut problems = Vec::new();
    for input in inputs() {
        let name = input.file_name().unwrap().to_string_lossy().into_owned();
        let stem = input.file_stem().unwrap().to_string_lossy().into_owned();
        let path = input.display().to_string();
        let output = out.path().join(format!("{stem}.glb"));
        for args in [
            vec!["inspect", path.as_str()],
            vec!["fix", path.as_str(), "-o", output.to_str().unwrap()],
        ] {
            let o = seamlit(&args);
            let errors = error_lines(&o);
            let what = format!("{name}: seamlit {}", args[0]);
            match o.status.code() {
                Some(0) if errors.is_empty() => {}
                Some(2) if errors.len() == 1 && errors[0].contains(&stem) => {}
                code => problems.push(format!("{what}: status {code:?}, stderr {:?}", stderr(&o))),
            }
            if stderr(&o).contains("panicked") {
                problems.push(format!("{what}: panicked: {}", stderr(&o)));
            }
            if args[0] == "fix" && o.status.code() == Some(2) && output.exists() {
                problems.push(format!("{what}: failed but left {}", output.display()));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn a_folder_of_hostile_files_reports_each_and_fixes_the_good_one() {
    let input = tempfile::tempdir().unwrap();
    let bad: Vec<String> = inputs()
        .into_iter()
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy();
            // Not bad here: an oversized texture is only a warning, and the MTL input's
            // library (in a subfolder, not copied) is then merely missing; the glTF inputs
            // of issue 32 that load (a channel that cannot be played is skipped with a
            // warning; a morph target's NORMAL is not read), and the .usdc of issue 33 whose
            // child that is not a name is skipped.
            !n.contains("texture_declares")
                && !n.contains("mtl_colour")
                && !n.starts_with("gltf_animation_channel_")
                && !n.contains("morph_target_normal_count_0")
                && !n.contains("usd_usdc_prim_child_not_a_name")
        })
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            std::fs::copy(&p, input.path().join(&name)).unwrap();
            name
        })
        .collect();
    write(input.path(), "good.obj", GOOD);
    let out = tempfile::tempdir().unwrap();
    let fixed = out.path().join("fixed");
    let o = seamlit(&["fix", input.path().to_str().unwrap(), "-o", fixed.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let errors = error_lines(&o);
    // One line per bad file, each naming its file, then the summary.
    for name in &bad {
        let lines: Vec<&String> = errors.iter().filter(|e| e.contains(name.as_str())).collect();
        assert_eq!(lines.len(), 1, "{name}: {errors:?}");
    }
    let total = bad.len() + 1;
    assert!(
        errors.last().unwrap().contains(&format!("{} of {total} models failed", bad.len())),
        "{errors:?}"
    );
    assert_eq!(errors.len(), bad.len() + 1, "{errors:?}");
    assert!(!stderr(&o).contains("panicked"));
    let written: Vec<String> = std::fs::read_dir(&fixed)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(written, ["good.glb"]);
}

#[test]
fn an_mtllib_outside_the_model_folder_is_refused_by_the_binary() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("model")).unwrap();
    write(dir.path(), "secret.mtl", "newmtl m\nKd 1 0 0\n");
    let obj = write(&dir.path().join("model"), "m.obj", &format!("mtllib ../secret.mtl\n{GOOD}"));
    let o = seamlit(&["inspect", obj.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let errors = error_lines(&o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(errors[0].contains("m.obj:1:"), "{errors:?}");
    assert!(errors[0].contains("leaves the model's folder"), "{errors:?}");
}

#[test]
fn fix_replaces_a_symlinked_output_instead_of_writing_through_it() {
    let dir = tempfile::tempdir().unwrap();
    let victim = write(dir.path(), "victim.glb", "precious");
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let link = out.join("m.glb");
    std::os::unix::fs::symlink(&victim, &link).unwrap();
    let model = write(dir.path(), "m.obj", GOOD);
    let o = seamlit(&["fix", model.to_str().unwrap(), "-o", link.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_file());
    assert!(std::fs::read(&link).unwrap().starts_with(b"glTF"));
}

#[test]
fn a_failed_replacement_keeps_the_old_output_and_a_write_failure_is_status_1() {
    let dir = tempfile::tempdir().unwrap();
    let model = write(dir.path(), "m.obj", GOOD);
    // The output's folder is a file: nothing can be written there.
    let blocker = write(dir.path(), "blocker", "a file, not a folder");
    let output = blocker.join("m.glb");
    let o = seamlit(&["fix", model.to_str().unwrap(), "-o", output.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let errors = error_lines(&o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    // The line names the folder at fault (crate::output's rule: missing folders are made).
    assert!(errors[0].contains("blocker: cannot create the output folder"), "{errors:?}");
    assert_eq!(std::fs::read_to_string(&blocker).unwrap(), "a file, not a folder");
    // A bad input never touches an existing output.
    let existing = write(dir.path(), "existing.glb", "old contents");
    let bad = write(dir.path(), "bad.obj", "v 0 0 0\nf 1 2 3\n");
    let o = seamlit(&["fix", bad.to_str().unwrap(), "-o", existing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&existing).unwrap(), "old contents");
}

/// Folder mode fixes small files on several threads at once: each file that panics is
/// reported with its own panic's message and place, whichever thread caught which.
#[test]
fn panics_in_files_fixed_at_once_are_each_their_own_file_s() {
    let input = tempfile::tempdir().unwrap();
    let names: Vec<String> =
        (0..12).map(|i| format!("{}{i:02}.obj", ["ok", "boom"][i % 2])).collect();
    for name in &names {
        write(input.path(), name, GOOD);
    }
    let out = tempfile::tempdir().unwrap();
    let fixed = out.path().join("fixed");
    let env = [("SEAMLIT_DEBUG_PANIC_ON", "boom"), ("RAYON_NUM_THREADS", "4")];
    let o =
        seamlit_with(&["fix", input.path().to_str().unwrap(), "-o", fixed.to_str().unwrap()], &env);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let errors = error_lines(&o);
    let booms: Vec<&String> = names.iter().filter(|n| n.starts_with("boom")).collect();
    assert_eq!(errors.len(), booms.len() + 1, "{errors:?}");
    // In the folder's order, each with its own message and place.
    for (line, name) in errors.iter().zip(&booms) {
        assert!(
            line.contains(&format!("{name}: internal error"))
                && line.contains(&format!("SEAMLIT_DEBUG_PANIC_ON matched \"{name}\" at "))
                && line.contains("fix.rs:"),
            "{name}: {line}"
        );
    }
}

#[test]
fn a_panic_in_one_file_of_a_folder_is_its_internal_error_and_the_others_go_on() {
    let input = tempfile::tempdir().unwrap();
    for name in ["a.obj", "boom.obj", "c.obj"] {
        write(input.path(), name, GOOD);
    }
    let out = tempfile::tempdir().unwrap();
    let fixed = out.path().join("fixed");
    // The debugging aid of `seamlit fix` (crates/seamlit/src/cmd/fix.rs): files whose name
    // contains the text panic while they are processed.
    let panic_on = [("SEAMLIT_DEBUG_PANIC_ON", "boom")];
    let args = ["fix", input.path().to_str().unwrap(), "-o", fixed.to_str().unwrap()];
    let o = seamlit_with(&args, &panic_on);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let errors = error_lines(&o);
    assert_eq!(errors.len(), 2, "{errors:?}");
    assert!(
        errors[0].contains("boom.obj: internal error")
            && errors[0].contains("SEAMLIT_DEBUG_PANIC_ON matched \"boom.obj\" at ")
            && errors[0].contains("fix.rs:"),
        "{errors:?}"
    );
    assert!(errors[1].contains("1 of 3 models failed"), "{errors:?}");
    // The panic is that one line: no default panic report, no backtrace hint.
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("RUST_BACKTRACE"), "{}", stderr(&o));
    let mut written: Vec<String> = std::fs::read_dir(&fixed)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(written, ["a.glb", "c.glb"]);

    // One file: the same line, status 1, no output.
    let boom = input.path().join("boom.obj");
    let output = out.path().join("boom.glb");
    let o =
        seamlit_with(&["fix", boom.to_str().unwrap(), "-o", output.to_str().unwrap()], &panic_on);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let errors = error_lines(&o);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(errors[0].contains("boom.obj: internal error"), "{errors:?}");
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    assert!(!output.exists());
}

/// Files with nothing to fix, or that are not text: every command that loads a model says so
/// in one line naming the file, with exit status 2, and `fix` writes nothing.
#[test]
fn a_model_without_triangles_or_text_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let files: [(&str, &[u8], &str); 5] = [
        ("empty.obj", b"", "no triangles"),
        ("points.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no triangles"),
        ("unknown.obj", b"xyz 1 2\nzq\n\tkk 7\n", "no triangles"),
        ("nul.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nq \x00\x01\n", "nul.obj:5: a NUL byte"),
        // Latin-1 where numbers belong (a Latin-1 name is read: others_files.rs).
        (
            "latin1.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\no cafe\nf 1 2 \xb3\n",
            "latin1.obj:5: invalid UTF-8",
        ),
    ];
    for (name, bytes, needle) in files {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let path = path.display().to_string();
        let output = dir.path().join("out.glb");
        let out = output.display().to_string();
        for args in [vec!["fix", path.as_str(), "-o", out.as_str()], vec!["inspect", &path]] {
            let o = seamlit(&args);
            assert_eq!(o.status.code(), Some(2), "{name} {}: {}", args[0], stderr(&o));
            let err = stderr(&o);
            let lines: Vec<&str> = err.lines().collect();
            assert_eq!(lines.len(), 1, "{name} {}: {lines:?}", args[0]);
            assert!(lines[0].starts_with("error: ") && lines[0].contains(name), "{lines:?}");
            assert!(lines[0].contains(needle), "{name}: {lines:?} lacks {needle:?}");
            assert!(!output.exists(), "{name}: {} wrote {out}", args[0]);
        }
    }
}

/// Issue 32: `seamlit fix` over the whole glTF Validator corpus (its 372 test files, 243 of
/// them invalid) writes the files with triangles, reports every other file in one line
/// naming it (exit status 2) and never an internal error (before, two files with animation
/// channels the gltf crate could not resolve panicked).
#[test]
fn fix_of_the_validator_corpus_reports_each_bad_file_and_no_internal_error() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/validator-corpus");
    let out = tempfile::tempdir().unwrap();
    let o = seamlit(&[
        "fix",
        corpus.to_str().unwrap(),
        "-o",
        out.path().to_str().unwrap(),
        "--format",
        "glb",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!stderr(&o).contains("internal error"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    let errors = error_lines(&o);
    // One line per bad file, then the summary.
    assert!(errors.len() > 300, "{errors:?}");
    let summary = errors.last().unwrap();
    assert!(summary.contains(&format!("{} of 372 models failed", errors.len() - 1)), "{summary}");
}
