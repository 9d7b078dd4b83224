//! Seams in motion on the command line: which animations, measured before and after `fix`,
//! as lines, a table and JSON.

use std::path::Path;

use seamlit_io::Asset;
use seamlit_io::motion::{Copies, SeamMotion, morph_seams};
use seamlit_mesh::FixOptions;

use crate::failure::Failure;

/// The animations `spec` names: `all`, a name, or an index (a name wins over an index).
///
/// # Errors
/// [`Failure::BadInput`] naming the file and listing its animations when none matches.
pub(crate) fn select(asset: &Asset, spec: &str, file: &Path) -> Result<Vec<usize>, Failure> {
    if spec == "all" {
        return Ok((0..asset.animations.len()).collect());
    }
    if let Some(i) = asset.animations.iter().position(|a| a.name == spec) {
        return Ok(vec![i]);
    }
    if let Ok(i) = spec.parse::<usize>()
        && i < asset.animations.len()
    {
        return Ok(vec![i]);
    }
    Err(Failure::input(format!("{}: no animation {spec:?}; {}", file.display(), list(asset))))
}

/// `the model has no animations`, or `its animations: 0 "Walk", 1 "Run"`.
pub(crate) fn list(asset: &Asset) -> String {
    if asset.animations.is_empty() {
        return "the model has no animations".to_owned();
    }
    let names: Vec<String> =
        asset.animations.iter().enumerate().map(|(i, a)| format!("{i} {:?}", a.name)).collect();
    format!("its animations: {}", names.join(", "))
}

/// The [`Copies`] of `asset`.
///
/// # Errors
/// [`Failure::BadInput`] naming `file` when the geometry is bad.
pub(crate) fn copies(asset: &Asset, options: &FixOptions, file: &Path) -> Result<Copies, Failure> {
    Copies::of(asset, options).map_err(|e| Failure::input(format!("{}: {e}", file.display())))
}

/// The seams of `asset` in each of `animations`, `samples` times each, at `copies` (see
/// [`copies`]), with the crease of `options`.
pub(crate) fn measure(
    asset: &Asset,
    animations: &[usize],
    samples: u32,
    options: &FixOptions,
    copies: &Copies,
) -> Vec<SeamMotion> {
    copies.measure(asset, animations, samples, options)
}

/// The morph targets whose deltas differ across the seam, as a line (empty where none do).
pub(crate) fn morph_line(asset: &Asset, copies: &[Vec<(u32, u32)>]) -> String {
    let seams = morph_seams(asset, copies);
    if seams.is_empty() {
        return String::new();
    }
    let each: Vec<String> = seams
        .iter()
        .map(|(name, n)| format!("{name:?} at {}", crate::table::count(*n, "shared position")))
        .collect();
    format!(
        "\n  morph targets whose deltas differ across the seam (it opens while they are active): {}",
        each.join(", ")
    )
}

/// One animation's figures: `gap 0.088 (4.4% of the bounds) at 0.50 s, normals 21.70° at 0.50 s`.
fn figures(m: &SeamMotion) -> String {
    let normals = m.max_normal_angle_deg.map_or_else(
        || "normals not compared".to_owned(),
        |a| format!("normals {a:.2}° at {:.2} s", m.max_normal_angle_time),
    );
    format!(
        "gap {:.3e} ({:.2}% of the bounds) at {:.2} s, {normals}",
        m.max_gap,
        100.0 * m.max_gap_fraction,
        m.max_gap_time
    )
}

/// A name for messages: `"Walk"` or `animation 2`.
fn label(m: &SeamMotion) -> String {
    if m.name.is_empty() { format!("animation {}", m.animation) } else { format!("{:?}", m.name) }
}

/// Lines for `fix`: per animation, before -> after.
pub(crate) fn lines(before: &[SeamMotion], after: &[SeamMotion]) -> String {
    before
        .iter()
        .zip(after)
        .map(|(b, a)| {
            format!(
                "\n  in motion, {} ({:.2} s, {} samples): {}\n    after: {}",
                label(b),
                b.duration,
                b.samples,
                figures(b),
                figures(a)
            )
        })
        .collect()
}

/// The JSON of one animation's figures.
pub(crate) fn json(m: &SeamMotion) -> serde_json::Value {
    serde_json::json!({
        "animation": m.animation,
        "name": m.name,
        "duration": m.duration,
        "samples": m.samples,
        "max_gap": m.max_gap,
        "max_gap_fraction": m.max_gap_fraction,
        "max_gap_time": m.max_gap_time,
        "max_normal_angle_deg": m.max_normal_angle_deg,
        "max_normal_angle_time": m.max_normal_angle_time,
    })
}
