//! Tangent generators side by side on the Newell teapot (32 objects, UVs, no normals in), at
//! about 64k, 256k and 1M triangles, on 1 and 2 threads:
//!
//! - `fix/mikktspace`: `seamlit_mesh::fix` with `TangentMethod::Mikktspace` (weld, normals,
//!   MikkTSpace across the weld, vertices split), what `seamlit fix` runs on a normal-mapped
//!   model without tangents;
//! - `fix/seamlit`: the same fix with seamlit's own tangents;
//! - `fix/normals-only`: the same fix without tangents (what the tangents add is the
//!   difference);
//! - `generator/bevy_mikktspace` and `generator/meshopt`: the peers' MikkTSpace on the fixed
//!   model's normals, all objects as one mesh (the generator alone: no weld, no normals, no
//!   splitting; meshoptimizer's `generate_tangents` with `TangentOptions::Compatible`).
//!   Both are single-threaded; bevy_mikktspace runs at 64k and 256k only (3.8 s at 1M).
//!
//! `cargo bench -p seamlit-mesh --bench tangents`; results in BENCHMARKS.md. The 4M-triangle
//! figures come from whole processes (`examples/time_tangents.rs`).

#[path = "../tests/common/mod.rs"]
mod common;

use common::Merged;
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use seamlit_mesh::{FixOptions, TangentMethod, fix};

/// Tessellations giving about 64k, 256k and 1M triangles (32 patches x 2 n^2).
const SIZES: [u32; 3] = [32, 64, 128];

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool")
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("tangents");
    group.sample_size(10);
    for n in SIZES {
        let model = common::teapot(n);
        let triangles = model.triangle_count();
        let size = format!("{}k", triangles / 1000);
        group.throughput(Throughput::Elements(triangles as u64));
        let cases = [
            ("fix/mikktspace", TangentMethod::Mikktspace),
            ("fix/seamlit", TangentMethod::Seamlit),
            ("fix/normals-only", TangentMethod::None),
        ];
        for threads in [1, 2] {
            let pool = pool(threads);
            for (name, tangents) in cases {
                let options = FixOptions { tangents, ..FixOptions::DEFAULT };
                let id = BenchmarkId::new(format!("{name}/{threads}t"), &size);
                group.bench_function(id, |b| {
                    b.iter(|| pool.install(|| fix(&model, &options).expect("valid")));
                });
            }
        }
        let fixed =
            fix(&model, &FixOptions { tangents: TangentMethod::None, ..FixOptions::DEFAULT })
                .expect("valid");
        let mut merged = Merged::of(&fixed);
        group.bench_function(BenchmarkId::new("generator/meshopt/1t", &size), |b| {
            b.iter(|| {
                meshopt::generate_tangents(
                    Some(&merged.indices),
                    &merged.positions,
                    &merged.normals,
                    &merged.uvs,
                    meshopt::TangentOptions::Compatible,
                )
            });
        });
        if n <= 64 {
            group.bench_function(BenchmarkId::new("generator/bevy_mikktspace/1t", &size), |b| {
                b.iter(|| bevy_mikktspace::generate_tangents(&mut merged).expect("infallible"));
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
