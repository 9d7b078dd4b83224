//! The glTF pass-through writer: an asset loaded from glTF or GLB and saved as glTF or GLB is
//! written as its input document with only what seamlit owns changed.
//!
//! What changes (design: `docs/gltf-pass-through.md`):
//!
//! - each fixed primitive gets new NORMAL and TANGENT accessors and a new index accessor
//!   (the input's component type where the vertex count fits, else `UNSIGNED_INT`), and its
//!   morph targets the NORMAL and TANGENT deltas `fix` computed, where it computed them
//!   ([`seamlit_mesh::MorphTarget`]);
//! - where [`seamlit_mesh::fix`] split vertices, every other attribute of the primitive and
//!   of its morph targets gets a new accessor: the input values, each split vertex a copy of
//!   the vertex it came from ([`Object::source_vertex`]), bytes unchanged;
//! - a mesh used by several nodes whose instances got different results is cloned for the
//!   differing ones (the report says so);
//! - new data is appended to buffer 0 (the GLB `BIN` chunk, or `NAME.bin` beside a `.gltf`);
//!   for a GLB, images read from files are embedded; for a `.gltf`, the other files the
//!   document names are copied beside the output.
//! - meshopt-compressed views are written decoded, or, with
//!   [`crate::SaveOptions::keep_compression`], kept as they were while the new views are
//!   encoded ([`crate::gltf_encode`]).
//!
//! Everything else is the input JSON, kept as a [`serde_json::Value`]: unknown extensions,
//! extras, skins, animations, cameras, materials, node transforms as written. Accessors,
//! buffer views and buffers the output still uses keep their indices (skins, animations and
//! extensions point at them); the ones only the replaced data used give their places and
//! bytes to the new data ([`crate::gltf_prune`]), unless an extension seamlit does not know
//! could point at them.

use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use seamlit_mesh::{Model, Object};
use serde_json::{Map, Value, json};

use crate::IoError;
use crate::error::BadAccessor;
use crate::gltf_encode::{Keep, Layout};
use crate::gltf_prune::Kept;
use crate::gltf_write::{check_object, unit_normal, unit_tangent};

/// The glTF document an [`crate::Asset`] was loaded from: the JSON as written, the buffers'
/// bytes, and for each object of the model the node, mesh and primitive it came from.
///
/// Opaque and cheap to clone (shared). [`crate::save`] uses it to write the input back with
/// only normals, tangents, split vertices and indices changed.
#[derive(Clone)]
pub struct GltfSource(Arc<Source>);

struct Source {
    /// The document, as parsed from the file.
    json: Value,
    /// Each buffer's bytes (at least its `byteLength`).
    buffers: Vec<Vec<u8>>,
    /// The file it was read from: relative URIs are resolved against its folder.
    path: PathBuf,
    /// Per object of the loaded model: where it came from.
    instances: Vec<Instance>,
}

/// Where an object came from: a primitive of a mesh, instanced by a node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Instance {
    /// Index into `nodes`.
    pub node: usize,
    /// Index into `meshes`.
    pub mesh: usize,
    /// Index into the mesh's `primitives`.
    pub primitive: usize,
}

impl std::fmt::Debug for GltfSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GltfSource")
            .field("path", &self.0.path)
            .field("objects", &self.0.instances.len())
            .field("buffer_bytes", &self.0.buffers.iter().map(Vec::len).sum::<usize>())
            .finish_non_exhaustive()
    }
}

impl GltfSource {
    /// Keeps a loaded document for the pass-through writer.
    pub(crate) fn new(
        json: Value,
        buffers: Vec<Vec<u8>>,
        path: &Path,
        instances: Vec<Instance>,
    ) -> Self {
        Self(Arc::new(Source { json, buffers, path: path.to_path_buf(), instances }))
    }

    /// Whether `model` is still the model of this source: one object per primitive instance,
    /// each with the input's vertices first (plus split copies of them). Returns why not.
    pub(crate) fn lines_up(&self, model: &Model) -> Result<(), String> {
        let source = &*self.0;
        if model.objects.len() != source.instances.len() {
            return Err(format!(
                "the model has {} objects, its glTF source {} primitive instances",
                model.objects.len(),
                source.instances.len()
            ));
        }
        for (object, instance) in model.objects.iter().zip(&source.instances) {
            let expected = source
                .primitive(*instance)
                .and_then(|p| uint(&p["attributes"], "POSITION"))
                .and_then(|a| uint(&source.json["accessors"][a], "count"));
            let input = object.vertex_count().checked_sub(object.split_from.len());
            if input.is_none() || input != expected {
                return Err(format!(
                    "object {:?} has {} input vertices, mesh {} primitive {} has {}",
                    object.name,
                    input.map_or_else(|| "fewer than no".to_owned(), |n| n.to_string()),
                    instance.mesh,
                    instance.primitive,
                    expected.map_or_else(|| "none".to_owned(), |n| n.to_string())
                ));
            }
            let input = input.unwrap_or_default();
            if let Some(&v) = object.split_from.iter().find(|&&v| v as usize >= input) {
                return Err(format!(
                    "object {:?}: a split vertex copies vertex {v}, past the {input} input vertices",
                    object.name
                ));
            }
        }
        Ok(())
    }
}

impl Source {
    /// The JSON of a primitive.
    fn primitive(&self, instance: Instance) -> Option<&Value> {
        self.json["meshes"].get(instance.mesh)?["primitives"].get(instance.primitive)
    }
}

