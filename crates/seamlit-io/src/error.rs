//! The one error type of this crate: every variant names the file and the place in it.

use std::path::PathBuf;

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
    #[error("{}: unknown model format (expected .obj, .gltf, .glb or a Newell patch file)", path.display())]
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
    /// seamlit's own checks, or holds compressed data that does not decode.
    #[error("{}: glTF {place}: {kind}", path.display())]
    Gltf {
        /// The file.
        path: PathBuf,
        /// Where: `GLB container`, `JSON line L column C`, or the JSON path of the invalid
        /// member (`meshes[0].primitives[0].indices`).
        place: String,
        /// What is wrong; its source is the foreign error (serde_json's, gltf-json's,
        /// meshoptimizer's, the Draco decoder's) where there is one.
        #[source]
        kind: GltfKind,
    },

    /// A glTF buffer is shorter than its declared `byteLength`.
    #[error("{}: glTF buffer {buffer}: expected {expected} bytes, found {actual}", path.display())]
    BufferLength {
        /// The file.
        path: PathBuf,
        /// Buffer index.
        buffer: usize,
        /// Declared length.
        expected: u64,
        /// Available length.
        actual: u64,
    },

    /// A glTF accessor (or its buffer view) reaches past the end of the data it points into.
    #[error("{}: glTF accessor {accessor} (buffer view {view}): needs bytes up to {needed}, but only {available} are available", path.display())]
    AccessorOutOfRange {
        /// The file.
        path: PathBuf,
        /// Accessor index.
        accessor: usize,
        /// Buffer view index.
        view: usize,
        /// One past the last byte the accessor reads (relative to the buffer view for
        /// accessors, to the buffer for buffer views).
        needed: u64,
        /// Bytes available.
        available: u64,
    },

    /// A glTF accessor has a layout this reader does not accept (wrong type for the
    /// attribute, a sparse accessor without data, a count that does not match the others).
    #[error("{}: glTF accessor {accessor}: {kind}", path.display())]
    BadAccessor {
        /// The file.
        path: PathBuf,
        /// Accessor index.
        accessor: usize,
        /// What is wrong, with expected and actual.
        kind: BadAccessor,
    },

    /// A vertex index in a glTF primitive is not below the vertex count.
    #[error("{}: glTF mesh {mesh} primitive {primitive}: index accessor {accessor} holds index {index}, but the primitive has {vertex_count} vertices", path.display())]
    IndexOutOfRange {
        /// The file.
        path: PathBuf,
        /// Mesh index.
        mesh: usize,
        /// Primitive index within the mesh.
        primitive: usize,
        /// Index accessor.
        accessor: usize,
        /// The offending index value.
        index: u32,
        /// Number of vertices (POSITION count).
        vertex_count: usize,
    },

    /// A glTF vertex attribute holds NaN or infinity.
    #[error("{}: glTF accessor {accessor} ({attribute}): element {element} is not finite", path.display())]
    AccessorNotFinite {
        /// The file.
        path: PathBuf,
        /// Accessor index.
        accessor: usize,
        /// The attribute (`POSITION`, `NORMAL`, ...).
        attribute: &'static str,
        /// Index of the first non-finite element.
        element: usize,
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
    /// An MTL colour statement (`Ka`, `Kd`, `Ks`, `Ke`) of fewer than three numbers.
    #[error("`{keyword}` needs 3 numbers, found {found}: {text:?}")]
    ShortColour {
        /// The statement's keyword.
        keyword: String,
        /// How many numbers the line has.
        found: usize,
        /// The line.
        text: String,
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

/// What is wrong with a glTF accessor (see [`IoError::BadAccessor`]): a kind, with the
/// expected and the actual values.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BadAccessor {
    /// The accessor's type or component type is not one the attribute takes.
    #[error("{attribute} must be {expected}, found {found}")]
    WrongType {
        /// The attribute (`POSITION`, `indices`, ...).
        attribute: String,
        /// The types it takes, as `Vec3 of [F32]`.
        expected: String,
        /// The accessor's, as `Vec2 of F32`.
        found: String,
    },
    /// The accessor's count is 0 (glTF requires at least 1).
    #[error("{attribute} has count 0; glTF requires at least 1")]
    ZeroCount {
        /// The attribute.
        attribute: String,
    },
    /// An accessor without a buffer view (zeros) declares more bytes than the file holds.
    #[error(
        "{attribute} declares {count} elements of {element} bytes without a buffer view, more than the file's {buffer_bytes} buffer bytes (or 1 MiB) can hold"
    )]
    ZerosTooLarge {
        /// The attribute.
        attribute: String,
        /// The declared count.
        count: u64,
        /// Bytes per element.
        element: u64,
        /// The file's buffer bytes.
        buffer_bytes: u64,
    },
    /// A vertex attribute whose count is not the primitive's vertex count (POSITION's).
    #[error("{attribute} has {count} elements, POSITION has {vertex_count}")]
    CountMismatch {
        /// The attribute.
        attribute: String,
        /// Its count.
        count: usize,
        /// POSITION's count.
        vertex_count: usize,
    },
    /// The accessor gave fewer elements than its count.
    #[error("expected {expected} elements, read {read}")]
    ShortRead {
        /// Its count.
        expected: usize,
        /// How many were read.
        read: usize,
    },
    /// A triangle list whose index count (or, without indices, vertex count) is not a
    /// multiple of 3.
    #[error("a {} needs a multiple of 3 {what}, found {count}", if *what == "vertices" { "non-indexed triangle list" } else { "triangle list" })]
    NotTriangles {
        /// `indices` or `vertices`.
        what: &'static str,
        /// The count.
        count: usize,
    },
    /// The sparse count is 0 (glTF requires at least 1).
    #[error("{attribute} has sparse count 0; glTF requires at least 1")]
    ZeroSparseCount {
        /// The attribute.
        attribute: String,
    },
    /// The sparse count exceeds the accessor's.
    #[error("sparse count {sparse} exceeds the accessor count {count}")]
    SparseCountExceeds {
        /// The sparse count.
        sparse: u64,
        /// The accessor's count.
        count: u64,
    },
    /// A sparse index that lies outside its buffer.
    #[error("sparse index {element} lies outside its buffer")]
    SparseIndexOutside {
        /// Which of the sparse indices.
        element: usize,
    },
    /// A sparse index past the accessor's elements.
    #[error(
        "sparse index {index} (element {element}) is out of range: the accessor has {count} elements"
    )]
    SparseIndexOutOfRange {
        /// The index.
        index: u32,
        /// Which of the sparse indices.
        element: usize,
        /// The accessor's count.
        count: usize,
    },
    /// Sparse indices that do not strictly increase.
    #[error(
        "sparse indices must be strictly increasing: element {element} is {index}, after {before}"
    )]
    SparseNotIncreasing {
        /// Which of the sparse indices.
        element: usize,
        /// Its value.
        index: u32,
        /// The value before it.
        before: u32,
    },
    /// A `componentType` that glTF does not define (or none).
    #[error("unknown componentType {found:?}")]
    UnknownComponentType {
        /// The value written, if it is a whole number.
        found: Option<u64>,
    },
    /// A `type` that glTF does not define (or none).
    #[error("unknown type {found:?}")]
    UnknownType {
        /// The value written, if it is a string.
        found: Option<String>,
    },
    /// An accessor the pass-through copies whose count is not its primitive's vertex count.
    #[error("has {count} elements, the primitive {vertices} vertices")]
    PrimitiveCount {
        /// Its count.
        count: usize,
        /// The primitive's vertex count.
        vertices: usize,
    },
    /// A sparse index past the accessor's elements (found by the pass-through).
    #[error("sparse index {index} is past the {count} elements")]
    SparseIndexPast {
        /// The index.
        index: usize,
        /// The accessor's count.
        count: usize,
    },
    /// No `count`.
    #[error("no count")]
    NoCount,
    /// A `sparse` without `count`.
    #[error("sparse without count")]
    SparseWithoutCount,
    /// Sparse indices of a component type other than an unsigned integer.
    #[error("sparse indices of componentType {found:?}")]
    SparseIndexType {
        /// The value written, if it is a whole number.
        found: Option<u64>,
    },
    /// A sparse `indices` or `values` without `bufferView`.
    #[error("sparse part without bufferView")]
    SparseWithoutView,
    /// An attribute that names no accessor index (the accessor number is then `usize::MAX`).
    #[error("an attribute names accessor {found}")]
    NotAnAccessor {
        /// The value written, as JSON.
        found: String,
    },
}

