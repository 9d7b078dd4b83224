//! Where a model's files are read from: the file system, or a set of files held in memory
//! (the web page's dropped files: a `.gltf` with its `.bin` and images, an OBJ with its MTL and
//! textures). Readers and pass-through writers read every side file through [`Files`], so
//! the same code reads a model from either.

use std::collections::BTreeMap;
use std::io;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

use crate::paths::NotInside;

/// Where a model's files are read from ([`crate::LoadOptions::files`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Files {
    /// The file system (the default): paths as the operating system resolves them, symbolic
    /// links followed and checked ([`crate::paths::real_inside`]).
    #[default]
    Disk,
    /// Files held in memory, by path: paths are resolved lexically (there are no links), and a
    /// path not in the set is missing.
    Memory(MemoryFiles),
}

/// A set of files in memory, each a path and its bytes; cheap to clone (shared).
///
/// Paths are kept lexically normalised (no `.`, `..` folded where it can be), so that
/// `textures/../a.png` and `a.png` name one file. Two sets are equal when they are the same
/// set (one made by [`MemoryFiles::new`] and its clones).
#[derive(Clone, Default)]
pub struct MemoryFiles(Arc<BTreeMap<PathBuf, Arc<[u8]>>>);

impl MemoryFiles {
    /// The files `files` (path, bytes: a `Vec<u8>`, a `&[u8]`, an `Arc<[u8]>` shared as
    /// is); of two with one path, the later one.
    pub fn new<B: Into<Arc<[u8]>>>(files: impl IntoIterator<Item = (PathBuf, B)>) -> Self {
        Self(Arc::new(files.into_iter().map(|(p, b)| (normalize(&p), b.into())).collect()))
    }

    /// The bytes of the file at `path`, if the set holds it (see [`MemoryFiles::find`]).
    #[must_use]
    pub fn get(&self, path: &Path) -> Option<&Arc<[u8]>> {
        self.find(path).map(|(_, bytes)| bytes)
    }

    /// The file at `path`: its path in the set and its bytes. A path the set does not hold
    /// finds the one file of the set with its file name, if there is exactly one: files
    /// picked in a dialog come without their folders (`textures/wood.png` given as
    /// `wood.png`).
    #[must_use]
    pub fn find(&self, path: &Path) -> Option<(&Path, &Arc<[u8]>)> {
        let path = normalize(path);
        if let Some((found, bytes)) = self.0.get_key_value(&path) {
            return Some((found.as_path(), bytes));
        }
        let name = path.file_name()?;
        let mut same_name = self.0.iter().filter(|(p, _)| p.file_name() == Some(name));
        match (same_name.next(), same_name.next()) {
            (Some((found, bytes)), None) => Some((found.as_path(), bytes)),
            _ => None,
        }
    }

    /// The paths of the set, in order.
    pub fn paths(&self) -> impl Iterator<Item = &Path> {
        self.0.keys().map(PathBuf::as_path)
    }
}

impl PartialEq for MemoryFiles {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Eq for MemoryFiles {}

impl std::fmt::Debug for MemoryFiles {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_map().entries(self.0.iter().map(|(p, b)| (p, b.len()))).finish()
    }
}

/// Files from this size up are read in parts, one per thread of rayon's pool (each part at
/// least this size): from the page cache, a read is the kernel copying into fresh pages, and
/// two threads did the 1M teapot's 17 MB in 5.7 ms where one took 9.3.
#[cfg(unix)]
const PART: usize = 4 << 20;

/// [`std::fs::read`], in parts on rayon's threads for a large file (unix). A file that
/// changes length while it is read is read again whole, as `std::fs::read` reads it.
fn read_file(path: &Path) -> io::Result<Vec<u8>> {
    #[cfg(unix)]
    {
        let file = std::fs::File::open(path)?;
        if let Ok(length) = usize::try_from(file.metadata()?.len()) {
            let parts = (length / PART).min(rayon::current_num_threads());
            if parts >= 2
                && let Ok(bytes) = read_in_parts(&file, length, parts)
            {
                return Ok(bytes);
            }
        }
    }
    std::fs::read(path)
}

