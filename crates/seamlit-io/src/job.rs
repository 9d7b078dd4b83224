//! One model through `seamlit fix`, as a library call: the steps between loading a file and
//! saving it, so that the command line, the Python package (and its Ray fleet) and the web
//! page fix a model the same way and say the same about it.
//!
//! [`fix_asset`] reads as its steps: the options for this asset (MikkTSpace where a normal
//! map has no tangents, unless a generator was asked for), the copies of the positions the
//! objects share (once, before the fix: split copies are appended, so the input vertices keep
//! their indices), the seams in motion before, the fix in place, the skin influences matched
//! at the copies, the seam report and the seams in motion after. [`fix_geometry`] stops
//! before those measures, which only read the fixed model: [`Unmeasured::measure_with`]
//! takes them while a save that streams writes it (the command line and the Python
//! package's `fix_file` do; the save, mostly one thread's work, was a tenth of the 1M
//! teapot's fix). [`Fixed`] holds what each
//! step found; [`Fixed::summary`] is the text `seamlit fix` prints for a file and
//! [`Fixed::json`] the document the Python package and the page report. [`Inspection`] is
//! `seamlit inspect`: the seam report as loaded and after each mode.
//!
//! ```
//! use seamlit_io::job::{FixJob, fix_asset};
//! use seamlit_io::{LoadOptions, newell};
//!
//! // Two flat patches side by side: one surface delivered as two objects.
//! let mut text = String::from("2\n");
//! text.push_str("1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n");
//! text.push_str("13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28\n28\n");
//! for j in 0..7 {
//!     for i in 0..4 {
//!         text.push_str(&format!("{i},{j},{}\n", 0.1 * (j as f32 - 3.0).powi(2)));
//!     }
//! }
//! let mut asset = newell::parse(&text, "two", 4)?;
//! let fixed = fix_asset(&mut asset, &FixJob::DEFAULT)?;
//! assert_eq!(fixed.report.cross_object.max_normal_angle_deg, Some(0.0));
//! assert!(fixed.summary(std::path::Path::new("two.glb")).starts_with("wrote two.glb: 2 objects"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod inspect;
mod summary;

use std::path::Path;

use seamlit_asset::Asset;
use seamlit_asset::error::IoError;

use crate::{SaveOptions, SaveReport};
use seamlit_asset::motion::{Copies, SeamMotion, morph_seams};
use seamlit_mesh::{
    AsLoaded, Changes, FixOptions, MeshError, ReportOptions, SeamReport, SkinMatch, Welded,
};

pub use inspect::Inspection;
pub use summary::{changes_line, count};

/// What to do with a model: the fix options and the command line's other choices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixJob {
    /// The fix options (`seamlit fix`'s flags).
    pub options: FixOptions,
    /// Whether a tangent generator was named (`--tangents`). When not, a model with a normal
    /// map and objects without tangents gets MikkTSpace ([`Asset::fix_options`]).
    pub tangents_asked: bool,
    /// What is done about skin influences that differ across a seam (`--skin-seams`).
    pub skin_seams: SkinSeams,
    /// How many times of each animation the seams in motion are measured at (`--samples`).
    pub samples: u32,
    /// Whether the seam report of the model as loaded is measured too ([`Fixed::as_loaded`]):
    /// one more pass over the model, which `seamlit fix` does not print.
    pub report_as_loaded: bool,
    /// Whether the seams in motion and the morph targets' seams are measured
    /// ([`Fixed::motion`], [`Fixed::morph_seams`]), which `seamlit fix` prints for a skinned,
    /// animated or morphed model. A measure only: without it the fix and its output are the
    /// same, those two are empty (`seamlit.ray`'s report has no column for them).
    pub motion: bool,
}

impl FixJob {
    /// `seamlit fix`'s defaults.
    pub const DEFAULT: Self = Self {
        options: FixOptions::DEFAULT,
        tangents_asked: false,
        skin_seams: SkinSeams::Match,
        samples: 30,
        report_as_loaded: false,
        motion: true,
    };
}

