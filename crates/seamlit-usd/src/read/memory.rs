//! The resolver for a stage whose files are in memory ([`Files::Memory`]: the web page's
//! dropped files): asset paths are resolved lexically against the layer that names them, as
//! openusd's default resolver does on disk, and looked up in the set; a path inside a `.usdz`
//! (`pkg.usdz[inner.usdc]`) is read from the package's bytes. Every layer is held to the same
//! limits as on disk ([`super::nesting::checked`]).

use std::io::{self, Read as _};
use std::path::Path;

use openusd::ar::{self, Resolver};
use seamlit_asset::files::{Files, MemoryFiles, normalize};

/// Resolves and opens asset paths in a set of files in memory.
pub(super) struct InMemory {
    files: MemoryFiles,
    max_file_bytes: u64,
}

impl InMemory {
    pub(super) fn new(files: MemoryFiles, max_file_bytes: u64) -> Self {
        Self { files, max_file_bytes }
    }
}

/// `leaf` attached inside the deepest package of `base` (`pkg[inner[leaf]]`).
fn nest(base: &str, leaf: &str) -> String {
    match ar::split_package_relative_path_outer(base) {
        Some((package, inner)) => ar::join_package_relative_path(&package, &nest(&inner, leaf)),
        None => ar::join_package_relative_path(base, leaf),
    }
}

/// `rel` joined to the folder `dir` inside a package: `/` separated, `.` and `..` folded
/// (nothing lies above a package's root).
fn join_packaged(dir: &str, rel: &str) -> String {
    let mut parts: Vec<&str> = dir.split('/').filter(|c| !c.is_empty()).collect();
    for part in rel.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => {
                parts.pop();
            }
            other => parts.push(other),
        }
    }
    parts.join("/")
}

/// The bytes of the entry `inner` of the package `package` (bytes of a zip).
fn package_entry(package: &[u8], inner: &str) -> io::Result<Vec<u8>> {
    if ar::is_package_relative_path(inner) {
        return Err(io::Error::other("a package inside a package is not read from memory"));
    }
    let mut zip = zip::ZipArchive::new(io::Cursor::new(package)).map_err(io::Error::other)?;
    let mut entry = zip.by_name(inner).map_err(io::Error::other)?;
    let mut bytes = Vec::new();
    entry.read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// The bytes an asset path resolved by [`InMemory`] names: a file of `files`, or an entry of
/// a package among them. The material reader opens textures inside packages with it.
pub(crate) fn read_resolved(files: &Files, resolved: &str) -> io::Result<Vec<u8>> {
    match ar::split_package_relative_path_outer(resolved) {
        Some((package, inner)) if ar::is_package_relative_path(resolved) => {
            package_entry(&files.read(Path::new(&package))?, &inner)
        }
        _ => files.read(Path::new(resolved)),
    }
}

impl Resolver for InMemory {
    fn create_identifier(&self, asset_path: &str, anchor: Option<&ar::ResolvedPath>) -> String {
        if asset_path.is_empty() {
            return String::new();
        }
        if ar::is_package_relative_path(asset_path) {
            if let Some((package, inner)) = ar::split_package_relative_path_outer(asset_path) {
                return nest(&self.create_identifier(&package, anchor), &inner);
            }
            return asset_path.to_owned();
        }
        let Some(anchor) = anchor else {
            return normalize(Path::new(asset_path)).to_string_lossy().into_owned();
        };
        let anchor = anchor.to_string_lossy();
        if ar::is_package_relative_path(&anchor)
            && let Some((package, inner)) = ar::split_package_relative_path_inner(&anchor)
        {
            let dir = inner.rsplit_once('/').map_or("", |(dir, _)| dir);
            return nest(&package, &join_packaged(dir, asset_path));
        }
        if anchor.to_ascii_lowercase().ends_with(".usdz") {
            return ar::join_package_relative_path(&anchor, &join_packaged("", asset_path));
        }
        let folder = Path::new(&*anchor).parent().unwrap_or(Path::new(""));
        normalize(&folder.join(asset_path)).to_string_lossy().into_owned()
    }

    fn resolve(&self, asset_path: &str) -> Option<ar::ResolvedPath> {
        if asset_path.is_empty() {
            return None;
        }
        if ar::is_package_relative_path(asset_path) {
            let (package, inner) = ar::split_package_relative_path_outer(asset_path)?;
            let (found, bytes) = self.files.find(Path::new(&package))?;
            // A package that does not open is left to the open, which says why.
            let listed = zip::ZipArchive::new(io::Cursor::new(&bytes[..])).map_or(true, |zip| {
                ar::is_package_relative_path(&inner) || zip.index_for_name(&inner).is_some()
            });
            let found = found.to_string_lossy();
            return listed
                .then(|| ar::ResolvedPath::new(ar::join_package_relative_path(&found, &inner)));
        }
        let (found, _) = self.files.find(Path::new(asset_path))?;
        Some(ar::ResolvedPath::new(found))
    }

    fn resolve_for_new_asset(&self, asset_path: &str) -> Option<ar::ResolvedPath> {
        (!asset_path.is_empty()).then(|| ar::ResolvedPath::new(normalize(Path::new(asset_path))))
    }

    fn open_asset(&self, resolved: &ar::ResolvedPath) -> io::Result<Box<dyn ar::Asset>> {
        let files = Files::Memory(self.files.clone());
        let bytes = read_resolved(&files, &resolved.to_string_lossy())?;
        super::nesting::checked(Box::new(io::Cursor::new(bytes)), self.max_file_bytes)
    }

    fn get_modification_timestamp(
        &self,
        _asset_path: &str,
        _resolved: &ar::ResolvedPath,
    ) -> Option<std::time::SystemTime> {
        None
    }

    fn identity(&self) -> String {
        "seamlit-in-memory".to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::{InMemory, join_packaged, nest};
    use openusd::ar::{ResolvedPath, Resolver};
    use seamlit_asset::files::MemoryFiles;
    use std::path::PathBuf;

    #[test]
    fn identifiers_are_made_as_the_default_resolver_makes_them_without_a_disk() {
        let resolver =
            InMemory::new(MemoryFiles::new([(PathBuf::from("kit/a.usda"), vec![])]), 1 << 20);
        let id = |path: &str, anchor: Option<&str>| {
            resolver.create_identifier(path, anchor.map(ResolvedPath::new).as_ref())
        };
        assert_eq!(id("kit/./a.usda", None), "kit/a.usda");
        assert_eq!(id("../geo/b.usda", Some("kit/layers/a.usda")), "kit/geo/b.usda");
        assert_eq!(id("tex/c.png", Some("m.usdz")), "m.usdz[tex/c.png]");
        assert_eq!(id("../d.usdc", Some("m.usdz[sub/a.usda]")), "m.usdz[d.usdc]");
        assert_eq!(id("m.usdz[x.usda]", Some("kit/a.usda")), "kit/m.usdz[x.usda]");
        assert_eq!(nest("a.usdz[b.usdz]", "c"), "a.usdz[b.usdz[c]]");
        assert_eq!(join_packaged("a/b", "../../../c"), "c");
    }
}
