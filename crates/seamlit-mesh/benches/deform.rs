//! What skins and morph targets cost `fix`: the teapot at about 1M triangles (32 objects),
//! plain, against the same model with one set of skin influences per vertex and two morph
//! targets (whose normal and tangent deltas `fix` computes). The budget: at most
//! 1.5 times the plain model's time.
//!
//! `cargo bench -p seamlit-mesh --bench deform`; `SEAMLIT_BENCH_N=40` for about 100k
//! triangles. Results in BENCHMARKS.md.

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Duration;

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use seamlit_mesh::{FixOptions, Influences, Model, MorphTarget, fix_in_place};

/// The teapot with skin influences (two joints by height) and two targets (a bulge along the
/// normal-ish radial direction, and a shear), every object.
fn deformed(model: &Model) -> Model {
    let mut out = model.clone();
    for object in &mut out.objects {
        let n = object.vertex_count();
        object.skin = vec![Influences {
            joints: vec![[1, 2, 0, 0]; n],
            weights: object
                .positions
                .iter()
                .map(|p| {
                    let w = (p.y / 3.0).clamp(0.0, 1.0);
                    [w, 1.0 - w, 0.0, 0.0]
                })
                .collect(),
        }];
        let bulge = object.positions.iter().map(|p| Vec3::new(p.x, 0.0, p.z) * 0.1).collect();
        let shear = object.positions.iter().map(|p| Vec3::new(0.2 * p.y, 0.0, 0.0)).collect();
        object.morph_targets = vec![
            MorphTarget { position_deltas: bulge, ..MorphTarget::default() },
            MorphTarget { position_deltas: shear, ..MorphTarget::default() },
        ];
    }
    out
}

fn bench_deform(c: &mut Criterion) {
    let n: u32 = std::env::var("SEAMLIT_BENCH_N").ok().and_then(|s| s.parse().ok()).unwrap_or(125);
    let plain = common::teapot(n);
    let skinned = deformed(&plain);
    let mut group = c.benchmark_group("fix_deform");
    group.sample_size(10).measurement_time(Duration::from_secs(20));
    group.throughput(Throughput::Elements(plain.triangle_count() as u64));
    let options = FixOptions::default();
    for (name, model) in [("plain", &plain), ("skin+2 morph targets", &skinned)] {
        group.bench_with_input(BenchmarkId::new(name, plain.triangle_count()), model, |b, m| {
            b.iter_batched(
                || m.clone(),
                |mut m| fix_in_place(&mut m, &options).expect("fix"),
                BatchSize::LargeInput,
            );
        });
    }
    group.finish();
}

criterion_group!(benches, bench_deform);
criterion_main!(benches);
