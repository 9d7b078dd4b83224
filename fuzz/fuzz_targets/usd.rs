//! The OpenUSD reader on arbitrary bytes. The first byte chooses the file's extension (`.usda`,
//! `.usdc`, `.usdz`: openusd reads by content, the extension only names it), the rest is
//! written to `model.EXT` in a private folder and loaded as `seamlit fix` loads it.
//!
//! seamlit-io runs openusd so that a panic inside it becomes an error
//! (`UsdKind::Panicked`, a last resort); here such an error is a finding, as any panic is.
#![no_main]

use std::path::PathBuf;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
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
    let path = folder().join(format!("model.{extension}"));
    std::fs::write(&path, bytes).expect("write the stage");
    // As `render` and `view` read it: the materials of GeomSubsets too, cut by them.
    let options =
        LoadOptions { max_elements: 1 << 20, ..LoadOptions::DEFAULT }.with_subset_materials();
    match seamlit_io::load(&path, &options) {
        Err(IoError::Usd { kind: UsdKind::Panicked { message }, .. }) => {
            panic!("openusd panicked (caught by seamlit-io): {message}");
        }
        Ok(mut asset) => asset.split_triangle_materials(),
        Err(_) => {}
    }
    let _ = std::fs::remove_file(&path);
});