/// An index (a non-negative integer, also written as a float).
/// The array member `key` of the document `json` (a JSON object), made an empty array when
/// missing or not an array.
pub(crate) fn array_member<'j>(json: &'j mut Value, key: &str) -> &'j mut Vec<Value> {
    if !json[key].is_array() {
        json[key] = Value::Array(Vec::new());
    }
    json[key].as_array_mut().expect("made an array above")
}

pub(crate) fn index(value: &Value) -> Option<usize> {
    integer(value).and_then(|n| usize::try_from(n).ok())
}

/// A non-negative integer member of a JSON object.
pub(crate) fn uint(value: &Value, key: &str) -> Option<usize> {
    value.get(key).and_then(integer).and_then(|n| usize::try_from(n).ok())
}

/// A non-negative integer, also when written as a float (`3.0`, which glTF allows).
#[expect(clippy::cast_possible_truncation, reason = "a whole number in u64's range, checked")]
fn integer(value: &Value) -> Option<u64> {
    value.as_u64().or_else(|| {
        let x = value.as_f64()?;
        // x is a whole number in u64's range, checked first.
        (x.fract() == 0.0 && (0.0..1.8e19).contains(&x)).then_some(x as u64)
    })
}

/// `ARRAY_BUFFER` and `ELEMENT_ARRAY_BUFFER`, buffer view targets.
pub(crate) const ARRAY_BUFFER: u32 = 34962;
pub(crate) const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// Component types of indices.
const UNSIGNED_BYTE: u64 = 5121;
const UNSIGNED_SHORT: u64 = 5123;
const UNSIGNED_INT: u64 = 5125;

/// Writes `asset` (whose model [`GltfSource::lines_up`] with `source`) as `.glb` (`binary`)
/// or `.gltf`, keeping meshopt compression when `keep_compression` is set
/// ([`crate::gltf_encode`]); returns the warnings.
pub(crate) fn save(
    asset: &crate::Asset,
    source: &GltfSource,
    path: &Path,
    binary: bool,
    keep_compression: bool,
) -> Result<Vec<String>, IoError> {
    for object in &asset.model.objects {
        check_object(object, path)?;
    }
    let mut out = Output::new(&source.0, path, binary);
    if keep_compression {
        out.keep_compression()?;
    } else {
        out.uncompress_views();
    }
    for group in instance_groups(&asset.model, &source.0.instances) {
        out.mesh(&asset.model, &group)?;
    }
    // Decoded at load (`gltf_draco`): the accessors hold plain data.
    let note = crate::gltf_draco::strip(&mut out.json, &source.0.path);
    out.warnings.extend(note);
    out.prune();
    out.finish_compression();
    out.place_buffers_and_images()?;
    out.write()?;
    Ok(out.warnings)
}

/// The instances of one mesh that got the same results, written as one mesh: the mesh
/// itself for the first group of a mesh, a clone for the others.
struct Group {
    mesh: usize,
    /// Whether this group writes into a clone of the mesh (not the first group).
    clone: bool,
    /// The nodes of the group.
    nodes: Vec<usize>,
    /// The representative instance's objects, by primitive index.
    objects: Vec<(usize, usize)>,
}

/// One node's use of a mesh: the node, and the object of each primitive (primitive, object).
type Use = (usize, Vec<(usize, usize)>);

/// Groups the objects by mesh instance (node), then the instances of each mesh by equal
/// results: same triangles, splits, normal and tangent bits.
fn instance_groups(model: &Model, instances: &[Instance]) -> Vec<Group> {
    // mesh -> its uses, in object order.
    let mut by_mesh: BTreeMap<usize, Vec<Use>> = BTreeMap::new();
    for (object, instance) in instances.iter().enumerate() {
        let uses = by_mesh.entry(instance.mesh).or_default();
        match uses.last_mut() {
            Some((node, objects)) if *node == instance.node => {
                objects.push((instance.primitive, object));
            }
            _ => uses.push((instance.node, vec![(instance.primitive, object)])),
        }
    }
    let same = |a: &[(usize, usize)], b: &[(usize, usize)]| {
        a.len() == b.len()
            && a.iter().zip(b).all(|(&(p, x), &(q, y))| {
                p == q && same_result(&model.objects[x], &model.objects[y])
            })
    };
    let mut groups = Vec::new();
    for (mesh, uses) in by_mesh {
        let first = groups.len();
        for (node, objects) in uses {
            match groups[first..].iter_mut().find(|g: &&mut Group| same(&g.objects, &objects)) {
                Some(group) => group.nodes.push(node),
                None => groups.push(Group {
                    mesh,
                    clone: groups.len() > first,
                    nodes: vec![node],
                    objects,
                }),
            }
        }
    }
    groups
}

/// How far apart (per component) two instances' normals or tangents may be and still count
/// as the same result: the rounding of the round trip through an instance's transform
/// (model space and back) is a few units in the last place; a real difference (a
/// neighbour's smoothing, a mirror) is orders of magnitude larger.
const SAME_FRAME: f32 = 1e-5;

