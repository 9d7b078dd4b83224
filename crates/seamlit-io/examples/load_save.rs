//! Loads a model file and saves it again: the I/O half of `seamlit fix`, for measuring the
//! time and peak memory of the readers and writers alone.
//!
//! ```text
//! cargo build --release -p seamlit-io --example load_save
//! /usr/bin/time -v target/release/examples/load_save /tmp/teapot1m.glb /tmp/out.glb
//! ```
//!
//! Textures are not decoded (as in `seamlit fix`); the output format follows the extension.

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use seamlit_io::{LoadOptions, SaveOptions};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = &args[..] else {
        eprintln!("usage: load_save INPUT OUTPUT");
        return ExitCode::from(2);
    };
    let start = Instant::now();
    let asset = match seamlit_io::load(Path::new(input), &LoadOptions::GEOMETRY) {
        Ok(asset) => asset,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let loaded = start.elapsed();
    if let Err(e) = seamlit_io::save(&asset, Path::new(output), &SaveOptions::default()) {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    println!(
        "{input} -> {output}: {} objects, {} triangles, {} vertices; load {:.1} ms, save {:.1} ms",
        asset.model.objects.len(),
        asset.model.triangle_count(),
        asset.model.vertex_count(),
        loaded.as_secs_f64() * 1e3,
        (start.elapsed() - loaded).as_secs_f64() * 1e3
    );
    ExitCode::SUCCESS
}
