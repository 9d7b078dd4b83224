//! One model through `seamlit fix` as a library call (`seamlit_io::job`), and the glTF
//! writer's memory destination (what the web page offers as a download): the same bytes as
//! the files it writes, on models by others.

use std::path::{Path, PathBuf};

use seamlit_io::files::Destination;
use seamlit_io::job::{FixJob, SkinSeams, fix_asset, fix_geometry};
use seamlit_io::{LoadOptions, SaveOptions};

fn model(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models").join(relative)
}

/// `relative` loaded and fixed with the command line's defaults.
fn fixed(relative: &str) -> seamlit_io::Asset {
    let mut asset = seamlit_io::load(&model(relative), &LoadOptions::FIX).unwrap();
    fix_asset(&mut asset, &FixJob::DEFAULT).unwrap();
    asset
}

/// The files `seamlit_io::save` writes for `asset` at `name` in a fresh folder, by name.
fn on_disk(asset: &seamlit_io::Asset, name: &str) -> Vec<(String, Vec<u8>)> {
    let dir = tempfile::tempdir().unwrap();
    seamlit_io::save(asset, &dir.path().join(name), &SaveOptions::default()).unwrap();
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            (
                path.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&path).unwrap(),
            )
        })
        .collect();
    files.sort();
    files
}

/// The files `seamlit_gltf::save_to` puts in memory for `asset` at `name`, by name.
fn in_memory(asset: &seamlit_io::Asset, name: &str) -> Vec<(String, Vec<u8>)> {
    let mut memory = Destination::memory();
    seamlit_io::gltf::save_to(asset, Path::new(name), &SaveOptions::default(), &mut memory)
        .unwrap();
    let mut files: Vec<(String, Vec<u8>)> = memory
        .into_memory()
        .into_iter()
        .map(|(path, bytes)| (path.to_string_lossy().into_owned(), bytes))
        .collect();
    files.sort();
    files
}

#[test]
fn memory_holds_the_bytes_the_files_get() {
    // The pass-through of a skinned, animated GLB; the generic writer (an OBJ as GLB); a
    // .gltf with its .bin beside it; a VRM avatar.
    for (input, output, count) in [
        ("fox/Fox.glb", "Fox.glb", 1),
        ("groups.obj", "groups.glb", 1),
        ("NormalTangentTest.glb", "NormalTangentTest.gltf", 2),
        ("groups.obj", "groups.gltf", 2),
    ] {
        let asset = fixed(input);
        let disk = on_disk(&asset, output);
        let memory = in_memory(&asset, output);
        assert_eq!(disk.len(), count, "{input} as {output}: {:?}", names(&disk));
        assert_eq!(names(&memory), names(&disk), "{input} as {output}");
        for ((name, a), (_, b)) in disk.iter().zip(&memory) {
            assert!(
                a == b,
                "{input} as {output}: {name} differs in memory ({} vs {} bytes)",
                b.len(),
                a.len()
            );
        }
    }
}

fn names(files: &[(String, Vec<u8>)]) -> Vec<&str> {
    files.iter().map(|(n, _)| n.as_str()).collect()
}

#[test]
fn the_job_matches_skin_seams_unless_asked_to_keep_them() {
    // A neck whose two objects' skin weights differ (assets/models/usd/make.py).
    let path = model("usd/skinned_neck.usda");
    let loaded = seamlit_io::load(&path, &LoadOptions::DEFAULT).unwrap();
    let job = FixJob { report_as_loaded: true, ..FixJob::DEFAULT };
    let mut asset = loaded.clone();
    let matched = fix_asset(&mut asset, &job).unwrap();
    let differed = matched.as_loaded.as_ref().unwrap().skin_seams.positions;
    assert!(differed > 0, "the neck's weights differ as loaded");
    assert_eq!(matched.matched.as_ref().unwrap().positions, differed);
    assert_eq!(matched.report.skin_seams.positions, 0, "and agree after");
    assert!(matched.summary(Path::new("out.usda")).contains("skins: gave the copies at"));

    let mut asset = loaded;
    let kept = fix_asset(&mut asset, &FixJob { skin_seams: SkinSeams::Keep, ..job }).unwrap();
    assert!(kept.matched.is_none());
    assert_eq!(kept.report.skin_seams.positions, differed, "kept as authored");
    assert!(kept.summary(Path::new("out.usda")).contains("where objects' skin weights differ"));
}