/// Whether two objects (instances of one primitive) got the same result: the same triangles
/// and split copies, normals and tangents equal up to [`SAME_FRAME`], the same handedness.
fn same_result(a: &Object, b: &Object) -> bool {
    fn close<const N: usize>(a: &[[f32; N]], b: &[[f32; N]], exact: usize) -> bool {
        a.len() == b.len()
            && a.iter().zip(b).all(|(x, y)| {
                (0..N).all(
                    |i| {
                        if i < exact { (x[i] - y[i]).abs() <= SAME_FRAME } else { x[i] == y[i] }
                    },
                )
            })
    }
    let normals =
        |o: &Object| o.normals.as_ref().map(|n| n.iter().map(|v| v.to_array()).collect::<Vec<_>>());
    let tangents = |o: &Object| {
        o.tangents.as_ref().map(|t| t.iter().map(|v| v.to_array()).collect::<Vec<_>>())
    };
    a.triangles == b.triangles
        && a.split_from == b.split_from
        && match (normals(a), normals(b)) {
            (Some(x), Some(y)) => close(&x, &y, 3),
            (x, y) => x.is_none() && y.is_none(),
        }
        && match (tangents(a), tangents(b)) {
            // xyz within SAME_FRAME, w (the handedness) equal.
            (Some(x), Some(y)) => close(&x, &y, 3),
            (x, y) => x.is_none() && y.is_none(),
        }
        && same_morph_deltas(a, b)
}

/// Whether two instances got the same computed morph normal and tangent deltas, up to
/// [`SAME_FRAME`].
fn same_morph_deltas(a: &Object, b: &Object) -> bool {
    let close = |x: &Option<Vec<glam::Vec3>>, y: &Option<Vec<glam::Vec3>>| match (x, y) {
        (Some(x), Some(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(p, q)| p.abs_diff_eq(*q, SAME_FRAME))
        }
        (x, y) => x.is_none() && y.is_none(),
    };
    a.morph_targets.len() == b.morph_targets.len()
        && a.morph_targets.iter().zip(&b.morph_targets).all(|(s, t)| {
            close(&s.normal_deltas, &t.normal_deltas) && close(&s.tangent_deltas, &t.tangent_deltas)
        })
}

/// The document being written and the bytes appended to buffer 0.
struct Output<'a> {
    source: &'a Source,
    /// The output document: the input's, changed in place.
    json: Value,
    /// Where appended data starts in buffer 0: its input length (or, once pruned, its kept
    /// bytes' length), padded to 4.
    base: usize,
    /// How buffer 0's input bytes were packed by pruning; `None`: kept as they were.
    kept: Option<Kept>,
    /// Appended data, each piece starting at a multiple of 4 bytes from `base`.
    pieces: Vec<Vec<u8>>,
    /// Bytes appended so far (pieces and their padding).
    appended: usize,
    /// Files to copy beside a `.gltf` output: (source, destination).
    copies: Vec<(PathBuf, PathBuf)>,
    path: &'a Path,
    binary: bool,
    warnings: Vec<String>,
    /// Set while a save keeps meshopt compression: new views are encoded.
    keep: Option<Keep>,
}

impl<'a> Output<'a> {
    fn new(source: &'a Source, path: &'a Path, binary: bool) -> Self {
        let host = source.json["buffers"].get(0).and_then(|b| uint(b, "byteLength")).unwrap_or(0);
        Self {
            source,
            json: source.json.clone(),
            base: host.next_multiple_of(4),
            kept: None,
            pieces: Vec::new(),
            appended: 0,
            copies: Vec::new(),
            path,
            binary,
            warnings: Vec::new(),
            keep: None,
        }
    }

    /// The array member `key` of the document, created when missing.
    fn array(&mut self, key: &str) -> &mut Vec<Value> {
        array_member(&mut self.json, key)
    }

    /// Appends `bytes` to buffer 0 at a multiple of 4; returns their offset in it.
    fn append(&mut self, bytes: Vec<u8>) -> usize {
        let offset = self.appended.next_multiple_of(4);
        self.appended = offset + bytes.len();
        self.pieces.push(bytes);
        self.base + offset
    }

    /// Buffer views the input stored compressed (EXT_ or KHR_meshopt_compression, decoded at load)
    /// become plain data appended to buffer 0, and the report says so
    /// (`gltf_decode::uncompress_views`).
    fn uncompress_views(&mut self) {
        let mut json = std::mem::take(&mut self.json);
        let source = self.source;
        let note = crate::gltf_decode::uncompress_views(
            &mut json,
            &source.buffers,
            &source.path,
            |bytes| self.append(bytes),
        );
        self.json = json;
        self.warnings.extend(note);
    }

    /// Keeps the input's meshopt compression ([`crate::gltf_encode`]): compressed views stay
    /// as written, and new views are encoded. The report says what was kept, or that the
    /// input had nothing to keep.
    ///
    /// # Errors
    ///
    /// [`IoError::CannotKeepCompression`] for a Draco-compressed input.
    fn keep_compression(&mut self) -> Result<(), IoError> {
        self.keep = Keep::start(&mut self.json, &self.source.path)?;
        if self.keep.is_none() {
            self.warnings.push(crate::gltf_encode::nothing_to_keep(&self.source.path));
        }
        Ok(())
    }

    /// Ends a save that keeps the compression (the gathered views written, the fallback
    /// buffer's length, the extension declared) and adds its report line.
    fn finish_compression(&mut self) {
        let Some(keep) = self.keep.take() else { return };
        let mut json = std::mem::take(&mut self.json);
        let note = keep.finish(&mut json, &self.source.path, |bytes| self.append(bytes));
        self.json = json;
        self.warnings.push(note);
    }

