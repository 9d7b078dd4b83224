//! What is wrong with a glTF or GLB file: the kinds that [`crate::IoError`]'s glTF variants
//! carry, by what they are about (the document, an accessor, a URI, the GLB container,
//! compressed data).

use std::path::PathBuf;

/// What is wrong with a glTF accessor (see [`GltfKind::Accessor`]): a kind, with the
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
    /// Its buffer view's `byteStride` is smaller than one element: the elements would overlap
    /// (the glTF Validator's `ACCESSOR_SMALL_BYTESTRIDE` error), and the gltf crate's reader
    /// panics on it.
    #[error(
        "bufferViews[{view}] has byteStride {stride}, less than the {element} bytes of one element"
    )]
    StrideBelowElement {
        /// The buffer view.
        view: usize,
        /// Its byteStride.
        stride: usize,
        /// The bytes of one element of the accessor.
        element: u64,
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

/// What is wrong with a glTF file (see [`crate::IoError::Gltf`]): a kind, with the numbers, and the
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
        /// gltf-json's kind of problem, as it says it.
        problem: String,
        /// How many more problems it found elsewhere.
        more: usize,
    },
    /// A glTF 1.0 document (`asset.version` "1.0"; `place` is `asset.version`): seamlit reads
    /// glTF 2.0, whose layout is not 1.0's.
    #[error(
        "glTF {version}: seamlit reads glTF 2.0; convert the file first (e.g. `assimp export IN OUT.glb`)"
    )]
    OldVersion {
        /// The version written.
        version: String,
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
    /// (boxed: its largest kind would double the size of every [`crate::IoError`]).
    #[error(transparent)]
    Draco(Box<Draco>),
    /// A buffer is shorter than its declared `byteLength` (`place` is `buffer N`).
    #[error("expected {expected} bytes, found {actual}")]
    BufferLength {
        /// Buffer index.
        buffer: usize,
        /// Declared length.
        expected: u64,
        /// Available length.
        actual: u64,
    },
    /// An accessor (or its buffer view) reaches past the end of the data it points into
    /// (`place` is `accessor N (buffer view M)`).
    #[error("needs bytes up to {needed}, but only {available} are available")]
    AccessorOutOfRange {
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
    /// An accessor has a layout this reader does not accept (wrong type for the attribute, a
    /// sparse accessor without data, a count that does not match the others; `place` is
    /// `accessor N`).
    #[error("{kind}")]
    Accessor {
        /// Accessor index.
        accessor: usize,
        /// What is wrong, with expected and actual (boxed, as [`GltfKind::Draco`] is).
        kind: Box<BadAccessor>,
    },
    /// A vertex index in a primitive is not below the vertex count (`place` is
    /// `mesh M primitive P`).
    #[error(
        "index accessor {accessor} holds index {index}, but the primitive has {vertex_count} vertices"
    )]
    IndexOutOfRange {
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
    /// A skin's or an animation sampler's data breaks glTF's rules (fewer inverse bind
    /// matrices than joints, key times not increasing, values that do not fit the keys;
    /// `place` is `skins[S]` or `animations[A].samplers[S]`).
    #[error("{problem}")]
    Animation {
        /// What is wrong, with the numbers.
        problem: String,
    },
    /// A vertex attribute holds NaN or infinity (`place` is `accessor N (ATTRIBUTE)`).
    #[error("element {element} is not finite")]
    AccessorNotFinite {
        /// Accessor index.
        accessor: usize,
        /// The attribute (`POSITION`, `NORMAL`, ...).
        attribute: &'static str,
        /// Index of the first non-finite element.
        element: usize,
    },
}

impl GltfKind {
    /// For a kind about geometry data, the place [`crate::IoError::Gltf`] names: the
    /// buffer, accessor or primitive (`buffer 0`, `accessor 3 (buffer view 1)`, `accessor 3`,
    /// `mesh 0 primitive 1`, `accessor 3 (POSITION)`); `None` for the kinds whose place is a
    /// JSON path or the container.
    #[must_use]
    pub fn data_place(&self) -> Option<String> {
        Some(match self {
            Self::BufferLength { buffer, .. } => format!("buffer {buffer}"),
            Self::AccessorOutOfRange { accessor, view, .. } => {
                format!("accessor {accessor} (buffer view {view})")
            }
            Self::Accessor { accessor, .. } => format!("accessor {accessor}"),
            Self::IndexOutOfRange { mesh, primitive, .. } => {
                format!("mesh {mesh} primitive {primitive}")
            }
            Self::AccessorNotFinite { accessor, attribute, .. } => {
                format!("accessor {accessor} ({attribute})")
            }
            _ => return None,
        })
    }
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
    #[error("meshoptimizer cannot decode it: {reason}")]
    Refused {
        /// meshoptimizer's error, as it says it.
        reason: String,
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

/// Why a glTF URI is refused (see [`crate::IoError::BadUri`]).
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
