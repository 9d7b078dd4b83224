//! Paths written inside model files (OBJ `mtllib`, MTL texture statements), resolved
//! lexically so that nothing outside the model's folder is ever read.

/// Resolves `reference`, a relative path as a file writes it (`/` or `\` separated), against
/// `start`: a folder given as its parts below the model's folder (empty for the folder itself).
///
/// Returns the parts of the result below the model's folder, or `None` when the path leaves
/// that folder: an absolute path, a drive letter or URI scheme (any `:`), or more `..` than
/// there are parts to go up.
#[must_use]
pub(crate) fn inside(start: &[String], reference: &str) -> Option<Vec<String>> {
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

#[cfg(test)]
mod tests {
    use super::inside;

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
}