impl Default for FixJob {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// What is done about the copies of a shared position whose skin influences differ (they
/// open into a gap when the model is posed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SkinSeams {
    /// Every copy gets one set of joints and weights ([`seamlit_asset::match_skin_seams`]):
    /// `--skin-seams match`, the default.
    #[default]
    Match,
    /// The influences stay as authored and the summary says where they differ.
    Keep,
}

/// What [`fix_asset`] found and did.
#[derive(Clone, Debug)]
pub struct Fixed {
    /// The options the model was fixed with (the job's, with the tangent generator this asset
    /// needs).
    pub options: FixOptions,
    /// The seam report as loaded, where [`FixJob::report_as_loaded`] asked for it.
    pub as_loaded: Option<SeamReport>,
    /// What the fix changed.
    pub changes: Changes,
    /// The seam report after the fix (and the skin match).
    pub report: SeamReport,
    /// What matching the skin influences changed (`None` under [`SkinSeams::Keep`]).
    pub matched: Option<SkinMatch>,
    /// The seams in motion per animation, before and after.
    pub motion: Vec<(SeamMotion, SeamMotion)>,
    /// The morph targets whose deltas differ across a seam, with how many shared positions.
    pub morph_seams: Vec<(String, usize)>,
}

/// Why [`fix_asset`] failed.
#[derive(Debug, thiserror::Error)]
pub enum FixError {
    /// The model's geometry is bad (a non-finite position, an index out of range): bad input.
    #[error("{0}")]
    Geometry(MeshError),
    /// The report after a successful fix failed: a bug, not the input's fault.
    #[error("measuring the fixed model: {0}")]
    Report(MeshError),
}

/// Runs `work` on a thread of rayon's global pool and returns what it returns: the parallel
/// loops of a fix (dozens for a small model) then run inline on that thread, their parts
/// stolen by the pool's other threads, instead of each being handed from the caller's thread
/// to the pool and waited for, which cost a small model's fix half its time again when the
/// pool's thread sat on another core (BENCHMARKS.md). The command line and the Python package
/// run each file so. The pool is built on first use as rayon builds it by default (its
/// threads from `RAYON_NUM_THREADS`, else one per CPU) but with the 8 MiB stacks of a main
/// thread, as a model's whole load now runs on them; a pool built before is used as it is.
pub fn in_pool<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    global_pool();
    rayon::scope(|_| work())
}

/// [`in_pool`], but where rayon's pool has one thread (`RAYON_NUM_THREADS=1`: a Ray task),
/// on the calling thread itself, made a pool of one ([`become_a_pool_of_one`]) on its first
/// call: for callers that run one model after another from a thread with a main thread's
/// stack (the Python package: 8 MiB on Linux, 16 MiB on macOS). Fixing 1,008 small files
/// so from Python, handing each to the pool's thread and waking it, maybe on the other core,
/// cost a tenth of the time (BENCHMARKS.md, seamlit.ray).
pub fn in_pool_or_here<T: Send>(work: impl FnOnce() -> T + Send) -> T {
    global_pool();
    if rayon::current_thread_index().is_none() && rayon::current_num_threads() == 1 {
        become_a_pool_of_one();
    }
    rayon::scope(|_| work())
}

/// Rayon's global pool, built on first use as rayon builds it by default but with 8 MiB
/// stacks (see [`in_pool`]); a pool built before is used as it is.
fn global_pool() {
    static POOL: std::sync::Once = std::sync::Once::new();
    POOL.call_once(|| {
        // Fails only when the global pool exists already: then that one is used.
        let _ = rayon::ThreadPoolBuilder::new().stack_size(8 << 20).build_global();
    });
}

