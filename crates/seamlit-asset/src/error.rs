//! The one error type of every reader and writer, [`IoError`]: every variant names the file
//! and the place in it. The kinds that only one format has are a module each ([`gltf`],
//! [`fbx`], [`usd`]): plain data, no dependency on that format's libraries, so that a load
//! error is one type whatever the format and the format crates share nothing but this crate.
//! The kinds here are those of the text formats and of writing.

pub mod fbx;
pub mod gltf;
pub mod usd;

use std::path::PathBuf;

use crate::error::fbx::FbxKind;
use crate::error::gltf::{BadUri, GltfKind};
use crate::error::usd::{UsdKind, UsdOutput};

/// Why a file could not be read or written.
///
/// Every variant names the file (`path`) and, where the format has one, the place in it: the
/// line of an OBJ or Newell file, the accessor, buffer or JSON path of a glTF file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IoError {
    /// Reading or writing the file failed at the operating-system level.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },

    /// The file's extension (or, for extension-less files, its first token) names no format
    /// this crate reads or writes.
    #[error("{}: unknown model format (expected .obj, .gltf, .glb, .fbx, .usda, .usdc, .usdz or a Newell patch file)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },

    /// The file is larger than [`crate::LoadOptions::max_file_bytes`].
    #[error("{}: file is {actual} bytes, more than the limit of {limit}", path.display())]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// The limit in bytes.
        limit: u64,
        /// The file's size in bytes.
        actual: u64,
    },

    /// A line of a text format (OBJ, MTL, Newell) could not be parsed.
    #[error("{}:{line}: {kind}", path.display())]
    Syntax {
        /// The file.
        path: PathBuf,
        /// One-based line number.
        line: usize,
        /// What is wrong, with the expected and the actual text.
        kind: Syntax,
    },

    /// A statement of a text format holds bytes that are not text: a NUL byte or invalid UTF-8
    /// (or, in a file with a UTF-16 byte-order mark, invalid UTF-16). Comments may hold
    /// anything.
    #[error("{}:{line}: {problem}", path.display())]
    NotText {
        /// The file.
        path: PathBuf,
        /// One-based line number.
        line: usize,
        /// What is wrong.
        problem: NotText,
    },

    /// The file holds no triangle: nothing to fix, inspect or draw (an empty file, only
    /// vertices, only statements this reader ignores).
    #[error("{}: the model has no triangles (no faces to fix or draw)", path.display())]
    NoTriangles {
        /// The file.
        path: PathBuf,
    },

    /// A value in a text format is NaN or infinite.
    #[error("{}:{line}: {what} is not a finite number: {text:?}", path.display())]
    NotFinite {
        /// The file.
        path: PathBuf,
        /// One-based line number.
        line: usize,
        /// What the number is (for example `vertex position`).
        what: &'static str,
        /// The offending text.
        text: String,
    },

    /// An OBJ face or a Newell patch refers to an element that does not exist.
    #[error("{}:{line}: {what} index {index} is out of range: {count} defined so far", path.display())]
    ReferenceOutOfRange {
        /// The file.
        path: PathBuf,
        /// One-based line number.
        line: usize,
        /// What the index refers to (`vertex`, `texture coordinate`, `normal`, `control point`).
        what: &'static str,
        /// The index as written in the file.
        index: i64,
        /// How many such elements exist.
        count: usize,
    },

    /// A count declared in the file is larger than the file can hold or than the limits allow.
    #[error("{}:{line}: declares {declared} {what}, but the file holds only {remaining} more non-empty lines", path.display())]
    BadCount {
        /// The file.
        path: PathBuf,
        /// One-based line number of the declaration.
        line: usize,
        /// What is counted.
        what: &'static str,
        /// The declared count.
        declared: u64,
        /// How many non-empty lines follow the declaration: fewer than the count needs.
        remaining: usize,
    },

    /// A file the model refers to (an `.mtl` library, a texture, a glTF buffer) is missing.
    /// Returned only where the reference is essential (glTF buffers) or
    /// [`crate::LoadOptions::strict`] is set; otherwise a warning.
    #[error("{}: {what} {} not found{}", path.display(), missing.display(), line.map(|l| format!(" (referenced at line {l})")).unwrap_or_default())]
    MissingFile {
        /// The file that refers to the missing one.
        path: PathBuf,
        /// What the missing file is (`material library`, `texture`, `buffer 0`).
        what: String,
        /// The missing file, resolved.
        missing: PathBuf,
        /// The referring line, for text formats.
        line: Option<usize>,
    },

    /// The glTF container or JSON could not be parsed, failed the gltf crate's validation or
    /// seamlit's own checks, holds geometry data that is out of range, of the wrong layout or
    /// not finite, or holds compressed data that does not decode.
    #[error("{}: glTF {place}: {kind}", path.display())]
    Gltf {
        /// The file.
        path: PathBuf,
        /// Where: `GLB container`, `JSON line L column C`, the JSON path of the invalid
        /// member (`meshes[0].primitives[0].indices`), or for geometry data the element it
        /// is about (`accessor 3`, `buffer 0`, `mesh 0 primitive 1`; see
        /// [`GltfKind::data_place`]).
        place: String,
        /// What is wrong; its source is the foreign error (serde_json's, gltf-json's,
        /// meshoptimizer's, the Draco decoder's) where there is one.
        #[source]
        kind: GltfKind,
    },

    /// An FBX file that ufbx refuses, that is truncated, or whose geometry is not finite.
    #[error("{}: FBX: {kind}", path.display())]
    Fbx {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        kind: FbxKind,
    },

    /// A USD stage that cannot be read: a layer openusd cannot read (missing, truncated,
    /// corrupted), a stage that does not compose (a missing reference or sublayer, a cycle),
    /// a mesh whose values do not fit it.
    #[error("{}: USD: {kind}", path.display())]
    Usd {
        /// The stage's root layer.
        path: PathBuf,
        /// What is wrong, naming the layer and the prim where known.
        kind: UsdKind,
    },

    /// A USD output (`.usda`, `.usdc`, `.usdz`) that cannot be written: a model that did not
    /// come from USD or no longer matches its stage, a file a package needs that cannot be
    /// read, a binary layer openusd cannot write. Nothing was written.
    #[error("{}: cannot write USD: {kind}", path.display())]
    UsdOutput {
        /// The output path.
        path: PathBuf,
        /// Why, and what to write instead.
        kind: UsdOutput,
    },

    /// An `.fbx` output path: seamlit writes no FBX (no maintained FBX writer exists in
    /// Rust). Nothing was written.
    #[error("{}: seamlit cannot write FBX; write .glb (or .gltf) instead, which every FBX tool imports", path.display())]
    FbxOutput {
        /// The output path.
        path: PathBuf,
    },

    /// A `.vrm` output of a model that is not a VRM avatar, or whose objects no longer match
    /// its source: VRM's extensions (humanoid bones, expressions, spring bones, MToon) refer
    /// to the input's nodes, meshes and morph targets, so only the pass-through writes them.
    /// Nothing was written.
    #[error("{}: a .vrm is written only from a VRM input, as the glTF pass-through keeps its VRM extensions, and {reason}; write .glb instead", path.display())]
    VrmOutput {
        /// The output path.
        path: PathBuf,
        /// Why the pass-through cannot write it.
        reason: String,
    },

    /// A glTF URI points outside the model's folder (`../`, an absolute path) or uses a scheme
    /// other than a relative file or a `data:` URI.
    #[error("{}: {what} URI {uri:?} is refused: {kind}", path.display())]
    BadUri {
        /// The file.
        path: PathBuf,
        /// What the URI is for (`buffer 0`, `image 2`).
        what: String,
        /// The URI as written.
        uri: String,
        /// Why it is refused.
        kind: BadUri,
    },

    /// An OBJ `mtllib` or MTL texture path that leaves the model's folder (`../`, an absolute
    /// path, a drive or scheme): refused, never read.
    #[error("{}{}: {what} path {reference:?} is refused: it leaves the model's folder", path.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
    PathEscapes {
        /// The file that holds the path (the OBJ, or the MTL for a texture).
        path: PathBuf,
        /// The line of the statement, when known.
        line: Option<usize>,
        /// What the path is for (`material library`, `texture`).
        what: &'static str,
        /// The path as written.
        reference: String,
    },

    /// A file the model refers to (a glTF buffer or image, an OBJ `mtllib`, an MTL texture)
    /// lies inside the model's folder by name, but is a symbolic link, or passes through a
    /// linked folder, that leads outside the folder: refused, never read. Links that stay
    /// inside the folder are followed.
    #[error("{}: {what} {reference:?} is refused: a symbolic link leads it out of the model's folder, to {}", path.display(), target.display())]
    LinkEscapes {
        /// The file that holds the reference (the glTF, OBJ, or the MTL for a texture; the
        /// model file when the referring library is not known).
        path: PathBuf,
        /// What the file is for (`buffer 0`, `image 2`, `material library`, `texture`).
        what: String,
        /// The reference as written (a URI, a path), or the file's path below the model's
        /// folder.
        reference: String,
        /// Where the links lead: the canonical path.
        target: PathBuf,
    },

    /// An object has more vertices or triangles than [`crate::LoadOptions::max_elements`]
    /// allows (or than 32-bit indices can address), or the model more triangles than
    /// [`crate::LoadOptions::max_model_triangles`].
    #[error("{}: {what} has {actual} elements, more than the limit of {limit}", path.display())]
    TooManyElements {
        /// The file.
        path: PathBuf,
        /// Where (object name or accessor).
        what: String,
        /// The limit.
        limit: usize,
        /// The count.
        actual: usize,
    },

    /// The output path is the file the asset was loaded from and
    /// [`crate::SaveOptions::overwrite_input`] is not set.
    #[error("{}: refusing to overwrite the model's own source file (set overwrite_input to allow it)", path.display())]
    WouldOverwriteInput {
        /// The output path.
        path: PathBuf,
    },

    /// [`crate::SaveOptions::keep_compression`] is set and the compression cannot be kept: the
    /// input is Draco-compressed (seamlit has no Draco encoder), or the output is OBJ. Nothing
    /// was written.
    #[error("{}: cannot keep the compression: {kind}", path.display())]
    CannotKeepCompression {
        /// The input (Draco) or the output (OBJ).
        path: PathBuf,
        /// Why, and what to do instead.
        kind: KeepCompression,
    },

    /// The asset cannot be written as it is (inconsistent attribute lengths, an index out of
    /// range, a source text that does not give the loaded faces).
    #[error("{}: cannot write object {object:?}: {kind}", path.display())]
    InvalidAsset {
        /// The output path.
        path: PathBuf,
        /// The object's name (empty when the problem is the whole file's).
        object: String,
        /// What is wrong, with the numbers.
        #[source]
        kind: InvalidAsset,
    },

    /// Encoding an image for output failed.
    #[error("{}: cannot encode texture {texture:?}: {source}", path.display())]
    Image {
        /// The output path.
        path: PathBuf,
        /// The texture's name.
        texture: String,
        /// What the image crate said.
        source: image::ImageError,
    },
}

