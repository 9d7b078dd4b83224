//! The fix of the demo teapot, timed: the page's measurement (BENCHMARKS.md) and its native
//! counterpart (`examples/teapot_fix_time.rs`) run this same code.

use seamlit_mesh::{FixOptions, TangentMethod, fix};

/// What one timed fix did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixTime {
    /// Triangles fixed.
    pub triangles: usize,
    /// Milliseconds `seamlit_mesh::fix` took, by the clock given.
    pub ms: f64,
}

/// Fixes `seamlit demo`'s teapot tessellated `n` x `n` quads a patch (32 objects, 64 n²
/// triangles: 1,000,000 at n = 125) with seamlit's default options and the `tangents` named
/// (`seamlit` or `mikktspace`, what `seamlit fix` picks for this model: a normal map, no
/// tangents), timing only the fix with `now` (milliseconds).
///
/// # Errors
///
/// An unknown tangents name, or the fix's error, as one line.
pub fn fix_demo_teapot(n: u32, tangents: &str, now: impl Fn() -> f64) -> Result<FixTime, String> {
    let tangents = match tangents {
        "seamlit" => TangentMethod::Seamlit,
        "mikktspace" => TangentMethod::Mikktspace,
        other => return Err(format!("unknown tangents {other:?} (seamlit, mikktspace)")),
    };
    let asset = seamlit_scene::demo::teapot_asset(n).map_err(|e| e.to_string())?;
    let options = FixOptions { tangents, ..FixOptions::DEFAULT };
    let start = now();
    let fixed = fix(&asset.model, &options).map_err(|e| format!("fixing the teapot: {e}"))?;
    let ms = now() - start;
    Ok(FixTime { triangles: fixed.triangle_count(), ms })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_timed_teapot_has_64_n_squared_triangles() {
        let t = fix_demo_teapot(4, "seamlit", || 0.0).unwrap();
        assert_eq!(t.triangles, 64 * 4 * 4);
        assert!(fix_demo_teapot(4, "mikk", || 0.0).unwrap_err().contains("mikk"));
    }
}