    /// Adds `accessor` (its JSON, less `bufferView`) over the new data `bytes`, laid out as
    /// `layout`; returns its index. The data gets a buffer view of its own in buffer 0, or,
    /// while the compression is kept, joins the new view of its layout
    /// ([`Keep::gather`]), at the offset the accessor then names.
    fn accessor_over(&mut self, bytes: Vec<u8>, layout: Layout, mut accessor: Value) -> usize {
        let mut keep = self.keep.take();
        let gathered =
            keep.as_mut().and_then(|k| k.gather(&bytes, layout, self.array("bufferViews")));
        self.keep = keep;
        let (view, offset) = gathered.unwrap_or_else(|| (self.view(bytes, layout), 0));
        accessor["bufferView"] = json!(view);
        if offset > 0 {
            accessor["byteOffset"] = json!(offset);
        }
        self.accessor(accessor)
    }

    /// Appends `bytes` to buffer 0 as a new buffer view laid out as `layout`; returns its
    /// index.
    fn view(&mut self, bytes: Vec<u8>, layout: Layout) -> usize {
        let view = self.plain_view(bytes, layout);
        let views = self.array("bufferViews");
        views.push(view);
        views.len() - 1
    }

    /// Appends `bytes` to buffer 0; returns their buffer view.
    fn plain_view(&mut self, bytes: Vec<u8>, layout: Layout) -> Value {
        let length = bytes.len();
        let offset = self.append(bytes);
        let mut view = json!({ "buffer": 0, "byteOffset": offset, "byteLength": length });
        match layout {
            Layout::Vertices { element, stride } => {
                if stride != element {
                    view["byteStride"] = json!(stride);
                }
                view["target"] = json!(ARRAY_BUFFER);
            }
            Layout::Triangles { .. } => view["target"] = json!(ELEMENT_ARRAY_BUFFER),
            Layout::Bytes => {}
        }
        view
    }

    /// Appends an accessor; returns its index.
    fn accessor(&mut self, accessor: Value) -> usize {
        let accessors = self.array("accessors");
        accessors.push(accessor);
        accessors.len() - 1
    }

    /// Drops what only the input's replaced data used ([`crate::gltf_prune`]) and packs
    /// buffer 0's remaining input bytes. Never while the compression is kept: packing would
    /// move compressed bytes that views name by offset (today no meshopt document is
    /// pruned anyway, its extension is not among `gltf_prune`'s known ones).
    fn prune(&mut self) {
        if self.keep.is_some() {
            return;
        }
        if let Some(kept) = crate::gltf_prune::prune(&self.source.json, &mut self.json, self.base) {
            self.base = kept.length;
            self.kept = Some(kept);
        }
    }

    /// Writes one group: its primitives into the mesh, or into a clone the group's nodes
    /// then point at.
    fn mesh(&mut self, model: &Model, group: &Group) -> Result<(), IoError> {
        let source = self.source;
        let mut mesh = source.json["meshes"][group.mesh].clone();
        for &(p, object) in &group.objects {
            let primitive = &source.json["meshes"][group.mesh]["primitives"][p];
            let written = self.primitive(primitive, &model.objects[object])?;
            mesh["primitives"][p] = written;
        }
        if !group.clone {
            self.json["meshes"][group.mesh] = mesh;
            return Ok(());
        }
        let meshes = self.array("meshes");
        meshes.push(mesh);
        let clone = meshes.len() - 1;
        for &node in &group.nodes {
            self.json["nodes"][node]["mesh"] = json!(clone);
        }
        self.warnings.push(format!(
            "{}: mesh {} is used by several nodes whose normals or tangents came out different (their neighbours or transforms differ): nodes {:?} now use a copy of it, mesh {clone}",
            self.path.display(),
            group.mesh,
            group.nodes
        ));
        Ok(())
    }

    /// A primitive with new NORMAL, TANGENT and indices, and its other attributes and morph
    /// targets duplicated for split vertices.
    fn primitive(&mut self, input: &Value, object: &Object) -> Result<Value, IoError> {
        let mut primitive = input.clone();
        let split = !object.split_from.is_empty();
        let mut attributes = input["attributes"].as_object().cloned().unwrap_or_default();
        attributes.remove("NORMAL");
        attributes.remove("TANGENT");
        if split {
            for accessor in attributes.values_mut() {
                *accessor = json!(self.duplicate(accessor, object)?);
            }
        }
        let count = object.vertex_count();
        if let Some(normals) = &object.normals {
            let bytes: Vec<u8> = normals
                .iter()
                .flat_map(|&n| unit_normal(n).to_array())
                .flat_map(f32::to_le_bytes)
                .collect();
            let layout = Layout::Vertices { element: 12, stride: 12 };
            let accessor = self.accessor_over(
                bytes,
                layout,
                json!({ "componentType": 5126, "count": count, "type": "VEC3" }),
            );
            attributes.insert("NORMAL".to_owned(), json!(accessor));
            if let Some(tangents) = &object.tangents {
                let bytes: Vec<u8> = tangents
                    .iter()
                    .flat_map(|&t| unit_tangent(t).to_array())
                    .flat_map(f32::to_le_bytes)
                    .collect();
                let layout = Layout::Vertices { element: 16, stride: 16 };
                let accessor = self.accessor_over(
                    bytes,
                    layout,
                    json!({ "componentType": 5126, "count": count, "type": "VEC4" }),
                );
                attributes.insert("TANGENT".to_owned(), json!(accessor));
            }
        }
        let (has_normal, has_tangent) =
            (attributes.contains_key("NORMAL"), attributes.contains_key("TANGENT"));
        primitive["attributes"] = Value::Object(attributes);
        if let Some(targets) = primitive.get_mut("targets").and_then(Value::as_array_mut) {
            for (k, target) in targets.iter_mut().filter_map(Value::as_object_mut).enumerate() {
                // A delta needs its base attribute.
                target.retain(|name, _| {
                    (name != "NORMAL" || has_normal) && (name != "TANGENT" || has_tangent)
                });
                let computed = self.computed_deltas(object, k, has_normal, has_tangent);
                if split {
                    for (name, accessor) in target.iter_mut() {
                        if !computed.iter().any(|(n, _)| n == name) {
                            *accessor = json!(self.duplicate(accessor, object)?);
                        }
                    }
                }
                target.extend(computed.into_iter().map(|(n, a)| (n.to_owned(), json!(a))));
            }
        }
        match self.indices(uint(input, "indices"), object) {
            Some(accessor) => primitive["indices"] = json!(accessor),
            None => {
                if let Some(p) = primitive.as_object_mut() {
                    p.remove("indices");
                }
            }
        }
        Ok(primitive)
    }