/// What is wrong with a line of a text format (see [`IoError::Syntax`]): a kind, with the
/// expected and the actual text.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Syntax {
    /// An OBJ statement (`v`, `vt`, `vn`) has fewer numbers than it needs.
    #[error("`{keyword}` needs {needed} numbers, found {found}")]
    TooFewNumbers {
        /// The statement's keyword.
        keyword: &'static str,
        /// How many numbers it needs.
        needed: usize,
        /// How many the line has.
        found: usize,
    },
    /// A word where an OBJ statement needs a number.
    #[error("`{keyword}`: expected a number, found {found:?}")]
    NotANumber {
        /// The statement's keyword.
        keyword: &'static str,
        /// The word.
        found: String,
    },
    /// An OBJ `v` whose count of numbers is none of 3, 4, 6 and 7.
    #[error(
        "`v` needs 3 numbers, 4 (x y z w), 6 (x y z r g b) or 7 (x y z r g b a), found {found}"
    )]
    VertexNumbers {
        /// How many numbers the line has (5 or 8, or more).
        found: usize,
    },
    /// A word where an OBJ `v` needs its w or a colour's component.
    #[error("`v`: expected a number (w, or a colour's r g b [a]), found {found:?}")]
    NotAVertexNumber {
        /// The word.
        found: String,
    },
    /// An OBJ `v x y z w` with `w` zero.
    #[error("`v`: w = {w} cannot scale a position")]
    ZeroW {
        /// The w written (0 or -0).
        w: f32,
    },
    /// An OBJ face corner of more than three indices (`1/2/3/4`).
    #[error("face corner {corner:?} has more than three indices")]
    CornerIndices {
        /// The corner as written.
        corner: String,
    },
    /// A word where an OBJ face corner needs an index.
    #[error("face corner {corner:?}: expected an index, found {found:?}")]
    NotAnIndex {
        /// The corner as written.
        corner: String,
        /// The field that is not an index.
        found: String,
    },
    /// An OBJ `s` that gives neither a group number nor `off`.
    #[error("`s` needs a smoothing group number (0 to {}) or `off`, found {found:?}", u32::MAX)]
    SmoothingGroup {
        /// The word.
        found: String,
    },
    /// A line of a material library that tobj rejects (the line alone, after a `newmtl`).
    #[error("{tobj}: {text:?}")]
    Material {
        /// tobj's description.
        tobj: String,
        /// The line.
        text: String,
    },
    /// A material library that tobj rejects as a whole, though no line alone is rejected
    /// (`line` is 0).
    #[error("{tobj}")]
    MaterialLibrary {
        /// tobj's description.
        tobj: String,
    },
    /// A Newell file ends inside its patch or point list.
    #[error("unexpected end of file in the {list} list")]
    UnexpectedEnd {
        /// `patch` or `point`.
        list: &'static str,
    },
    /// A Newell file ends where it declares a count.
    #[error("expected the {what} count, found the end of the file")]
    MissingCount {
        /// `patches` or `points`.
        what: &'static str,
    },
    /// A Newell count that is not an integer.
    #[error("expected the {what} count (an integer), found {found:?}")]
    NotACount {
        /// `patches` or `points`.
        what: &'static str,
        /// The line, trimmed.
        found: String,
    },
    /// A Newell patch or point line with more values than it holds.
    #[error("expected {expected} {what}, found more: {text:?}")]
    TooManyValues {
        /// 16 or 3.
        expected: usize,
        /// `control-point indices` or `coordinates`.
        what: &'static str,
        /// The line.
        text: String,
    },
    /// A Newell patch or point line with fewer values than it holds.
    #[error("expected {expected} {what}, found {found}")]
    TooFewValues {
        /// 16 or 3.
        expected: usize,
        /// `control-point indices` or `coordinates`.
        what: &'static str,
        /// How many the line has.
        found: usize,
    },
    /// A word where a Newell line needs a value.
    #[error("expected {expected}, found {found:?}")]
    NotAValue {
        /// `a control-point index` or `a number`.
        expected: &'static str,
        /// The word.
        found: String,
    },
    /// Text after a Newell file's points.
    #[error("expected the end of the file after {points} points, found {text:?}")]
    TrailingText {
        /// The declared count of points.
        points: usize,
        /// The line.
        text: String,
    },
}

