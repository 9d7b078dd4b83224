//! glTF 2.0 and GLB in, through the gltf crate.
//!
//! The JSON is parsed and validated by gltf-json, less the few rules in which it is stricter
//! than the specification (`gltf_spec`); the GLB container is split by its chunk headers
//! here. Buffers and images are resolved here, so that this reader decides what a URI may
//! point to and names the place of every problem:
//!
//! - buffers and images come from the GLB `BIN` chunk, `data:` URIs (base64) or files beside
//!   the model; a URI that leaves the model's folder (`../`, an absolute path, a symbolic
//!   link leading out) or names another scheme is refused;
//! - every accessor a primitive uses is checked against its buffer view, and every view
//!   against its buffer, before a byte is read; every index against the vertex count; every
//!   attribute for NaN and infinity;
//! - quantised attributes (KHR_mesh_quantization) are read as floats and meshopt-compressed
//!   buffer views (EXT_meshopt_compression) are decoded at load (`gltf_decode.rs`), and so
//!   are Draco-compressed primitives with the `draco` feature (`gltf_draco.rs`); without it
//!   such a primitive is refused, naming it and a command that decompresses it.
//!
//! Every primitive of every mesh instance in the default scene (or the first scene; in a file
//! without scenes, under the nodes that are no node's child) becomes an object, its
//! transform the composition of the node transforms above it (a mesh used by two nodes is
//! two objects). An object is named after its node (else its mesh, else
//! `mesh{index}`), with `.{primitive}` appended when the mesh has several primitives.

use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::json::validation::Error as Problem;
use gltf::mesh::Mode;
use seamlit_mesh::{Object, VAxis};

use crate::error::{BadAccessor, BadUri, Glb, GltfKind};
use crate::gltf_decode::{read_directions, read_floats};
use crate::gltf_pass::Instance;

mod deform;
use crate::{
    Asset, GltfSource, IoError, LoadOptions, Material, Node, Texture, TextureRef, TextureSource,
    UvTransform,
};

/// Reads a glTF (`.gltf`, with its buffers and images) or GLB file.
///
/// # Errors
///
/// [`IoError::Gltf`] for a malformed container, JSON or a document the gltf crate rejects
/// (with the JSON path); [`IoError::BufferLength`], [`IoError::AccessorOutOfRange`],
/// [`IoError::BadAccessor`], [`IoError::IndexOutOfRange`], [`IoError::AccessorNotFinite`]
/// for bad geometry data; [`IoError::BadUri`] for a URI outside the model's folder,
/// [`IoError::LinkEscapes`] for one whose symbolic links lead out of it;
/// [`IoError::MissingFile`] for a missing buffer file (or texture, when `options.strict`).
pub fn load(path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    let mut bytes = crate::read_bytes(path, options)?;
    let (document, json, bin) = document(&bytes, path)?;
    // The file's bytes become the BIN chunk's buffer, moved to the front in place: a GLB is
    // never held twice. A JSON file's bytes are freed here.
    let blob = bin.map(|range| {
        let length = range.len();
        bytes.copy_within(range, 0);
        bytes.truncate(length);
        bytes.shrink_to_fit();
        bytes
    });
    let mut asset = read(&document, json, blob, path, options)?;
    asset.source = Some(path.to_path_buf());
    Ok(asset)
}

/// Parses glTF or GLB bytes; `path` names the file in errors and its folder resolves
/// relative URIs.
///
/// # Errors
///
/// As [`load`].
pub fn parse(bytes: &[u8], path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    let (document, json, bin) = document(bytes, path)?;
    read(&document, json, bin.map(|range| bytes[range].to_vec()), path, options)
}

/// The validated document of glTF or GLB bytes, the same JSON as written (for the
/// pass-through writer) and, for a GLB with a BIN chunk, where that chunk's data lies in
/// `bytes`.
fn document(
    bytes: &[u8],
    path: &Path,
) -> Result<(gltf::Document, serde_json::Value, Option<Range<usize>>), IoError> {
    let (json, bin) = if bytes.starts_with(b"glTF") {
        let (json, bin) = glb_chunks(bytes, path)?;
        (&bytes[json], bin)
    } else {
        (bytes, None)
    };
    // Parsed as plain JSON (what the pass-through writer writes back), then as typed glTF.
    let value: serde_json::Value = serde_json::from_slice(json).map_err(|e| json_error(e, path))?;
    // A document gltf-json refuses is read again as the specification allows (see
    // `lenient`); if that fails too, the first error (with its line) is reported.
    let root = gltf::json::Root::from_slice(json).or_else(|error| {
        lenient(&value).and_then(|patched| serde_json::from_value(patched).ok()).ok_or(error)
    });
    let root = root.map_err(|e| json_error(e, path))?;
    #[cfg(not(feature = "draco"))]
    crate::gltf_draco::refuse(&value, path)?;
    let document = validated(root, path)?;
    Ok((document, value, bin))
}

/// The typed document of a parsed root, after the checks that must run before gltf-json's
/// validation and that validation less what the specification allows (`gltf_spec`).
fn validated(mut root: gltf::json::Root, path: &Path) -> Result<gltf::Document, IoError> {
    check_position_indices(&root, path)?;
    check_image_sources(&root, path)?;
    check_required_extensions(&root, path)?;
    // The gltf crate refuses every required extension it does not implement; seamlit passes
    // through the ones that do not change how geometry is read (checked above).
    root.extensions_required.clear();
    crate::gltf_spec::validate(&root).map_err(|problems| validation_error(&problems, path))?;
    Ok(gltf::Document::from_json_without_validation(root))
}

/// Decodes the document's Draco-compressed primitives into plain data (`gltf_draco`),
/// changing `json` and buffer 0; returns the typed document of the changed JSON, or `None`
/// when there was nothing to decode.
#[cfg(feature = "draco")]
fn decode_draco(
    json: &mut serde_json::Value,
    buffers: &mut [Vec<u8>],
    options: &LoadOptions,
    path: &Path,
) -> Result<Option<gltf::Document>, IoError> {
    if crate::gltf_draco::decode(json, buffers, options.max_elements, path)? == 0 {
        return Ok(None);
    }
    let root = serde_json::from_value(json.clone())
        .or_else(|error| lenient(json).and_then(|p| serde_json::from_value(p).ok()).ok_or(error));
    let root = root.map_err(|e| json_error(e, path))?;
    validated(root, path).map(Some)
}

/// What the specification allows and gltf-json 1.4.1 refuses, made acceptable to it: a
/// scene without `nodes` (an empty scene) gets `"nodes": []`, whole numbers written as
/// floats (`"count": 3.0`) become integers (float fields read integers as well), and
/// animation channels without a target node are dropped (see `gltf_spec`). `None` when
/// there is nothing to change.
fn lenient(document: &serde_json::Value) -> Option<serde_json::Value> {
    fn patch(value: &mut serde_json::Value, changed: &mut bool) {
        match value {
            serde_json::Value::Number(n) if n.is_f64() => {
                let x = n.as_f64().unwrap_or(f64::NAN);
                if x.fract() == 0.0 && (-9.0e15..9.0e15).contains(&x) {
                    #[expect(clippy::cast_possible_truncation, reason = "a whole number, checked")]
                    let whole = x as i64;
                    *value = serde_json::Value::from(whole);
                    *changed = true;
                }
            }
            serde_json::Value::Array(items) => items.iter_mut().for_each(|v| patch(v, changed)),
            serde_json::Value::Object(members) => {
                members.values_mut().for_each(|v| patch(v, changed));
            }
            _ => {}
        }
    }
    let mut patched = document.clone();
    let mut changed = crate::gltf_spec::drop_channels_without_node(&mut patched);
    patch(&mut patched, &mut changed);
    let scenes = patched.get_mut("scenes").and_then(serde_json::Value::as_array_mut);
    for scene in scenes.into_iter().flatten().filter_map(serde_json::Value::as_object_mut) {
        if !scene.contains_key("nodes") {
            scene.insert("nodes".to_owned(), serde_json::Value::Array(Vec::new()));
            changed = true;
        }
    }
    changed.then_some(patched)
}