    /// The morph target `k`'s normal and tangent deltas that `fix` computed for `object`
    /// (see `seamlit_mesh::MorphTarget`), as new `FLOAT` `VEC3` accessors: `("NORMAL",
    /// accessor)` where the primitive has normals, `("TANGENT", accessor)` where it has
    /// tangents. Empty where nothing was computed: the input's deltas are kept.
    fn computed_deltas(
        &mut self,
        object: &Object,
        k: usize,
        has_normal: bool,
        has_tangent: bool,
    ) -> Vec<(&'static str, usize)> {
        let Some(target) = object.morph_targets.get(k) else {
            return Vec::new();
        };
        let wanted = [
            ("NORMAL", has_normal, &target.normal_deltas),
            ("TANGENT", has_tangent, &target.tangent_deltas),
        ];
        let mut out = Vec::new();
        for (name, has_base, deltas) in wanted {
            let Some(deltas) = deltas.as_ref().filter(|_| has_base) else { continue };
            let bytes: Vec<u8> =
                deltas.iter().flat_map(|d| d.to_array()).flat_map(f32::to_le_bytes).collect();
            let layout = Layout::Vertices { element: 12, stride: 12 };
            let accessor = self.accessor_over(
                bytes,
                layout,
                json!({ "componentType": 5126, "count": deltas.len(), "type": "VEC3" }),
            );
            out.push((name, accessor));
        }
        out
    }

    /// The object's triangles as a new index accessor, in the input's component type where
    /// every index fits below its restart value, else `UNSIGNED_INT`. `None` for a
    /// non-indexed input whose triangles are still `0, 1, 2, ...`.
    fn indices(&mut self, input: Option<usize>, object: &Object) -> Option<usize> {
        let n = object.vertex_count();
        let corners = object.triangles.as_flattened();
        if input.is_none()
            && corners.len() == n
            && corners.iter().enumerate().all(|(i, &c)| c as usize == i)
        {
            return None;
        }
        let template = input.map(|a| self.source.json["accessors"][a].clone());
        let wanted = template.as_ref().and_then(|a| integer(&a["componentType"]));
        let fits = |component: u64| match component {
            UNSIGNED_BYTE => n <= usize::from(u8::MAX),
            UNSIGNED_SHORT => n <= usize::from(u16::MAX),
            _ => true,
        };
        let component = match wanted {
            Some(c @ (UNSIGNED_BYTE | UNSIGNED_SHORT)) if fits(c) => c,
            Some(_) => UNSIGNED_INT,
            None if fits(UNSIGNED_SHORT) => UNSIGNED_SHORT,
            None => UNSIGNED_INT,
        };
        // Every index fits the component type, checked by `fits`.
        #[expect(clippy::cast_possible_truncation, reason = "each index fits, checked by `fits`")]
        let bytes: Vec<u8> = match component {
            UNSIGNED_BYTE => corners.iter().map(|&i| i as u8).collect(),
            UNSIGNED_SHORT => corners.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect(),
            _ => corners.iter().flat_map(|&i| i.to_le_bytes()).collect(),
        };
        let size = match component {
            UNSIGNED_BYTE => 1,
            UNSIGNED_SHORT => 2,
            _ => 4,
        };
        let mut accessor = match template {
            Some(Value::Object(mut a)) => {
                for key in ["byteOffset", "sparse", "min", "max", "normalized"] {
                    a.remove(key);
                }
                a
            }
            _ => Map::new(),
        };
        accessor.insert("componentType".to_owned(), json!(component));
        accessor.insert("count".to_owned(), json!(corners.len()));
        accessor.insert("type".to_owned(), json!("SCALAR"));
        Some(self.accessor_over(bytes, Layout::Triangles { size }, Value::Object(accessor)))
    }

    /// A new accessor holding the input accessor `index`'s elements for the object's
    /// vertices: each input vertex's own, each split vertex a copy of its source's. The
    /// elements keep their bytes (component type, normalisation, min and max as written).
    fn duplicate(&mut self, index: &Value, object: &Object) -> Result<usize, IoError> {
        let source = self.source;
        let Some(index) = integer(index).and_then(|i| usize::try_from(i).ok()) else {
            return Err(IoError::BadAccessor {
                path: source.path.clone(),
                accessor: usize::MAX,
                kind: BadAccessor::NotAnAccessor { found: index.to_string() },
            });
        };
        let elements = read_elements(source, index, object.input_vertex_count())?;
        let size = elements.size;
        let stride = size.next_multiple_of(4);
        let mut bytes = Vec::with_capacity(stride * object.vertex_count());
        // Below u32::MAX: check_object, which `save` runs first.
        for v in (0..u32::MAX).take(object.vertex_count()) {
            let from = object.source_vertex(v) as usize * size;
            bytes.extend_from_slice(&elements.bytes[from..from + size]);
            bytes.resize(bytes.len() + stride - size, 0);
        }
        let mut accessor = source.json["accessors"][index].as_object().cloned().unwrap_or_default();
        accessor.remove("byteOffset");
        accessor.remove("sparse");
        accessor.insert("count".to_owned(), json!(object.vertex_count()));
        let layout = Layout::Vertices { element: size, stride };
        Ok(self.accessor_over(bytes, layout, Value::Object(accessor)))
    }

