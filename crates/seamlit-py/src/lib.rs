//! `seamlit._seamlit`: the native half of the `seamlit` Python package.
//!
//! The package's public functions live in `python/seamlit/__init__.py`, which checks and
//! converts the caller's arguments (NumPy dtypes, keyword options) and calls the
//! functions here. Each runs the same steps as the command line and releases the GIL while
//! the geometry work runs:
//!
//! - [`fix_file`]: load, fix as the command line does ([`seamlit_io::job::fix_geometry`]),
//!   save: `seamlit fix INPUT -o OUTPUT`;
//! - [`inspect`]: load, measure the seams as loaded and after a fix: `seamlit inspect`;
//! - [`fix`]: the fix on arrays, for callers that hold their meshes in memory;
//! - [`fix_model_bytes`]: [`fix_file`] for a model held in memory, into memory;
//! - `seamlit.ray`'s per-file calls ([`fleet`]): a file's fix, output and report row in one;
//!   the report's hashes of a task's files, made together ([`digests`]).
//!
//! Options arrive as JSON ([`Settings`]): the fix options by their serde names (e.g.
//! `{"fix": {"mode": "model", "crease_angle_deg": 60}, "weld_tolerance": "rel:1e-6"}`).
//! Results and reports go back as JSON text (the Python side parses it) or NumPy arrays.
//! Errors are [`SeamlitError`] with the command line's one-line message, or
//! `FileNotFoundError` for a missing input.

use std::path::{Path, PathBuf};

mod digests;
mod fleet;

use glam::{Mat4, Vec2, Vec3, Vec4};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;
use seamlit_io::files::{Files, MemoryFiles};
use seamlit_io::job::{FixJob, Fixed, SkinSeams, fix_asset, fix_geometry};
use seamlit_io::{Asset, LoadOptions, SaveOptions};
use seamlit_mesh::{FixOptions, Model, Object, ReportOptions, WeldTolerance};

pyo3::create_exception!(
    _seamlit,
    SeamlitError,
    PyValueError,
    "A model seamlit cannot read or fix, or options it does not accept; the message names the file and the place."
);

/// The error for a message.
fn error(message: impl std::fmt::Display) -> PyErr {
    SeamlitError::new_err(message.to_string())
}

/// What a call asks for, as the Python side sends it (JSON): the fix options (serde names;
/// absent members keep the defaults), the weld tolerance in the command line's spelling,
/// and what the command line's other flags say.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Settings {
    #[serde(default)]
    fix: FixOptions,
    #[serde(default)]
    weld_tolerance: Option<String>,
    /// Whether the caller named a tangent generator (else [`Asset::fix_options`] chooses).
    #[serde(default)]
    tangents_asked: bool,
    #[serde(default = "default_tessellation")]
    tessellation: u32,
    #[serde(default)]
    overwrite_input: bool,
    /// `--keep-compression` ([`SaveOptions::keep_compression`]).
    #[serde(default)]
    keep_compression: bool,
    /// `--asset-root` ([`LoadOptions::asset_roots`]).
    #[serde(default)]
    asset_roots: Vec<PathBuf>,
    /// `--skin-seams match` (the default) or `keep`, for [`fix_file`].
    #[serde(default = "default_match_skin_seams")]
    match_skin_seams: bool,
    /// `--samples`: times of each animation the seams in motion are measured at.
    #[serde(default = "default_samples")]
    samples: u32,
}

/// `--samples`' default.
fn default_samples() -> u32 {
    FixJob::DEFAULT.samples
}

/// `--skin-seams`' default: `match`.
fn default_match_skin_seams() -> bool {
    true
}

/// `--tessellation`'s default.
fn default_tessellation() -> u32 {
    16
}

impl Settings {
    /// `base` with the settings that concern loading.
    fn load_options(&self, base: LoadOptions) -> LoadOptions {
        LoadOptions {
            tessellation: self.tessellation,
            asset_roots: self.asset_roots.clone(),
            ..base
        }
    }

