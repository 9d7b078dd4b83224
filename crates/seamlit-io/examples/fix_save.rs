//! `seamlit fix` without the command line, with a choice of writer, to measure what the
//! glTF pass-through costs against the generic writer in one build and one run.
//!
//! ```text
//! cargo build --release -p seamlit-io --example fix_save
//! target/release/examples/fix_save IN.glb OUT.glb auto|recompute|generic|keep
//! ```
//!
//! `auto` and `recompute` are `seamlit fix --normals auto|recompute` (the pass-through);
//! `generic` recomputes every normal and writes with the generic writer (the model rewritten
//! from seamlit's types), which is what `seamlit fix` did before the pass-through; `keep` is
//! `auto` with `seamlit fix --keep-compression` (meshopt compression kept). Each run loads,
//! fixes, measures the seams and saves, as `seamlit fix` does.

use std::path::Path;
use std::process::ExitCode;

use seamlit_io::{LoadOptions, SaveOptions};
use seamlit_mesh::{FixOptions, NormalPolicy, ReportOptions};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output, how] = &args[..] else {
        eprintln!("usage: fix_save INPUT OUTPUT auto|recompute|generic|keep");
        return ExitCode::from(2);
    };
    let normals = match how.as_str() {
        "auto" | "keep" => NormalPolicy::Auto,
        "recompute" | "generic" => NormalPolicy::Recompute,
        other => {
            eprintln!("unknown writer {other:?}: auto, recompute, generic or keep");
            return ExitCode::from(2);
        }
    };
    let run = || -> Result<(), Box<dyn std::error::Error>> {
        let mut asset = seamlit_io::load(Path::new(input), &LoadOptions::DEFAULT)?;
        if how == "generic" {
            asset.document = None;
        }
        let options = asset.fix_options(FixOptions { normals, ..FixOptions::DEFAULT }, false);
        seamlit_mesh::fix_in_place(&mut asset.model, &options)?;
        seamlit_mesh::report(&asset.model, &ReportOptions::from(&options))?;
        let save = SaveOptions { keep_compression: how == "keep", ..SaveOptions::default() };
        seamlit_io::save(&asset, Path::new(output), &save)?;
        Ok(())
    };
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
