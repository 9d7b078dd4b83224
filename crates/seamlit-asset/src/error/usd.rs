//! What can be wrong with a USD stage, and why a USD output is refused: the kinds of
//! [`crate::IoError::Usd`] and [`crate::IoError::UsdOutput`]. They carry no openusd types, so
//! that the error type is the same with the `usd` feature off.

/// What is wrong with a USD stage (see [`crate::IoError::Usd`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum UsdKind {
    /// A layer that openusd cannot read: missing, truncated, corrupted, not USD.
    #[error("layer {layer}: {message}")]
    Layer {
        /// The layer, as the stage names it (the file, or `package.usdz[inner.usdc]`).
        layer: String,
        /// openusd's description, its causes joined.
        message: String,
    },
    /// The stage does not compose: a reference or sublayer that is missing or unreadable, a
    /// cycle of references. openusd's description names the layer (`@asset@`) and the prim.
    #[error("{message}")]
    Composition {
        /// openusd's description.
        message: String,
    },
    /// In the strict mode ([`crate::LoadOptions::asset_roots`] given), a layer (sublayer,
    /// reference, payload) that resolves outside the stage's folder and those folders:
    /// seamlit does not open it.
    #[error(
        "{layer}: it lies outside the stage's folder {folder}; seamlit reads layers only from there and from folders given with --asset-root DIR"
    )]
    Outside {
        /// openusd's composition error for the arc (it names the layer and the prim), else
        /// the layer's asset path and file.
        layer: String,
        /// The root layer's folder.
        folder: String,
    },
    /// A prim whose values cannot be read as a mesh (an index out of range, face counts that
    /// do not add up to the face-vertex indices, a value that is not finite).
    #[error("prim <{prim}>: {message}")]
    Prim {
        /// The prim's path in the composed stage.
        prim: String,
        /// What is wrong, with the numbers.
        message: String,
    },
    /// openusd stopped with a panic on the stage: seamlit catches it, as a last resort, and
    /// reports the stage as unreadable.
    #[error("openusd cannot read it (it stopped with: {message}); the file is probably corrupt")]
    Panicked {
        /// The panic's message.
        message: String,
    },
}

/// Why a USD output is refused (see [`crate::IoError::UsdOutput`]). Nothing was written.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum UsdOutput {
    /// A `.usdc` output that openusd could not make of the override layer's text.
    #[error("the binary layer cannot be written: {reason}; write .usda")]
    Usdc {
        /// openusd's description.
        reason: String,
    },
    /// A `.usdz` output whose package cannot be made: a file of the input that cannot be
    /// read (or its name put in a package).
    #[error("the package cannot be made: {reason}")]
    Package {
        /// What failed, naming the file.
        reason: String,
    },
    /// A `.usda` output for a model that was not loaded from USD: the output is a layer of
    /// opinions over the input stage, so it needs one.
    #[error(
        "a .usda output is a layer of the fixed normals over the input stage, and this model was not loaded from USD; write .glb or .gltf"
    )]
    NotFromUsd,
    /// An object's normal is NaN or infinite, which a `.usda` file cannot hold.
    #[error("object {object:?} has a normal that is not a finite number")]
    NotFinite {
        /// The object's name (its mesh's prim path).
        object: String,
    },
    /// The model no longer matches the stage it was loaded from (objects added, removed or
    /// re-triangulated), so its normals cannot be placed on the stage's meshes.
    #[error("the model no longer matches the stage it was loaded from: {reason}")]
    ModelChanged {
        /// What differs.
        reason: String,
    },
}