/// Required extensions that change how vertex data is stored and that seamlit does not
/// decode: a file that requires one of these cannot be read without it. Any other required
/// extension (lights, material and texture extensions, unknown ones) is passed through
/// untouched; KHR_mesh_quantization and EXT_/KHR_meshopt_compression are decoded
/// (`gltf_decode.rs`), and KHR_draco_mesh_compression with the `draco` feature
/// (`gltf_draco.rs`).
#[cfg(not(feature = "draco"))]
const GEOMETRY_EXTENSIONS: [&str; 1] = ["KHR_draco_mesh_compression"];
#[cfg(feature = "draco")]
const GEOMETRY_EXTENSIONS: [&str; 0] = [];

/// Refuses a file that requires an extension in [`GEOMETRY_EXTENSIONS`].
fn check_required_extensions(root: &gltf::json::Root, path: &Path) -> Result<(), IoError> {
    match root
        .extensions_required
        .iter()
        .enumerate()
        .find(|(_, e)| GEOMETRY_EXTENSIONS.contains(&e.as_str()))
    {
        Some((i, extension)) => Err(IoError::Gltf {
            path: path.to_path_buf(),
            place: format!("extensionsRequired[{i}]"),
            kind: GltfKind::UnsupportedExtension { extension: extension.clone() },
        }),
        None => Ok(()),
    }
}

/// Reads the asset of a validated document; `blob` is the GLB's BIN chunk. The buffers and
/// `json` (the document as written, Draco primitives decoded) end in the asset's
/// [`GltfSource`], for the pass-through writer.
fn read(
    document: &gltf::Document,
    json: serde_json::Value,
    blob: Option<Vec<u8>>,
    path: &Path,
    options: &LoadOptions,
) -> Result<Asset, IoError> {
    let reader =
        Reader { path, folder: path.parent().unwrap_or(Path::new("")), options, buffer_bytes: 0 };
    let without_data = buffers_without_data(document, &json, blob.is_some());
    let mut buffers = reader.buffers(document, &json, blob)?;
    crate::gltf_decode::decode_meshopt(&json, &mut buffers, path)?;
    #[cfg(feature = "draco")]
    let mut json = json;
    #[cfg(feature = "draco")]
    let decoded = decode_draco(&mut json, &mut buffers, options, path)?;
    #[cfg(feature = "draco")]
    let document = decoded.as_ref().unwrap_or(document);
    let reader = Reader { buffer_bytes: buffers.iter().map(|b| b.len() as u64).sum(), ..reader };
    reader.check_views(document, &buffers, &without_data)?;

    let mut asset = Asset::default();
    let mut warnings = Vec::new();
    asset.textures = reader.images(document, &buffers)?;
    asset.materials = document.materials().map(|m| material(&m)).collect();
    let scene = document.default_scene().or_else(|| document.scenes().next());
    let roots: Vec<gltf::Node<'_>> = match &scene {
        Some(scene) => scene.nodes().collect(),
        None => crate::gltf_spec::root_nodes(document),
    };
    if scene.is_none() && document.meshes().len() > 0 {
        warnings.push(format!(
            "{}: no scene; the nodes that are no node's child are placed as one",
            path.display()
        ));
    }
    let mut placing = Placing::new(&reader, &buffers, &without_data);
    placing.walk(roots, &mut asset, &mut warnings)?;
    let instances = placing.instances;
    asset.model.v_axis = VAxis::Down;
    asset.lights = punctual_lights(document, scene.as_ref(), &mut warnings);
    asset.gltf_source = Some(GltfSource::new(json, buffers, path, instances));
    warnings.extend(crate::texture::decode_all(&mut asset.textures, path, options)?);
    asset.warnings = warnings;
    Ok(asset)
}

/// The buffers without data (see `gltf_spec`): a buffer without `uri` outside a GLB, unless
/// it is a meshopt fallback buffer, which `decode_meshopt` fills.
fn buffers_without_data(
    document: &gltf::Document,
    json: &serde_json::Value,
    glb: bool,
) -> Vec<usize> {
    let meshopt_fallback = |b: &usize| {
        let extensions = &json["buffers"][*b]["extensions"];
        extensions.get("EXT_meshopt_compression").is_some()
            || extensions.get("KHR_meshopt_compression").is_some()
    };
    crate::gltf_spec::buffers_without_data(document, glb)
        .into_iter()
        .filter(|b| !meshopt_fallback(b))
        .collect()
}

/// The walk over a scene's node tree that makes an object of every triangle primitive of
/// every mesh instance (a mesh used by two nodes is two objects) and a [`Node`] of every
/// node.
struct Placing<'r> {
    reader: &'r Reader<'r>,
    buffers: &'r [Vec<u8>],
    without_data: &'r [usize],
    /// Decoded primitives by (mesh, primitive): the object of their first instance, cloned
    /// for the other nodes that instance the mesh.
    decoded: HashMap<(usize, usize), usize>,
    /// Their skin influences as read (joints index the skin's `joints`), mapped per instance.
    influences: HashMap<(usize, usize), Vec<seamlit_mesh::Influences>>,
    /// Per object: where it came from in the document, for the pass-through writer.
    instances: Vec<Instance>,
    /// Triangles placed so far, instances counted.
    triangles: usize,
}

impl<'r> Placing<'r> {
    fn new(reader: &'r Reader<'r>, buffers: &'r [Vec<u8>], without_data: &'r [usize]) -> Self {
        Self {
            reader,
            buffers,
            without_data,
            decoded: HashMap::new(),
            influences: HashMap::new(),
            instances: Vec::new(),
            triangles: 0,
        }
    }