    /// Buffer 0 holds the input's bytes and the appended ones: the GLB `BIN` chunk, or a new
    /// `NAME.bin` beside a `.gltf`. Other buffers and images named by file are copied beside
    /// a `.gltf`; in a GLB, images named by file are embedded.
    fn place_buffers_and_images(&mut self) -> Result<(), IoError> {
        let buffer_count = self.json["buffers"].as_array().map_or(0, Vec::len);
        for b in 1..buffer_count {
            let uri = self.json["buffers"][b]["uri"].as_str().map(str::to_owned);
            if let Some(uri) = uri {
                self.copy(&uri, &format!("buffer {b}"))?;
            }
        }
        let image_count = self.json["images"].as_array().map_or(0, Vec::len);
        for i in 0..image_count {
            let Some(uri) = self.json["images"][i]["uri"].as_str().map(str::to_owned) else {
                continue;
            };
            let what = format!("image {i}");
            if self.binary && self.embed(i, &uri, &what)? {
                continue;
            }
            self.copy(&uri, &what)?;
        }
        if self.host_without_data() {
            return self.keep_host_without_data();
        }
        if buffer_count == 0 {
            if self.appended == 0 {
                return Ok(());
            }
            self.array("buffers").push(json!({ "byteLength": 0 }));
        }
        let length = if self.appended > 0 {
            self.base + self.appended
        } else {
            uint(&self.json["buffers"][0], "byteLength").unwrap_or(0)
        };
        let host_uri = (!self.binary).then(|| self.host_name());
        if let Some(buffer) = self.json["buffers"][0].as_object_mut() {
            buffer.insert("byteLength".to_owned(), json!(length));
            match host_uri {
                Some(uri) => buffer.insert("uri".to_owned(), json!(uri)),
                None => buffer.remove("uri"),
            };
        }
        Ok(())
    }

    /// A file name for buffer 0 beside a `.gltf` output: `STEM.bin`, or `STEM_N.bin` where a
    /// copied file has that name.
    fn host_name(&self) -> String {
        let stem = self.path.file_stem().map_or_else(
            || "model".to_owned(),
            |s| crate::gltf_write::safe_name(&s.to_string_lossy()),
        );
        let folder = self.path.parent().unwrap_or(Path::new(""));
        let taken = |name: &str| self.copies.iter().any(|(_, to)| to == &folder.join(name));
        let mut name = format!("{stem}.bin");
        let mut n = 1;
        while taken(&name) {
            name = format!("{stem}_{n}.bin");
            n += 1;
        }
        name
    }

    /// Plans the copy of the file `uri` names to the same place beside the output. A
    /// missing file is a warning.
    fn copy(&mut self, uri: &str, what: &str) -> Result<(), IoError> {
        let Some((file, real)) = crate::gltf::resolve_file(&self.source.path, uri, what)? else {
            return Ok(());
        };
        let Some(real) = real else {
            self.warnings.push(format!(
                "{}: {what} {} is missing; the output names it still",
                self.source.path.display(),
                file.display()
            ));
            return Ok(());
        };
        let folder = self.source.path.parent().unwrap_or(Path::new(""));
        let relative = file.strip_prefix(folder).unwrap_or(&file);
        let destination = self.path.parent().unwrap_or(Path::new("")).join(relative);
        if !crate::same_file(&real, &destination) {
            self.copies.push((real, destination));
        }
        Ok(())
    }

    /// Embeds image `i`, named by `uri`, in buffer 0 (GLB output); `false` when it stays a
    /// URI (a `data:` URI, a missing file, a format whose MIME type is unknown).
    fn embed(&mut self, i: usize, uri: &str, what: &str) -> Result<bool, IoError> {
        let Some((_, Some(real))) = crate::gltf::resolve_file(&self.source.path, uri, what)? else {
            return Ok(false);
        };
        let bytes = std::fs::read(&real).map_err(|e| IoError::io(&real, e))?;
        let declared = self.json["images"][i]["mimeType"].as_str().map(str::to_owned);
        let Some(mime) = declared.or_else(|| sniff(&bytes).map(str::to_owned)) else {
            return Ok(false);
        };
        let view = self.view(bytes, Layout::Bytes);
        if let Some(image) = self.json["images"][i].as_object_mut() {
            image.remove("uri");
            image.insert("bufferView".to_owned(), json!(view));
            image.insert("mimeType".to_owned(), json!(mime));
        }
        Ok(true)
    }

