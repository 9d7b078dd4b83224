//! What can be wrong with an FBX file: the kinds of [`crate::IoError::Fbx`]. They carry no
//! ufbx types, so that the error type is the same with the `fbx` feature off.

/// What is wrong with an FBX file (see [`crate::IoError::Fbx`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FbxKind {
    /// The file ends before its content does (ufbx's `TRUNCATED_FILE`).
    #[error("the file is truncated: {description}")]
    Truncated {
        /// ufbx's description of where.
        description: String,
    },
    /// ufbx does not read the file as FBX: not an FBX file, an unsupported version, broken
    /// content (the error kind and ufbx's description).
    #[error("ufbx cannot read the file ({error}): {description}")]
    Refused {
        /// ufbx's error kind, as ufbx names it (`UNRECOGNIZED_FILE_FORMAT`, `BAD_INDEX`).
        error: String,
        /// ufbx's description.
        description: String,
    },
    /// A value of a mesh is NaN or infinite.
    #[error("mesh {mesh:?}: {what} is not a finite number")]
    NotFinite {
        /// The mesh's node name.
        mesh: String,
        /// What the value is (`vertex position`, `normal`).
        what: &'static str,
    },
}
