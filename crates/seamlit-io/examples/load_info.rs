//! Loads model files and prints what they hold and how long loading took; or writes the
//! 1M-triangle benchmark models.
//!
//! ```text
//! cargo run --release -p seamlit-io --example load_info -- FILE...
//! cargo run --release -p seamlit-io --example load_info -- --generate DIR
//! ```
//!
//! `--generate DIR` writes `DIR/teapot-1m.obj` and `DIR/teapot-1m.glb`: Newell's teapot at
//! 125 x 125 per patch (32 x 2 x 125^2 = 1,000,000 triangles), with UVs and normals, written
//! by this crate's writers. `benches/compare_assimp.sh` times this example against
//! `assimp info` on them.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use seamlit_io::{LoadOptions, SaveOptions};

const TEAPOT: &str = include_str!("../../../../shared/models/newell_teaset/teapot");

/// The benchmark model: the teapot at `n` x `n` per patch with placeholder normals (the
/// normalised position: the files need realistic `vn` lines, not correct normals).
fn teapot(n: u32) -> Result<seamlit_io::Asset, seamlit_io::IoError> {
    let mut asset = seamlit_io::newell::parse(TEAPOT, "teapot", n)?;
    for object in &mut asset.model.objects {
        object.normals =
            Some(object.positions.iter().map(|p| p.normalize_or(glam::Vec3::Z)).collect());
    }
    Ok(asset)
}

fn generate(dir: &Path) -> Result<(), seamlit_io::IoError> {
    std::fs::create_dir_all(dir)
        .map_err(|e| seamlit_io::IoError::Io { path: dir.to_path_buf(), source: e })?;
    let asset = teapot(125)?;
    for name in ["teapot-1m.obj", "teapot-1m.glb"] {
        let path = dir.join(name);
        seamlit_io::save(&asset, &path, &SaveOptions::default())?;
        println!("{} ({} triangles)", path.display(), asset.model.triangle_count());
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [flag, dir] = &args[..]
        && flag == "--generate"
    {
        return match generate(&PathBuf::from(dir)) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        };
    }
    if args.is_empty() {
        eprintln!("usage: load_info FILE... | load_info --generate DIR");
        return ExitCode::from(2);
    }
    let mut status = ExitCode::SUCCESS;
    for file in &args {
        let start = Instant::now();
        match seamlit_io::load(Path::new(file), &LoadOptions::default()) {
            Ok(asset) => {
                let elapsed = start.elapsed();
                println!(
                    "{file}: {} objects, {} triangles, {} vertices, {} materials, {} textures, loaded in {:.1} ms",
                    asset.model.objects.len(),
                    asset.model.triangle_count(),
                    asset.model.vertex_count(),
                    asset.materials.len(),
                    asset.textures.len(),
                    elapsed.as_secs_f64() * 1e3
                );
                for warning in &asset.warnings {
                    println!("  warning: {warning}");
                }
            }
            Err(e) => {
                eprintln!("error: {e}");
                status = ExitCode::from(2);
            }
        }
    }
    status
}