    /// Writes the side files, then the document.
    fn write(&self) -> Result<(), IoError> {
        for (from, to) in &self.copies {
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent).map_err(|e| IoError::io(parent, e))?;
            }
            crate::atomic::write_with(to, |out| {
                std::io::copy(&mut std::fs::File::open(from)?, out).map(|_| ())
            })?;
        }
        let has_host = self.json["buffers"].get(0).is_some() && !self.host_without_data();
        let host_length = self.json["buffers"].get(0).and_then(|b| uint(b, "byteLength"));
        let host_length = host_length.unwrap_or(0);
        let folder = self.path.parent().unwrap_or(Path::new(""));
        let serialise = |json: &Value, pretty: bool| {
            let bytes =
                if pretty { serde_json::to_vec_pretty(json) } else { serde_json::to_vec(json) };
            bytes.map_err(|e| IoError::InvalidAsset {
                path: self.path.to_path_buf(),
                object: String::new(),
                kind: crate::InvalidAsset::Json { source: e },
            })
        };
        if !self.binary {
            if let Some(uri) = self.json["buffers"][0]["uri"].as_str() {
                crate::atomic::write_with(&folder.join(uri), |out| {
                    self.write_host(out, host_length)
                })?;
            }
            return crate::atomic::write(self.path, &serialise(&self.json, true)?);
        }
        let json = serialise(&self.json, false)?;
        let bin = has_host.then_some(host_length);
        crate::gltf_write::write_glb(self.path, json, bin, |out| self.write_host(out, host_length))
    }

    /// Writes buffer 0: the input's bytes (those pruning kept), then the appended pieces,
    /// `length` bytes in all.
    fn write_host(&self, out: &mut dyn Write, length: usize) -> std::io::Result<()> {
        let input_length = if self.appended > 0 { self.base } else { length };
        let input = self.source.buffers.first().map_or(&[][..], Vec::as_slice);
        let zeros = |out: &mut dyn Write, n: usize| {
            std::io::copy(&mut std::io::repeat(0).take(n as u64), out).map(|_| ())
        };
        match &self.kept {
            None => {
                let kept = input.len().min(input_length);
                out.write_all(&input[..kept])?;
                zeros(out, input_length - kept)?;
            }
            Some(kept) => {
                let mut at = 0;
                for (range, start) in &kept.ranges {
                    zeros(out, start - at)?;
                    let bytes = input.get(range.start.min(input.len())..range.end.min(input.len()));
                    let bytes = bytes.unwrap_or_default();
                    out.write_all(bytes)?;
                    zeros(out, range.len() - bytes.len())?;
                    at = start + range.len();
                }
                zeros(out, input_length - at)?;
            }
        }
        let mut written = 0usize;
        for piece in &self.pieces {
            let padding = written.next_multiple_of(4) - written;
            out.write_all(&[0; 3][..padding])?;
            out.write_all(piece)?;
            written += padding + piece.len();
        }
        debug_assert_eq!(input_length + written, length);
        Ok(())
    }
}

/// The MIME type of image bytes seamlit passes through, from their signature.
fn sniff(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some("image/png")
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        Some("image/jpeg")
    } else if bytes.starts_with(b"\xABKTX 20\xBB\r\n\x1A\n") {
        Some("image/ktx2")
    } else if bytes.len() >= 12 && &bytes[..4] == b"RIFF" && &bytes[8..12] == b"WEBP" {
        Some("image/webp")
    } else {
        None
    }
}

/// An accessor's elements, densely packed (sparse substitution applied).
struct Elements {
    bytes: Vec<u8>,
    /// Bytes per element, as stored (matrix columns padded to 4 bytes).
    size: usize,
}

/// Reads accessor `index` of the source, which must have `expected` elements: every
/// element's bytes, from its buffer view (or zeros) with the sparse values substituted.
fn read_elements(source: &Source, index: usize, expected: usize) -> Result<Elements, IoError> {
    let accessor = &source.json["accessors"][index];
    let at = AccessorAt { source, index };
    // Bytes per element, from componentType and type.
    let size = at.element_size(accessor)?;
    let count = uint(accessor, "count").ok_or_else(|| at.bad(BadAccessor::NoCount))?;
    if count != expected {
        return Err(at.bad(BadAccessor::PrimitiveCount { count, vertices: expected }));
    }
    // The dense elements: from the buffer view, or zeros.
    let mut bytes = vec![0u8; count * size];
    if let Some(view) = uint(accessor, "bufferView") {
        at.copy_dense(accessor, view, size, &mut bytes)?;
    }
    // The sparse values over them.
    if let Some(sparse) = accessor.get("sparse") {
        at.substitute_sparse(sparse, size, &mut bytes)?;
    }
    Ok(Elements { bytes, size })
}

/// Accessor `index` of `source`, being read by [`read_elements`].
struct AccessorAt<'a> {
    source: &'a Source,
    index: usize,
}