/// Why an asset cannot be written (see [`IoError::InvalidAsset`]), with the numbers.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum InvalidAsset {
    /// An attribute array whose length is not the object's vertex count.
    #[error("{count} {attribute} for {positions} positions")]
    AttributeLength {
        /// `uvs`, `normals`, `tangents` or `colors`.
        attribute: &'static str,
        /// The array's length.
        count: usize,
        /// The vertex count.
        positions: usize,
    },
    /// Smoothing groups whose count is not the triangle count.
    #[error("{groups} smoothing groups for {triangles} triangles")]
    SmoothingGroups {
        /// The groups' count.
        groups: usize,
        /// The triangle count.
        triangles: usize,
    },
    /// More vertices than 32-bit indices address.
    #[error("{vertices} vertices do not fit 32-bit indices")]
    TooManyVertices {
        /// The vertex count.
        vertices: usize,
    },
    /// A triangle that names a vertex past the object's.
    #[error("triangle {triangle:?} refers past the {vertices} vertices")]
    IndexOutOfRange {
        /// The triangle's indices.
        triangle: [u32; 3],
        /// The vertex count.
        vertices: usize,
    },
    /// A position that is NaN or infinite.
    #[error("a position is not finite")]
    NotFinite,
    /// A GLB over the format's 4 GiB.
    #[error("a GLB holds at most 4 GiB; this one would take {bytes} bytes")]
    GlbTooLarge {
        /// The bytes it would take.
        bytes: usize,
    },
    /// The document could not be serialised.
    #[error("JSON serialisation failed: {source}")]
    Json {
        /// serde_json's error.
        source: serde_json::Error,
    },
    /// The input's buffer 0 has no `uri` and no data, and the output is a GLB, whose buffer 0
    /// without `uri` is its BIN chunk.
    #[error(
        "buffer 0 of the input has no uri and no data (it comes from an extension or elsewhere), and a GLB's buffer 0 without uri is its BIN chunk: write it as .gltf"
    )]
    HostInGlb,
    /// The input's buffer 0 has no `uri` and no data, and new data would be appended to it.
    #[error(
        "buffer 0 of the input has no uri and no data (it comes from an extension or elsewhere): the new normals and tangents cannot be appended to it"
    )]
    HostCannotGrow,
    /// An OBJ face of the source text that is not among the loaded triangles.
    #[error("line {line}: the face is not among the loaded triangles")]
    FaceNotLoaded {
        /// The face's line, from 1.
        line: usize,
    },
    /// A corner of an OBJ face of the source text that is not in the face's triangles.
    #[error("line {line}: corner {corner} is not in its triangles")]
    CornerNotLoaded {
        /// The face's line, from 1.
        line: usize,
        /// The corner, from 1.
        corner: usize,
    },
    /// The OBJ source text's faces give another number of triangles than were loaded.
    #[error("the file's faces give {faces} triangles, {loaded} were loaded")]
    TriangleCount {
        /// Triangles the faces give.
        faces: usize,
        /// Triangles loaded.
        loaded: usize,
    },
}