    /// Walks the trees under `roots` depth first, in document order, pushing the nodes and
    /// objects into `asset`.
    ///
    /// # Errors
    ///
    /// [`IoError::Gltf`] for a node reached twice (a cycle, or two parents); the errors of
    /// [`Self::mesh_instance`].
    fn walk<'d>(
        &mut self,
        roots: Vec<gltf::Node<'d>>,
        asset: &mut Asset,
        warnings: &mut Vec<String>,
    ) -> Result<(), IoError> {
        let path = self.reader.path;
        let mut stack: Vec<(gltf::Node<'d>, Option<usize>, Mat4)> =
            roots.into_iter().rev().map(|n| (n, None, Mat4::IDENTITY)).collect();
        let mut visited = std::collections::HashSet::new();
        while let Some((node, parent, parent_global)) = stack.pop() {
            if !visited.insert(node.index()) {
                return Err(IoError::Gltf {
                    path: path.to_path_buf(),
                    place: format!("nodes[{}]", node.index()),
                    kind: GltfKind::NodeReachedTwice,
                });
            }
            let local = Mat4::from_cols_array_2d(&node.transform().matrix());
            let global = parent_global * local;
            let node_index = asset.nodes.len();
            let objects = match node.mesh() {
                Some(mesh) => self.mesh_instance(&node, &mesh, global, asset, warnings)?,
                None => Vec::new(),
            };
            asset.nodes.push(Node {
                name: node.name().unwrap_or_default().to_owned(),
                local_transform: local,
                parent,
                objects,
            });
            for child in node.children().collect::<Vec<_>>().into_iter().rev() {
                stack.push((child, Some(node_index), global));
            }
        }
        Ok(())
    }

    /// The objects of one node's mesh, one per triangle primitive, placed at `global` (a
    /// skinned mesh at its bind pose); returns their indices in `asset.model.objects`.
    fn mesh_instance(
        &mut self,
        node: &gltf::Node<'_>,
        mesh: &gltf::Mesh<'_>,
        global: Mat4,
        asset: &mut Asset,
        warnings: &mut Vec<String>,
    ) -> Result<Vec<usize>, IoError> {
        let path = self.reader.path;
        let mut objects = Vec::new();
        for primitive in mesh.primitives() {
            let Some(mut object) = self.first_object(mesh, &primitive, asset, warnings)? else {
                continue;
            };
            let key = (mesh.index(), primitive.index());
            let read = self.influences.entry(key).or_insert_with(|| object.skin.clone());
            object.skin = deform::joint_nodes(read, node, path)?;
            // Instancing multiplies triangles without costing file bytes: capped.
            self.triangles = self.triangles.saturating_add(object.triangles.len());
            let limit = self.reader.options.max_model_triangles;
            if self.triangles > limit {
                return Err(IoError::TooManyElements {
                    path: path.to_path_buf(),
                    what: format!("the model (mesh instances up to nodes[{}])", node.index()),
                    limit,
                    actual: self.triangles,
                });
            }
            // A skinned mesh is placed by its joints, never by its node (glTF 2.0,
            // "Skins"): it is welded in its bind-pose space.
            let placed = if node.skin().is_some() { Mat4::IDENTITY } else { global };
            objects.push(asset.model.objects.len());
            self.instances.push(Instance {
                node: node.index(),
                mesh: mesh.index(),
                primitive: primitive.index(),
            });
            asset.model.objects.push(Object {
                name: object_name(node, mesh, &primitive),
                transform: (placed != Mat4::IDENTITY).then_some(placed),
                ..object
            });
        }
        Ok(objects)
    }

    /// The object of a primitive as its first instance read it (a clone for the others), or
    /// `None`, with a warning, for a primitive that is not a triangle list or whose data is
    /// not in the file.
    fn first_object(
        &mut self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        asset: &Asset,
        warnings: &mut Vec<String>,
    ) -> Result<Option<Object>, IoError> {
        let (path, m, p) = (self.reader.path.display(), mesh.index(), primitive.index());
        if primitive.mode() != Mode::Triangles {
            warnings.push(format!(
                "{path}: mesh {m} primitive {p}: mode {:?} skipped (only triangles are read)",
                primitive.mode()
            ));
            return Ok(None);
        }
        if let Some(&first) = self.decoded.get(&(m, p)) {
            return Ok(Some(asset.model.objects[first].clone()));
        }
        if let Some(reason) = crate::gltf_spec::without_data(primitive, self.without_data) {
            warnings.push(format!("{path}: mesh {m} primitive {p} skipped: {reason}"));
            return Ok(None);
        }
        let object = self.reader.primitive(mesh, primitive, self.buffers, warnings)?;
        if object.is_some() {
            self.decoded.insert((m, p), asset.model.objects.len());
        }
        Ok(object)
    }
}

/// An object's name: its node's (else its mesh's, else `mesh{index}`), with `.{primitive}`
/// appended when the mesh has several primitives.
fn object_name(
    node: &gltf::Node<'_>,
    mesh: &gltf::Mesh<'_>,
    primitive: &gltf::Primitive<'_>,
) -> String {
    let base = node
        .name()
        .filter(|n| !n.is_empty())
        .or_else(|| mesh.name().filter(|n| !n.is_empty()))
        .map_or_else(|| format!("mesh{}", mesh.index()), str::to_owned);
    if mesh.primitives().len() > 1 { format!("{base}.{}", primitive.index()) } else { base }
}

/// Every primitive's `POSITION` names an existing accessor. gltf-json 1.4.1's validation
/// indexes the accessors with it unchecked and panics otherwise (found by the `gltf` fuzz
/// target: regression input `tests/regressions/gltf_position_accessor_missing.gltf`), so this
/// runs before it.
fn check_position_indices(root: &gltf::json::Root, path: &Path) -> Result<(), IoError> {
    let semantic = gltf::json::validation::Checked::Valid(gltf::Semantic::Positions);
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(index) = primitive.attributes.get(&semantic)
                && index.value() >= root.accessors.len()
            {
                return Err(IoError::Gltf {
                    path: path.to_path_buf(),
                    place: format!("meshes[{m}].primitives[{p}].attributes.POSITION"),
                    kind: GltfKind::NoSuchAccessor {
                        accessor: index.value(),
                        count: root.accessors.len(),
                    },
                });
            }
        }
    }
    Ok(())
}

/// Every image has a `uri`, or a `bufferView` with a `mimeType`: gltf 1.4.1's
/// `Image::source` unwraps them and its validation lets them through (found by the `gltf`
/// fuzz target: regression input `tests/regressions/gltf_image_without_uri.gltf`).
fn check_image_sources(root: &gltf::json::Root, path: &Path) -> Result<(), IoError> {
    for (i, image) in root.images.iter().enumerate() {
        let kind = match (&image.uri, &image.buffer_view, &image.mime_type) {
            (_, Some(_), None) => GltfKind::ImageWithoutMimeType,
            (None, None, _) => GltfKind::ImageWithoutSource,
            _ => continue,
        };
        return Err(IoError::Gltf {
            path: path.to_path_buf(),
            place: format!("images[{i}]"),
            kind,
        });
    }
    Ok(())
}

/// The JSON chunk's and, when the second chunk is one, the BIN chunk's data in GLB `bytes`,
/// after checking the 12-byte header and the chunk headers against the declared length, so
/// that a truncated file gets a message that says how much is missing. As the
/// specification allows, bytes after the declared length and chunks of other types after
/// the first two are ignored.
fn glb_chunks(bytes: &[u8], path: &Path) -> Result<(Range<usize>, Option<Range<usize>>), IoError> {
    let err = |kind: Glb| IoError::Gltf {
        path: path.to_path_buf(),
        place: "GLB container".to_owned(),
        kind: GltfKind::Glb(kind),
    };
    let word = |at: usize| -> Option<u32> {
        bytes.get(at..at + 4).and_then(|b| b.try_into().ok()).map(u32::from_le_bytes)
    };
    let (Some(version), Some(declared)) = (word(4), word(8)) else {
        return Err(err(Glb::ShortHeader { bytes: bytes.len() }));
    };
    if version != 2 {
        return Err(err(Glb::Version { version }));
    }
    let declared = declared as usize;
    if declared > bytes.len() {
        return Err(err(Glb::Truncated { declared, bytes: bytes.len() }));
    }
    let mut at = 12;
    let mut chunk = 0;
    let mut chunks = Vec::new();
    while at < declared {
        let (Some(length), Some(kind)) = (word(at), word(at + 4)) else {
            return Err(err(Glb::ShortChunkHeader { chunk, at }));
        };
        let end = at as u64 + 8 + u64::from(length);
        if end > declared as u64 {
            return Err(err(Glb::ShortChunk {
                chunk,
                chunk_type: String::from_utf8_lossy(&kind.to_le_bytes()).into_owned(),
                length,
                start: at + 8,
                declared,
            }));
        }
        #[expect(clippy::cast_possible_truncation, reason = "at most `declared`, checked above")]
        let end = end as usize;
        chunks.push((kind, at + 8..end));
        at = end;
        chunk += 1;
    }
    match chunks.as_slice() {
        [(JSON_CHUNK, json), rest @ ..] => Ok((
            json.clone(),
            rest.first().filter(|(kind, _)| *kind == BIN_CHUNK).map(|(_, bin)| bin.clone()),
        )),
        [(kind, _), ..] => Err(err(Glb::FirstChunkNotJson {
            chunk_type: String::from_utf8_lossy(&kind.to_le_bytes())
                .trim_end_matches('\0')
                .to_owned(),
        })),
        [] => Err(err(Glb::NoJsonChunk)),
    }
}

