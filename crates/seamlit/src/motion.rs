//! Seams in motion on the command line (`inspect --animation`): which animations, and their
//! measures before and after `fix`.

use std::path::Path;

use seamlit_io::Asset;
use seamlit_io::motion::{Copies, SeamMotion};
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