/// What is wrong with a glTF file (see [`IoError::Gltf`]): a kind, with the numbers, and the
/// foreign error as its source where one exists.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GltfKind {
    /// The JSON does not parse, or a member has a type gltf-json does not take (`place` is
    /// `JSON line L column C`).
    #[error("{source}")]
    Json {
        /// serde_json's error.
        source: serde_json::Error,
    },
    /// The GLB container (header and chunks) is malformed (`place` is `GLB container`).
    #[error(transparent)]
    Glb(Glb),
    /// gltf-json's validation refused the document: the first problem, at `place`.
    #[error("{problem}{}", more_problems(*more))]
    Validation {
        /// gltf-json's kind of problem.
        #[source]
        problem: gltf::json::validation::Error,
        /// How many more problems it found elsewhere.
        more: usize,
    },
    /// A primitive's `POSITION` names an accessor that does not exist.
    #[error("accessor {accessor} does not exist (the file has {count})")]
    NoSuchAccessor {
        /// The accessor index written.
        accessor: usize,
        /// How many accessors the file has.
        count: usize,
    },
    /// An image in a buffer view without a `mimeType`.
    #[error("an image in a bufferView needs a mimeType")]
    ImageWithoutMimeType,
    /// An image with neither a `uri` nor a `bufferView`.
    #[error("an image needs a uri or a bufferView")]
    ImageWithoutSource,
    /// A required extension that changes how geometry is stored and that this build does
    /// not decode.
    #[error("{extension} is required, and seamlit does not read it yet")]
    UnsupportedExtension {
        /// The extension's name.
        extension: String,
    },
    /// A node reached twice from the scene's roots (`place` is the node).
    #[error("the node is reached twice: the node graph has a cycle or a node with two parents")]
    NodeReachedTwice,
    /// A buffer view reaches past the end of its buffer.
    #[error("reaches byte {end} of buffer {buffer}, which has {available}")]
    ViewOutsideBuffer {
        /// One past the view's last byte.
        end: u64,
        /// The buffer index.
        buffer: usize,
        /// The buffer's length.
        available: u64,
    },
    /// A vertex's joint index is past its skin's `joints` (`place` is the skin's joints).
    #[error("JOINTS_{set} of vertex {vertex} names joint {joint}, the skin has {joints}")]
    JointOutOfRange {
        /// The `JOINTS_n` set.
        set: usize,
        /// The vertex.
        vertex: usize,
        /// The joint index written.
        joint: u32,
        /// How many joints the skin has.
        joints: usize,
    },
    /// Draco-compressed geometry in a build without the `draco` feature.
    #[error(
        "the geometry is Draco-compressed, and this build of seamlit has no Draco decoder (the `draco` feature); decompress the file first, e.g. `npx @gltf-transform/cli copy {0} uncompressed.glb` (glTF-Transform's copy removes Draco)",
        file.display()
    )]
    NoDracoDecoder {
        /// The file, as the command that decompresses it names it.
        file: PathBuf,
    },
    /// Draco-decoded data has no buffer 0 with data to go to (`place` is `buffers[0]`).
    #[error("the decoded KHR_draco_mesh_compression data goes to buffer 0, which has no data")]
    NoDracoHost,
    /// A buffer view's EXT_/KHR_meshopt_compression is malformed or its data does not decode.
    #[error(transparent)]
    Meshopt(Meshopt),
    /// A primitive's KHR_draco_mesh_compression is malformed or its stream does not decode
    /// (boxed: its largest kind would double the size of every [`IoError`]).
    #[error(transparent)]
    Draco(Box<Draco>),
}

