//! Structure-aware fuzzing of the glTF reader (issue 32). Inputs are glTF JSON documents
//! (buffers in `data:` URIs); the custom mutator parses one and changes its objects and
//! indices as `crates/seamlit-io/tests/common/mutate.rs` does (indices out of range, wrong
//! types, keys deleted or added in animations, skins, nodes, accessors, meshes and morph
//! targets, ...), so that mutants stay well-formed JSON and reach the checks past the parser;
//! a third of the time, and for an input that is not JSON, libFuzzer's own byte mutations.
//! What loads then goes through what `seamlit fix` does with it (`mutate::use_asset`: fix,
//! seams in motion, skin seams matched, posing, the pass-through and generic writers).
#![no_main]

#[path = "../../crates/seamlit-io/tests/common/mutate.rs"]
mod mutate;

use std::path::PathBuf;
use std::sync::OnceLock;

use libfuzzer_sys::{fuzz_mutator, fuzz_target, fuzzer_mutate};
use seamlit_io::LoadOptions;

/// A private folder: the model "lives" there and its outputs are written there.
fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::Builder::new().prefix("seamlit-fuzz-gltf-json-").tempdir();
        dir.expect("tempdir").keep()
    })
}

fuzz_target!(
    init: {
        // seamlit-io catches the Draco decoder's panics (and turns them into errors);
        // libfuzzer-sys' hook would abort at the panic itself, before the catch. Any panic
        // that escapes still aborts: libfuzzer-sys wraps every run in catch_unwind.
        std::panic::set_hook(Box::new(|_| {}));
    },
    |data: &[u8]| {
        let options = LoadOptions { max_elements: 1 << 20, ..LoadOptions::DEFAULT };
        let path = folder().join("model.gltf");
        if let Ok(asset) = seamlit_io::gltf::parse(data, &path, &options) {
            mutate::use_asset(asset, folder());
        }
    }
);

fuzz_mutator!(|data: &mut [u8], size: usize, max_size: usize, seed: u32| {
    let mut choices = mutate::Choices::new(u64::from(seed));
    if choices.below(3) == 0 {
        return fuzzer_mutate(data, size, max_size);
    }
    let Ok(mut json) = serde_json::from_slice::<serde_json::Value>(&data[..size]) else {
        return fuzzer_mutate(data, size, max_size);
    };
    mutate::mutate(&mut json, &mut choices);
    match serde_json::to_vec(&json) {
        Ok(bytes) if bytes.len() <= max_size => {
            data[..bytes.len()].copy_from_slice(&bytes);
            bytes.len()
        }
        _ => fuzzer_mutate(data, size, max_size),
    }
});
