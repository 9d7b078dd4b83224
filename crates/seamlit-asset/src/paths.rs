//! Paths written inside model files (OBJ `mtllib`, MTL texture statements, glTF URIs):
//! resolved lexically so that nothing outside the model's folder is ever named, then, before a
//! file is read, through the file system so that no symbolic link leads out of it either.

use std::path::{Path, PathBuf};

/// Resolves `reference`, a relative path as a file writes it (`/` or `\` separated), against
/// `start`: a folder given as its parts below the model's folder (empty for the folder itself).
///
/// Returns the parts of the result below the model's folder, or `None` when the path leaves
/// that folder: an absolute path, a drive letter or URI scheme (any `:`), or more `..` than
/// there are parts to go up.
#[must_use]
pub fn inside(start: &[String], reference: &str) -> Option<Vec<String>> {
    if reference.starts_with(['/', '\\']) || reference.contains(':') {
        return None;
    }
    let mut parts = start.to_vec();
    for part in reference.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => {
                parts.pop()?;
            }
            part => parts.push(part.to_owned()),
        }
    }
    Some(parts)
}

/// Why [`real_inside`] gives no path to read.
#[derive(Debug)]
pub enum NotInside {
    /// The file (or the model's folder) cannot be resolved: missing, a dangling link, no
    /// permission.
    Io(std::io::Error),
    /// The file exists, but a symbolic link on its way leads outside the model's folder; the
    /// path it really names.
    Outside(PathBuf),
}

/// The real path of `file`, a path joined lexically below `folder` (the model's folder):
/// every symbolic link on the way is followed (`canonicalize`), and the result must still lie
/// below the real path of `folder`. Read the returned path, not `file`, so that a link changed
/// in between is not followed.
///
/// # Errors
///
/// [`NotInside::Io`] when `file` or `folder` cannot be resolved (a missing file is
/// [`std::io::ErrorKind::NotFound`]); [`NotInside::Outside`] when a link leads out.
pub fn real_inside(folder: &Path, file: &Path) -> Result<PathBuf, NotInside> {
    let folder = if folder.as_os_str().is_empty() { Path::new(".") } else { folder };
    let real_folder = folder.canonicalize().map_err(NotInside::Io)?;
    let real = file.canonicalize().map_err(NotInside::Io)?;
    if real.starts_with(&real_folder) { Ok(real) } else { Err(NotInside::Outside(real)) }
}

#[cfg(test)]
mod tests {
    use super::{NotInside, inside, real_inside};

    fn parts(p: &[&str]) -> Vec<String> {
        p.iter().map(|s| (*s).to_owned()).collect()
    }

    #[test]
    fn relative_paths_below_the_folder_resolve() {
        assert_eq!(inside(&[], "a.mtl"), Some(parts(&["a.mtl"])));
        assert_eq!(inside(&[], "./sub\\b.mtl"), Some(parts(&["sub", "b.mtl"])));
        assert_eq!(inside(&parts(&["sub"]), "../tex/c.png"), Some(parts(&["tex", "c.png"])));
    }

    #[test]
    fn paths_that_leave_the_folder_are_refused() {
        assert_eq!(inside(&[], "../a.mtl"), None);
        assert_eq!(inside(&[], "sub/../../a.mtl"), None);
        assert_eq!(inside(&parts(&["sub"]), "../../c.png"), None);
        assert_eq!(inside(&[], "/etc/passwd"), None);
        assert_eq!(inside(&[], "\\\\server\\share\\a.png"), None);
        assert_eq!(inside(&[], "C:\\Windows\\a.png"), None);
        assert_eq!(inside(&[], "file:///etc/passwd"), None);
    }

    #[cfg(unix)]
    #[test]
    fn links_are_followed_only_while_they_stay_inside_the_folder() {
        use std::os::unix::fs::symlink;
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        std::fs::create_dir_all(root.join("model/sub")).unwrap();
        std::fs::create_dir_all(root.join("elsewhere")).unwrap();
        std::fs::write(root.join("model/sub/a.png"), "a").unwrap();
        std::fs::write(root.join("elsewhere/secret"), "s").unwrap();
        symlink("sub/a.png", root.join("model/inside_link")).unwrap();
        symlink(root.join("elsewhere/secret"), root.join("model/outside_link")).unwrap();
        symlink(root.join("elsewhere"), root.join("model/outside_dir")).unwrap();
        symlink(root.join("model/sub"), root.join("model/inside_dir")).unwrap();
        let folder = root.join("model");
        let real = |p: &str| root.join(p).canonicalize().unwrap();

        assert_eq!(
            real_inside(&folder, &folder.join("sub/a.png")).unwrap(),
            real("model/sub/a.png")
        );
        assert_eq!(
            real_inside(&folder, &folder.join("inside_link")).unwrap(),
            real("model/sub/a.png")
        );
        assert_eq!(
            real_inside(&folder, &folder.join("inside_dir/a.png")).unwrap(),
            real("model/sub/a.png")
        );
        for escaping in ["outside_link", "outside_dir/secret"] {
            match real_inside(&folder, &folder.join(escaping)) {
                Err(NotInside::Outside(target)) => assert_eq!(target, real("elsewhere/secret")),
                other => panic!("{escaping}: {other:?}"),
            }
        }
        match real_inside(&folder, &folder.join("missing.png")) {
            Err(NotInside::Io(e)) => assert_eq!(e.kind(), std::io::ErrorKind::NotFound),
            other => panic!("{other:?}"),
        }
        // The model's folder reached through a link is the folder: its files are inside.
        symlink(&folder, root.join("model_link")).unwrap();
        let linked = root.join("model_link");
        assert!(real_inside(&linked, &linked.join("inside_link")).is_ok());
    }
}