/// Makes the calling thread the one thread of a rayon pool of its own, for good: the work
/// it hands to rayon from then on runs on it, inline (its stack is the thread's own). The
/// pool is leaked (rayon keeps a pool that uses the current thread for the thread's life:
/// one small registry per thread, and no thread of its own). Where the thread cannot be
/// made one (already a pool's), nothing changes.
pub fn become_a_pool_of_one() {
    if let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(1).use_current_thread().build() {
        std::mem::forget(pool);
    }
}

/// Fixes `asset` in place as `seamlit fix` does (the module's docs list the steps) and says
/// what was found and done: [`fix_geometry`], then [`Unmeasured::measure`].
///
/// # Errors
/// [`FixError::Geometry`] for bad geometry; [`FixError::Report`] when measuring the fixed
/// model fails.
pub fn fix_asset(asset: &mut Asset, job: &FixJob) -> Result<Fixed, FixError> {
    fix_geometry(asset, job)?.measure(asset)
}

/// [`fix_asset`] up to the fixed model's measures: the options, the copies of the shared
/// positions and the seams in motion before, the fix in place and the skin match. The
/// measures after ([`Unmeasured::measure`]) only read the model, as a save does: a caller
/// that saves the model may run the two side by side (the command line does).
///
/// # Errors
/// [`FixError::Geometry`] for bad geometry.
pub fn fix_geometry(asset: &mut Asset, job: &FixJob) -> Result<Unmeasured, FixError> {
    let options = asset.fix_options(job.options, job.tangents_asked);
    let animations: Vec<usize> =
        if job.motion { (0..asset.animations.len()).collect() } else { Vec::new() };
    let copies = Copies::of(asset, &options).map_err(FixError::Geometry)?;
    let before = copies.measure(asset, &animations, job.samples, &options);
    let report_options = ReportOptions::from(&options);
    // The weld as loaded spares the fix welding the model again, and the fix counts the
    // triangles for both reports.
    let (as_loaded, loaded) = if job.report_as_loaded {
        let (report, weld) = seamlit_mesh::report_before_fix(&asset.model, &report_options)
            .map_err(FixError::Geometry)?;
        (Some(report), Some(weld))
    } else {
        (None, None)
    };
    // Fixed in place: computed normals and tangents overwrite the loaded ones, never copied.
    // The fix's weld, where it can give one, spares the report welding the model again.
    let (changes, welded) =
        seamlit_mesh::fix_in_place_welded(&mut asset.model, &options, loaded.as_ref())
            .map_err(FixError::Geometry)?;
    let matched = match job.skin_seams {
        SkinSeams::Match => Some(seamlit_asset::match_skin_seams(asset, &copies.copies)),
        SkinSeams::Keep => None,
    };
    Ok(Unmeasured {
        options,
        animations,
        samples: job.samples,
        motion: job.motion,
        copies,
        before,
        as_loaded,
        welded,
        changes,
        matched,
    })
}

/// A model [`fix_geometry`] fixed, with what its measures after the fix need.
pub struct Unmeasured {
    options: FixOptions,
    animations: Vec<usize>,
    samples: u32,
    motion: bool,
    copies: Copies,
    before: Vec<SeamMotion>,
    as_loaded: Option<AsLoaded>,
    welded: Option<Welded>,
    changes: Changes,
    matched: Option<SkinMatch>,
}

impl Unmeasured {
    /// The measures of the fixed model `asset` (the one [`fix_geometry`] fixed): the seam
    /// report, and the seams in motion after.
    ///
    /// # Errors
    /// [`FixError::Report`] when measuring the fixed model fails.
    pub fn measure(self, asset: &Asset) -> Result<Fixed, FixError> {
        let report_options = ReportOptions::from(&self.options);
        let (as_loaded, report) = match self.as_loaded {
            Some(before) => before
                .with_fixed(&asset.model, &report_options, self.welded.as_ref())
                .map(|(before, after)| (Some(before), after)),
            None => {
                seamlit_mesh::report_welded(&asset.model, &report_options, self.welded.as_ref())
                    .map(|after| (None, after))
            }
        }
        .map_err(FixError::Report)?;
        let after = self.copies.measure(asset, &self.animations, self.samples, &self.options);
        Ok(Fixed {
            options: self.options,
            as_loaded,
            changes: self.changes,
            report,
            matched: self.matched,
            motion: self.before.into_iter().zip(after).collect(),
            morph_seams: if self.motion {
                morph_seams(asset, &self.copies.copies)
            } else {
                Vec::new()
            },
        })
    }

