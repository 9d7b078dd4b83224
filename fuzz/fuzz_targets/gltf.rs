//! The glTF / GLB reader on arbitrary bytes, textures decoded. The model "lives" in a folder
//! that does not exist: on the disk every external buffer or image is a missing file; for an
//! input of odd length it is read from memory instead (as the web page and `seamlit.ray` give
//! a model with its files), the same bytes also standing as `model.bin` and `texture.png`
//! beside it, so that URIs resolve to something and the set's name lookup is exercised.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use seamlit_io::LoadOptions;
use seamlit_io::files::{Files, MemoryFiles};

fuzz_target!(|data: &[u8]| {
    let path = if data.starts_with(b"glTF") {
        Path::new("/nonexistent-seamlit-fuzz/model.glb")
    } else {
        Path::new("/nonexistent-seamlit-fuzz/model.gltf")
    };
    let mut options = LoadOptions { max_elements: 1 << 20, ..LoadOptions::DEFAULT };
    if data.len() % 2 == 1 {
        let folder = Path::new("/nonexistent-seamlit-fuzz");
        let files = [path.to_path_buf(), folder.join("model.bin"), folder.join("texture.png")]
            .map(|p| (p, data.to_vec()));
        options.files = Files::Memory(MemoryFiles::new(files));
    }
    let _ = seamlit_io::gltf::parse(data, path, &options);
});
