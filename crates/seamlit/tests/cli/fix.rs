//! `fix`: files, folders, authored normals, VRM.

use super::*;

// --- fix ---------------------------------------------------------------------------------

#[test]
fn fix_writes_a_model_with_normals_and_tangents() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("teapot.glb");
    let o = seamlit(&[
        "fix",
        &teapot(),
        "-o",
        &out.display().to_string(),
        "--tessellation",
        "4",
        "--crease",
        "45",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout(&o).contains("wrote"));
    let asset = seamlit_io::load(&out, &seamlit_io::LoadOptions::DEFAULT).unwrap();
    assert_eq!(asset.model.objects.len(), 32);
    assert!(asset.model.objects.iter().all(|o| o.normals.is_some() && o.tangents.is_some()));
    assert_eq!(listing(dir.path()), ["teapot.glb"]);
}

/// Two objects sharing the edge x = 1, each with its own face normal authored: they disagree
/// there by about 11.3 degrees.
const SEAM_OBJ: &str = "o a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
    vn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n\
    o b\nv 1 0 0\nv 2 0 -0.2\nv 2 1 -0.2\nv 1 1 0\nvn 0.19611613 0 0.98058068\n\
    f 5/1/2 6/2/2 7/3/2\nf 5/1/2 7/3/2 8/4/2\n";

#[test]
fn fix_keeps_authored_normals_repairs_the_seam_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "seam.obj", SEAM_OBJ);
    let out = dir.path().join("out.glb").display().to_string();
    let run = |policy: Option<&str>| {
        let mut args = vec!["fix", input.as_str(), "-o", out.as_str()];
        args.extend(policy.map(|p| ["--normals", p]).into_iter().flatten());
        let o = seamlit(&args);
        assert_eq!(o.status.code(), Some(0), "{policy:?}: {}", String::from_utf8_lossy(&o.stderr));
        stdout(&o)
    };
    // Each side carries its own face's normal: an authored hard edge, which the default
    // keeps and says so (issue 31); `smooth-shared` (the rule before) averages it.
    let auto = run(None);
    assert_eq!(run(Some("auto")), auto);
    assert!(
        auto.contains(
            "normals (auto): kept in every object; changed at 0 of 8 vertices; 0 vertices split"
        ),
        "{auto}"
    );
    assert!(auto.contains("0 seams repaired, 2 kept as authored hard edges"), "{auto}");
    assert!(auto.contains("within 11.31° (kept ones included)"), "{auto}");
    let shared = run(Some("smooth-shared"));
    assert!(shared.contains("normals across seams within 0.00°"), "{shared}");
    assert!(
        shared
            .contains("normals (smooth-shared): kept in every object; changed at 4 of 8 vertices"),
        "{shared}"
    );
    let keep = run(Some("keep"));
    assert!(keep.contains("normals across seams within 11.31°"), "{keep}");
    assert!(
        keep.contains("normals (keep): kept in every object; changed at 0 of 8 vertices"),
        "{keep}"
    );
    let recompute = run(Some("recompute"));
    assert!(recompute.contains("normals across seams within 0.00°"), "{recompute}");
    assert!(recompute.contains("normals (recompute): computed in every object"), "{recompute}");
}

#[test]
fn a_normal_map_without_tangents_gets_mikktspace_unless_asked_otherwise() {
    let dir = tempfile::tempdir().unwrap();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([128, 128, 255, 255]))
        .save(dir.path().join("n.png"))
        .unwrap();
    write(dir.path(), "seam.mtl", "newmtl mapped\nnorm n.png\n");
    let mapped = format!("mtllib seam.mtl\nusemtl mapped\n{SEAM_OBJ}");
    let input = write(dir.path(), "mapped.obj", &mapped);
    let plain = write(dir.path(), "plain.obj", SEAM_OBJ);
    let out = dir.path().join("out.glb").display().to_string();
    let run = |args: &[&str]| {
        let o = seamlit(&[&["fix", "-o", out.as_str()][..], args].concat());
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
        stdout(&o)
    };
    assert!(run(&[&input]).contains("; tangents: mikktspace"), "{}", run(&[&input]));
    assert!(run(&[&input, "--tangents", "seamlit"]).contains("; tangents: seamlit"));
    assert!(run(&[&plain]).contains("; tangents: seamlit"), "no normal map");
}