/// The first `length` bytes of `file`, read in `parts` parts of (nearly) equal length on
/// rayon's threads; an error where the file does not end there.
#[cfg(unix)]
fn read_in_parts(file: &std::fs::File, length: usize, parts: usize) -> io::Result<Vec<u8>> {
    use std::os::unix::fs::FileExt;

    use rayon::prelude::*;

    let mut bytes = vec![0; length];
    let part = length.div_ceil(parts);
    bytes
        .par_chunks_mut(part)
        .enumerate()
        .try_for_each(|(i, chunk)| file.read_exact_at(chunk, (i * part) as u64))?;
    match file.read_at(&mut [0], length as u64)? {
        0 => Ok(bytes),
        _ => Err(io::Error::other("the file grew while it was read")),
    }
}

fn not_found(path: &Path) -> io::Error {
    io::Error::new(
        io::ErrorKind::NotFound,
        format!("{} is not among the files given", path.display()),
    )
}

impl Files {
    /// The bytes of the file at `path`.
    ///
    /// # Errors
    ///
    /// The file system's error; in memory, [`io::ErrorKind::NotFound`] for a path not in the
    /// set.
    pub fn read(&self, path: &Path) -> io::Result<Vec<u8>> {
        match self {
            Self::Disk => read_file(path),
            Self::Memory(files) => {
                files.get(path).map(|b| b.to_vec()).ok_or_else(|| not_found(path))
            }
        }
    }

    /// The size in bytes of the file at `path`.
    ///
    /// # Errors
    ///
    /// As [`Files::read`].
    pub fn size(&self, path: &Path) -> io::Result<u64> {
        match self {
            Self::Disk => std::fs::metadata(path).map(|m| m.len()),
            Self::Memory(files) => {
                files.get(path).map(|b| b.len() as u64).ok_or_else(|| not_found(path))
            }
        }
    }

    /// Whether a file (on disk: of any kind, a dangling link too) is at `path`.
    #[must_use]
    pub fn exists(&self, path: &Path) -> bool {
        match self {
            Self::Disk => path.symlink_metadata().is_ok(),
            Self::Memory(files) => files.get(path).is_some(),
        }
    }

    /// The path to read for `file`, a path joined below `folder` (the model's folder), where it
    /// stays inside that folder: on disk [`crate::paths::real_inside`] (links followed); in
    /// memory its path in the set ([`MemoryFiles::find`]), which must lie below `folder` when
    /// found by its full path (a file found by its name alone is one the user gave).
    ///
    /// # Errors
    ///
    /// As [`crate::paths::real_inside`]: [`NotInside::Io`] for a missing file,
    /// [`NotInside::Outside`] for one outside the folder.
    pub fn real_inside(&self, folder: &Path, file: &Path) -> Result<PathBuf, NotInside> {
        match self {
            Self::Disk => crate::paths::real_inside(folder, file),
            Self::Memory(files) => {
                let file = normalize(file);
                let Some((found, _)) = files.find(&file) else {
                    return Err(NotInside::Io(not_found(&file)));
                };
                let inside = found != file || file.starts_with(normalize(folder));
                if inside { Ok(found.to_path_buf()) } else { Err(NotInside::Outside(file)) }
            }
        }
    }

    /// Whether the input file `input` (read from here) is the output file `output`: on disk
    /// by canonical path when both exist; never for files in memory, which no output is
    /// written into.
    #[must_use]
    pub fn same_file(&self, input: &Path, output: &Path) -> bool {
        match self {
            Self::Disk => same_file(input, output),
            Self::Memory(_) => false,
        }
    }
}

