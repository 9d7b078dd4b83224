//! The asset resolver seamlit opens stages with: openusd's default resolver, checking each
//! layer before openusd parses it, and confined to folders where the user asks for it.
//!
//! A stage's layers (sublayers, references, payloads) may name any file by an absolute or
//! `../` path, and asset libraries do (a kit's entry layer referencing `../geo/` and
//! `../../materials/`): they are read as USD resolves them ([`Reach::Anywhere`]). With
//! [`seamlit_asset::LoadOptions::asset_roots`] (`--asset-root`, the strict mode for services)
//! a layer outside the root layer's folder and those folders is not opened
//! ([`Reach::Within`]): the stage fails to compose with one line naming it. Either way only
//! regular files are opened (never a device or a folder), every layer, not only the root
//! one, is held to the file size limit and, in text form, to the nesting depth openusd's
//! parser survives; and what a `.usdz` output packs is confined all the same (package.rs).

use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use openusd::ar::{self, Resolver};

use super::nesting::checked;

/// The folders a stage's files may come from, canonical: the root layer's and `roots`
/// (folders that do not exist are left out).
pub(crate) fn allowed_folders(root_layer: &Path, roots: &[PathBuf]) -> Vec<PathBuf> {
    let folder = root_layer.parent().unwrap_or(Path::new("."));
    let folder = if folder.as_os_str().is_empty() { Path::new(".") } else { folder };
    std::iter::once(folder)
        .chain(roots.iter().map(PathBuf::as_path))
        .filter_map(|r| r.canonicalize().ok())
        .collect()
}

/// Where a stage's files may come from.
#[derive(Clone, Debug)]
pub(crate) enum Reach {
    /// Wherever its asset paths resolve (no `--asset-root` given).
    Anywhere,
    /// Only these folders, canonical: the root layer's and the asset roots.
    Within(Vec<PathBuf>),
}

impl Reach {
    /// The reach of a stage whose root layer is `root_layer`, read with `asset_roots`.
    pub(crate) fn of(root_layer: &Path, asset_roots: &[PathBuf]) -> Self {
        if asset_roots.is_empty() {
            Self::Anywhere
        } else {
            Self::Within(allowed_folders(root_layer, asset_roots))
        }
    }

    /// Whether `real` (a canonical path) may be read.
    pub(crate) fn admits(&self, real: &Path) -> bool {
        match self {
            Self::Anywhere => true,
            Self::Within(folders) => folders.iter().any(|f| real.starts_with(f)),
        }
    }
}

/// A layer the resolver would not open: its asset path and where it resolved.
#[derive(Clone, Debug)]
pub(super) struct Outside {
    pub asset: String,
    pub resolved: PathBuf,
}

/// Where layers may come from, and what was refused.
pub(super) struct Confined {
    inner: ar::DefaultResolver,
    reach: Reach,
    max_file_bytes: u64,
    refused: Arc<Mutex<Vec<Outside>>>,
}

impl Confined {
    /// A resolver for the stage whose root layer is `root_layer`, read with `roots` (see
    /// [`Reach::of`]). Layers it refuses are added to `refused`.
    pub(super) fn new(
        root_layer: &Path,
        roots: &[PathBuf],
        max_file_bytes: u64,
        refused: Arc<Mutex<Vec<Outside>>>,
    ) -> Self {
        let reach = Reach::of(root_layer, roots);
        Self { inner: ar::DefaultResolver::new(), reach, max_file_bytes, refused }
    }

    /// Whether the file `resolved` names (the package of a path inside a `.usdz`) lies
    /// within the reach.
    fn allowed(&self, resolved: &Path) -> bool {
        file_of(resolved).canonicalize().is_ok_and(|real| self.reach.admits(&real))
    }
}

impl Resolver for Confined {
    fn create_identifier(&self, asset_path: &str, anchor: Option<&ar::ResolvedPath>) -> String {
        self.inner.create_identifier(asset_path, anchor)
    }

    fn resolve(&self, asset_path: &str) -> Option<ar::ResolvedPath> {
        let resolved = self.inner.resolve(asset_path)?;
        if self.allowed(&resolved) {
            return Some(resolved);
        }
        let outside = Outside { asset: asset_path.to_owned(), resolved: resolved.to_path_buf() };
        if let Ok(mut refused) = self.refused.lock() {
            refused.push(outside);
        }
        None
    }

    fn resolve_for_new_asset(&self, asset_path: &str) -> Option<ar::ResolvedPath> {
        self.inner.resolve_for_new_asset(asset_path)
    }

    fn open_asset(&self, resolved: &ar::ResolvedPath) -> io::Result<Box<dyn ar::Asset>> {
        // A device (/dev/zero never ends) or a folder is not a layer.
        if !std::fs::metadata(file_of(resolved)).is_ok_and(|m| m.is_file()) {
            return Err(io::Error::other("not a regular file; seamlit opens no other"));
        }
        checked(self.inner.open_asset(resolved)?, self.max_file_bytes)
    }

    fn get_extension<'a>(&self, asset_path: &'a str) -> &'a str {
        self.inner.get_extension(asset_path)
    }

    fn get_asset_info(&self, asset_path: &str, resolved: &ar::ResolvedPath) -> ar::AssetInfo {
        self.inner.get_asset_info(asset_path, resolved)
    }

    fn get_modification_timestamp(
        &self,
        asset_path: &str,
        resolved: &ar::ResolvedPath,
    ) -> Option<std::time::SystemTime> {
        self.inner.get_modification_timestamp(asset_path, resolved)
    }

    fn identity(&self) -> String {
        format!("seamlit-confined{:?}", self.reach)
    }
}

/// The file a resolved path names: the package of a path inside a `.usdz`, else the path.
fn file_of(resolved: &Path) -> PathBuf {
    let text = resolved.to_string_lossy();
    match ar::split_package_relative_path_outer(&text) {
        Some((package, _)) if ar::is_package_relative_path(&text) => PathBuf::from(package),
        _ => resolved.to_path_buf(),
    }
}
