//! Structure-aware mutations of animated, skinned and morphed glTF never end in a panic
//! (issue 32): each mutated document (indices out of range, values of the wrong type, keys
//! deleted or added in animations, skins, nodes, accessors, meshes and their morph targets;
//! `common/mutate.rs`) either loads, and then goes through what `seamlit fix` does with it
//! (`common::mutate::use_asset`), or is refused with one line naming the file. Seeded, so
//! every run tries the same cases; the `gltf_json` fuzz target (fuzz/) runs the same
//! mutations for as long as it is given. A case that panics is written to
//! `CARGO_TARGET_TMPDIR/mutated-gltf/`, to be kept in tests/regressions/.

mod common;

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use common::mutate::{Choices, mutate, use_asset};
use seamlit_io::LoadOptions;
use serde_json::Value;

/// Mutated cases per seed document.
const CASES: u64 = 300;

/// A seed document: a name, its JSON and, for a GLB, its BIN chunk.
struct Seed {
    name: String,
    json: Value,
    bin: Option<Vec<u8>>,
}

/// The seeds: the two-object character (skins, an animation, a morph target), SimpleMorph
/// (morph targets animated), the Fox (a skin of 24 joints, three animations, a texture; GLB)
/// and the validator's valid files on animations, skins, joints and KHR_animation_pointer.
fn seeds(dir: &Path) -> Vec<Seed> {
    let character = dir.join("character.gltf");
    seamlit_testkit::character::write_with(&character, true);
    let mut files = vec![character, common::model("simple_morph/SimpleMorph.gltf")];
    let corpus =
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/validator-corpus"));
    for file in [
        "test/base/data/animation/valid.gltf",
        "test/base/data/skin/valid.gltf",
        "test/base/data/mesh_data/joints_weights_complex.gltf",
        "test/ext/KHR_animation_pointer/data/animation/channel/target/valid.gltf",
    ] {
        files.push(corpus.join(file));
    }
    let mut seeds: Vec<Seed> = files
        .iter()
        .map(|file| Seed {
            name: file.file_name().unwrap().to_string_lossy().into_owned(),
            json: serde_json::from_slice(&std::fs::read(file).unwrap()).unwrap(),
            bin: None,
        })
        .collect();
    let (json, bin) =
        common::gltf::glb_chunks(&std::fs::read(common::model("fox/Fox.glb")).unwrap());
    seeds.push(Seed { name: "Fox.glb".to_owned(), json, bin });
    seeds
}

/// While alive, a panic's message and place are kept for [`QuietPanics::take`] instead of
/// being printed; the previous hook is restored on drop.
struct QuietPanics {
    last: Arc<Mutex<Option<String>>>,
}

impl QuietPanics {
    fn install() -> Self {
        let last = Arc::new(Mutex::new(None));
        let keep = Arc::clone(&last);
        std::panic::set_hook(Box::new(move |info| {
            let place = info.location().map(|l| format!(" at {l}")).unwrap_or_default();
            *keep.lock().unwrap() =
                Some(format!("{}{place}", info.payload_as_str().unwrap_or("?")));
        }));
        Self { last }
    }

    fn take(&self) -> String {
        self.last.lock().unwrap().take().unwrap_or_default()
    }
}

impl Drop for QuietPanics {
    fn drop(&mut self) {
        let _ = std::panic::take_hook();
    }
}

#[test]
fn mutated_animated_and_skinned_gltf_loads_or_fails_in_one_line() {
    let work = tempfile::tempdir().unwrap();
    let found = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("mutated-gltf");
    let _ = std::fs::remove_dir_all(&found);
    let options = LoadOptions { max_elements: 1 << 20, ..LoadOptions::DEFAULT };
    let (mut loaded, mut refused, mut problems) = (0, 0, Vec::new());
    let quiet = QuietPanics::install();
    for (s, seed) in seeds(work.path()).iter().enumerate() {
        let extension = if seed.bin.is_some() { "glb" } else { "gltf" };
        let path = work.path().join(format!("mutated.{extension}"));
        for case in 0..CASES {
            let mut json = seed.json.clone();
            let mut choices = Choices::new((s as u64) << 32 | case);
            let mutations = mutate(&mut json, &mut choices);
            let text = serde_json::to_vec(&json).unwrap();
            let bytes = seed
                .bin
                .as_ref()
                .map_or_else(|| text.clone(), |bin| seamlit_testkit::glb_of_text(&text, bin));
            let out = work.path().join("out");
            std::fs::create_dir_all(&out).unwrap();
            let result = std::panic::catch_unwind(|| {
                seamlit_io::gltf::parse(&bytes, &path, &options).map(|asset| use_asset(asset, &out))
            });
            match result {
                Ok(Ok(())) => loaded += 1,
                Ok(Err(e)) => {
                    refused += 1;
                    let line = e.to_string();
                    if line.contains('\n') || !line.contains("mutated") {
                        problems.push(format!(
                            "{} case {case}: not one line naming the file: {line:?}",
                            seed.name
                        ));
                    }
                }
                Err(_) => {
                    let message = quiet.take();
                    std::fs::create_dir_all(&found).unwrap();
                    let kept = found.join(format!("{}_{case}.{extension}", seed.name));
                    std::fs::write(&kept, &bytes).unwrap();
                    problems.push(format!(
                        "{} case {case} ({}): panicked: {message}; kept as {}",
                        seed.name,
                        mutations.join(", "),
                        kept.display()
                    ));
                }
            }
        }
    }
    drop(quiet);
    println!("{loaded} mutated documents loaded and used, {refused} refused in one line");
    assert!(problems.is_empty(), "{} problems:\n{}", problems.len(), problems.join("\n"));
    // Not vacuous: the mutations keep many documents loadable, and break many.
    assert!(loaded > 200 && refused > 200, "{loaded} loaded, {refused} refused");
}
