//! The TOML scene parser on arbitrary text (paths resolve against a folder that does not
//! exist; parsing does not load the models).
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use seamlit_scene::Scene;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = Scene::parse(
        &text,
        Path::new("/nonexistent-seamlit-fuzz"),
        Path::new("/nonexistent-seamlit-fuzz/scene.toml"),
    );
});
