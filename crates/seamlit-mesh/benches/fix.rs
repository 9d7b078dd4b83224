//! Benchmarks of `fix` on teapot-like multi-object meshes (32 objects, 10k to 2M triangles):
//! every mode, the paper's reference (small sizes only: it is O(V x F)), and bevy_mikktspace
//! tangent generation on the same meshes as the baseline users have today.
//!
//! `cargo bench -p seamlit-mesh --bench fix`; results in BENCHMARKS.md.

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use seamlit_mesh::{
    FixOptions, Mode, Model, NormalPolicy, TangentMethod, fix, fix_in_place, reference,
};

/// Tessellations giving about 10k, 100k, 1M and 2M triangles (32 patches x 2 n^2).
const SIZES: [u32; 4] = [13, 40, 125, 177];

struct Mikk<'a> {
    object: &'a seamlit_mesh::Object,
    tangents: Vec<[f32; 4]>,
}

impl bevy_mikktspace::Geometry for Mikk<'_> {
    fn num_faces(&self) -> usize {
        self.object.triangles.len()
    }
    fn num_vertices_of_face(&self, _: usize) -> usize {
        3
    }
    fn position(&self, f: usize, v: usize) -> [f32; 3] {
        self.object.positions[self.object.triangles[f][v] as usize].to_array()
    }
    fn normal(&self, f: usize, v: usize) -> [f32; 3] {
        self.object.normals.as_ref().expect("normals")[self.object.triangles[f][v] as usize]
            .to_array()
    }
    fn tex_coord(&self, f: usize, v: usize) -> [f32; 2] {
        self.object.uvs.as_ref().expect("uvs")[self.object.triangles[f][v] as usize].to_array()
    }
    fn set_tangent(&mut self, t: Option<bevy_mikktspace::TangentSpace>, f: usize, v: usize) {
        if let Some(t) = t {
            self.tangents[f * 3 + v] = t.tangent_encoded();
        }
    }
}

/// bevy_mikktspace over every object of an already-smoothed model, one object after the other,
/// as a tool that generates tangents per mesh does.
/// bevy_mikktspace on every object, the objects in parallel (rayon, as `fix` uses): the
/// baseline gets the same cores.
fn mikktspace_all(model: &Model) -> usize {
    use rayon::prelude::*;
    model
        .objects
        .par_iter()
        .map(|object| {
            let mut g = Mikk { object, tangents: vec![[0.0; 4]; object.triangles.len() * 3] };
            bevy_mikktspace::generate_tangents(&mut g).expect("infallible");
            g.tangents.len()
        })
        .sum()
}

fn bench_fix(c: &mut Criterion) {
    let mut group = c.benchmark_group("fix");
    group.sample_size(10);
    for n in SIZES {
        let model = common::teapot(n);
        let tris = model.triangle_count() as u64;
        group.throughput(Throughput::Elements(tris));
        for (name, mode) in [("model", Mode::Model), ("object", Mode::Object), ("flat", Mode::Flat)]
        {
            let opts = FixOptions::DEFAULT.with_mode(mode);
            group.bench_with_input(BenchmarkId::new(name, tris), &model, |b, m| {
                b.iter(|| fix(m, &opts).expect("valid"));
            });
        }
        // What `seamlit fix` runs: the loaded model fixed where it is (the copy made outside
        // the timing).
        group.bench_with_input(BenchmarkId::new("model-in-place", tris), &model, |b, m| {
            b.iter_batched(
                || m.clone(),
                |mut m| {
                    fix_in_place(&mut m, &FixOptions::DEFAULT).expect("valid");
                    m
                },
                BatchSize::LargeInput,
            );
        });
        // A model that carries normals and tangents (the teapot's own, computed once): the
        // seam-only repair of `--normals auto` against `--normals recompute`, in place as
        // `seamlit fix` runs them (the copy made outside the timing).
        let recompute = FixOptions::DEFAULT.with_normals(NormalPolicy::Recompute);
        let authored = fix(&model, &recompute.with_mode(Mode::Object)).expect("valid");
        for (name, opts) in
            [("authored-auto", FixOptions::DEFAULT), ("authored-recompute", recompute)]
        {
            group.bench_with_input(BenchmarkId::new(name, tris), &authored, |b, m| {
                b.iter_batched(
                    || m.clone(),
                    |mut m| {
                        fix_in_place(&mut m, &opts).expect("valid");
                        m
                    },
                    BatchSize::LargeInput,
                );
            });
        }
        let normals_only = FixOptions { tangents: TangentMethod::None, ..FixOptions::DEFAULT };
        group.bench_with_input(BenchmarkId::new("model-normals-only", tris), &model, |b, m| {
            b.iter(|| fix(m, &normals_only).expect("valid"));
        });
        if n <= 125 {
            let smoothed = fix(&model, &normals_only).expect("valid");
            group.bench_with_input(BenchmarkId::new("bevy_mikktspace", tris), &smoothed, |b, m| {
                b.iter(|| mikktspace_all(m));
            });
        }
        if n <= 22 {
            group.bench_with_input(BenchmarkId::new("reference", tris), &model, |b, m| {
                b.iter(|| reference::fix(m).expect("valid"));
            });
        }
    }
    // The reference at about 30k triangles too (O(V x F): the slowest of these runs).
    let model = common::teapot(22);
    group.throughput(Throughput::Elements(model.triangle_count() as u64));
    group.bench_with_input(
        BenchmarkId::new("reference", model.triangle_count()),
        &model,
        |b, m| {
            b.iter(|| reference::fix(m).expect("valid"));
        },
    );
    group.finish();
}

criterion_group!(benches, bench_fix);
criterion_main!(benches);