    /// The command line's job for these settings, the seams as loaded measured too.
    fn job(&self) -> FixJob {
        FixJob {
            options: self.fix,
            tangents_asked: self.tangents_asked,
            skin_seams: if self.match_skin_seams { SkinSeams::Match } else { SkinSeams::Keep },
            samples: self.samples,
            report_as_loaded: true,
            motion: true,
        }
    }

    /// [`Self::job`] for `seamlit.ray`'s report row ([`fleet::Row`]), which has no column
    /// for the seams in motion: they are not measured (the fleet bench's task loop 0.97x,
    /// BENCHMARKS.md).
    fn row_job(&self) -> FixJob {
        FixJob { motion: false, ..self.job() }
    }

    /// The settings of a call, with the weld tolerance applied to the fix options.
    fn parse(json: &str) -> PyResult<Self> {
        let mut settings: Self =
            serde_json::from_str(json).map_err(|e| error(format!("options: {e}")))?;
        if let Some(t) = &settings.weld_tolerance {
            settings.fix.weld_tolerance =
                t.parse::<WeldTolerance>().map_err(|e| error(format!("weld_tolerance: {e}")))?;
        }
        Ok(settings)
    }
}

/// Loads a model file as the command line does: a missing file is `FileNotFoundError`.
fn load(path: &Path, options: &LoadOptions) -> PyResult<Asset> {
    if !path.is_file() {
        let what =
            if path.is_dir() { "is a folder, expected a model file" } else { "no such file" };
        return Err(PyFileNotFoundError::new_err(format!("{}: {what}", path.display())));
    }
    seamlit_io::load(path, options).map_err(error)
}

/// JSON text of a value that serialises (seamlit's reports always do).
fn json_text<T: serde::Serialize + ?Sized>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(error)
}

/// `seamlit fix INPUT -o OUTPUT`: loads `input`, fixes it as the command line does
/// ([`seamlit_io::job::fix_geometry`], then its measures while it is written: the same
/// steps, so the same bytes), writes `output`;
/// returns the JSON of the job's report ([`seamlit_io::job::Fixed::json`]: `options`,
/// `as_loaded`, `fixed`, `changes`, `skin_seams_matched`, `motion`, `morph_seams`) with
/// `input`, `output`, `summary` (the lines the command line prints) and `warnings`.
#[pyfunction]
fn fix_file(py: Python<'_>, input: PathBuf, output: PathBuf, settings: &str) -> PyResult<String> {
    let settings = Settings::parse(settings)?;
    let load_options = settings.load_options(LoadOptions::FIX);
    let save = SaveOptions {
        overwrite_input: settings.overwrite_input,
        keep_compression: settings.keep_compression,
    };
    let job = settings.job();
    let run = || -> PyResult<serde_json::Value> {
        let mut asset = load(&input, &load_options)?;
        let unmeasured = fix_geometry(&mut asset, &job)
            .map_err(|e| error(format!("{}: {e}", input.display())))?;
        let (fixed, saved) = unmeasured.measure_and_save(&asset, &output, &save);
        let fixed = fixed.map_err(|e| error(format!("{}: {e}", input.display())))?;
        let saved = saved.map_err(error)?;
        let warnings = asset.warnings.iter().chain(&saved.warnings);
        Ok(fixed.file_json(&input.display().to_string(), &output, warnings))
    };
    json_text(&detached(py, run)?)
}

