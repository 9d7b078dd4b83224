//! The FBX reader's two ways in, against each other: `seamlit_io::fbx::load` of a file on
//! disk (streamed to ufbx, and read again whole where ufbx refuses the stream) and
//! `seamlit_io::fbx::parse` of the same bytes. They must give the same asset or the same
//! error line; a difference panics (a finding).
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use seamlit_io::LoadOptions;

fuzz_target!(|data: &[u8]| {
    static DIR: OnceLock<tempfile::TempDir> = OnceLock::new();
    let dir = DIR.get_or_init(|| tempfile::tempdir().expect("a temporary folder"));
    let path = dir.path().join("model.fbx");
    std::fs::write(&path, data).expect("the input written");
    let options =
        LoadOptions { max_elements: 1 << 20, max_model_triangles: 1 << 22, ..LoadOptions::DEFAULT };
    let streamed = seamlit_io::fbx::load(&path, &options);
    let given = seamlit_io::fbx::parse(data, &path, &options);
    match (&streamed, &given) {
        (Ok(a), Ok(b)) => assert_eq!(format!("{a:?}"), format!("{b:?}")),
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
        _ => panic!("streamed {streamed:?}, given {given:?}"),
    }
});