/// ` (and N more problems)` when there are more.
fn more_problems(more: usize) -> String {
    if more > 0 { format!(" (and {more} more problems)") } else { String::new() }
}

/// What is wrong with a GLB container (see [`GltfKind::Glb`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum Glb {
    /// Fewer than the header's 12 bytes.
    #[error("truncated: {bytes} bytes, the header alone needs 12")]
    ShortHeader {
        /// The file's length.
        bytes: usize,
    },
    /// A version other than 2.
    #[error("version {version}, expected 2")]
    Version {
        /// The version written.
        version: u32,
    },
    /// The header declares more bytes than the file has.
    #[error("truncated: the header declares {declared} bytes, the file has {bytes}")]
    Truncated {
        /// The length the header declares.
        declared: usize,
        /// The file's length.
        bytes: usize,
    },
    /// A chunk header cut off by the declared length.
    #[error("truncated: chunk {chunk} header at byte {at} is incomplete")]
    ShortChunkHeader {
        /// The chunk's number, from 0.
        chunk: usize,
        /// Where its header starts.
        at: usize,
    },
    /// A chunk longer than the declared length leaves it.
    #[error(
        "truncated: chunk {chunk} ({chunk_type}) declares {length} bytes from byte {start}, but the file ends at {declared}"
    )]
    ShortChunk {
        /// The chunk's number, from 0.
        chunk: usize,
        /// Its type, as text.
        chunk_type: String,
        /// The length it declares.
        length: u32,
        /// Where its data starts.
        start: usize,
        /// The length the header declares.
        declared: usize,
    },
    /// A first chunk that is not JSON.
    #[error("the first chunk is {chunk_type}, not JSON")]
    FirstChunkNotJson {
        /// Its type, as text.
        chunk_type: String,
    },
    /// No chunk at all.
    #[error("no JSON chunk")]
    NoJsonChunk,
}

