//! `seamlit fix`: load, fix, write. A folder in gives a folder out, with a progress bar; a
//! file that fails is reported and the others go on. A folder's small files are fixed several
//! at a time, one per thread, its large ones one at a time with every thread on each; what
//! each file says (warnings, its line or error) is printed in the folder's order.
//!
//! A panic while a file is processed (a bug, never expected) is caught and reported as that
//! file's failure, "internal error" on one line with the panic's message and place, exit
//! status 1; a folder run goes on with the next file. While files are processed a quiet panic
//! hook records the message instead of printing it (with a backtrace hint) through the
//! progress bar; with `RUST_BACKTRACE` set (not `0`) the standard report is printed as well.
//!
//! Test hook, compiled into debug builds only (`#[cfg(debug_assertions)]`: the binary's tests
//! run the debug build, and no input reaches this path otherwise; the release build that users
//! install does not contain the hook or read the variable): with `SEAMLIT_DEBUG_PANIC_ON=TEXT`
//! set, processing a file whose name contains TEXT panics, so that this path can be exercised
//! (`a_panic_in_one_file_of_a_folder_is_its_internal_error_and_the_others_go_on`,
//! crates/seamlit/tests/hostile.rs).

use std::panic::{AssertUnwindSafe, PanicHookInfo};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

use indicatif::{ProgressBar, ProgressStyle};
use rayon::iter::{IntoParallelIterator, ParallelIterator};
use seamlit_io::job::{FixJob, SkinSeams, fix_geometry};
use seamlit_io::{InvalidAsset, IoError, LoadOptions, SaveOptions};
use seamlit_mesh::FixOptions;

use crate::cli::{FixArgs, SkinSeamsArg};
use crate::failure::{Classify, Failure};

/// Runs `seamlit fix`.
///
/// # Errors
/// The first failure for a file; for a folder, a summary failure when any file failed
/// (bad input if any file was bad input).
pub(crate) fn run(args: &FixArgs) -> Result<(), Failure> {
    seamlit_io::job::in_pool(|| run_in_pool(args))
}

fn run_in_pool(args: &FixArgs) -> Result<(), Failure> {
    let options = args.fix.apply(FixOptions::DEFAULT).with_mode(args.mode.into());
    let load = args.load.options(LoadOptions::FIX);
    let save = SaveOptions {
        overwrite_input: args.overwrite_input,
        keep_compression: args.keep_compression,
    };
    if args.input.is_dir() {
        check_keep_compression(args.keep_compression, &args.output, args.format.extension())?;
        return run_folder(args, &options, &load, &save);
    }
    check_output_extension(&args.output)?;
    let extension = args.output.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    check_keep_compression(args.keep_compression, &args.output, &extension.unwrap_or_default())?;
    let _quiet = QuietPanics::install();
    let job = job(args, &options);
    let mut warnings = Vec::new();
    let result = guarded(&args.input, || {
        fix_file(&args.input, &args.output, &job, (&load, &save), &mut warnings)
    });
    for warning in &warnings {
        eprintln!("warning: {warning}");
    }
    println!("{}", result?);
    Ok(())
}

fn check_output_extension(output: &Path) -> Result<(), Failure> {
    let ext = output.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("glb" | "gltf" | "obj" | "vrm" | "usda" | "usd" | "usdc" | "usdz") => Ok(()),
        // The library's own line: seamlit writes no FBX, write .glb.
        Some("fbx") => {
            Err(Failure::BadInput(IoError::FbxOutput { path: output.to_path_buf() }.into()))
        }
        _ => Err(Failure::input(format!(
            "{}: unknown output format (expected a .glb, .gltf, .obj, .vrm, .usda, .usdc or .usdz file name)",
            output.display()
        ))),
    }
}

/// `--keep-compression` with OBJ output (a file, or `--format obj` for a folder) is refused
/// before anything is read or written: OBJ holds no compressed geometry.
fn check_keep_compression(keep: bool, output: &Path, extension: &str) -> Result<(), Failure> {
    if keep && extension == "obj" {
        return Err(Failure::input(format!(
            "{}: --keep-compression needs glTF or GLB output (an OBJ file holds no compressed geometry); write .glb or .gltf, or leave the flag out",
            output.display()
        )));
    }
    Ok(())
}

