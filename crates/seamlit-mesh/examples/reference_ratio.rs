//! Times the paper's reference algorithm once against the fast path (median of 5) on the
//! teapot at a given tessellation, and prints the ratio. The reference is far too slow for a
//! criterion benchmark at 100k triangles.
//!
//! `cargo run --release -p seamlit-mesh --example reference_ratio -- 40` (about 100k triangles)

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::Instant;

use seamlit_mesh::{FixOptions, fix, reference};

fn main() {
    let n: u32 = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(40);
    let model = common::teapot(n);
    let mut fast: Vec<f64> = (0..5)
        .map(|_| {
            let t = Instant::now();
            std::hint::black_box(fix(&model, &FixOptions::PAPER).expect("valid"));
            t.elapsed().as_secs_f64()
        })
        .collect();
    fast.sort_by(f64::total_cmp);
    let t = Instant::now();
    std::hint::black_box(reference::fix(&model).expect("valid"));
    let slow = t.elapsed().as_secs_f64();
    println!(
        "teapot n={n}: {} triangles, fix(PAPER) median {:.2} ms, reference {:.2} s, ratio {:.0}x",
        model.triangle_count(),
        fast[2] * 1e3,
        slow,
        slow / fast[2]
    );
}