/// GLB chunk types: `JSON` and `BIN\0`, little-endian.
const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;

/// The bytes an accessor without a buffer view (zeros, plus sparse values) may take when the
/// file's buffers hold fewer: small all-zero accessors need no buffer at all.
const ZEROS_FLOOR: u64 = 1 << 20;

/// An [`IoError::Gltf`] for JSON that does not parse as a glTF document.
fn json_error(error: serde_json::Error, path: &Path) -> IoError {
    IoError::Gltf {
        path: path.to_path_buf(),
        place: format!("JSON line {} column {}", error.line(), error.column()),
        kind: GltfKind::Json { source: error },
    }
}

/// An [`IoError::Gltf`] for gltf-json's validation problems: the first, at its JSON path.
fn validation_error(problems: &[(gltf::json::Path, Problem)], path: &Path) -> IoError {
    let (place, problem) = problems
        .first()
        .map_or(("document".to_owned(), Problem::Invalid), |(p, e)| (p.to_string(), *e));
    IoError::Gltf {
        path: path.to_path_buf(),
        place,
        kind: GltfKind::Validation { problem, more: problems.len().saturating_sub(1) },
    }
}

/// For the pass-through writer: the file that a URI of the model at `path` names, checked
/// as the loader checks it (inside the model's folder, links included): the file as named
/// and its real path when it exists. `None` for a `data:` URI.
///
/// # Errors
///
/// [`IoError::BadUri`] or [`IoError::LinkEscapes`], as when loading.
pub(crate) fn resolve_file(
    path: &Path,
    uri: &str,
    what: &str,
) -> Result<Option<(PathBuf, Option<PathBuf>)>, IoError> {
    if uri.starts_with("data:") {
        return Ok(None);
    }
    let reader = Reader {
        path,
        folder: path.parent().unwrap_or(Path::new("")),
        options: &LoadOptions::DEFAULT,
        buffer_bytes: 0,
    };
    match reader.resolve(uri, what)? {
        Resolved::File { file, real } => Ok(Some((file, real))),
        Resolved::Data(..) => Ok(None),
    }
}

/// What a URI resolved to.
enum Resolved {
    /// Decoded `data:` bytes, with the MIME type the URI declared.
    Data(Vec<u8>, String),
    /// A file inside the model's folder: its path as named, and its real path (links
    /// followed, checked to stay inside) when it exists.
    File {
        /// The model's folder joined with the URI's parts.
        file: PathBuf,
        /// The canonical path to read; `None` when it could not be resolved (missing).
        real: Option<PathBuf>,
    },
}

struct Reader<'a> {
    path: &'a Path,
    folder: &'a Path,
    options: &'a LoadOptions,
    /// The bytes of all buffers together: what the file can hold.
    buffer_bytes: u64,
}

/// A primitive being read, and its vertex count (POSITION's).
struct Vertices<'p, 'd> {
    primitive: &'p gltf::Primitive<'d>,
    count: usize,
}

/// Whether a vertex attribute's element is finite (no NaN, no infinity).
trait Finite {
    fn finite(&self) -> bool;
}