/// What is wrong with a buffer view's EXT_/KHR_meshopt_compression (see
/// [`GltfKind::Meshopt`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Meshopt {
    /// A member the extension needs is missing.
    #[error("{member} is missing")]
    Missing {
        /// The member (`buffer`, `byteLength`, `byteStride`, `count`).
        member: &'static str,
    },
    /// A `mode` the extension does not define (or none).
    #[error("unknown mode {found:?}")]
    UnknownMode {
        /// The mode written, if it is a string.
        found: Option<String>,
    },
    /// A `filter` the extension does not define.
    #[error("unknown filter {found:?}")]
    UnknownFilter {
        /// The filter written, if it is a string.
        found: Option<String>,
    },
    /// A `byteStride` the mode and filter do not allow.
    #[error("byteStride {stride} is not allowed for mode {mode} with filter {filter}")]
    StrideNotAllowed {
        /// The stride.
        stride: usize,
        /// The mode, as the extension names it (`ATTRIBUTES`).
        mode: String,
        /// The filter, as the extension names it (`NONE`).
        filter: String,
    },
    /// A `byteStride` that is no vertex size meshoptimizer decodes.
    #[error("byteStride {stride} is not a vertex size")]
    NotAVertexSize {
        /// The stride.
        stride: usize,
    },
    /// Mode TRIANGLES with a count that is not a multiple of 3.
    #[error("mode TRIANGLES needs a multiple of 3 indices, found {count}")]
    NotTriangles {
        /// The count.
        count: usize,
    },
    /// The compressed bytes lie outside their buffer.
    #[error("the compressed bytes {start}..{end} lie outside buffer {buffer}")]
    CompressedOutside {
        /// Their first byte.
        start: usize,
        /// One past their last byte.
        end: usize,
        /// The buffer.
        buffer: usize,
    },
    /// `count` elements of `byteStride` bytes are not the view's `byteLength`.
    #[error("{count} elements of {stride} bytes do not make the view's byteLength {length}")]
    LengthMismatch {
        /// The extension's count.
        count: usize,
        /// The extension's byteStride.
        stride: usize,
        /// The view's byteLength.
        length: usize,
    },
    /// The view's own bytes lie outside its buffer.
    #[error("the view's bytes {start}..{end} lie outside buffer {buffer} ({available} bytes)")]
    ViewOutside {
        /// The view's first byte.
        start: usize,
        /// One past its last byte.
        end: usize,
        /// Its buffer.
        buffer: usize,
        /// The buffer's length.
        available: usize,
    },
    /// meshoptimizer refused the compressed data.
    #[error("meshoptimizer cannot decode it: {source}")]
    Refused {
        /// meshoptimizer's error.
        source: meshopt::Error,
    },
    /// The data decoded to a length other than the view's.
    #[error("decodes to {decoded} bytes, not {length}")]
    DecodedLength {
        /// Bytes decoded.
        decoded: usize,
        /// The view's byteLength.
        length: usize,
    },
}