#[test]
fn the_seams_in_motion_are_measured_only_when_asked_and_change_nothing() {
    // A two-object character whose neck opens as it nods (seamlit-testkit's character): the
    // job without the measure fixes and writes the same, and measures nothing in motion.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("character.gltf");
    seamlit_testkit::character::write(&path);
    let loaded = seamlit_io::load(&path, &LoadOptions::FIX).unwrap();
    let mut measured = loaded.clone();
    let with = fix_asset(&mut measured, &FixJob::DEFAULT).unwrap();
    assert_eq!(with.motion.len(), 1, "the nod, measured before and after");
    assert!(with.motion[0].0.max_gap > 0.0, "the neck opens as loaded");

    let mut unmeasured = loaded;
    let without = fix_asset(&mut unmeasured, &FixJob { motion: false, ..FixJob::DEFAULT }).unwrap();
    assert!(without.motion.is_empty() && without.morph_seams.is_empty());
    assert!(without.matched.is_some(), "the skins still matched");
    let rest = |fixed: &seamlit_io::job::Fixed| {
        let mut json = fixed.json();
        json["motion"] = serde_json::Value::Null;
        json["morph_seams"] = serde_json::Value::Null;
        json
    };
    assert_eq!(rest(&with), rest(&without));
    assert!(in_memory(&measured, "out.glb") == in_memory(&unmeasured, "out.glb"), "same bytes");
}

#[test]
fn a_normal_mapped_model_without_tangents_gets_mikktspace_unless_one_was_asked_for() {
    // NormalTangentTest has a normal map; its tangents dropped, the job picks MikkTSpace as
    // the command line does, and keeps the generator a caller named.
    let path = model("NormalTangentTest.glb");
    let mut asset = seamlit_io::load(&path, &LoadOptions::DEFAULT).unwrap();
    for object in &mut asset.model.objects {
        object.tangents = None;
    }
    let mut a = asset.clone();
    let chosen = fix_asset(&mut a, &FixJob::DEFAULT).unwrap();
    assert_eq!(chosen.options.tangents, seamlit_mesh::TangentMethod::Mikktspace);
    let asked = FixJob { tangents_asked: true, ..FixJob::DEFAULT };
    let kept = fix_asset(&mut asset, &asked).unwrap();
    assert_eq!(kept.options.tangents, FixJob::DEFAULT.options.tangents);
    assert!(kept.json()["options"]["tangents"].is_string(), "{}", kept.json()["options"]);
}

#[test]
fn fix_reads_no_pixels_and_writes_what_decoding_them_wrote() {
    // `seamlit fix` reads textures without decoding them (LoadOptions::FIX): a KTX2 normal
    // map a generic writer re-encodes as PNG is decoded then, giving the same files as a
    // model loaded with its textures decoded.
    let lamp = "anisotropy_barn_lamp/AnisotropyBarnLamp.gltf";
    let undecoded = fixed(lamp);
    assert!(!undecoded.textures.is_empty());
    assert!(undecoded.textures.iter().all(|t| t.image.is_none()), "fix decoded a texture");
    let mut decoded = seamlit_io::load(&model(lamp), &LoadOptions::DEFAULT).unwrap();
    assert!(decoded.textures.iter().any(|t| t.image.is_some()));
    fix_asset(&mut decoded, &FixJob::DEFAULT).unwrap();
    let written = on_disk(&undecoded, "lamp.obj");
    assert!(
        written.iter().any(|(n, _)| n.ends_with("normalbump.png")),
        "{:?}",
        written.iter().map(|(n, _)| n).collect::<Vec<_>>()
    );
    assert!(written == on_disk(&decoded, "lamp.obj"), "the OBJ's files differ");

    // A missing texture is still a warning, as when decoding.
    let cornell =
        seamlit_io::load(&model("cornell_box/cornell_box.obj"), &LoadOptions::FIX).unwrap();
    let default =
        seamlit_io::load(&model("cornell_box/cornell_box.obj"), &LoadOptions::DEFAULT).unwrap();
    assert!(
        cornell.warnings.iter().any(|w| w.contains("has spaces.jpg")),
        "{:?}",
        cornell.warnings
    );
    assert_eq!(cornell.warnings, default.warnings);
}