impl Finite for Vec2 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl Finite for Vec3 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl Finite for Vec4 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl Reader<'_> {
    fn bad_uri(&self, what: &str, uri: &str, kind: BadUri) -> IoError {
        IoError::BadUri {
            path: self.path.to_path_buf(),
            what: what.to_owned(),
            uri: uri.to_owned(),
            kind,
        }
    }

    /// Resolves a URI: `data:` URIs are decoded (base64 or percent-encoded), relative paths
    /// are percent-decoded and
    /// joined to the model's folder; anything that would leave the folder is refused.
    fn resolve(&self, uri: &str, what: &str) -> Result<Resolved, IoError> {
        if let Some(data) = uri.strip_prefix("data:") {
            let Some((header, payload)) = data.split_once(',') else {
                return Err(self.bad_uri(what, uri, BadUri::DataWithoutComma));
            };
            // RFC 2397: base64, or the bytes themselves, percent-encoded where needed.
            let (mime, bytes) = match header.strip_suffix(";base64") {
                Some(mime) => (
                    mime,
                    base64::decode(payload)
                        .map_err(|_| self.bad_uri(what, uri, BadUri::MalformedBase64))?,
                ),
                None => (header, percent_encoding::percent_decode_str(payload).collect()),
            };
            return Ok(Resolved::Data(bytes, mime.to_owned()));
        }
        if uri.contains("://") || uri.split_once(':').is_some_and(|(s, _)| s.len() > 1) {
            return Err(self.bad_uri(what, uri, BadUri::NotRelative));
        }
        let decoded = percent_encoding::percent_decode_str(uri).decode_utf8_lossy();
        if decoded.starts_with('/') || decoded.starts_with('\\') || decoded.contains(':') {
            return Err(self.bad_uri(what, uri, BadUri::Absolute));
        }
        let mut parts: Vec<&str> = Vec::new();
        for part in decoded.split(['/', '\\']) {
            match part {
                "" | "." => {}
                ".." => {
                    if parts.pop().is_none() {
                        return Err(self.bad_uri(what, uri, BadUri::LeavesFolder));
                    }
                }
                part => parts.push(part),
            }
        }
        if parts.is_empty() {
            return Err(self.bad_uri(what, uri, BadUri::NoFile));
        }
        let file = parts.iter().fold(self.folder.to_path_buf(), |p, part| p.join(part));
        // Inside by name; a symbolic link on the way must not lead out either.
        let real = match crate::paths::real_inside(self.folder, &file) {
            Ok(real) => Some(real),
            // Missing or unreadable: the read names the problem.
            Err(crate::paths::NotInside::Io(_)) => None,
            Err(crate::paths::NotInside::Outside(target)) => {
                return Err(IoError::LinkEscapes {
                    path: self.path.to_path_buf(),
                    what: what.to_owned(),
                    reference: uri.to_owned(),
                    target,
                });
            }
        };
        Ok(Resolved::File { file, real })
    }

    fn buffers(
        &self,
        document: &gltf::Document,
        json: &serde_json::Value,
        mut blob: Option<Vec<u8>>,
    ) -> Result<Vec<Vec<u8>>, IoError> {
        let mut buffers = Vec::with_capacity(document.buffers().len());
        for buffer in document.buffers() {
            let what = format!("buffer {}", buffer.index());
            // Filled by `gltf_decode::decode_meshopt`.
            let limit = self.options.max_file_bytes;
            if let Some(length) =
                crate::gltf_decode::fallback_length(json, buffer.index(), limit, self.path)?
            {
                buffers.push(vec![0; length]);
                continue;
            }
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => match blob.take() {
                    Some(blob) => blob,
                    // No uri and not the BIN chunk: no data (see `gltf_spec`).
                    None => {
                        buffers.push(Vec::new());
                        continue;
                    }
                },
                gltf::buffer::Source::Uri(uri) => match self.resolve(uri, &what)? {
                    Resolved::Data(bytes, _) => bytes,
                    Resolved::File { file, real } => {
                        match crate::read_bytes(real.as_deref().unwrap_or(&file), self.options) {
                            Err(IoError::Io { source, .. })
                                if source.kind() == std::io::ErrorKind::NotFound =>
                            {
                                return Err(IoError::MissingFile {
                                    path: self.path.to_path_buf(),
                                    what,
                                    missing: file,
                                    line: None,
                                });
                            }
                            other => other?,
                        }
                    }
                },
            };
            if (data.len() as u64) < buffer.length() as u64 {
                return Err(IoError::BufferLength {
                    path: self.path.to_path_buf(),
                    buffer: buffer.index(),
                    expected: buffer.length() as u64,
                    actual: data.len() as u64,
                });
            }
            buffers.push(data);
        }
        Ok(buffers)
    }

    /// Every buffer view must lie inside its buffer (but those of buffers `without_data`,
    /// which no primitive reads).
    fn check_views(
        &self,
        document: &gltf::Document,
        buffers: &[Vec<u8>],
        without_data: &[usize],
    ) -> Result<(), IoError> {
        for view in document.views().filter(|v| !without_data.contains(&v.buffer().index())) {
            let end = (view.offset() as u64).saturating_add(view.length() as u64);
            let available = buffers.get(view.buffer().index()).map_or(0, Vec::len) as u64;
            if end > available {
                return Err(IoError::Gltf {
                    path: self.path.to_path_buf(),
                    place: format!("bufferViews[{}]", view.index()),
                    kind: GltfKind::ViewOutsideBuffer {
                        end,
                        buffer: view.buffer().index(),
                        available,
                    },
                });
            }
        }
        Ok(())
    }

    /// Checks an accessor's type and that every element lies inside its buffer view.
    fn check_accessor(
        &self,
        accessor: &gltf::Accessor<'_>,
        dimensions: Dimensions,
        types: &[DataType],
        attribute: &str,
    ) -> Result<(), IoError> {
        let check = AccessorCheck { reader: self, accessor, attribute };
        // Type, count at least 1 and within the limits.
        check.layout(dimensions, types)?;
        // The elements inside their buffer view (or the zeros within what the file can hold).
        let count = accessor.count() as u64;
        let element = accessor.size() as u64;
        match accessor.view() {
            Some(view) => check.extent(view, accessor.offset() as u64, count, element)?,
            None => check.zeros(count, element)?,
        }
        // The sparse indices and values inside theirs.
        if let Some(sparse) = accessor.sparse() {
            check.sparse(&sparse, count, element)?;
        }
        Ok(())
    }

    /// A vertex attribute's checks: [`Self::check_accessor`] for its `(dimensions, types)`,
    /// its sparse indices, and as many elements as POSITION's `vertex_count`.
    fn check_attribute(
        &self,
        accessor: &gltf::Accessor<'_>,
        (dimensions, types): (Dimensions, &[DataType]),
        name: &str,
        buffers: &[Vec<u8>],
        vertex_count: usize,
    ) -> Result<(), IoError> {
        self.check_accessor(accessor, dimensions, types, name)?;
        self.check_sparse_indices(accessor, buffers)?;
        if accessor.count() != vertex_count {
            return Err(IoError::BadAccessor {
                path: self.path.to_path_buf(),
                accessor: accessor.index(),
                kind: BadAccessor::CountMismatch {
                    attribute: name.to_owned(),
                    count: accessor.count(),
                    vertex_count,
                },
            });
        }
        Ok(())
    }

    /// A sparse accessor's indices must be below its count and strictly increasing (glTF 2.0
    /// spec, "Sparse Accessors"): gltf's reader skips the others silently, loading wrong
    /// values. The caller has checked with [`Self::check_accessor`] that they lie inside
    /// their view.
    fn check_sparse_indices(
        &self,
        accessor: &gltf::Accessor<'_>,
        buffers: &[Vec<u8>],
    ) -> Result<(), IoError> {
        let Some(sparse) = accessor.sparse() else { return Ok(()) };
        let bad = |kind: BadAccessor| IoError::BadAccessor {
            path: self.path.to_path_buf(),
            accessor: accessor.index(),
            kind,
        };
        let indices = sparse.indices();
        let view = indices.view();
        let size = indices.index_type().size();
        let stride = view.stride().unwrap_or(size);
        let bytes = buffers.get(view.buffer().index()).map_or(&[][..], Vec::as_slice);
        let mut previous: Option<u32> = None;
        for k in 0..sparse.count() {
            let at = view.offset() + indices.offset() + k * stride;
            let index = match bytes.get(at..at + size) {
                Some(&[a]) => u32::from(a),
                Some(&[a, b]) => u32::from(u16::from_le_bytes([a, b])),
                Some(&[a, b, c, d]) => u32::from_le_bytes([a, b, c, d]),
                _ => return Err(bad(BadAccessor::SparseIndexOutside { element: k })),
            };
            if index as usize >= accessor.count() {
                return Err(bad(BadAccessor::SparseIndexOutOfRange {
                    index,
                    element: k,
                    count: accessor.count(),
                }));
            }
            if let Some(before) = previous.filter(|&before| index <= before) {
                return Err(bad(BadAccessor::SparseNotIncreasing { element: k, index, before }));
            }
            previous = Some(index);
        }
        Ok(())
    }

    /// Decodes one triangle primitive into an object (name and transform set by the caller).
    fn primitive(
        &self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        buffers: &[Vec<u8>],
        warnings: &mut Vec<String>,
    ) -> Result<Option<Object>, IoError> {
        let Some(position) = primitive.get(&gltf::Semantic::Positions) else {
            warnings.push(format!(
                "{}: mesh {} primitive {} has no POSITION; skipped",
                self.path.display(),
                mesh.index(),
                primitive.index()
            ));
            return Ok(None);
        };
        self.check_primitive(primitive, &position, buffers)?;
        let vertices = Vertices { primitive, count: position.count() };
        // Floats, or KHR_mesh_quantization's integers; an accessor without a view or sparse
        // data is zeros (the readers give nothing).
        let positions = self
            .vertex_attribute(&vertices, gltf::Semantic::Positions, "POSITION", |a| {
                read_floats::<3>(a, buffers).map(|v| v.into_iter().map(Vec3::from_array).collect())
            })?
            .unwrap_or_default();
        if positions.len() != vertices.count {
            return Err(self.short(&position, positions.len()));
        }
        let normals = self.vertex_attribute(&vertices, gltf::Semantic::Normals, "NORMAL", |a| {
            read_directions::<3>(a, buffers).map(|v| v.into_iter().map(Vec3::from_array).collect())
        })?;
        let tangents =
            self.vertex_attribute(&vertices, gltf::Semantic::Tangents, "TANGENT", |a| {
                read_directions::<4>(a, buffers)
                    .map(|v| v.into_iter().map(Vec4::from_array).collect())
            })?;
        let uvs =
            self.vertex_attribute(&vertices, gltf::Semantic::TexCoords(0), "TEXCOORD_0", |a| {
                read_floats::<2>(a, buffers).map(|v| v.into_iter().map(Vec2::from_array).collect())
            })?;
        let uvs1 =
            self.vertex_attribute(&vertices, gltf::Semantic::TexCoords(1), "TEXCOORD_1", |a| {
                read_floats::<2>(a, buffers).map(|v| v.into_iter().map(Vec2::from_array).collect())
            })?;
        let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
        let colors =
            self.vertex_attribute(&vertices, gltf::Semantic::Colors(0), "COLOR_0", |_| {
                reader.read_colors(0).map(|it| it.into_rgba_f32().map(Vec4::from_array).collect())
            })?;
        let triangles = self.triangles(mesh, primitive, buffers, vertices.count)?;
        let (skin, morph_targets) = self.deformation(primitive, buffers, vertices.count)?;
        Ok(Some(Object {
            name: String::new(),
            positions,
            uvs,
            uvs1,
            normals,
            tangents,
            colors,
            triangles,
            transform: None,
            material: primitive.material().index(),
            smoothing_groups: None,
            split_from: Vec::new(),
            skin,
            morph_targets,
        }))
    }

    /// Checks a primitive's accessors before anything is read: POSITION, NORMAL, TANGENT,
    /// TEXCOORD_0, TEXCOORD_1 and COLOR_0 (types, extent, as many elements as POSITION) and the indices
    /// (a triangle list: a multiple of 3).
    fn check_primitive(
        &self,
        primitive: &gltf::Primitive<'_>,
        position: &gltf::Accessor<'_>,
        buffers: &[Vec<u8>],
    ) -> Result<(), IoError> {
        let vertex_count = position.count();
        // KHR_mesh_quantization: integers, normalised or not, besides floats.
        let quantized = [DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16];
        let signed = [DataType::F32, DataType::I8, DataType::I16];
        self.check_accessor(position, Dimensions::Vec3, &quantized, "POSITION")?;
        self.check_sparse_indices(position, buffers)?;
        // COLOR_0 is RGB or RGBA, of floats or normalised integers.
        let color_dimensions =
            primitive.get(&gltf::Semantic::Colors(0)).map_or(Dimensions::Vec4, |a| {
                match a.dimensions() {
                    Dimensions::Vec3 => Dimensions::Vec3,
                    _ => Dimensions::Vec4,
                }
            });
        let colors = [DataType::F32, DataType::U8, DataType::U16];
        let attributes = [
            (gltf::Semantic::Normals, Dimensions::Vec3, &signed[..], "NORMAL"),
            (gltf::Semantic::Tangents, Dimensions::Vec4, &signed[..], "TANGENT"),
            (gltf::Semantic::TexCoords(0), Dimensions::Vec2, &quantized[..], "TEXCOORD_0"),
            (gltf::Semantic::TexCoords(1), Dimensions::Vec2, &quantized[..], "TEXCOORD_1"),
            (gltf::Semantic::Colors(0), color_dimensions, &colors[..], "COLOR_0"),
        ];
        for (semantic, dimensions, types, name) in attributes {
            if let Some(accessor) = primitive.get(&semantic) {
                self.check_attribute(&accessor, (dimensions, types), name, buffers, vertex_count)?;
            }
        }
        let bad = |accessor: &gltf::Accessor<'_>, kind: BadAccessor| IoError::BadAccessor {
            path: self.path.to_path_buf(),
            accessor: accessor.index(),
            kind,
        };
        let Some(accessor) = primitive.indices() else {
            if !vertex_count.is_multiple_of(3) {
                return Err(bad(
                    position,
                    BadAccessor::NotTriangles { what: "vertices", count: vertex_count },
                ));
            }
            return Ok(());
        };
        let types = [DataType::U8, DataType::U16, DataType::U32];
        self.check_accessor(&accessor, Dimensions::Scalar, &types, "indices")?;
        self.check_sparse_indices(&accessor, buffers)?;
        if !accessor.count().is_multiple_of(3) {
            return Err(bad(
                &accessor,
                BadAccessor::NotTriangles { what: "indices", count: accessor.count() },
            ));
        }
        Ok(())
    }

    /// The error for an accessor that gave fewer elements than its count.
    fn short(&self, accessor: &gltf::Accessor<'_>, got: usize) -> IoError {
        IoError::BadAccessor {
            path: self.path.to_path_buf(),
            accessor: accessor.index(),
            kind: BadAccessor::ShortRead { expected: accessor.count(), read: got },
        }
    }

    /// A primitive's attribute `semantic`, read by `read` (zeros when its accessor has
    /// neither a view nor sparse data), checked to hold one finite element per vertex;
    /// `None` when the primitive has no such attribute or `read` gives nothing.
    fn vertex_attribute<T: Clone + Default + Finite>(
        &self,
        vertices: &Vertices<'_, '_>,
        semantic: gltf::Semantic,
        attribute: &'static str,
        read: impl FnOnce(&gltf::Accessor<'_>) -> Option<Vec<T>>,
    ) -> Result<Option<Vec<T>>, IoError> {
        let Some(accessor) = vertices.primitive.get(&semantic) else { return Ok(None) };
        let values = crate::gltf_spec::zeros_without_view(Some(&accessor), read(&accessor));
        let Some(values) = values else { return Ok(None) };
        if values.len() != vertices.count {
            return Err(self.short(&accessor, values.len()));
        }
        if let Some(element) = values.iter().position(|v| !v.finite()) {
            return Err(IoError::AccessorNotFinite {
                path: self.path.to_path_buf(),
                accessor: accessor.index(),
                attribute,
                element,
            });
        }
        Ok(Some(values))
    }

    /// A primitive's triangles: its indices, checked against the vertex count, or `0, 1,
    /// 2, ...` for a non-indexed list.
    fn triangles(
        &self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        buffers: &[Vec<u8>],
        vertex_count: usize,
    ) -> Result<Vec<[u32; 3]>, IoError> {
        let reader = primitive.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
        let index_accessor = primitive.indices();
        let indices = crate::gltf_spec::zeros_without_view(
            index_accessor.as_ref(),
            reader.read_indices().map(|read| read.into_u32().collect::<Vec<u32>>()),
        );
        let (Some(accessor), Some(read)) = (index_accessor, indices) else {
            let Ok(count) = u32::try_from(vertex_count) else {
                return Err(IoError::TooManyElements {
                    path: self.path.to_path_buf(),
                    what: format!("mesh {} primitive {}", mesh.index(), primitive.index()),
                    limit: u32::MAX as usize,
                    actual: vertex_count,
                });
            };
            return Ok((0..count / 3).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect());
        };
        let mut read = read.into_iter();
        let mut triangles = Vec::with_capacity(accessor.count() / 3);
        while let (Some(a), Some(b), Some(c)) = (read.next(), read.next(), read.next()) {
            triangles.push([a, b, c]);
        }
        if triangles.len() * 3 != accessor.count() {
            return Err(self.short(&accessor, triangles.len() * 3));
        }
        if let Some(&index) = triangles.as_flattened().iter().find(|&&i| i as usize >= vertex_count)
        {
            return Err(IoError::IndexOutOfRange {
                path: self.path.to_path_buf(),
                mesh: mesh.index(),
                primitive: primitive.index(),
                accessor: accessor.index(),
                index,
                vertex_count,
            });
        }
        Ok(triangles)
    }

    /// The images, as textures; `data:` and buffer-view images are embedded bytes, files are
    /// resolved (and refused if they leave the model's folder). Nothing is decoded here.
    fn images(
        &self,
        document: &gltf::Document,
        buffers: &[Vec<u8>],
    ) -> Result<Vec<Texture>, IoError> {
        document
            .images()
            .map(|image| {
                let what = format!("image {}", image.index());
                let fallback = || image.name().map_or_else(|| what.clone(), str::to_owned);
                let (name, source) = match image.source() {
                    gltf::image::Source::View { view, mime_type } => {
                        let start = view.offset();
                        let bytes = buffers
                            .get(view.buffer().index())
                            .and_then(|b| b.get(start..start + view.length()))
                            .unwrap_or_default();
                        let source = TextureSource::Embedded {
                            mime_type: mime_type.to_owned(),
                            bytes: Arc::from(bytes),
                        };
                        (fallback(), source)
                    }
                    gltf::image::Source::Uri { uri, mime_type } => {
                        match self.resolve(uri, &what)? {
                            Resolved::Data(bytes, declared) => {
                                let mime_type = mime_type.map_or(declared, str::to_owned);
                                (
                                    fallback(),
                                    TextureSource::Embedded { mime_type, bytes: bytes.into() },
                                )
                            }
                            Resolved::File { file, .. } => {
                                let name = image.name().map(str::to_owned).unwrap_or_else(|| {
                                    file.file_name().map_or_else(
                                        || uri.to_owned(),
                                        |n| n.to_string_lossy().into_owned(),
                                    )
                                });
                                (name, TextureSource::File(file))
                            }
                        }
                    }
                };
                Ok(Texture { name, source, image: None })
            })
            .collect()
    }
}