/// Runs `work` on `input` (a model file), with a panic turned into a processing failure
/// naming the file.
fn guarded(
    input: &Path,
    work: impl FnOnce() -> Result<String, Failure>,
) -> Result<String, Failure> {
    // Nothing the closure touches is observed after a panic: its state is dropped.
    let result = std::panic::catch_unwind(AssertUnwindSafe(|| {
        #[cfg(debug_assertions)]
        debug_panic(input);
        work()
    }));
    result.unwrap_or_else(|payload| {
        let message = panic_message(&*payload);
        let message = QuietPanics::take(&message).unwrap_or(message);
        Err(Failure::processing(format!(
            "{}: internal error (a bug in seamlit, please report it): {message}",
            input.display()
        )))
    })
}

/// The text a panic was raised with.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_owned())
}

/// The `SEAMLIT_DEBUG_PANIC_ON` test hook (see the module docs): panics when the file's name
/// contains the variable's text. Not compiled into release builds.
#[cfg(debug_assertions)]
fn debug_panic(input: &Path) {
    let Some(text) = std::env::var_os("SEAMLIT_DEBUG_PANIC_ON") else { return };
    let name = input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    if !text.is_empty() && name.contains(&*text.to_string_lossy()) {
        panic!("SEAMLIT_DEBUG_PANIC_ON matched {name:?}");
    }
}

