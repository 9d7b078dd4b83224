//! The per-file work of `seamlit.ray` (the Python package's fleet runs), in one native call
//! each: the input's SHA-256, the fix, the output's bytes and their SHA-256, and the report
//! row's columns, without the interpreter in between. A Ray task fixes hundreds of small
//! files one after another, and reading, hashing and writing each in Python, with the full
//! JSON report in between, took a tenth of its time (BENCHMARKS.md, "seamlit.ray").
//!
//! - [`fix_file_row`]: a local file into a local GLB or VRM, written atomically as the
//!   command line writes it;
//! - [`Row`]: the row's columns, also of a model held in memory (read from an object store)
//!   that [`crate::fix_model_bytes`] fixes, its output's bytes handed back to upload.

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use seamlit_io::SaveOptions;
use seamlit_io::job::{Fixed, fix_asset};
use sha2::{Digest, Sha256};

use crate::digests::{Digests, Stamp, hex, sha256};
use crate::{Settings, detached, error, json_text, load};

/// The report's columns a fix fills for one file (docs/fleet.md), by their column names.
#[derive(serde::Serialize)]
pub(crate) struct Row {
    /// `None` where the caller's [`Digests`] makes it.
    input_sha256: Option<String>,
    /// `None` where the caller's [`Digests`] makes it.
    output_sha256: Option<String>,
    objects: usize,
    triangles: usize,
    shared_positions: usize,
    seams_repaired: usize,
    kept_hard_edges: usize,
    kept_custom: usize,
    largest_seam_before_deg: Option<f32>,
    largest_seam_after_deg: Option<f32>,
    warnings: Vec<String>,
    /// Whether the fix changed a normal or split a vertex (`fixed`, else `unchanged`).
    changed: bool,
}

impl Row {
    /// The row of a file fixed as `fixed` says, its input's and output's SHA-256 as given.
    pub(crate) fn of<'a>(
        fixed: &Fixed,
        warnings: impl IntoIterator<Item = &'a String>,
        input_sha256: Option<String>,
        output_sha256: Option<String>,
    ) -> Self {
        // Measured as loaded by every job of this module (`Settings::job`); the fixed
        // model's counts are the loaded one's where it was not.
        let before = fixed.as_loaded.as_ref().unwrap_or(&fixed.report);
        let shared = &fixed.changes.shared;
        Self {
            input_sha256,
            output_sha256,
            objects: before.objects,
            triangles: before.triangles,
            shared_positions: before.shared_positions,
            seams_repaired: shared.repaired,
            kept_hard_edges: shared.hard_edges,
            kept_custom: shared.custom,
            largest_seam_before_deg: before.cross_object.max_normal_angle_deg,
            largest_seam_after_deg: fixed.report.cross_object.max_normal_angle_deg,
            warnings: warnings.into_iter().cloned().collect(),
            changed: fixed
                .changes
                .objects
                .iter()
                .any(|o| o.normals_changed > 0 || o.vertices_split > 0),
        }
    }
}

/// The SHA-256 of the file at `path`, read in pieces into one small buffer, not whole into
/// fresh memory again after the loader had read it: NormalTangentTest.glb (1.9 MB) spent 7%
/// of its time in a Ray task reading the file, half of it that second read, and 10% hashing
/// it (`perf`).
fn file_sha256(path: &Path) -> std::io::Result<String> {
    let mut file = std::io::BufReader::with_capacity(256 * 1024, std::fs::File::open(path)?);
    let mut hasher = Sha256::new();
    std::io::copy(&mut file, &mut hasher)?;
    Ok(hex(&hasher.finalize()))
}

/// `seamlit fix INPUT -o OUTPUT` for one local file into a local `.glb` or `.vrm`, as
/// [`crate::fix_file`] does it (the same bytes), and returns the JSON of the report row's
/// columns: both files' SHA-256, the seams as loaded and fixed, what the repair decided, the
/// warnings, and `changed`. The output is written under a temporary name and renamed once
/// complete; an error writing it starts with the output's path.
///
/// With `digests`, the two files are not hashed here: the input file and the output's bytes
/// go to `digests` under `keys` (input, output), and the row's two hashes are `null`.
#[pyfunction]
#[pyo3(signature = (input, output, settings, digests = None, keys = (0, 0)))]
pub(crate) fn fix_file_row(
    py: Python<'_>,
    input: PathBuf,
    output: PathBuf,
    settings: &str,
    digests: Option<Bound<'_, Digests>>,
    keys: (u64, u64),
) -> PyResult<String> {
    let settings = Settings::parse(settings)?;
    let load_options = settings.load_options(seamlit_io::LoadOptions::FIX);
    let save = SaveOptions {
        overwrite_input: settings.overwrite_input,
        keep_compression: settings.keep_compression,
    };
    let job = settings.row_job();
    let deferred = digests.is_some();
    let run = || -> PyResult<(Row, Vec<u8>, Option<Stamp>)> {
        // What the file is before the loader reads it: hashed later only if still that.
        let stamp = if deferred { Stamp::of(&input).ok() } else { None };
        let mut asset = load(&input, &load_options)?;
        // Read again for its hash: from the page cache.
        let input_sha256 = if deferred {
            None
        } else {
            Some(file_sha256(&input).map_err(|e| error(format!("{}: {e}", input.display())))?)
        };
        let fixed =
            fix_asset(&mut asset, &job).map_err(|e| error(format!("{}: {e}", input.display())))?;
        let (bytes, saved) = glb_in_memory(&asset, &output, &save, &input)?;
        seamlit_io::files::write(&output, &bytes).map_err(error)?;
        let output_sha256 = (!deferred).then(|| sha256(&bytes));
        let row = Row::of(&fixed, asset.warnings.iter().chain(&saved), input_sha256, output_sha256);
        Ok((row, bytes, stamp))
    };
    let (row, bytes, stamp) = detached(py, run)?;
    if let Some(digests) = digests {
        let mut digests = digests.borrow_mut();
        match stamp {
            Some(stamp) => digests.push_file(keys.0, input, stamp),
            // Gone before it was loaded and there again when it was: nothing to vouch for.
            None => digests.push_gone(keys.0),
        }
        digests.push_bytes(keys.1, bytes);
    }
    json_text(&row)
}

/// The model written by the glTF writer into memory as `output` (`.glb` or `.vrm`: one
/// file), with the writer's warnings; refused where that would overwrite `input` without
/// `overwrite_input`, as [`seamlit_io::save`] refuses it.
fn glb_in_memory(
    asset: &seamlit_io::Asset,
    output: &Path,
    save: &SaveOptions,
    input: &Path,
) -> PyResult<(Vec<u8>, Vec<String>)> {
    if !save.overwrite_input && seamlit_io::files::same_file(input, output) {
        return Err(error(seamlit_io::IoError::WouldOverwriteInput { path: output.to_path_buf() }));
    }
    let mut memory = seamlit_io::files::Destination::memory();
    let saved = seamlit_io::gltf::save_to(asset, output, save, &mut memory).map_err(error)?;
    let mut files = memory.into_memory();
    if files.len() != 1 {
        return Err(error(format!("{}: the fixed model needs files beside it", input.display())));
    }
    Ok((files.remove(0).1, saved))
}