    /// [`Self::measure`] and `write(asset)` (a save: both only read the fixed model), each
    /// run whatever the other returns: beside each other on rayon's threads where `beside`
    /// (for a save that streams, [`crate::save_streams`]: a writer is mostly one thread's
    /// work, and the measures take the others), else one after the other (a save that builds
    /// its output in memory would add that memory to the measures').
    pub fn measure_with<T: Send>(
        self,
        asset: &Asset,
        beside: bool,
        write: impl FnOnce(&Asset) -> T + Send,
    ) -> (Result<Fixed, FixError>, T) {
        if beside {
            rayon::join(|| self.measure(asset), || write(asset))
        } else {
            let fixed = self.measure(asset);
            (fixed, write(asset))
        }
    }

    /// [`Self::measure_with`] [`crate::save`] of the fixed model to `path`, beside the
    /// measures where the save streams ([`crate::save_streams`]): what the command line and
    /// the Python package's `fix_file` do after the fix.
    pub fn measure_and_save(
        self,
        asset: &Asset,
        path: &Path,
        options: &SaveOptions,
    ) -> (Result<Fixed, FixError>, Result<SaveReport, IoError>) {
        let beside = crate::save_streams(path, options);
        self.measure_with(asset, beside, |asset| crate::save(asset, path, options))
    }
}

impl Fixed {
    /// What `seamlit fix` prints for a model written to `output`: what was written, then what
    /// the fix changed, then the skins, the seams in motion and the morph targets where there
    /// are any.
    #[must_use]
    pub fn summary(&self, output: &Path) -> String {
        summary::text(self, output)
    }

    /// The JSON of what was done: `{"options", "as_loaded" (where measured), "fixed",
    /// "changes", "skin_seams_matched", "motion", "morph_seams"}`.
    #[must_use]
    pub fn json(&self) -> serde_json::Value {
        let motion: Vec<serde_json::Value> = self
            .motion
            .iter()
            .map(|(b, a)| serde_json::json!({ "as_loaded": motion_json(b), "fixed": motion_json(a) }))
            .collect();
        let morphs: Vec<serde_json::Value> = self
            .morph_seams
            .iter()
            .map(|(name, n)| serde_json::json!({ "name": name, "shared_positions": n }))
            .collect();
        serde_json::json!({
            "options": self.options,
            "as_loaded": self.as_loaded,
            "fixed": self.report,
            "changes": self.changes,
            "skin_seams_matched": self.matched.as_ref().map(|m| m.positions),
            "motion": motion,
            "morph_seams": morphs,
        })
    }
}

impl Fixed {
    /// The report of one file: [`Fixed::json`] with `input` (as named), `output`, `summary`
    /// ([`Fixed::summary`]) and the loader's and writer's `warnings`, as the Python package
    /// and the web page hand it on.
    #[must_use]
    pub fn file_json<'a>(
        &self,
        input: &str,
        output: &Path,
        warnings: impl IntoIterator<Item = &'a String>,
    ) -> serde_json::Value {
        let mut json = self.json();
        json["input"] = input.into();
        json["output"] = output.display().to_string().into();
        json["summary"] = self.summary(output).into();
        json["warnings"] = warnings.into_iter().map(String::as_str).collect::<Vec<_>>().into();
        json
    }
}

/// The JSON of one animation's seams in motion (`inspect --json`'s `motion` members).
#[must_use]
pub fn motion_json(m: &SeamMotion) -> serde_json::Value {
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
