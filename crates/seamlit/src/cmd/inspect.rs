//! `seamlit inspect`: the seam report of a model as loaded and after each mode.

use std::path::Path;

use seamlit_io::job::Inspection;
use seamlit_io::motion::SeamMotion;
use seamlit_io::{Asset, LoadOptions};
use seamlit_mesh::{FixOptions, Mode, Model};

use crate::cli::InspectArgs;
use crate::failure::{Classify, Failure};
use crate::prepare::default_tangents;
use crate::table::{changes_line, changes_table, report_table};

/// [`Inspection::measure`] of the model from `file`.
///
/// # Errors
/// [`Failure::BadInput`] naming `file` when the geometry is bad.
pub(crate) fn measure(
    model: &Model,
    options: &FixOptions,
    file: &Path,
) -> Result<Inspection, Failure> {
    Inspection::measure(model, options)
        .map_err(|e| Failure::input(format!("{}: {e}", file.display())))
}

/// The readable table of `inspection`.
#[must_use]
pub(crate) fn table(inspection: &Inspection) -> String {
    let [(_, flat, _), (_, object, _), (_, model, _)] = &inspection.modes;
    report_table(&[
        ("as loaded", &inspection.as_loaded),
        ("flat", flat),
        ("object", object),
        ("model", model),
    ])
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
    let load = args.load.options(LoadOptions::GEOMETRY);
    let asset = seamlit_io::load(&args.input, &load).bad_input()?;
    for warning in &asset.warnings {
        eprintln!("warning: {warning}");
    }
    let options =
        default_tangents(&asset, args.fix.apply(FixOptions::DEFAULT), args.fix.tangents.is_some());
    let reports = measure(&asset.model, &options, &args.input)?;
    let motion = match &args.animation {
        Some(spec) => Some(Motion::measure(&asset, spec, args.samples, &options, &args.input)?),
        None => None,
    };
    if args.json {
        let mut json = reports.json(&args.input.display().to_string(), &options);
        if let Some(motion) = &motion {
            json["motion"] = motion.json();
        }
        let text = serde_json::to_string_pretty(&json).processing()?;
        println!("{text}");
    } else {
        println!(
            "{}: seam report (--crease {} --weld-tolerance {} --weighting {})\n",
            args.input.display(),
            options.crease_angle_deg,
            crate::cli::tolerance_flag(options.weld_tolerance),
            crate::cli::weighting_flag(options.weighting),
        );
        print!("{}", table(&reports));
        let (_, _, changes) = &reports.modes[2];
        println!("\nWhat `fix` changes (model mode): {}\n", changes_line(changes, &options));
        print!("{}", changes_table(changes));
        if let Some(motion) = &motion {
            print!("\n{}", motion.table());
        }
    }
    Ok(())
}

/// The seams in motion as loaded and after `fix` (model mode, skin seams matched).
struct Motion {
    as_loaded: Vec<SeamMotion>,
    fixed: Vec<SeamMotion>,
    /// Shared positions whose copies `fix` gives the same skin influences.
    matched: usize,
}

impl Motion {
    fn measure(
        asset: &Asset,
        spec: &str,
        samples: u32,
        options: &FixOptions,
        file: &Path,
    ) -> Result<Self, Failure> {
        let animations = crate::motion::select(asset, spec, file)?;
        let copies = crate::motion::copies(asset, options, file)?;
        let as_loaded = crate::motion::measure(asset, &animations, samples, options, &copies);
        let mut fixed = asset.clone();
        let bad = |e: seamlit_mesh::MeshError| Failure::input(format!("{}: {e}", file.display()));
        seamlit_mesh::fix_in_place(&mut fixed.model, &options.with_mode(Mode::Model))
            .map_err(bad)?;
        let matched = seamlit_io::match_skin_seams(&mut fixed, &copies.copies).positions;
        let after = crate::motion::measure(&fixed, &animations, samples, options, &copies);
        Ok(Self { as_loaded, fixed: after, matched })
    }

    fn table(&self) -> String {
        use std::fmt::Write as _;
        let mut out = format!(
            "Seams in motion (the copies of each shared position posed at {} times per animation; `fix` matches the skin influences at {}):\n",
            self.as_loaded.first().map_or(0, |m| m.samples),
            crate::table::count(self.matched, "shared position")
        );
        let _ = writeln!(
            out,
            "  {:<24} {:>8}  {:>22} {:>22}  {:>14} {:>14}",
            "animation",
            "length",
            "gap as loaded",
            "gap after fix",
            "normals loaded",
            "normals fixed"
        );
        for (a, f) in self.as_loaded.iter().zip(&self.fixed) {
            let gap = |m: &SeamMotion| {
                format!(
                    "{:.2e} ({:.2}%) @{:.2}s",
                    m.max_gap,
                    100.0 * m.max_gap_fraction,
                    m.max_gap_time
                )
            };
            let angle = |m: &SeamMotion| {
                m.max_normal_angle_deg.map_or_else(
                    || "-".to_owned(),
                    |d| format!("{d:.2}° @{:.2}s", m.max_normal_angle_time),
                )
            };
            let name = if a.name.is_empty() { format!("#{}", a.animation) } else { a.name.clone() };
            let _ = writeln!(
                out,
                "  {name:<24} {:>7.2}s  {:>22} {:>22}  {:>14} {:>14}",
                a.duration,
                gap(a),
                gap(f),
                angle(a),
                angle(f)
            );
        }
        out
    }

    fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "matched_positions": self.matched,
            "as_loaded": self.as_loaded.iter().map(seamlit_io::job::motion_json).collect::<Vec<_>>(),
            "fixed": self.fixed.iter().map(seamlit_io::job::motion_json).collect::<Vec<_>>(),
        })
    }
}