/// While alive, panics are recorded (message and place) for [`QuietPanics::take`] instead of
/// being printed; the previous hook is restored on drop. Files are fixed on several threads
/// at once, and a panic may arise on another thread than the one that catches it (a part of
/// a parallel loop): each is found again by its message.
struct QuietPanics {
    previous: Arc<dyn Fn(&PanicHookInfo<'_>) + Send + Sync>,
}

/// The panics recorded by the quiet hook and not yet taken: (message, " at file:line").
static PANICS: Mutex<Vec<(String, String)>> = Mutex::new(Vec::new());

impl QuietPanics {
    fn install() -> Self {
        let previous: Arc<dyn Fn(&PanicHookInfo<'_>) + Send + Sync> =
            Arc::from(std::panic::take_hook());
        let backtrace = std::env::var_os("RUST_BACKTRACE").is_some_and(|v| v != "0");
        let chained = Arc::clone(&previous);
        std::panic::set_hook(Box::new(move |info| {
            let message = panic_message(info.payload());
            let place = info.location().map(|l| format!(" at {}:{}", l.file(), l.line()));
            if let Ok(mut panics) = PANICS.lock() {
                panics.push((message, place.unwrap_or_default()));
            }
            if backtrace {
                chained(info);
            }
        }));
        Self { previous }
    }

    /// The recorded panic with this message, with its place, taken out of the record.
    fn take(message: &str) -> Option<String> {
        let mut panics = PANICS.lock().ok()?;
        let i = panics.iter().rposition(|(m, _)| m == message)?;
        let (message, place) = panics.swap_remove(i);
        Some(format!("{message}{place}"))
    }
}

impl Drop for QuietPanics {
    fn drop(&mut self) {
        let previous = Arc::clone(&self.previous);
        std::panic::set_hook(Box::new(move |info| previous(info)));
    }
}

/// The [`FixJob`] of the command line's flags.
fn job(args: &FixArgs, options: &FixOptions) -> FixJob {
    FixJob {
        options: *options,
        tangents_asked: args.fix.tangents.is_some(),
        skin_seams: match args.skin_seams {
            SkinSeamsArg::Match => SkinSeams::Match,
            SkinSeamsArg::Keep => SkinSeams::Keep,
        },
        samples: args.samples,
        report_as_loaded: false,
        motion: true,
    }
}

/// Loads, fixes ([`seamlit_io::job::fix_geometry`]) and writes one model, while it is measured
/// where the save streams ([`seamlit_io::job::Unmeasured::measure_and_save`]); returns its summary:
/// what was written, then what the fix changed. Its warnings go to `warnings` as they arise
/// (the caller prints them before the summary or the error).
fn fix_file(
    input: &Path,
    output: &Path,
    job: &FixJob,
    (load, save): (&LoadOptions, &SaveOptions),
    warnings: &mut Vec<String>,
) -> Result<String, Failure> {
    if !input.exists() {
        return Err(Failure::input(format!("{}: no such file", input.display())));
    }
    let mut asset = seamlit_io::load(input, load).bad_input()?;
    warnings.extend(asset.warnings.iter().map(ToString::to_string));
    let unmeasured = fix_geometry(&mut asset, job)
        .map_err(|e| Failure::input(format!("{}: {e}", input.display())))?;
    crate::output::prepare_folder_of(output)?;
    let (fixed, saved) = unmeasured.measure_and_save(&asset, output, save);
    let saved = saved.map_err(classify_save);
    // A failed measure is a bug (`FixError::Report`); the model was fixed and may be written.
    let fixed = fixed.map_err(|e| {
        let written = if saved.is_ok() {
            format!(" ({} was written)", output.display())
        } else {
            String::new()
        };
        Failure::processing(format!("{}: {e}{written}", input.display()))
    })?;
    warnings.extend(saved?.warnings.iter().map(ToString::to_string));
    Ok(fixed.summary(output))
}

/// Writing fails through bad input (an output that is the input, an unknown extension, a
/// buffer 0 without data written as GLB, a file a .usdz package needs that cannot be read) or
/// through the machine (a full disk).
fn classify_save(e: IoError) -> Failure {
    match e {
        // The library names its option; the user of the command line needs the flag.
        IoError::WouldOverwriteInput { path } => Failure::input(format!(
            "{}: refusing to overwrite the model's own source file (pass --overwrite-input to allow it)",
            path.display()
        )),
        // A buffer 0 without data of its own cannot become a GLB's BIN chunk or grow: the
        // input's shape, and the line says to write .gltf.
        IoError::UnknownFormat { .. }
        | IoError::FbxOutput { .. }
        | IoError::VrmOutput { .. }
        | IoError::CannotKeepCompression { .. }
        // A .usdz package reads the input's files again (its layers in every variant, its
        // textures): one that cannot be read is bad input, as when loading.
        | IoError::Usd { .. }
        | IoError::UsdOutput { kind: seamlit_io::UsdOutput::Package { .. }, .. }
        | IoError::InvalidAsset {
            kind: InvalidAsset::HostInGlb | InvalidAsset::HostCannotGrow,
            ..
        } => Failure::BadInput(e.into()),
        other => Failure::Processing(other.into()),
    }
}

fn run_folder(
    args: &FixArgs,
    options: &FixOptions,
    load: &LoadOptions,
    save: &SaveOptions,
) -> Result<(), Failure> {
    if args.output.exists() && !args.output.is_dir() {
        return Err(Failure::input(format!(
            "{}: is a file; with a folder INPUT, OUTPUT must be a folder",
            args.output.display()
        )));
    }
    let inputs = model_files(&args.input, &args.output, !args.no_recurse)?;
    crate::output::prepare_folder(&args.output)?;
    let bar = ProgressBar::new(inputs.len() as u64);
    if let Ok(style) = ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed} {wide_msg}") {
        bar.set_style(style);
    }
    // The output names first, in the inputs' order: folder mode's rule for names that clash.
    let mut names = seamlit_io::folder::OutputNames::new();
    let outputs: Vec<PathBuf> = inputs
        .iter()
        .map(|input| {
            let relative = input.strip_prefix(&args.input).unwrap_or(input);
            let extension = seamlit_io::folder::output_extension(input, args.format.extension());
            names.name(relative, &args.output, extension)
        })
        .collect();
    let quiet = QuietPanics::install();
    let job = job(args, options);
    let lines = Mutex::new(InOrder::default());
    for group in groups(&inputs) {
        group.into_par_iter().for_each(|i| {
            let input = &inputs[i];
            let relative = input.strip_prefix(&args.input).unwrap_or(input);
            bar.set_message(relative.display().to_string());
            let mut warnings = Vec::new();
            let result =
                guarded(input, || fix_file(input, &outputs[i], &job, (load, save), &mut warnings));
            // A poisoned lock (a panic while printing) still holds every count.
            let mut lines = lines.lock().unwrap_or_else(PoisonError::into_inner);
            lines.done(i, (warnings, result), &bar);
            drop(lines);
            bar.inc(1);
        });
    }
    drop(quiet);
    bar.finish_and_clear();
    let InOrder { failed, bad_input, .. } =
        lines.into_inner().unwrap_or_else(PoisonError::into_inner);
    let total = inputs.len();
    println!("fixed {} of {total} models into {}", total - failed, args.output.display());
    match (failed, bad_input) {
        (0, _) => Ok(()),
        (n, true) => Err(Failure::input(format!("{n} of {total} models failed"))),
        (n, false) => Err(Failure::processing(format!("{n} of {total} models failed"))),
    }
}

