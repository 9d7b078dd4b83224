//! The glTF / GLB reader on arbitrary bytes, textures decoded. The model "lives" in a folder
//! that does not exist, so every external buffer or image is a missing file.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use seamlit_io::LoadOptions;

fuzz_target!(|data: &[u8]| {
    let path = if data.starts_with(b"glTF") {
        Path::new("/nonexistent-seamlit-fuzz/model.glb")
    } else {
        Path::new("/nonexistent-seamlit-fuzz/model.gltf")
    };
    let options = LoadOptions { max_elements: 1 << 20, ..LoadOptions::DEFAULT };
    let _ = seamlit_io::gltf::parse(data, path, &options);
});
