//! `seamlit inspect`: the seam report of a model as loaded and after each mode.

use std::path::Path;

use seamlit_io::LoadOptions;
use seamlit_mesh::{Changes, FixOptions, Mode, Model, ReportOptions, SeamReport};

use crate::cli::InspectArgs;
use crate::failure::{Classify, Failure};
use crate::prepare::default_tangents;
use crate::table::{changes_line, changes_table, report_table};

/// The model's reports: as loaded, then after `fix` in each mode.
pub struct Reports {
    /// The model as the file gave it.
    pub as_loaded: SeamReport,
    /// After each mode, in the order flat, object, model, with what the fix changed.
    pub modes: [(Mode, SeamReport, Changes); 3],
}

impl Reports {
    /// Measures `model` with `options` (its mode is replaced by each mode in turn).
    ///
    /// # Errors
    /// [`Failure::BadInput`] naming `file` when the geometry is bad.
    pub(crate) fn measure(
        model: &Model,
        options: &FixOptions,
        file: &Path,
    ) -> Result<Self, Failure> {
        let report_options = ReportOptions::from(options);
        let bad = |e: seamlit_mesh::MeshError| Failure::input(format!("{}: {e}", file.display()));
        let as_loaded = seamlit_mesh::report(model, &report_options).map_err(bad)?;
        let one = |mode: Mode| -> Result<(Mode, SeamReport, Changes), Failure> {
            let mut fixed = model.clone();
            let changes =
                seamlit_mesh::fix_in_place(&mut fixed, &options.with_mode(mode)).map_err(bad)?;
            Ok((mode, seamlit_mesh::report(&fixed, &report_options).map_err(bad)?, changes))
        };
        Ok(Self { as_loaded, modes: [one(Mode::Flat)?, one(Mode::Object)?, one(Mode::Model)?] })
    }

    /// The readable table.
    #[must_use]
    pub(crate) fn table(&self) -> String {
        let [(_, flat, _), (_, object, _), (_, model, _)] = &self.modes;
        report_table(&[
            ("as loaded", &self.as_loaded),
            ("flat", flat),
            ("object", object),
            ("model", model),
        ])
    }

    /// The JSON document `inspect --json` prints: the reports, and under `changes` what the
    /// fix changed in each mode.
    #[must_use]
    pub(crate) fn json(&self, file: &Path, options: &FixOptions) -> serde_json::Value {
        let [(_, flat, cf), (_, object, co), (_, model, cm)] = &self.modes;
        serde_json::json!({
            "file": file.display().to_string(),
            "options": options,
            "as_loaded": self.as_loaded,
            "flat": flat,
            "object": object,
            "model": model,
            "changes": { "flat": cf, "object": co, "model": cm },
        })
    }
}

/// Runs `seamlit inspect`.
///
/// # Errors
/// [`Failure::BadInput`] for a missing or malformed model.
pub(crate) fn run(args: &InspectArgs) -> Result<(), Failure> {
    if !args.input.is_file() {
        let what =
            if args.input.is_dir() { "is a folder, expected a model file" } else { "no such file" };
        return Err(Failure::input(format!("{}: {what}", args.input.display())));
    }
    let load = LoadOptions { tessellation: args.load.tessellation, ..LoadOptions::GEOMETRY };
    let asset = seamlit_io::load(&args.input, &load).bad_input()?;
    for warning in &asset.warnings {
        eprintln!("warning: {warning}");
    }
    let options =
        default_tangents(&asset, args.fix.apply(FixOptions::DEFAULT), args.fix.tangents.is_some());
    let reports = Reports::measure(&asset.model, &options, &args.input)?;
    if args.json {
        let text =
            serde_json::to_string_pretty(&reports.json(&args.input, &options)).processing()?;
        println!("{text}");
    } else {
        println!(
            "{}: seam report (--crease {} --weld-tolerance {} --weighting {})\n",
            args.input.display(),
            options.crease_angle_deg,
            crate::cli::tolerance_flag(options.weld_tolerance),
            crate::cli::weighting_flag(options.weighting),
        );
        print!("{}", reports.table());
        let (_, _, changes) = &reports.modes[2];
        println!("\nWhat `fix` changes (model mode): {}\n", changes_line(changes, &options));
        print!("{}", changes_table(changes));
    }
    Ok(())
}