/// Whether two paths name the same file (by canonical path when both exist).
#[must_use]
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// `path` with `.` left out and each `..` folded into the part before it (a `..` with nothing
/// before it to fold is kept).
#[must_use]
pub fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                let folds = matches!(out.components().next_back(), Some(Component::Normal(_)));
                if folds {
                    out.pop();
                } else {
                    out.push("..");
                }
            }
            other => out.push(other),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{Files, MemoryFiles, NotInside, normalize};
    #[cfg(unix)]
    use super::{PART, read_in_parts};
    use std::path::{Path, PathBuf};

    /// A large file is read in parts on several threads, each at its own offset: the bytes
    /// are the file's, for files of two and three parts whose length is no multiple of them;
    /// a file longer than said is refused (and read whole by `Files::read`).
    #[test]
    #[cfg(unix)]
    fn a_large_file_read_in_parts_is_its_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        for (length, parts) in [(2 * PART + 12_345, 2), (3 * PART + 7, 3), (PART + 1, 5)] {
            let mut state = 0x9e37_79b9_u32;
            let bytes: Vec<u8> = (0..length)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 17;
                    state ^= state << 5;
                    state.to_le_bytes()[0]
                })
                .collect();
            let path = dir.path().join(format!("{length}.bin"));
            std::fs::write(&path, &bytes).unwrap();
            let file = std::fs::File::open(&path).unwrap();
            let read = pool.install(|| read_in_parts(&file, length, parts)).unwrap();
            assert!(read == bytes, "{length} bytes read in {parts} parts differ");
            assert!(pool.install(|| read_in_parts(&file, length - 1, parts)).is_err());
            assert!(pool.install(|| Files::Disk.read(&path)).unwrap() == bytes);
        }
    }

    fn set() -> Files {
        Files::Memory(MemoryFiles::new([
            (PathBuf::from("kit/model.gltf"), b"{}".to_vec()),
            (PathBuf::from("kit/textures/../a.bin"), vec![1, 2, 3]),
            (PathBuf::from("secret.txt"), b"s".to_vec()),
        ]))
    }

    #[test]
    fn paths_are_normalised_lexically() {
        assert_eq!(normalize(Path::new("a/./b/../c")), Path::new("a/c"));
        assert_eq!(normalize(Path::new("../a/../../b")), Path::new("../../b"));
        assert_eq!(normalize(Path::new("/a/b/..")), Path::new("/a"));
    }

    #[test]
    fn memory_files_are_read_by_any_spelling_of_their_path() {
        let files = set();
        assert_eq!(files.read(Path::new("kit/a.bin")).unwrap(), [1, 2, 3]);
        assert_eq!(files.read(Path::new("kit/x/../a.bin")).unwrap(), [1, 2, 3]);
        assert_eq!(files.size(Path::new("kit/model.gltf")).unwrap(), 2);
        assert!(files.exists(Path::new("./kit/model.gltf")));
        let missing = files.read(Path::new("kit/b.bin")).unwrap_err();
        assert_eq!(missing.kind(), std::io::ErrorKind::NotFound);
        assert!(missing.to_string().contains("kit/b.bin"), "{missing}");
    }

    #[test]
    fn memory_files_stay_inside_the_models_folder() {
        let files = set();
        let folder = Path::new("kit");
        assert_eq!(
            files.real_inside(folder, Path::new("kit/a.bin")).unwrap(),
            Path::new("kit/a.bin")
        );
        assert!(matches!(
            files.real_inside(folder, Path::new("kit/../secret.txt")),
            Err(NotInside::Outside(p)) if p == Path::new("secret.txt")
        ));
        assert!(matches!(
            files.real_inside(folder, Path::new("kit/none.png")),
            Err(NotInside::Io(e)) if e.kind() == std::io::ErrorKind::NotFound
        ));
    }

    #[test]
    fn a_file_given_without_its_folder_is_found_by_its_unique_name() {
        let files = Files::Memory(MemoryFiles::new([
            (PathBuf::from("model.gltf"), b"{}".to_vec()),
            (PathBuf::from("wood.png"), vec![7]),
            (PathBuf::from("a/same.png"), vec![1]),
            (PathBuf::from("b/same.png"), vec![2]),
        ]));
        let folder = Path::new("");
        assert_eq!(files.read(Path::new("textures/wood.png")).unwrap(), [7]);
        assert_eq!(
            files.real_inside(folder, Path::new("textures/wood.png")).unwrap(),
            Path::new("wood.png")
        );
        // Two candidates: neither is guessed.
        assert!(!files.exists(Path::new("c/same.png")));
        assert_eq!(files.read(Path::new("b/same.png")).unwrap(), [2]);
    }

    #[test]
    fn two_sets_are_equal_only_when_they_are_one() {
        let a = MemoryFiles::new([(PathBuf::from("a"), vec![1])]);
        let b = MemoryFiles::new([(PathBuf::from("a"), vec![1])]);
        assert_eq!(a, a.clone());
        assert_ne!(a, b);
        assert_eq!(Files::default(), Files::Disk);
    }
}
