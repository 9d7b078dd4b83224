//! Loads model files and prints what they hold and how long loading took; or writes the
//! 1M-triangle benchmark models.
//!
//! ```text
//! cargo run --release -p seamlit-io --example load_info -- FILE...
//! cargo run --release -p seamlit-io --example load_info -- --generate DIR
//! cargo run --release -p seamlit-io --example load_info -- --digest FILE...
//! ```
//!
//! `--generate DIR` writes `DIR/teapot-1m.obj` and `DIR/teapot-1m.glb`: Newell's teapot at
//! 125 x 125 per patch (32 x 2 x 125^2 = 1,000,000 triangles), with UVs and normals, written
//! by this crate's writers. `benches/compare_assimp.sh` times this example against
//! `assimp info` on them.
//!
//! `--digest` prints, per file, a hash of everything loaded (object names, materials,
//! vertex arrays, triangles, warnings) or the error, instead of timings: for checking that
//! a change to a loader keeps its output, or that it is the same with one thread
//! (`RAYON_NUM_THREADS=1`) and many.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use seamlit_io::{LoadOptions, SaveOptions};

const TEAPOT: &str = include_str!("../../../assets/models/newell_teaset/teapot");

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

/// FNV-1a over the bytes fed to it.
struct Digest(u64);

impl Digest {
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
    }
    fn floats(&mut self, values: impl IntoIterator<Item = f32>) {
        for v in values {
            self.bytes(&v.to_bits().to_le_bytes());
        }
    }
}

fn digest(asset: &seamlit_io::Asset) -> u64 {
    let mut d = Digest(0xcbf2_9ce4_8422_2325);
    for object in &asset.model.objects {
        d.bytes(
            format!("{}|{:?}|{:?}|", object.name, object.material, object.transform).as_bytes(),
        );
        d.floats(object.positions.iter().flat_map(|p| p.to_array()));
        d.bytes(b"|uv");
        d.floats(object.uvs.iter().flatten().flat_map(|p| p.to_array()));
        d.bytes(b"|n");
        d.floats(object.normals.iter().flatten().flat_map(|p| p.to_array()));
        d.bytes(b"|t");
        for t in &object.triangles {
            for i in t {
                d.bytes(&i.to_le_bytes());
            }
        }
    }
    d.bytes(
        format!("{:?}{:?}{:?}", asset.materials, asset.textures.len(), asset.warnings).as_bytes(),
    );
    d.0
}

fn main() -> ExitCode {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let digests = args.first().is_some_and(|a| a == "--digest");
    if digests {
        args.remove(0);
        for file in &args {
            match seamlit_io::load(Path::new(file), &LoadOptions::default()) {
                Ok(asset) => println!("{file}: {:016x}", digest(&asset)),
                Err(e) => println!("{file}: error: {e}"),
            }
        }
        return ExitCode::SUCCESS;
    }
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
