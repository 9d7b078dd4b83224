//! The OpenUSD reader on arbitrary bytes. The first byte chooses the file's extension (`.usda`,
//! `.usdc`, `.usdz`: openusd reads by content, the extension only names it; `% 3`) and where
//! it is read from (`/ 3 % 2`: a file, or memory as the web page and `fix_bytes` give it,
//! through the in-memory resolver); the rest is the file, loaded as `seamlit fix` loads it.
//!
//! seamlit-io runs openusd so that a panic inside it becomes an error
//! (`UsdKind::Panicked`, a last resort); here such an error is a finding, as any panic is.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use seamlit_io::files::{Files, MemoryFiles};
use seamlit_io::{IoError, LoadOptions, UsdKind};

fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::Builder::new().prefix("seamlit-fuzz-usd-").tempdir().expect("tempdir");
        dir.keep()
    })
}

fuzz_target!(
    init: {
        // The panics the reader catches are reported by the check below, with their message.
        std::panic::set_hook(Box::new(|_| {}));
    },
    |data: &[u8]| {
    let Some((&choice, bytes)) = data.split_first() else { return };
    let extension = ["usda", "usdc", "usdz"][usize::from(choice % 3)];
    let in_memory = (choice / 3) % 2 == 1;
    let path = folder().join(format!("model.{extension}"));
    // As `render` and `view` read it: the materials of GeomSubsets too, cut by them.
    let mut options =
        LoadOptions { max_elements: 1 << 20, ..LoadOptions::DEFAULT }.with_subset_materials();
    if in_memory {
        let files = MemoryFiles::new([(path.clone(), bytes.to_vec())]);
        options.files = Files::Memory(files);
    } else {
        std::fs::write(&path, bytes).expect("write the stage");
    }
    match seamlit_io::load(&path, &options) {
        Err(IoError::Usd { kind: UsdKind::Panicked { message }, .. }) => {
            panic!("openusd panicked (caught by seamlit-io): {message}");
        }
        Ok(mut asset) => asset.split_triangle_materials(),
        Err(_) => {}
    }
    if !in_memory {
        let _ = std::fs::remove_file(&path);
    }
});