/// A texture reference: glTF texture -> its image (the index into [`Asset::textures`]);
/// `None` for a texture whose image only an extension names (no `source`: KTX2 through
/// KHR_texture_basisu, WebP), which seamlit does not decode. The coordinate set is the texture
/// info's `texCoord` unless its KHR_texture_transform gives its own, which then overrides it
/// (the extension's specification).
fn texture_ref(
    texture: &gltf::Texture<'_>,
    tex_coord: u32,
    transform: Option<(UvTransform, Option<u32>)>,
) -> Option<TextureRef> {
    let tex_coord = transform.and_then(|(_, own)| own).unwrap_or(tex_coord);
    let transform = transform.map(|(t, _)| t);
    Some(TextureRef { texture: texture.source()?.index(), tex_coord, transform })
}

/// KHR_texture_transform as the gltf crate types it, with its `texCoord` override.
fn uv_transform(t: &gltf::texture::TextureTransform<'_>) -> (UvTransform, Option<u32>) {
    (UvTransform { offset: t.offset(), rotation: t.rotation(), scale: t.scale() }, t.tex_coord())
}

/// A JSON number as the `f32` that glTF's float properties are: rounded to nearest (a
/// magnitude past f32's range becomes infinite); `None` for anything else.
#[expect(clippy::cast_possible_truncation, reason = "glTF's floats are f32: rounding is the point")]
fn json_f32(value: &serde_json::Value) -> Option<f32> {
    value.as_f64().map(|x| x as f32)
}