impl AccessorAt<'_> {
    fn bad(&self, kind: BadAccessor) -> IoError {
        IoError::BadAccessor { path: self.source.path.clone(), accessor: self.index, kind }
    }

    /// Bytes per element as stored (matrix columns padded to 4 bytes).
    fn element_size(&self, accessor: &Value) -> Result<usize, IoError> {
        let component: usize = match integer(&accessor["componentType"]) {
            Some(5120 | 5121) => 1,
            Some(5122 | 5123) => 2,
            Some(5125 | 5126) => 4,
            found => return Err(self.bad(BadAccessor::UnknownComponentType { found })),
        };
        let (columns, rows) = match accessor["type"].as_str() {
            Some("SCALAR") => (1, 1),
            Some("VEC2") => (1, 2),
            Some("VEC3") => (1, 3),
            Some("VEC4") => (1, 4),
            Some("MAT2") => (2, 2),
            Some("MAT3") => (3, 3),
            Some("MAT4") => (4, 4),
            found => {
                let found = found.map(str::to_owned);
                return Err(self.bad(BadAccessor::UnknownType { found }));
            }
        };
        Ok(if columns == 1 {
            rows * component
        } else {
            columns * (rows * component).next_multiple_of(4)
        })
    }

    /// Copies the elements of buffer view `view` into `bytes` (`size` bytes each).
    fn copy_dense(
        &self,
        accessor: &Value,
        view: usize,
        size: usize,
        bytes: &mut [u8],
    ) -> Result<(), IoError> {
        let count = bytes.len() / size;
        let (data, stride) = view_bytes(self.source, self.index, view, size)?;
        let offset = uint(accessor, "byteOffset").unwrap_or(0);
        // Saturating: offsets and strides come from the file.
        let needed = match count {
            0 => 0,
            _ => offset.saturating_add(stride.saturating_mul(count - 1)).saturating_add(size),
        };
        if needed > data.len() {
            return Err(IoError::AccessorOutOfRange {
                path: self.source.path.clone(),
                accessor: self.index,
                view,
                needed: needed as u64,
                available: data.len() as u64,
            });
        }
        for (k, element) in bytes.chunks_exact_mut(size).enumerate() {
            let at = offset + k * stride;
            element.copy_from_slice(&data[at..at + size]);
        }
        Ok(())
    }

    /// Writes the accessor's sparse values over `bytes` (`size` bytes an element).
    fn substitute_sparse(
        &self,
        sparse: &Value,
        size: usize,
        bytes: &mut [u8],
    ) -> Result<(), IoError> {
        let count = bytes.len() / size;
        let n = uint(sparse, "count").ok_or_else(|| self.bad(BadAccessor::SparseWithoutCount))?;
        let indices = &sparse["indices"];
        let index_size = match integer(&indices["componentType"]) {
            Some(UNSIGNED_BYTE) => 1,
            Some(UNSIGNED_SHORT) => 2,
            Some(UNSIGNED_INT) => 4,
            found => return Err(self.bad(BadAccessor::SparseIndexType { found })),
        };
        let sparse_indices = self.sparse_part(indices, n, index_size)?;
        let values = self.sparse_part(&sparse["values"], n, size)?;
        for (k, value) in values.chunks_exact(size).enumerate() {
            let at = &sparse_indices[k * index_size..(k + 1) * index_size];
            let mut word = [0u8; 4];
            word[..index_size].copy_from_slice(at);
            let target = u32::from_le_bytes(word) as usize;
            if target >= count {
                return Err(self.bad(BadAccessor::SparseIndexPast { index: target, count }));
            }
            bytes[target * size..(target + 1) * size].copy_from_slice(value);
        }
        Ok(())
    }

    /// The bytes of a sparse part (`indices` or `values`): `n` elements of `element` bytes.
    fn sparse_part<'s>(
        &'s self,
        part: &Value,
        n: usize,
        element: usize,
    ) -> Result<&'s [u8], IoError> {
        let view =
            uint(part, "bufferView").ok_or_else(|| self.bad(BadAccessor::SparseWithoutView))?;
        let (data, _) = view_bytes(self.source, self.index, view, element)?;
        let offset = uint(part, "byteOffset").unwrap_or(0);
        let needed = offset.saturating_add(n.saturating_mul(element));
        data.get(offset..needed).ok_or(IoError::AccessorOutOfRange {
            path: self.source.path.clone(),
            accessor: self.index,
            view,
            needed: needed as u64,
            available: data.len() as u64,
        })
    }
}

/// A buffer view's bytes and its stride (`element` when it declares none).
fn view_bytes(
    source: &Source,
    accessor: usize,
    index: usize,
    element: usize,
) -> Result<(&[u8], usize), IoError> {
    let view = &source.json["bufferViews"][index];
    let buffer = uint(view, "buffer").and_then(|b| source.buffers.get(b));
    let offset = uint(view, "byteOffset").unwrap_or(0);
    let length = uint(view, "byteLength").unwrap_or(0);
    let data = buffer.and_then(|b| b.get(offset..offset.checked_add(length)?));
    let Some(data) = data else {
        return Err(IoError::AccessorOutOfRange {
            path: source.path.clone(),
            accessor,
            view: index,
            needed: offset.saturating_add(length) as u64,
            available: buffer.map_or(0, Vec::len) as u64,
        });
    };
    Ok((data, uint(view, "byteStride").unwrap_or(element)))
}

impl Output<'_> {
    /// Whether buffer 0 of the input has no data: no `uri` and not a GLB's BIN chunk (valid
    /// glTF: its data "MAY be provided by an extension or other means"; see `gltf_spec`).
    fn host_without_data(&self) -> bool {
        let host = &self.source.json["buffers"][0];
        host.is_object()
            && host.get("uri").is_none()
            && self.source.buffers.first().map_or(0, Vec::len)
                < uint(host, "byteLength").unwrap_or(0)
    }

    /// Buffer 0 without data is written as it was (no `uri`) in a `.gltf`. A GLB cannot
    /// hold it (there, buffer 0 without `uri` is the BIN chunk), and nothing can be appended
    /// to it.
    fn keep_host_without_data(&self) -> Result<(), IoError> {
        let kind = if self.appended > 0 {
            crate::InvalidAsset::HostCannotGrow
        } else if self.binary {
            crate::InvalidAsset::HostInGlb
        } else {
            return Ok(());
        };
        Err(IoError::InvalidAsset { path: self.path.to_path_buf(), object: String::new(), kind })
    }
}