/// Why the compression cannot be kept (see [`IoError::CannotKeepCompression`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum KeepCompression {
    /// A primitive of the input is Draco-compressed: seamlit has no Draco encoder.
    #[error(
        "{primitive} is Draco-compressed and seamlit has no Draco encoder; write it uncompressed (without --keep-compression, or keep_compression: false), then compress the output, e.g. `npx @gltf-transform/cli draco OUT.glb OUT.glb`"
    )]
    Draco {
        /// The primitive, as a JSON place (`meshes[0].primitives[1]` with the extension).
        primitive: String,
    },
    /// The output is OBJ, which holds no compressed geometry.
    #[error(
        "an OBJ file holds no compressed geometry; write .glb or .gltf, or save without keep_compression"
    )]
    ObjOutput,
}

/// Why a line of a text file is not text (see [`IoError::NotText`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum NotText {
    /// A NUL byte in a statement (a binary file, or UTF-16 without a byte-order mark).
    #[error("a NUL byte in a statement: not a text file (UTF-16 needs a byte-order mark)")]
    Nul,
    /// Bytes that are not UTF-8 in a statement.
    #[error("invalid UTF-8 in a statement")]
    InvalidUtf8,
    /// An unpaired surrogate or an odd number of bytes in a file marked as UTF-16.
    #[error("invalid UTF-16 (an unpaired surrogate or a lone final byte)")]
    InvalidUtf16,
}

impl IoError {
    /// An [`IoError::Gltf`] about geometry data, at the place its kind names
    /// ([`GltfKind::data_place`]).
    pub fn gltf_data(path: PathBuf, kind: GltfKind) -> Self {
        let place = kind.data_place().unwrap_or_default();
        Self::Gltf { path, place, kind }
    }

    /// An [`IoError::Io`] for `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io { path: path.into(), source }
    }
}
