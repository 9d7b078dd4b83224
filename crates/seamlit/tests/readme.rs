//! Every command line that README.md, docs/rendering.md and the example scenes show runs as
//! written, from the repository's root, through the built binary. Placeholder file names (`model.obj`,
//! `scene.toml`, `DIR`...) stand for the repository's own models and for files in a temporary
//! folder; optional parts in brackets (`[--json]`) are run with the option.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().unwrap()
}

/// The command lines of `text`'s ```sh blocks that run seamlit (`cargo run --release --`
/// is the binary), without their comments.
fn readme_lines(text: &str) -> Vec<String> {
    let mut lines = Vec::new();
    let mut in_sh = false;
    for line in text.lines() {
        if line.starts_with("```") {
            in_sh = line.trim() == "```sh";
            continue;
        }
        let command = line.split(" # ").next().unwrap_or("").trim();
        if in_sh && command.starts_with("seamlit ") {
            lines.push(command.to_owned());
        } else if in_sh && let Some(rest) = command.strip_prefix("cargo run --release -- ") {
            lines.push(format!("seamlit {rest}"));
        }
    }
    lines
}

/// The `#   seamlit ...` lines in the example scenes' header comments.
fn example_lines() -> Vec<String> {
    let mut lines = Vec::new();
    for entry in std::fs::read_dir(root().join("examples")).unwrap() {
        let text = std::fs::read_to_string(entry.unwrap().path()).unwrap();
        for line in text.lines() {
            // Command lines are indented in the comment (`#   seamlit ...`); prose is not.
            if let Some(command) = line.strip_prefix("#  ").map(str::trim)
                && command.starts_with("seamlit ")
            {
                lines.push(command.to_owned());
            }
        }
    }
    lines
}

/// Runs one line: placeholders replaced, `<command>` expanded to every subcommand, `view`
/// under Xvfb for three frames. Returns what each run gave.
fn run(line: &str, tmp: &Path) -> Vec<(String, Output)> {
    let assets = root().join("assets/models");
    let t = |name: &str| tmp.join(name).display().to_string();
    let substitutions: Vec<(&str, String)> = vec![
        ("model.obj", assets.join("cornell_box/cornell_box.obj").display().to_string()),
        ("models/", t("models")),
        ("fixed/", t("fixed")),
        ("fixed.glb", t("fixed.glb")),
        ("head.gltf", t("head.gltf")),
        ("head.glb", t("head.glb")),
        ("model.glb", t("model.glb")),
        ("character.glb", assets.join("fox/Fox.glb").display().to_string()),
        ("scene.toml", "examples/teapot.toml".to_owned()),
        ("out.png", t("out.png")),
        ("n.png", t("n.png")),
        ("grid.png", t("grid.png")),
        ("teapot.png", t("teapot.png")),
        ("DIR", t("demo")),
    ];
    let words: Vec<String> = line
        .split_whitespace()
        .skip(1)
        .map(|w| w.trim_start_matches('[').trim_end_matches(']'))
        .map(|w| {
            substitutions
                .iter()
                .find(|(from, _)| *from == w)
                .map_or_else(|| w.to_owned(), |(_, to)| to.clone())
        })
        .collect();
    let commands: Vec<Vec<String>> = if words[0] == "<command>" {
        ["demo", "fix", "inspect", "render", "compare", "view"]
            .iter()
            .map(|c| std::iter::once((*c).to_owned()).chain(words[1..].iter().cloned()).collect())
            .collect()
    } else {
        vec![words]
    };
    commands
        .into_iter()
        .map(|args| {
            let mut command = if args[0] == "view" && !args.iter().any(|a| a == "--help") {
                let mut c = Command::new("xvfb-run");
                c.args(["-a", "-s", "-screen 0 1024x768x24", env!("CARGO_BIN_EXE_seamlit")]);
                c.args(&args).args(["--exit-after-frames", "3"]);
                c
            } else {
                let mut c = Command::new(env!("CARGO_BIN_EXE_seamlit"));
                c.args(&args);
                c
            };
            let start = std::time::Instant::now();
            let output = command
                .current_dir(root())
                .env("RUST_BACKTRACE", "0")
                .output()
                .expect("the binary (and xvfb-run, which .ci/run installs) run");
            eprintln!("{:6.1} s  seamlit {}", start.elapsed().as_secs_f64(), args.join(" "));
            (args.join(" "), output)
        })
        .collect()
}

#[test]
fn every_command_line_in_the_readme_and_the_examples_runs() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let mut lines = readme_lines(&readme);
    // The two commands, and the ten lines (the list is checked so that a README edit that
    // breaks the parsing fails here instead of testing nothing).
    assert!(lines.contains(&"seamlit demo".to_owned()), "{lines:?}");
    assert_eq!(lines.len(), 12, "{lines:?}");
    // The rendering page's lines, moved there from the README (issue 40).
    let rendering = std::fs::read_to_string(root().join("docs/rendering.md")).unwrap();
    let moved = readme_lines(&rendering);
    assert_eq!(moved.len(), 2, "{moved:?}");
    lines.extend(moved);
    let examples = example_lines();
    assert!(examples.len() >= 2, "{examples:?}");

    let tmp = tempfile::tempdir().unwrap();
    // Inputs the lines name: a folder of models, and glTF files made from the Cornell box.
    std::fs::create_dir(tmp.path().join("models")).unwrap();
    std::fs::copy(root().join("assets/models/groups.obj"), tmp.path().join("models/groups.obj"))
        .unwrap();
    let cornell = root().join("assets/models/cornell_box/cornell_box.obj");
    for made in ["head.gltf", "model.glb"] {
        let o = Command::new(env!("CARGO_BIN_EXE_seamlit"))
            .arg("fix")
            .arg(&cornell)
            .arg("-o")
            .arg(tmp.path().join(made))
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    }

    let mut failures = Vec::new();
    for line in lines.iter().chain(&examples) {
        for (args, o) in run(line, tmp.path()) {
            if o.status.code() != Some(0) {
                failures.push(format!(
                    "{line}\n  ran: seamlit {args}\n  status {:?}: {}",
                    o.status.code(),
                    String::from_utf8_lossy(&o.stderr).trim()
                ));
            }
        }
    }
    assert!(failures.is_empty(), "README / example lines that fail:\n{}", failures.join("\n"));
    // The lines did their work: a few of the files they say they write.
    for written in ["fixed.glb", "head.glb", "out.png", "n.png", "grid.png", "teapot.png"] {
        assert!(tmp.path().join(written).is_file(), "{written} was not written");
    }
    assert!(tmp.path().join("fixed/groups.glb").is_file());
    assert!(tmp.path().join("demo/compare.png").is_file());
}