/// [`fix_file`] for a model in one file held in memory (GLB, VRM, USDZ, FBX), all in memory:
/// read from `data` as the set of one file named `name`
/// ([`seamlit_io::files::Files::Memory`]: the readers read it, and anything it names, from
/// there), fixed, written by the glTF writer into memory
/// ([`seamlit_io::files::Destination::memory`]) as `output` (a name: `NAME.glb`, or `NAME.vrm`);
/// returns the output's bytes and the JSON of [`fix_file`]. `name` names the input in errors.
/// `companions`: the files a model of several names (a `.gltf`'s buffers and images, an OBJ's
/// MTL and textures, a USD layer's layers), each by its path beside `name`'s, in the same set.
/// `row`: the JSON of `seamlit.ray`'s report row ([`fleet::Row`]: both files' SHA-256 and
/// the columns a fix fills) in place of the report; with `digests`, the row's two hashes are
/// `null` and `data` and the output go to `digests` under `keys` (input, output) instead,
/// to be hashed with others.
#[pyfunction]
#[pyo3(signature = (data, name, output, settings, companions = Vec::new(), row = false, digests = None, keys = (0, 0)))]
#[allow(clippy::too_many_arguments)] // Python's keywords, each with its default
fn fix_model_bytes<'py>(
    py: Python<'py>,
    data: &[u8],
    name: &str,
    output: &str,
    settings: &str,
    companions: Vec<(PathBuf, Bound<'py, pyo3::types::PyBytes>)>,
    row: bool,
    digests: Option<Bound<'py, digests::Digests>>,
    keys: (u64, u64),
) -> PyResult<(Bound<'py, pyo3::types::PyBytes>, String)> {
    let settings = Settings::parse(settings)?;
    let companions: Vec<(PathBuf, &[u8])> =
        companions.iter().map(|(path, bytes)| (path.clone(), bytes.as_bytes())).collect();
    let deferred = row && digests.is_some();
    let run = || -> PyResult<(Vec<u8>, String)> {
        let job = if row { settings.row_job() } else { settings.job() };
        let (bytes, fixed, warnings) =
            fix_in_memory(data, name, output, &settings, &job, companions)?;
        let report = if row {
            let hash = |bytes: &[u8]| (!deferred).then(|| digests::sha256(bytes));
            json_text(&fleet::Row::of(&fixed, &warnings, hash(data), hash(&bytes)))?
        } else {
            json_text(&fixed.file_json(name, Path::new(output), &warnings))?
        };
        Ok((bytes, report))
    };
    let (bytes, report) = detached(py, run)?;
    let output = pyo3::types::PyBytes::new(py, &bytes);
    if let Some(digests) = digests.filter(|_| deferred) {
        let mut digests = digests.borrow_mut();
        digests.push_bytes(keys.0, data.to_vec());
        digests.push_bytes(keys.1, bytes);
    }
    Ok((output, report))
}

/// Loads the model `name` from `data` (with `companions`, the files beside it, each by its
/// path beside `name`'s) as the set of files in memory the readers read, fixes it as `job`
/// says (the command line's steps), and writes it with the glTF writer into memory as
/// `output` (one file: `NAME.glb` or `NAME.vrm`); returns the output's bytes, what the fix
/// did, and the loader's and writer's warnings.
fn fix_in_memory(
    data: &[u8],
    name: &str,
    output: &str,
    settings: &Settings,
    job: &FixJob,
    companions: Vec<(PathBuf, &[u8])>,
) -> PyResult<(Vec<u8>, Fixed, Vec<String>)> {
    // Each file copied once, from Python's bytes into the set's shared buffers.
    let files = MemoryFiles::new(std::iter::once((PathBuf::from(name), data)).chain(companions));
    let load_options =
        LoadOptions { files: Files::Memory(files), ..settings.load_options(LoadOptions::FIX) };
    let save =
        SaveOptions { keep_compression: settings.keep_compression, ..SaveOptions::default() };
    let output = Path::new(output);
    let mut asset = seamlit_io::load(Path::new(name), &load_options).map_err(error)?;
    let fixed = fix_asset(&mut asset, job).map_err(|e| error(format!("{name}: {e}")))?;
    let mut memory = seamlit_io::files::Destination::memory();
    let saved = seamlit_io::gltf::save_to(&asset, output, &save, &mut memory).map_err(error)?;
    let mut files = memory.into_memory();
    if files.len() != 1 {
        return Err(error(format!("{name}: the fixed model needs files beside it")));
    }
    let warnings = asset.warnings.into_iter().chain(saved).collect();
    Ok((files.remove(0).1, fixed, warnings))
}

/// Runs `work` without the interpreter's lock, on a thread of rayon's pool, or with a pool
/// of one thread (a Ray task's `RAYON_NUM_THREADS=1`) on the calling thread itself
/// ([`seamlit_io::job::in_pool_or_here`]). Handed off from the interpreter's thread, the
/// many small loops of fixing a small model ran 1.5 times slower, the pool's thread woken on
/// the other core for each; and then each file, handed to the pool's thread, 1.1 times.
fn detached<T: Send>(py: Python<'_>, work: impl FnOnce() -> T + Send) -> T {
    py.detach(|| seamlit_io::job::in_pool_or_here(work))
}

