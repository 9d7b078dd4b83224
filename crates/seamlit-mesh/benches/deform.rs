//! What skins and morph targets cost `fix`: the teapot at about 1M triangles (32 objects),
//! plain, against the same model with one set of skin influences per vertex and two morph
//! targets (whose normal and tangent deltas `fix` computes). The targets come in two kinds:
//! **dense**, each moving every vertex (the worst case), and **sparse**, each moving a region
//! as blend shapes do (the lid's knob lifted, the spout's tip bent: a few percent of the
//! vertices each). The budget: at most 1.5 times the plain model's time.
//!
//! `cargo bench -p seamlit-mesh --bench deform`; `SEAMLIT_BENCH_N=40` for about 100k
//! triangles. Results in BENCHMARKS.md.

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Duration;

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use seamlit_mesh::{FixOptions, Influences, Model, MorphTarget, fix_in_place};

/// Which targets [`deformed`] gives the model.
#[derive(Clone, Copy)]
enum Targets {
    /// A bulge along the radial direction and a shear, moving every vertex.
    Dense,
    /// The knob lifted (`y > 2.9`) and the spout's tip bent (`x > 2.6`); zero elsewhere.
    Sparse,
}

/// The teapot with skin influences (two joints by height) and two morph targets, every object.
fn deformed(model: &Model, targets: Targets) -> Model {
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
        let moves: [fn(Vec3) -> Vec3; 2] = match targets {
            Targets::Dense => {
                [|p| Vec3::new(p.x, 0.0, p.z) * 0.1, |p| Vec3::new(0.2 * p.y, 0.0, 0.0)]
            }
            Targets::Sparse => [
                |p| if p.y > 2.9 { Vec3::new(0.0, 0.3 * (p.y - 2.9), 0.0) } else { Vec3::ZERO },
                |p| if p.x > 2.6 { Vec3::new(0.0, 0.5 * (p.x - 2.6), 0.0) } else { Vec3::ZERO },
            ],
        };
        object.morph_targets = moves
            .iter()
            .map(|m| MorphTarget {
                position_deltas: object.positions.iter().map(|&p| m(p)).collect(),
                ..MorphTarget::default()
            })
            .collect();
    }
    out
}

fn bench_deform(c: &mut Criterion) {
    let n: u32 = std::env::var("SEAMLIT_BENCH_N").ok().and_then(|s| s.parse().ok()).unwrap_or(125);
    let plain = common::teapot(n);
    let dense = deformed(&plain, Targets::Dense);
    let sparse = deformed(&plain, Targets::Sparse);
    for (k, name) in ["knob", "spout"].iter().enumerate() {
        let moved = sparse.objects.iter().flat_map(|o| &o.morph_targets[k].position_deltas);
        let moved = moved.filter(|d| **d != Vec3::ZERO).count();
        eprintln!("sparse target {name}: {moved} of {} vertices moved", plain.vertex_count());
    }
    let mut group = c.benchmark_group("fix_deform");
    group.sample_size(10).measurement_time(Duration::from_secs(20));
    group.throughput(Throughput::Elements(plain.triangle_count() as u64));
    let options = FixOptions::default();
    let models =
        [("plain", &plain), ("skin+2 sparse targets", &sparse), ("skin+2 dense targets", &dense)];
    for (name, model) in models {
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
