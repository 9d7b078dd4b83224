//! The folder mode's rules (`seamlit fix DIR -o DIR`): which files of a folder tree are
//! models ([`model_files`], [`is_model_name`]), and the name each one's output gets
//! ([`output_extension`], [`OutputNames`]). Other drivers of many files (the Python package's
//! fleet runs) follow the same rules, so that the same inputs give the same outputs.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use seamlit_asset::IoError;

use crate::Format;

/// The model files in `dir` and, with `recurse`, in its subfolders, sorted by path: the
/// files whose format [`Format::of`] knows and whose name [`is_model_name`] accepts. Hidden
/// entries (`.git`, `.cache`: a name that starts with `.`), symbolic links to folders (which
/// could loop) and the folder `skip` (the output folder, when it lies inside `dir`, so that a
/// second run does not fix the first run's output) are passed over.
///
/// # Errors
///
/// [`IoError::Io`] naming the folder that cannot be read.
pub fn model_files(
    dir: &Path,
    skip: Option<&Path>,
    recurse: bool,
) -> Result<Vec<PathBuf>, IoError> {
    let skip = skip.and_then(|s| s.canonicalize().ok());
    let mut files = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        let entries = std::fs::read_dir(&folder).map_err(|e| IoError::io(&folder, e))?;
        for entry in entries.filter_map(Result::ok) {
            let path = entry.path();
            let hidden = !is_model_name(&entry.file_name().to_string_lossy());
            let Ok(kind) = entry.file_type() else { continue };
            if kind.is_dir() && recurse && !hidden {
                if skip.is_none() || path.canonicalize().ok() != skip {
                    folders.push(path);
                }
            } else if !hidden && path.is_file() && Format::of(&path).is_some() {
                files.push(path);
            }
        }
    }
    files.sort();
    Ok(files)
}

/// Whether folder mode looks at an entry of this name (a file or a folder): every name but a
/// hidden one (starting with `.`).
#[must_use]
pub fn is_model_name(name: &str) -> bool {
    !name.starts_with('.')
}

/// The extension of a folder input's output, when the outputs are written as `extension`
/// (`"glb"`, `"gltf"`, `"obj"`): that one, but a VRM avatar written as GLB stays a `.vrm` (the
/// same bytes a `.glb` would hold, under the name avatar tools look for).
#[must_use]
pub fn output_extension<'a>(input: &Path, extension: &'a str) -> &'a str {
    let vrm = input.extension().is_some_and(|e| e.eq_ignore_ascii_case("vrm"));
    if vrm && extension == "glb" { "vrm" } else { extension }
}

/// The output names of one folder run: `out/sub/stem.ext` for the input `sub/stem.srcext`
/// (relative to the input folder), or `out/sub/stem-srcext.ext` when an earlier input of the
/// run already took that name (two inputs of one folder that share a stem). Name the inputs in
/// [`model_files`]' order, so that the same tree gives the same names.
#[derive(Clone, Debug, Default)]
pub struct OutputNames {
    used: HashSet<PathBuf>,
}

impl OutputNames {
    /// A run that has named nothing yet.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The output path of the input `relative` (to the input folder), in the output folder
    /// `out`, with the extension `extension` (see [`output_extension`]).
    pub fn name(&mut self, relative: &Path, out: &Path, extension: &str) -> PathBuf {
        let stem = relative
            .file_stem()
            .map_or_else(|| "model".into(), |s| s.to_string_lossy().into_owned());
        let folder = out.join(relative.parent().unwrap_or(Path::new("")));
        let mut path = folder.join(format!("{stem}.{extension}"));
        if self.used.contains(&path) {
            let src = relative
                .extension()
                .map_or_else(String::new, |e| format!("-{}", e.to_string_lossy()));
            path = folder.join(format!("{stem}{src}.{extension}"));
        }
        self.used.insert(path.clone());
        path
    }
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use super::{OutputNames, is_model_name, output_extension};

    #[test]
    fn two_inputs_with_one_stem_get_two_names() {
        let mut names = OutputNames::new();
        let out = Path::new("out");
        assert_eq!(
            names.name(Path::new("a/chair.obj"), out, "glb"),
            PathBuf::from("out/a/chair.glb")
        );
        assert_eq!(
            names.name(Path::new("a/chair.gltf"), out, "glb"),
            PathBuf::from("out/a/chair-gltf.glb")
        );
        assert_eq!(
            names.name(Path::new("b/chair.gltf"), out, "glb"),
            PathBuf::from("out/b/chair.glb")
        );
    }

    #[test]
    fn a_vrm_stays_a_vrm_only_as_glb() {
        assert_eq!(output_extension(Path::new("x/Avatar.VRM"), "glb"), "vrm");
        assert_eq!(output_extension(Path::new("x/Avatar.vrm"), "gltf"), "gltf");
        assert_eq!(output_extension(Path::new("x/box.glb"), "glb"), "glb");
    }

    #[test]
    fn hidden_names_are_passed_over() {
        assert!(!is_model_name(".git"));
        assert!(is_model_name("teapot.glb"));
    }
}