/// Files below this size are fixed several at a time, one per thread of the pool (each
/// file's own loops then run on its thread); a file of this size or more is fixed alone, its
/// loops spread over the pool, so that no more than one large model's working set (tens of
/// times its file's size) is held at once.
const FIX_TOGETHER_BELOW: u64 = 8 << 20;

/// The inputs' indices in groups run one after another: each run of consecutive small files
/// together, each large file alone.
fn groups(inputs: &[PathBuf]) -> Vec<Vec<usize>> {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut small = Vec::new();
    for (i, input) in inputs.iter().enumerate() {
        let size = std::fs::metadata(input).map_or(0, |m| m.len());
        if size < FIX_TOGETHER_BELOW {
            small.push(i);
        } else {
            if !small.is_empty() {
                groups.push(std::mem::take(&mut small));
            }
            groups.push(vec![i]);
        }
    }
    if !small.is_empty() {
        groups.push(small);
    }
    groups
}

/// One file's warnings and its line or failure.
type Outcome = (Vec<String>, Result<String, Failure>);

/// Each file's warnings and line (or error) printed in the inputs' order as files finish in
/// any order, and the failures counted.
#[derive(Default)]
struct InOrder {
    next: usize,
    waiting: std::collections::BTreeMap<usize, Outcome>,
    failed: usize,
    bad_input: bool,
}

impl InOrder {
    fn done(&mut self, i: usize, outcome: Outcome, bar: &ProgressBar) {
        self.waiting.insert(i, outcome);
        while let Some((warnings, result)) = self.waiting.remove(&self.next) {
            for warning in warnings {
                bar.suspend(|| eprintln!("warning: {warning}"));
            }
            match result {
                Ok(line) => bar.suspend(|| println!("{line}")),
                Err(f) => {
                    self.failed += 1;
                    self.bad_input |= f.is_bad_input();
                    bar.suspend(|| eprintln!("error: {f}"));
                }
            }
            self.next += 1;
        }
    }
}

/// The model files in `dir` by folder mode's rules ([`seamlit_io::folder::model_files`]), or
/// bad input when the folder cannot be read or holds none.
fn model_files(dir: &Path, output: &Path, recurse: bool) -> Result<Vec<PathBuf>, Failure> {
    let files =
        seamlit_io::folder::model_files(dir, Some(output), recurse).map_err(|e| match e {
            IoError::Io { path, source } => {
                Failure::input(format!("{}: cannot read the folder: {source}", path.display()))
            }
            other => Failure::input(other.to_string()),
        })?;
    if files.is_empty() {
        let where_ = if recurse { "in this folder or its subfolders" } else { "in this folder" };
        return Err(Failure::input(format!(
            "{}: no model files (.obj, .gltf, .glb, .vrm, .fbx, .usda, .usdc, .usdz, Newell patches) {where_}",
            dir.display()
        )));
    }
    Ok(files)
}
