//! The OBJ loader on arbitrary bytes. The bytes are written to `model.obj` in a private
//! folder (the loader reads from a path, so that `mtllib` and texture paths resolve against
//! it); a second input half, after the first `\0`, becomes `model.mtl` beside it.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use seamlit_io::LoadOptions;

fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::Builder::new().prefix("seamlit-fuzz-obj-").tempdir().expect("tempdir");
        dir.keep()
    })
}

fuzz_target!(
    init: {
        // seamlit-io catches tobj's own panics (and turns them into errors); libfuzzer-sys'
        // hook would abort at the panic itself, before the catch. Any panic that escapes
        // still aborts: libfuzzer-sys wraps every run in catch_unwind.
        std::panic::set_hook(Box::new(|_| {}));
    },
    |data: &[u8]| {
    let (obj, mtl) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], Some(&data[i + 1..])),
        None => (data, None),
    };
    let dir = folder();
    let path = dir.join("model.obj");
    let mtl_path = dir.join("model.mtl");
    std::fs::write(&path, obj).expect("write obj");
    match mtl {
        Some(m) => std::fs::write(&mtl_path, m).expect("write mtl"),
        None => {
            let _ = std::fs::remove_file(&mtl_path);
        }
    }
    let options = LoadOptions { max_elements: 1 << 20, ..LoadOptions::DEFAULT };
    let _ = seamlit_io::load(&path, &options);
});
