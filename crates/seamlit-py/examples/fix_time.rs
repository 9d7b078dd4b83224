//! The Rust baseline for `bench/python_overhead.py`: loads a model with seamlit-io and times
//! `seamlit_mesh::fix_in_place` on fresh copies of it, with the options the Python side uses
//! (`--normals recompute`, everything else default).
//!
//! ```sh
//! cargo run --release -p seamlit-py --example fix_time -- MODEL.glb [RUNS]
//! ```
//! Prints one line: `vertices V triangles T runs N min MS median MS`.

use std::time::Instant;

use seamlit_io::LoadOptions;
use seamlit_mesh::{FixOptions, NormalPolicy};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: fix_time MODEL [RUNS]")?;
    let runs: usize = args.next().map_or(Ok(7), |r| r.parse())?;
    let asset = seamlit_io::load(path.as_ref(), &LoadOptions::GEOMETRY)?;
    let options = FixOptions { normals: NormalPolicy::Recompute, ..FixOptions::DEFAULT };
    let mut times = Vec::with_capacity(runs);
    for _ in 0..runs {
        let mut model = asset.model.clone();
        // Python hands over positions, triangles and UVs only.
        for object in &mut model.objects {
            object.normals = None;
            object.tangents = None;
        }
        let start = Instant::now();
        seamlit_mesh::fix_in_place(&mut model, &options)?;
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    println!(
        "vertices {} triangles {} runs {runs} min {:.1} median {:.1}",
        asset.model.vertex_count(),
        asset.model.triangle_count(),
        times[0],
        times[runs / 2]
    );
    Ok(())
}