/// A thread made a pool of one of its own runs the work it hands to rayon itself, the fix's
/// loops and ufbx's inflating tasks (`quaternius-bus.fbx`'s compressed arrays) among them,
/// and fixes a model as the global pool does. Run on a thread of its own: the test's thread
/// stays as it was.
#[test]
fn a_pool_of_one_does_its_work_on_its_own_thread() {
    use rayon::prelude::*;
    let relative = "lowpoly/quaternius-bus.fbx";
    let expected = in_memory(&fixed(relative), "bus.glb");
    let (sender, receiver) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        seamlit_io::job::become_a_pool_of_one();
        let me = std::thread::current().id();
        let threads: Vec<_> =
            (0..256).into_par_iter().map(|_| std::thread::current().id()).collect();
        let asset = seamlit_io::job::in_pool_or_here(|| fixed(relative));
        let ran_here = seamlit_io::job::in_pool_or_here(|| std::thread::current().id()) == me;
        let inline = threads.iter().all(|&t| t == me) && ran_here;
        sender.send((inline, rayon::current_num_threads(), in_memory(&asset, "bus.glb"))).unwrap();
    });
    // A load that waited on a task no thread would run would never answer.
    let (inline, threads, files) =
        receiver.recv_timeout(std::time::Duration::from_secs(300)).expect("the load ended");
    assert!(inline, "work handed to rayon ran on another thread");
    assert_eq!(threads, 1);
    assert!(files == expected, "fixed otherwise than on the global pool");
}

#[test]
fn a_model_measured_while_it_is_written_is_reported_and_written_as_one_after_the_other() {
    // The command line and the Python package measure a fixed model while they save it
    // (`Unmeasured::measure_with`): the same report as `fix_asset`'s, and the writer sees
    // the fixed model. With the report as loaded and without; a character in motion, a
    // skinned and animated GLB, a model with a normal map.
    let dir = tempfile::tempdir().unwrap();
    let character = dir.path().join("character.gltf");
    seamlit_testkit::character::write(&character);
    let cases = [
        (character, false),
        (model("fox/Fox.glb"), true),
        (model("NormalTangentTest.glb"), false),
        (model("NormalTangentTest.glb"), true),
    ];
    for ((path, report_as_loaded), together) in
        cases.into_iter().flat_map(|c| [(c.clone(), true), (c, false)])
    {
        let job = FixJob { report_as_loaded, ..FixJob::DEFAULT };
        let loaded = seamlit_io::load(&path, &LoadOptions::FIX).unwrap();
        let mut whole = loaded.clone();
        let expected = fix_asset(&mut whole, &job).unwrap();
        let mut beside = loaded;
        let unmeasured = fix_geometry(&mut beside, &job).unwrap();
        let (fixed, written) =
            unmeasured.measure_with(&beside, together, |asset| in_memory(asset, "out.glb"));
        let fixed = fixed.unwrap();
        assert_eq!(fixed.json(), expected.json(), "{} (beside: {together})", path.display());
        assert_eq!(fixed.summary(Path::new("out.glb")), expected.summary(Path::new("out.glb")));
        assert!(
            written == in_memory(&whole, "out.glb"),
            "{}: the fixed model written",
            path.display()
        );
    }
}

#[test]
fn only_the_gltf_writers_stream_what_they_save() {
    // A save that builds its output in memory is not run beside the measures: the two
    // memories would add up (the 1M teapot's `.usdc` peaked 9 MiB higher).
    let plain = SaveOptions::default();
    for name in ["a.glb", "a.GLTF", "avatar.vrm"] {
        assert!(seamlit_io::save_streams(Path::new(name), &plain), "{name}");
    }
    for name in ["a.obj", "a.usda", "a.usdc", "a.usdz", "a.fbx", "a"] {
        assert!(!seamlit_io::save_streams(Path::new(name), &plain), "{name}");
    }
    let kept = SaveOptions { keep_compression: true, ..SaveOptions::default() };
    assert!(!seamlit_io::save_streams(Path::new("a.glb"), &kept), "meshopt views re-encoded");
}
