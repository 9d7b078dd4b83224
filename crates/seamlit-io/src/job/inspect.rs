//! `seamlit inspect` as a library call: a model's seam report as loaded and after `fix` in
//! each mode, and the JSON `seamlit inspect --json` prints (the web page shows the same).

use seamlit_mesh::{Changes, FixOptions, MeshError, Mode, Model, ReportOptions, SeamReport};

/// A model's seam reports: as loaded, then after `fix` in each mode.
#[derive(Clone, Debug)]
pub struct Inspection {
    /// The model as the file gave it.
    pub as_loaded: SeamReport,
    /// After each mode, in the order flat, object, model, with what the fix changed.
    pub modes: [(Mode, SeamReport, Changes); 3],
}

impl Inspection {
    /// Measures `model` with `options` (its mode replaced by each mode in turn), each fixed
    /// model with its skin seams matched, as `fix` does by default.
    ///
    /// # Errors
    /// The model's bad geometry (a non-finite position, an index out of range).
    pub fn measure(model: &Model, options: &FixOptions) -> Result<Self, MeshError> {
        let report_options = ReportOptions::from(options);
        // The weld as loaded is the model mode's fix's too: not made again.
        let (as_loaded, loaded) = seamlit_mesh::report_with_weld(model, &report_options)?;
        let skinned = model.objects.iter().any(|o| !o.skin.is_empty());
        let one = |mode: Mode| -> Result<(Mode, SeamReport, Changes), MeshError> {
            let mut fixed = model.clone();
            let (changes, welded) = seamlit_mesh::fix_in_place_welded(
                &mut fixed,
                &options.with_mode(mode),
                Some(&loaded),
            )?;
            // As `fix` does by default (--skin-seams match).
            if skinned {
                let copies = seamlit_mesh::shared_copies(model, options.weld_tolerance)?;
                seamlit_mesh::match_skin_seams(&mut fixed, &copies);
            }
            let report =
                seamlit_mesh::report_fixed(&fixed, &report_options, welded.as_ref(), &as_loaded)?;
            Ok((mode, report, changes))
        };
        let modes = [one(Mode::Flat)?, one(Mode::Object)?, one(Mode::Model)?];
        Ok(Self { as_loaded, modes })
    }

    /// The JSON document `seamlit inspect --json` prints for the model file named `file`
    /// (as the user named it), measured with `options`: the reports, and under `changes` what
    /// the fix changed in each mode.
    #[must_use]
    pub fn json(&self, file: &str, options: &FixOptions) -> serde_json::Value {
        let [(_, flat, cf), (_, object, co), (_, model, cm)] = &self.modes;
        serde_json::json!({
            "file": file,
            "options": options,
            "as_loaded": self.as_loaded,
            "flat": flat,
            "object": object,
            "model": model,
            "changes": { "flat": cf, "object": co, "model": cm },
        })
    }
}