/// Loads `path` and measures its seams as loaded and after a fix, without writing
/// anything; returns the JSON of `{"file", "options", "as_loaded", "fixed", "changes",
/// "warnings"}`.
#[pyfunction]
fn inspect(py: Python<'_>, path: PathBuf, settings: &str) -> PyResult<String> {
    let settings = Settings::parse(settings)?;
    let load_options = settings.load_options(LoadOptions::GEOMETRY);
    let run = || -> PyResult<serde_json::Value> {
        let mut asset = load(&path, &load_options)?;
        let options = asset.fix_options(settings.fix, settings.tangents_asked);
        let at = |e: &dyn std::fmt::Display| error(format!("{}: {e}", path.display()));
        let report_options = ReportOptions::from(&options);
        let (before, loaded) =
            seamlit_mesh::report_before_fix(&asset.model, &report_options).map_err(|e| at(&e))?;
        let (changes, welded) =
            seamlit_mesh::fix_in_place_welded(&mut asset.model, &options, Some(&loaded))
                .map_err(|e| at(&e))?;
        let (as_loaded, fixed) = before
            .with_fixed(&asset.model, &report_options, welded.as_ref())
            .map_err(|e| at(&e))?;
        Ok(serde_json::json!({
            "file": path.display().to_string(),
            "options": options,
            "as_loaded": as_loaded,
            "fixed": fixed,
            "changes": changes,
            "warnings": asset.warnings,
        }))
    };
    json_text(&detached(py, run)?)
}

/// One object as the Python side passes it: positions (n x 3), triangles (m x 3), optional
/// UVs (n x 2), normals (n x 3), tangents (n x 4) and a 4 x 4 transform (row-major, the
/// translation in the last column, as NumPy users write it).
type ObjectArrays<'py> = (
    String,
    PyReadonlyArray2<'py, f32>,
    PyReadonlyArray2<'py, u32>,
    Option<PyReadonlyArray2<'py, f32>>,
    Option<PyReadonlyArray2<'py, f32>>,
    Option<PyReadonlyArray2<'py, f32>>,
    Option<PyReadonlyArray2<'py, f32>>,
);

/// One fixed object for the Python side: normals (n' x 3), tangents (n' x 4, or none),
/// for every vertex the input vertex it copies (n'), and the triangles (m x 3).
type FixedArrays<'py> = (
    Bound<'py, PyArray2<f32>>,
    Option<Bound<'py, PyArray2<f32>>>,
    Bound<'py, numpy::PyArray1<u32>>,
    Bound<'py, PyArray2<u32>>,
);

/// Rows of `columns` values of a 2-D array, checked: `what` of object `index` names it in
/// the error.
fn rows<T: numpy::Element + Copy, const N: usize>(
    array: &PyReadonlyArray2<'_, T>,
    index: usize,
    what: &str,
) -> PyResult<Vec<[T; N]>> {
    let shape = array.shape();
    if shape[1] != N {
        return Err(error(format!(
            "object {index}: {what} must have shape (n, {N}), not ({}, {})",
            shape[0], shape[1]
        )));
    }
    let values = array
        .as_slice()
        .map_err(|_| error(format!("object {index}: {what} is not a contiguous array")))?;
    Ok(values.as_chunks::<N>().0.to_vec())
}