/// KHR_texture_transform from raw extension JSON (the gltf crate does not type it on
/// normal and occlusion textures), with its `texCoord` override.
fn uv_transform_json(value: &serde_json::Value) -> (UvTransform, Option<u32>) {
    let pair = |key: &str, default: [f32; 2]| -> [f32; 2] {
        value
            .get(key)
            .and_then(|v| v.as_array())
            .and_then(|a| Some([json_f32(a.first()?)?, json_f32(a.get(1)?)?]))
            .unwrap_or(default)
    };
    let transform = UvTransform {
        offset: pair("offset", [0.0, 0.0]),
        rotation: value.get("rotation").and_then(json_f32).unwrap_or(0.0),
        scale: pair("scale", [1.0, 1.0]),
    };
    let tex_coord = value
        .get("texCoord")
        .and_then(serde_json::Value::as_u64)
        .and_then(|set| u32::try_from(set).ok());
    (transform, tex_coord)
}

fn material(m: &gltf::Material<'_>) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let base_color_texture = pbr.base_color_texture().and_then(|info| {
        let transform = info.texture_transform().map(|t| uv_transform(&t));
        texture_ref(&info.texture(), info.tex_coord(), transform)
    });
    let normal = m.normal_texture();
    let normal_texture = normal.as_ref().and_then(|n| {
        let transform = n.extension_value("KHR_texture_transform").map(uv_transform_json);
        texture_ref(&n.texture(), n.tex_coord(), transform)
    });
    let base = pbr.base_color_factor();
    let metallic = pbr.metallic_factor();
    let roughness = pbr.roughness_factor();
    // Specular colour: 4 % for dielectrics, the base colour for metals (the usual
    // metallic-roughness to specular-glossiness conversion).
    let specular = std::array::from_fn(|i| 0.04 + (base[i] - 0.04) * metallic);
    Material {
        name: m.name().map_or_else(|| format!("material{}", m.index().unwrap_or(0)), str::to_owned),
        base_color: base,
        base_color_texture,
        normal_texture,
        normal_scale: normal.as_ref().map_or(1.0, gltf::material::NormalTexture::scale),
        normal_green_down: false,
        specular,
        shininess: crate::roughness_to_shininess(roughness),
        metallic,
        roughness,
        double_sided: m.double_sided(),
        metallic_roughness_texture: pbr.metallic_roughness_texture().and_then(|i| info_ref(&i)),
        occlusion_texture: m.occlusion_texture().and_then(|o| {
            let transform = o.extension_value("KHR_texture_transform").map(uv_transform_json);
            texture_ref(&o.texture(), o.tex_coord(), transform)
        }),
        occlusion_strength: m.occlusion_texture().map_or(1.0, |o| o.strength()),
        emissive: m.emissive_factor().map(|c| c * emissive_strength(m)),
        emissive_texture: m.emissive_texture().and_then(|i| info_ref(&i)),
        alpha_mode: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => crate::AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => {
                crate::AlphaMode::Mask { cutoff: m.alpha_cutoff().unwrap_or(0.5) }
            }
            gltf::material::AlphaMode::Blend => crate::AlphaMode::Blend,
        },
        unlit: m.extension_value("KHR_materials_unlit").is_some(),
    }
}

/// A texture slot's reference with its KHR_texture_transform.
fn info_ref(info: &gltf::texture::Info<'_>) -> Option<TextureRef> {
    let transform = info.texture_transform().map(|t| uv_transform(&t));
    texture_ref(&info.texture(), info.tex_coord(), transform)
}

/// KHR_materials_emissive_strength's `emissiveStrength`, 1 without it. Read from the raw
/// extension JSON, as the texture transforms of normal maps are, so that gltf-json's typed
/// extension features (which would re-serialise the pass-through's JSON) stay off.
fn emissive_strength(m: &gltf::Material<'_>) -> f32 {
    m.extension_value("KHR_materials_emissive_strength")
        .and_then(|e| e.get("emissiveStrength"))
        .and_then(json_f32)
        .unwrap_or(1.0)
}

