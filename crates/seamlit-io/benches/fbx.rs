//! `fix` on an FBX against `fix` on the same model as GLB: the teapot at 126 x 126 quads per
//! patch less its degenerate pole triangles (32 objects, 1,008,000 triangles, UVs, normals)
//! written as GLB by this crate, imported by Blender (the bpy module)
//! and exported by Blender as FBX and as GLB (`fbx_inputs.py`), so that both files hold the
//! same scene. Each case is what `seamlit fix IN -o OUT.glb` does in-process: load, fix with
//! the defaults, save as GLB; and the load alone.
//!
//! `cargo bench -p seamlit-io --bench fbx` (needs python3 with bpy; skips with a message
//! without it); results in BENCHMARKS.md ("FBX in").

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use seamlit_io::{LoadOptions, SaveOptions};

const TEAPOT: &str = include_str!("../../../assets/models/newell_teaset/teapot");

/// Writes `dir/model.fbx` and `dir/model.glb`; `false` (with a message) when Blender is
/// missing.
fn inputs(dir: &Path) -> bool {
    let mut asset = seamlit_io::newell::parse(TEAPOT, "teapot", 126).expect("teapot");
    // Without the poles' degenerate triangles: Blender's FBX exporter writes zero normals
    // there and its glTF exporter does not, which would give `fix` different work on the
    // two files.
    for object in &mut asset.model.objects {
        let positions = &object.positions;
        object.triangles.retain(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            (b - a).cross(c - a).length() > 1e-12
        });
    }
    seamlit_mesh::fix_in_place(&mut asset.model, &seamlit_mesh::FixOptions::default())
        .expect("fix");
    let source = dir.join("source.glb");
    seamlit_io::save(&asset, &source, &SaveOptions::default()).expect("write");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/fbx_inputs.py");
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".to_owned());
    match Command::new(python).arg(script).arg(&source).arg(dir).output() {
        Ok(o) if o.status.success() => true,
        Ok(o) => {
            eprintln!(
                "benches/fbx.rs: skipped: Blender could not write the inputs (pip install bpy==5.0.1): {}",
                String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or_default()
            );
            false
        }
        Err(e) => {
            eprintln!("benches/fbx.rs: skipped: python3 did not run: {e}");
            false
        }
    }
}

fn fbx_against_glb(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temporary folder");
    if !inputs(dir.path()) {
        return;
    }
    let mut group = c.benchmark_group("fbx_against_glb_1m");
    group.sample_size(10).measurement_time(Duration::from_secs(20));
    for extension in ["glb", "fbx"] {
        let input = dir.path().join(format!("model.{extension}"));
        let asset = seamlit_io::load(&input, &LoadOptions::GEOMETRY).expect("load");
        group.throughput(Throughput::Elements(asset.model.triangle_count() as u64));
        let output = dir.path().join(format!("fixed-{extension}.glb"));
        group.bench_function(format!("load/{extension}"), |b| {
            b.iter(|| seamlit_io::load(&input, &LoadOptions::GEOMETRY).expect("load"));
        });
        group.bench_function(format!("fix/{extension}"), |b| {
            b.iter(|| {
                let mut asset = seamlit_io::load(&input, &LoadOptions::GEOMETRY).expect("load");
                let options = asset.fix_options(seamlit_mesh::FixOptions::default(), false);
                seamlit_mesh::fix_in_place(&mut asset.model, &options).expect("fix");
                seamlit_io::save(&asset, &output, &SaveOptions::default()).expect("save");
            });
        });
    }
    group.finish();
}

criterion_group!(benches, fbx_against_glb);
criterion_main!(benches);