/// What is wrong with a primitive's KHR_draco_mesh_compression (see [`GltfKind::Draco`]):
/// its members, the accessors it fills, or a stream that does not hold what they declare.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Draco {
    /// A member the extension needs is missing.
    #[error("{member} is missing")]
    Missing {
        /// `bufferView` or `attributes`.
        member: &'static str,
    },
    /// The stream's buffer view does not exist.
    #[error("buffer view {view} does not exist")]
    NoSuchView {
        /// The view index.
        view: usize,
    },
    /// The stream's buffer view lies outside its buffer.
    #[error("buffer view {view} lies outside buffer {buffer}")]
    ViewOutside {
        /// The view index.
        view: usize,
        /// The buffer it names (`usize::MAX` when none).
        buffer: usize,
    },
    /// An `attributes` member that is not an attribute id.
    #[error("attributes.{name} is not an attribute id")]
    NotAnId {
        /// The attribute's name.
        name: String,
    },
    /// An `attributes` member that the primitive's own `attributes` lack.
    #[error("attributes.{name} names no attribute of the primitive")]
    NotAnAttribute {
        /// The attribute's name.
        name: String,
    },
    /// A Draco primitive without `indices`.
    #[error("the primitive has no indices")]
    NoIndices,
    /// An accessor the stream fills does not exist.
    #[error("{name}: accessor {accessor} does not exist")]
    NoSuchAccessor {
        /// The attribute's name (or `indices`).
        name: String,
        /// The accessor index.
        accessor: usize,
    },
    /// An accessor the stream fills has data of its own.
    #[error(
        "{name}: accessor {accessor} has data of its own (uncompressed fallback data, or it is shared with another primitive); seamlit reads Draco primitives whose accessors have none, as glTF-Transform and gltfpack write them"
    )]
    AccessorHasData {
        /// The attribute's name (or `indices`).
        name: String,
        /// The accessor index.
        accessor: usize,
    },
    /// An accessor that declares more elements than the limit.
    #[error("{name}: accessor {accessor} declares {count} elements, more than {limit}")]
    TooManyElements {
        /// The attribute's name (or `indices`).
        name: String,
        /// The accessor index.
        accessor: usize,
        /// Its count.
        count: usize,
        /// [`crate::LoadOptions::max_elements`].
        limit: usize,
    },
    /// An accessor whose `type` glTF does not define.
    #[error("{name}: accessor {accessor} has type {found:?}")]
    AccessorType {
        /// The attribute's name (or `indices`).
        name: String,
        /// The accessor index.
        accessor: usize,
        /// The type written, if it is a string.
        found: Option<String>,
    },
    /// The decoder refused the stream.
    #[error("the Draco stream is malformed: {source}")]
    Malformed {
        /// The decoder's error (draco-oxide-decoder's, boxed: the crate is a pinned alpha).
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// The decoder panicked on the stream (the panic is caught).
    #[error(
        "the Draco decoder failed on this stream (it panicked): the stream is malformed or uses what draco-oxide-decoder does not support"
    )]
    DecoderPanicked,
    /// Decoded attributes that cover different numbers of points.
    #[error(
        "the decoded attribute {attribute} covers {points} points, attribute {first} covers {first_points}"
    )]
    PointCounts {
        /// The attribute id.
        attribute: usize,
        /// Its points.
        points: usize,
        /// The first attribute's id.
        first: usize,
        /// The first attribute's points.
        first_points: usize,
    },
    /// A point that names a value its attribute lacks.
    #[error("point {point} names a value attribute {attribute} lacks")]
    NoValue {
        /// The point.
        point: usize,
        /// The attribute id.
        attribute: usize,
    },
    /// An attribute id the stream does not hold.
    #[error("{name}: the stream has no attribute {id}")]
    NoSuchId {
        /// The attribute's name.
        name: String,
        /// The id.
        id: usize,
    },
    /// A decoded attribute whose count, components or type differ from its accessor's.
    #[error(
        "{name}: the stream holds {count} values of {components} x {component}, accessor {accessor} declares {declared} of {declared_components} x componentType {component_type}"
    )]
    AttributeMismatch {
        /// The attribute's name.
        name: String,
        /// Values decoded.
        count: usize,
        /// Components per decoded value.
        components: usize,
        /// The decoded component type, as the decoder names it.
        component: String,
        /// The accessor index.
        accessor: usize,
        /// The accessor's count.
        declared: usize,
        /// The accessor's components per element.
        declared_components: usize,
        /// The accessor's componentType.
        component_type: u64,
    },
    /// A decoded triangle that names a point the stream lacks.
    #[error("a triangle names point {point}, the stream has {points}")]
    NoSuchPoint {
        /// The point.
        point: usize,
        /// The stream's points.
        points: usize,
    },
    /// Decoded triangle corners other than the indices accessor's count.
    #[error(
        "the stream holds {corners} triangle corners, indices accessor {accessor} declares {declared}"
    )]
    CornerCount {
        /// Corners decoded.
        corners: usize,
        /// The indices accessor.
        accessor: usize,
        /// Its count.
        declared: usize,
    },
    /// An indices accessor whose componentType is not an unsigned integer.
    #[error("indices accessor {accessor} has componentType {component_type}")]
    IndexType {
        /// The indices accessor.
        accessor: usize,
        /// Its componentType.
        component_type: u64,
    },
    /// More decoded vertices than the indices' component type can name.
    #[error("{vertices} vertices do not fit the indices' componentType {component_type}")]
    IndicesTooNarrow {
        /// Vertices decoded.
        vertices: usize,
        /// The indices accessor's componentType.
        component_type: u64,
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

/// Why a glTF URI is refused (see [`IoError::BadUri`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BadUri {
    /// A `data:` URI without the comma before its payload.
    #[error("a data: URI needs a comma before its payload")]
    DataWithoutComma,
    /// A `data:` URI whose base64 payload does not decode.
    #[error("the base64 payload is malformed")]
    MalformedBase64,
    /// A URI with a scheme (`https:`, `file:`): remote resources are never fetched.
    #[error("only relative file paths and data: URIs are read")]
    NotRelative,
    /// An absolute path (`/etc/passwd`, `C:/...`).
    #[error("an absolute path leaves the model's folder")]
    Absolute,
    /// A relative path whose `..` parts leave the model's folder.
    #[error("it leaves the model's folder")]
    LeavesFolder,
    /// A path with no file name in it (`./`).
    #[error("it names no file")]
    NoFile,
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
    /// An [`IoError::Io`] for `path`.
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io { path: path.into(), source }
    }
}