/// A model object from the arrays of object `index`.
fn object(index: usize, arrays: &ObjectArrays<'_>) -> PyResult<Object> {
    let (name, positions, triangles, uvs, normals, tangents, transform) = arrays;
    let positions = rows::<f32, 3>(positions, index, "positions")?;
    let n = positions.len();
    let per_vertex = |what: &str, count: usize| {
        if count == n {
            Ok(())
        } else {
            Err(error(format!("object {index}: {what} has {count} rows, positions {n}")))
        }
    };
    let mut object = Object::new(
        name.clone(),
        positions.into_iter().map(Vec3::from_array).collect(),
        rows::<u32, 3>(triangles, index, "triangles")?,
    );
    if let Some(uvs) = uvs {
        let uvs = rows::<f32, 2>(uvs, index, "uvs")?;
        per_vertex("uvs", uvs.len())?;
        object.uvs = Some(uvs.into_iter().map(Vec2::from_array).collect());
    }
    if let Some(normals) = normals {
        let normals = rows::<f32, 3>(normals, index, "normals")?;
        per_vertex("normals", normals.len())?;
        object.normals = Some(normals.into_iter().map(Vec3::from_array).collect());
    }
    if let Some(tangents) = tangents {
        let tangents = rows::<f32, 4>(tangents, index, "tangents")?;
        per_vertex("tangents", tangents.len())?;
        object.tangents = Some(tangents.into_iter().map(Vec4::from_array).collect());
    }
    if let Some(transform) = transform {
        let rows = rows::<f32, 4>(transform, index, "transform")?;
        let [r0, r1, r2, r3]: [[f32; 4]; 4] = rows
            .try_into()
            .map_err(|_| error(format!("object {index}: transform must be 4 x 4")))?;
        object.transform = Some(Mat4::from_cols_array_2d(&[r0, r1, r2, r3]).transpose());
    }
    Ok(object)
}

/// Fixes the objects together (one model); returns per object its normals, tangents, the
/// input vertex each output vertex copies, and the triangles.
#[pyfunction]
fn fix<'py>(
    py: Python<'py>,
    objects: Vec<ObjectArrays<'py>>,
    settings: &str,
) -> PyResult<Vec<FixedArrays<'py>>> {
    let options = Settings::parse(settings)?.fix;
    let objects =
        objects.iter().enumerate().map(|(i, arrays)| object(i, arrays)).collect::<PyResult<_>>()?;
    let mut model = Model::new(objects);
    detached(py, || seamlit_mesh::fix_in_place(&mut model, &options)).map_err(error)?;
    model
        .objects
        .into_iter()
        .map(|object| {
            // Below u32::MAX: fix refuses models whose vertices plus corners exceed
            // seamlit_mesh::MAX_ELEMENTS, and it adds at most one vertex per corner.
            let n = u32::try_from(object.vertex_count()).map_err(|_| {
                error(format!(
                    "object {:?}: {} vertices after the fix, past 32-bit indices",
                    object.name,
                    object.vertex_count()
                ))
            })?;
            let remap: Vec<u32> = (0..n).map(|v| object.source_vertex(v)).collect();
            // Normals and triangles are handed over without a copy; tangents (16-byte
            // aligned `Vec4`s) are copied into plain floats.
            let normals = object.normals.unwrap_or_default();
            let normals = Array2::from_shape_vec(
                (normals.len(), 3),
                bytemuck::allocation::cast_vec::<Vec3, f32>(normals),
            )
            .map_err(error)?;
            let tangents = object
                .tangents
                .map(|t| {
                    Array2::from_shape_vec(
                        (t.len(), 4),
                        t.iter().flat_map(|v| v.to_array()).collect(),
                    )
                })
                .transpose()
                .map_err(error)?;
            let triangles = Array2::from_shape_vec(
                (object.triangles.len(), 3),
                bytemuck::allocation::cast_vec::<[u32; 3], u32>(object.triangles),
            )
            .map_err(error)?;
            Ok((
                normals.into_pyarray(py),
                tangents.map(|t| t.into_pyarray(py)),
                remap.into_pyarray(py),
                triangles.into_pyarray(py),
            ))
        })
        .collect()
}

/// The module: the functions above and the error type.
#[pymodule]
fn _seamlit(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SeamlitError", m.py().get_type::<SeamlitError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(fix_file, m)?)?;
    m.add_function(wrap_pyfunction!(fix_model_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(fleet::fix_file_row, m)?)?;
    m.add_class::<digests::Digests>()?;
    m.add_function(wrap_pyfunction!(inspect, m)?)?;
    m.add_function(wrap_pyfunction!(fix, m)?)?;
    Ok(())
}
