//! Quick timing of `fix` modes on the teapot at one tessellation (median of N runs), for
//! profiling; the criterion benchmark is the reference measurement.
//!
//! `cargo run --release -p seamlit-mesh --example time_fix -- 125 9 [MODE]`; `RAYON_NUM_THREADS`
//! sets the threads. The modes `bevy_mikktspace` and `meshopt` time the peers' MikkTSpace
//! alone on the fixed model's normals, all objects as one mesh (single-threaded).

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Instant;

use seamlit_mesh::{FixOptions, Mode, TangentMethod, fix, fix_in_place};

fn main() {
    let mut args = std::env::args().skip(1);
    let n: u32 = args.next().and_then(|a| a.parse().ok()).unwrap_or(125);
    let runs: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(7);
    let only = args.next();
    let model = common::teapot(n);
    println!("teapot n={n}: {} triangles, {} objects", model.triangle_count(), model.objects.len());
    let cases = [
        ("model", FixOptions::DEFAULT, false),
        ("model-in-place", FixOptions::DEFAULT, true),
        (
            "model-normals-only",
            FixOptions { tangents: TangentMethod::None, ..FixOptions::DEFAULT },
            false,
        ),
        ("object", FixOptions::DEFAULT.with_mode(Mode::Object), false),
        ("flat", FixOptions::DEFAULT.with_mode(Mode::Flat), false),
        (
            "mikktspace",
            FixOptions { tangents: TangentMethod::Mikktspace, ..FixOptions::DEFAULT },
            false,
        ),
    ];
    for (name, opts, in_place) in cases {
        if only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let mut t: Vec<f64> = (0..runs)
            .map(|_| {
                if in_place {
                    // What `seamlit fix` runs: the loaded model fixed where it is.
                    let mut m = model.clone();
                    let s = Instant::now();
                    fix_in_place(&mut m, &opts).expect("valid");
                    let ms = s.elapsed().as_secs_f64() * 1e3;
                    std::hint::black_box(m);
                    ms
                } else {
                    let s = Instant::now();
                    std::hint::black_box(fix(&model, &opts).expect("valid"));
                    s.elapsed().as_secs_f64() * 1e3
                }
            })
            .collect();
        t.sort_by(f64::total_cmp);
        let med = t[runs / 2];
        println!(
            "{name:>20}: median {med:8.1} ms  ({:.2} M triangles/s)",
            model.triangle_count() as f64 / med / 1e3
        );
    }
    for name in ["meshopt", "bevy_mikktspace"] {
        if only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let options = FixOptions { tangents: TangentMethod::None, ..FixOptions::DEFAULT };
        let mut merged = common::Merged::of(&fix(&model, &options).expect("valid"));
        let mut t: Vec<f64> = (0..runs)
            .map(|_| {
                let s = Instant::now();
                if name == "meshopt" {
                    std::hint::black_box(meshopt::generate_tangents(
                        Some(&merged.indices),
                        &merged.positions,
                        &merged.normals,
                        &merged.uvs,
                        meshopt::TangentOptions::Compatible,
                    ));
                } else {
                    bevy_mikktspace::generate_tangents(&mut merged).expect("infallible");
                }
                s.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        t.sort_by(f64::total_cmp);
        println!("{name:>20}: median {:8.1} ms (the generator alone)", t[runs / 2]);
    }
}