/// KHR_lights_punctual: the lights that the nodes of `scene` carry, placed by the nodes'
/// global transforms (a light shines down its node's -Z). Read from the raw extension JSON,
/// as `emissive_strength` is. A node naming a light that does not exist, or a light of an
/// unknown type, is left out with a warning.
fn punctual_lights(
    document: &gltf::Document,
    scene: Option<&gltf::Scene<'_>>,
    warnings: &mut Vec<String>,
) -> Vec<crate::PunctualLight> {
    let defs = document
        .extension_value("KHR_lights_punctual")
        .and_then(|e| e.get("lights"))
        .and_then(serde_json::Value::as_array);
    let mut out = Vec::new();
    let mut stack: Vec<(gltf::Node<'_>, Mat4)> =
        scene.map(|s| s.nodes().map(|n| (n, Mat4::IDENTITY)).collect()).unwrap_or_default();
    while let Some((node, parent)) = stack.pop() {
        let global = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let index = node
            .extension_value("KHR_lights_punctual")
            .and_then(|e| e.get("light"))
            .and_then(serde_json::Value::as_u64);
        if let Some(index) = index {
            let def = defs.and_then(|d| d.get(usize::try_from(index).ok()?));
            match def.map(|d| punctual_light(d, global)) {
                Some(Ok(light)) => out.push(light),
                Some(Err(kind)) => warnings.push(format!(
                    "nodes[{}]: KHR_lights_punctual light {index} has the unknown type {kind:?}; left out",
                    node.index()
                )),
                None => warnings.push(format!(
                    "nodes[{}]: KHR_lights_punctual light {index} does not exist; left out",
                    node.index()
                )),
            }
        }
        stack.extend(node.children().map(|c| (c, global)));
    }
    out
}

/// One KHR_lights_punctual light definition at `global`, with the extension's defaults
/// (white, intensity 1, unlimited range, spot cones 0 and pi/4); `Err` with the type when it
/// is not directional, point or spot.
fn punctual_light(def: &serde_json::Value, global: Mat4) -> Result<crate::PunctualLight, String> {
    let number = |v: &serde_json::Value, key: &str| v.get(key).and_then(json_f32);
    let spot = def.get("spot").unwrap_or(&serde_json::Value::Null);
    let kind = match def.get("type").and_then(serde_json::Value::as_str).unwrap_or_default() {
        "directional" => crate::PunctualKind::Directional,
        "point" => crate::PunctualKind::Point,
        "spot" => crate::PunctualKind::Spot {
            inner_cone_angle: number(spot, "innerConeAngle").unwrap_or(0.0),
            outer_cone_angle: number(spot, "outerConeAngle").unwrap_or(std::f32::consts::FRAC_PI_4),
        },
        other => return Err(other.to_owned()),
    };
    let color = def
        .get("color")
        .and_then(serde_json::Value::as_array)
        .and_then(|c| Some([json_f32(c.first()?)?, json_f32(c.get(1)?)?, json_f32(c.get(2)?)?]))
        .unwrap_or([1.0; 3]);
    Ok(crate::PunctualLight {
        name: def.get("name").and_then(serde_json::Value::as_str).unwrap_or_default().to_owned(),
        kind,
        color,
        intensity: number(def, "intensity").unwrap_or(1.0),
        position: global.transform_point3(Vec3::ZERO),
        direction: global.transform_vector3(Vec3::NEG_Z).try_normalize().unwrap_or(Vec3::NEG_Z),
        range: number(def, "range").filter(|r| *r > 0.0),
    })
}

/// One accessor being checked by [`Reader::check_accessor`], with what its errors name.
struct AccessorCheck<'a, 'r, 'd> {
    reader: &'a Reader<'r>,
    accessor: &'a gltf::Accessor<'d>,
    attribute: &'a str,
}

impl AccessorCheck<'_, '_, '_> {
    fn bad(&self, kind: BadAccessor) -> IoError {
        IoError::BadAccessor {
            path: self.reader.path.to_path_buf(),
            accessor: self.accessor.index(),
            kind,
        }
    }

    /// The accessor's type is one of `(dimensions, types)`; its count is at least 1 and
    /// within [`crate::LoadOptions::max_elements`].
    fn layout(&self, dimensions: Dimensions, types: &[DataType]) -> Result<(), IoError> {
        let (accessor, attribute) = (self.accessor, self.attribute);
        if accessor.dimensions() != dimensions || !types.contains(&accessor.data_type()) {
            return Err(self.bad(BadAccessor::WrongType {
                attribute: attribute.to_owned(),
                expected: format!("{dimensions:?} of {types:?}"),
                found: format!("{:?} of {:?}", accessor.dimensions(), accessor.data_type()),
            }));
        }
        let count = accessor.count() as u64;
        // glTF requires count >= 1; gltf 1.4.1's reader computes `count - 1` unchecked (found
        // by the `gltf` fuzz target: regression input `gltf_index_accessor_count_0.gltf`).
        if count == 0 {
            return Err(self.bad(BadAccessor::ZeroCount { attribute: attribute.to_owned() }));
        }
        if count > self.reader.options.max_elements as u64 {
            return Err(IoError::TooManyElements {
                path: self.reader.path.to_path_buf(),
                what: format!("accessor {} ({attribute})", accessor.index()),
                limit: self.reader.options.max_elements,
                actual: accessor.count(),
            });
        }
        Ok(())
    }

    /// `count` elements of `element` bytes from `offset` lie inside `view`.
    fn extent(
        &self,
        view: gltf::buffer::View<'_>,
        offset: u64,
        count: u64,
        element: u64,
    ) -> Result<(), IoError> {
        let stride = view.stride().map_or(element, |s| s as u64);
        // Saturating: offsets and strides come from the file and may be near u64::MAX.
        let needed = if count == 0 {
            0
        } else {
            offset.saturating_add(stride.saturating_mul(count - 1)).saturating_add(element)
        };
        if needed > view.length() as u64 {
            return Err(IoError::AccessorOutOfRange {
                path: self.reader.path.to_path_buf(),
                accessor: self.accessor.index(),
                view: view.index(),
                needed,
                available: view.length() as u64,
            });
        }
        Ok(())
    }

    /// An accessor without a view is zeros (plus its sparse values): its count costs memory
    /// that the file does not hold, so it may not exceed the file's bytes.
    fn zeros(&self, count: u64, element: u64) -> Result<(), IoError> {
        if count.saturating_mul(element) > self.reader.buffer_bytes.max(ZEROS_FLOOR) {
            return Err(self.bad(BadAccessor::ZerosTooLarge {
                attribute: self.attribute.to_owned(),
                count,
                element,
                buffer_bytes: self.reader.buffer_bytes,
            }));
        }
        Ok(())
    }

    /// The sparse count is 1 to `count`, and its indices and values lie inside their views.
    fn sparse(
        &self,
        sparse: &gltf::accessor::sparse::Sparse<'_>,
        count: u64,
        element: u64,
    ) -> Result<(), IoError> {
        let n = sparse.count() as u64;
        // glTF requires sparse.count >= 1; gltf 1.4.1's reader computes `count - 1`
        // unchecked (tests/sparse.rs).
        if n == 0 {
            return Err(
                self.bad(BadAccessor::ZeroSparseCount { attribute: self.attribute.to_owned() })
            );
        }
        if n > count {
            return Err(self.bad(BadAccessor::SparseCountExceeds { sparse: n, count }));
        }
        let indices = sparse.indices();
        self.extent(
            indices.view(),
            indices.offset() as u64,
            n,
            indices.index_type().size() as u64,
        )?;
        let values = sparse.values();
        self.extent(values.view(), values.offset() as u64, n, element)
    }
}
