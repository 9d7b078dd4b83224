//! The native side of the page's fix timing (BENCHMARKS.md, "The web page"):
//! `RAYON_NUM_THREADS=1 cargo run --release -p seamlit-web --example teapot_fix_time -- 125 mikktspace 3`
//! fixes the 1M-triangle demo teapot three times and prints each time.

use std::time::Instant;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n = args.first().map_or(Ok(125), |a| a.parse()).map_err(|e| format!("N: {e}"))?;
    let tangents = args.get(1).map_or("mikktspace", String::as_str);
    let runs: usize = args.get(2).map_or(Ok(3), |a| a.parse()).map_err(|e| format!("RUNS: {e}"))?;
    let clock = Instant::now();
    let now = || clock.elapsed().as_secs_f64() * 1e3;
    for _ in 0..runs {
        let t = seamlit_web::timing::fix_demo_teapot(n, tangents, now)?;
        println!("{} triangles, tangents {tangents}: {:.0} ms", t.triangles, t.ms);
    }
    Ok(())
}
