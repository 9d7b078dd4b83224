//! The document a file was read from, kept in the asset for its format's writer.
//!
//! The asset crate knows no file format: each format crate defines the type its reader keeps
//! (the glTF document and buffers, the OBJ text, how a USD stage was read), puts it in
//! [`crate::Asset::document`] with [`SourceDocument::new`], and its writer finds it again
//! with [`SourceDocument::get`]. An asset read by one format never yields another format's
//! document.

use std::any::Any;
use std::fmt;
use std::sync::Arc;

/// What a format's reader kept of the file it read ([`crate::Asset::document`]): any
/// `Send + Sync + Debug` value, shared (cloning the asset clones a pointer).
#[derive(Clone)]
pub struct SourceDocument(Arc<dyn Kept>);

/// The bounds of a kept document; implemented for every type that meets them.
trait Kept: Any + Send + Sync + fmt::Debug {}

impl<T: Any + Send + Sync + fmt::Debug> Kept for T {}

impl SourceDocument {
    /// Keeps `document` for its format's writer.
    #[must_use]
    pub fn new<T: Any + Send + Sync + fmt::Debug>(document: T) -> Self {
        Self(Arc::new(document))
    }

    /// The kept document, if it is a `T`.
    #[must_use]
    pub fn get<T: Any>(&self) -> Option<&T> {
        let any: &dyn Any = &*self.0;
        any.downcast_ref()
    }
}

impl fmt::Debug for SourceDocument {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::SourceDocument;

    #[derive(Debug, PartialEq)]
    struct Text(&'static str);

    #[derive(Debug)]
    struct Other;

    #[test]
    fn a_document_is_found_as_its_own_type_only() {
        let kept = SourceDocument::new(Text("v 0 0 0"));
        assert_eq!(kept.get::<Text>(), Some(&Text("v 0 0 0")));
        assert!(kept.get::<Other>().is_none());
        assert_eq!(format!("{kept:?}"), "Text(\"v 0 0 0\")");
    }
}
