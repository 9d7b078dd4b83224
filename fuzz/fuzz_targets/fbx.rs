//! The FBX reader (ufbx, then seamlit-io's conversion) on arbitrary bytes, textures decoded.
//! The model "lives" in a folder that does not exist, so every texture file is missing.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use seamlit_io::LoadOptions;

fuzz_target!(|data: &[u8]| {
    let path = Path::new("/nonexistent-seamlit-fuzz/model.fbx");
    let options = LoadOptions {
        max_elements: 1 << 20,
        max_model_triangles: 1 << 22,
        ..LoadOptions::DEFAULT
    };
    if let Ok(asset) = seamlit_io::fbx::parse(data, path, &options) {
        // What the commands do next: the model must pass fix's checks or fail them cleanly.
        let _ = seamlit_mesh::report(&asset.model, &seamlit_mesh::ReportOptions::default());
    }
});
