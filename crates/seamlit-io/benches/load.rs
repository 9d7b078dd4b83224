//! Loading speed: the 1M-triangle teapot (32 objects, UVs and normals) as OBJ and as GLB,
//! written with this crate's writers into a temporary folder, then loaded.
//!
//! `cargo bench -p seamlit-io --bench load`; results in BENCHMARKS.md ("Loading
//! (seamlit-io)"), next to `assimp info` on the same files (`benches/compare_assimp.sh`).

use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use seamlit_io::{LoadOptions, SaveOptions};

const TEAPOT: &str = include_str!("../../../assets/models/newell_teaset/teapot");

fn loading(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temporary folder");
    let mut asset = seamlit_io::newell::parse(TEAPOT, "teapot", 125).expect("teapot");
    for object in &mut asset.model.objects {
        object.normals =
            Some(object.positions.iter().map(|p| p.normalize_or(glam::Vec3::Z)).collect());
    }
    let triangles = asset.model.triangle_count() as u64;
    assert_eq!(triangles, 1_000_000);
    let mut group = c.benchmark_group("load_teapot_1m");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(10))
        .throughput(Throughput::Elements(triangles));
    for extension in ["obj", "glb", "gltf"] {
        let path = dir.path().join(format!("teapot.{extension}"));
        seamlit_io::save(&asset, &path, &SaveOptions::default()).expect("write");
        group.bench_function(extension, |b| {
            b.iter(|| seamlit_io::load(&path, &LoadOptions::default()).expect("load"));
        });
    }
    group.finish();
}

criterion_group!(benches, loading);
criterion_main!(benches);