#[test]
fn inspect_says_what_fix_keeps_in_text_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "seam.obj", SEAM_OBJ);
    let o = seamlit(&["inspect", &input]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let text = stdout(&o);
    assert!(text.contains("What `fix` changes (model mode): normals (auto): kept in every object"));
    let row = |name: &str| {
        let line = text.lines().find(|l| l.starts_with(name)).unwrap_or_default();
        line.split_whitespace().map(str::to_owned).collect::<Vec<_>>()
    };
    // object, normals, tangents, vertices, normals changed, split: flat sides, kept.
    assert_eq!(row("a "), ["a", "kept", "computed", "4", "0", "0"], "{text}");
    assert_eq!(row("b "), ["b", "kept", "computed", "4", "0", "0"], "{text}");
    assert!(text.contains("2 kept as authored hard edges"), "{text}");

    let o = seamlit(&["inspect", &input, "--json", "--normals", "recompute"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["options"]["normals"], "recompute");
    let model = &v["changes"]["model"]["objects"];
    assert_eq!(model[0]["kept_normals"], false);
    assert_eq!(model[1]["name"], "b");
    let o = seamlit(&["inspect", &input, "--json", "--normals", "keep"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["changes"]["model"]["objects"][0]["kept_normals"], true);
    assert_eq!(v["changes"]["model"]["objects"][0]["normals_changed"], 0);
    let seam = v["model"]["cross_object"]["max_normal_angle_deg"].as_f64().unwrap();
    assert!(seam > 11.0, "keep leaves the seam: {seam}");
}

#[test]
fn every_command_takes_normals_and_refuses_a_bad_policy() {
    for command in ["fix", "inspect", "render", "compare", "view"] {
        let help = stdout(&seamlit(&[command, "--help"]));
        assert!(help.contains("--normals") && help.contains("recompute"), "{command} --help");
        // clap checks the value as it reads it, before missing arguments.
        let o = seamlit(&[command, "--normals", "sometimes", "a.obj"]);
        assert_eq!(o.status.code(), Some(2), "{command}: {}", String::from_utf8_lossy(&o.stderr));
        assert!(String::from_utf8_lossy(&o.stderr).contains("sometimes"), "{command}");
    }
    // render and compare run with it (fix and inspect: the tests above).
    let dir = tempfile::tempdir().unwrap();
    let input = write(dir.path(), "seam.obj", SEAM_OBJ);
    for command in ["render", "compare"] {
        let png = dir.path().join(format!("{command}.png")).display().to_string();
        let o = seamlit(&[command, &input, "-o", &png, "--size", "64x48", "--normals", "keep"]);
        assert_eq!(o.status.code(), Some(0), "{command}: {}", String::from_utf8_lossy(&o.stderr));
        assert!(Path::new(&png).is_file(), "{command}");
    }
}

#[test]
fn fix_refuses_bad_input_and_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let bad = write(dir.path(), "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    let out = dir.path().join("out.glb").display().to_string();
    assert_bad_input(&seamlit(&["fix", &bad, "-o", &out]), &["bad.obj"]);
    let missing = dir.path().join("missing.obj").display().to_string();
    assert_bad_input(&seamlit(&["fix", &missing, "-o", &out]), &["missing.obj", "no such file"]);
    let txt = dir.path().join("out.txt").display().to_string();
    assert_bad_input(&seamlit(&["fix", &teapot(), "-o", &txt]), &["out.txt", "output format"]);
    assert_eq!(listing(dir.path()), ["bad.obj"]);
    // The output may not be the input itself.
    let good = write(dir.path(), "good.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_bad_input(&seamlit(&["fix", &good, "-o", &good]), &["good.obj", "--overwrite-input"]);
    assert_eq!(std::fs::read_to_string(&good).unwrap(), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
}

#[test]
fn fix_a_folder_goes_on_past_a_bad_file_and_says_so() {
    let input = tempfile::tempdir().unwrap();
    let output = tempfile::tempdir().unwrap();
    write(
        input.path(),
        "a.obj",
        "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no b\nv 1 0 0\nv 0 1 0\nv 1 1 -0.2\nf 1 3 2\n",
    );
    write(input.path(), "b.obj", "v 0 0 0\nf 1 2 3\n");
    write(input.path(), "notes.txt", "not a model");
    let out_dir = output.path().join("fixed");
    let o = seamlit(&[
        "fix",
        &input.path().display().to_string(),
        "-o",
        &out_dir.display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    let errors = errors(&o);
    assert!(errors.iter().any(|e| e.contains("b.obj")), "{errors:?}");
    assert!(errors.last().unwrap().contains("1 of 2 models failed"), "{errors:?}");
    assert_eq!(listing(&out_dir), ["a.glb"]);
    assert!(stdout(&o).contains("fixed 1 of 2 models"));
}

/// A VRM avatar stays a `.vrm` (file and folder mode); a GLB that is no avatar is refused as
/// one, in one line, before anything is written.
#[test]
fn fix_writes_a_vrm_as_a_vrm_and_refuses_one_from_a_plain_glb() {
    let dir = tempfile::tempdir().unwrap();
    let (mut document, bin) = seamlit_testkit::character::document(false);
    let plain = dir.path().join("plain.glb");
    std::fs::write(&plain, seamlit_testkit::glb(&document, &bin)).unwrap();
    document["extensionsUsed"] = serde_json::json!(["VRMC_vrm"]);
    document["extensions"] = serde_json::json!({"VRMC_vrm": {"specVersion": "1.0",
        "meta": {"name": "tube"}, "humanoid": {"humanBones": {"hips": {"node": 2}}}}});
    let models = dir.path().join("models");
    std::fs::create_dir(&models).unwrap();
    std::fs::write(models.join("avatar.vrm"), seamlit_testkit::glb(&document, &bin)).unwrap();

    let fixed = dir.path().join("avatar-fixed.vrm");
    let o = seamlit(&[
        "fix",
        &models.join("avatar.vrm").display().to_string(),
        "-o",
        &fixed.display().to_string(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(&std::fs::read(&fixed).unwrap()[..4], b"glTF");

    let out_dir = dir.path().join("fixed");
    let o = seamlit(&["fix", &models.display().to_string(), "-o", &out_dir.display().to_string()]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(listing(&out_dir), ["avatar.vrm"]);

    let refused = dir.path().join("plain.vrm");
    let o = seamlit(&["fix", &plain.display().to_string(), "-o", &refused.display().to_string()]);
    assert_bad_input(&o, &["plain.vrm", "VRM input", "write .glb"]);
    assert!(!refused.exists());
}

/// Every file under `dir`, relative, sorted.
fn tree(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p.strip_prefix(dir).unwrap().display().to_string());
            }
        }
    }
    out.sort();
    out
}

/// A folder run descends into subfolders and mirrors the tree, each model's texture beside
/// it; hidden folders and the output folder inside the input are not read; `--no-recurse`
/// keeps to the top folder.
#[test]
fn fix_a_folder_tree_mirrors_it_with_textures_beside_each_model() {
    let input = tempfile::tempdir().unwrap();
    let quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
    write(input.path(), "a.obj", &format!("{quad}f 1/1 2/2 3/3 4/4\n"));
    let hero = input.path().join("chars/hero");
    std::fs::create_dir_all(&hero).unwrap();
    write(&hero, "head.mtl", "newmtl skin\nmap_Kd skin.png\n");
    image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 150, 120, 255]))
        .save(hero.join("skin.png"))
        .unwrap();
    write(&hero, "head.obj", &format!("mtllib head.mtl\nusemtl skin\n{quad}f 1/1 2/2 3/3 4/4\n"));
    std::fs::create_dir_all(input.path().join("props")).unwrap();
    write(&input.path().join("props"), "chair.obj", &format!("{quad}f 1/1 2/2 3/3\n"));
    std::fs::create_dir_all(input.path().join(".git")).unwrap();
    write(&input.path().join(".git"), "hidden.obj", &format!("{quad}f 1/1 2/2 3/3\n"));

    // The output folder lies inside the input: the second run must not fix the first's output.
    let out = input.path().join("fixed");
    let out_arg = out.display().to_string();
    let in_arg = input.path().display().to_string();
    for _ in 0..2 {
        let o = seamlit(&["fix", &in_arg, "-o", &out_arg, "--format", "gltf"]);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(stdout(&o).contains("fixed 3 of 3 models"), "{}", stdout(&o));
    }
    let files = tree(&out);
    for expected in ["a.gltf", "chars/hero/head.gltf", "props/chair.gltf"] {
        assert!(files.iter().any(|f| f == expected), "{expected} not in {files:?}");
    }
    assert!(
        files.iter().any(|f| f.starts_with("chars/hero/") && f.ends_with(".png")),
        "the hero's texture is not beside it: {files:?}"
    );
    assert!(!files.iter().any(|f| f.contains("hidden") || f.starts_with("fixed")), "{files:?}");

    let top = tempfile::tempdir().unwrap();
    let o = seamlit(&["fix", &in_arg, "-o", &top.path().display().to_string(), "--no-recurse"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(tree(top.path()), ["a.glb"]);
}

/// Two grids of n x n quads that meet along one edge, as OBJ: a model that takes a while.
fn two_grids(n: usize) -> String {
    let mut text = String::new();
    for part in 0..2 {
        text.push_str(&format!("o part{part}\n"));
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
                text.push_str(&format!("v {} {y} {}\n", x + part as f32, (x * 3.0).sin() * 0.1));
            }
        }
        let base = part * (n + 1) * (n + 1) + 1;
        for j in 0..n {
            for i in 0..n {
                let a = base + j * (n + 1) + i;
                text.push_str(&format!("f {a} {} {} {}\n", a + 1, a + n + 2, a + n + 1));
            }
        }
    }
    text
}

/// Folder mode fixes small files several at a time: on four threads it writes the bytes one
/// thread writes and prints each file's warnings and line in the folder's order, though the
/// first file (the slow one) finishes last.
#[test]
fn fix_a_folder_on_several_threads_writes_and_says_what_one_thread_does_in_order() {
    let input = tempfile::tempdir().unwrap();
    write(input.path(), "a.obj", &two_grids(150));
    for name in ["b", "c", "d", "e", "f", "g", "h"] {
        // A missing material library: one warning each.
        let text = format!("mtllib {name}.mtl\no {name}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        write(input.path(), &format!("{name}.obj"), &text);
    }
    let output = tempfile::tempdir().unwrap();
    let run = |threads: &str| {
        let out = output.path().join(format!("threads{threads}"));
        let o = Command::new(env!("CARGO_BIN_EXE_seamlit"))
            .args(["fix", &input.path().display().to_string(), "-o", &out.display().to_string()])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .expect("the binary runs");
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        let said = stdout(&o).replace(&out.display().to_string(), "OUT");
        (out, said, String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (one, said_one, warned_one) = run("1");
    let (four, said_four, warned_four) = run("4");
    // "wrote OUT/a.glb: ..." for a to h, in that order.
    let order: Vec<&str> =
        said_four.lines().filter_map(|l| l.strip_prefix("wrote OUT/")?.split('.').next()).collect();
    assert_eq!(order, ["a", "b", "c", "d", "e", "f", "g", "h"], "{said_four}");
    assert_eq!(said_four, said_one);
    assert_eq!(warned_four, warned_one);
    assert_eq!(warned_four.matches("warning:").count(), 7, "{warned_four}");
    assert_eq!(listing(&four), listing(&one));
    for name in listing(&one) {
        assert_eq!(
            std::fs::read(four.join(&name)).unwrap(),
            std::fs::read(one.join(&name)).unwrap(),
            "{name}"
        );
    }
}
