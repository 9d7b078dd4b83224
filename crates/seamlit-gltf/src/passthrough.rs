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
//!   [`seamlit_asset::SaveOptions::keep_compression`], kept as they were while the new views are
//!   encoded (`passthrough/encode.rs`).
//!
//! Everything else is the input JSON, kept as a [`serde_json::Value`]: unknown extensions,
//! extras, skins, animations, cameras, materials, node transforms as written. Accessors,
//! buffer views and buffers the output still uses keep their indices (skins, animations and
//! extensions point at them); the ones only the replaced data used give their places and
//! bytes to the new data (`passthrough/prune.rs`), unless an extension seamlit does not know
//! could point at them.

mod accessors;
mod encode;
mod files;
mod piece;
mod prune;
mod uncompress;
mod unread;

pub(crate) use unread::unread;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use seamlit_mesh::{Model, Object};
use serde_json::{Map, Value, json};

use crate::json::{
    ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER, FLOAT, TRIANGLES, UNSIGNED_BYTE, UNSIGNED_INT,
    UNSIGNED_SHORT, array_member, integer, usize_member,
};
use crate::source::{GltfSource, Instance, Source};
use accessors::{Elements, read_elements};
use encode::{Layout, Recompression};
use piece::Piece;
use prune::KeptBytes;
use seamlit_asset::Asset;
use seamlit_asset::check::check_object;
use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::{BadAccessor, GltfKind};
use seamlit_asset::files::Destination;

/// Writes `asset` (whose model passes [`GltfSource::check_model`] for `source`) as `.glb`
/// (`binary`) or `.gltf`, keeping meshopt compression when `keep_compression` is set
/// (`encode.rs`); returns the warnings.
pub(crate) fn save(
    asset: &Asset,
    source: &GltfSource,
    path: &Path,
    binary: bool,
    keep_compression: bool,
    to: &mut Destination,
) -> Result<Vec<String>, IoError> {
    for object in &asset.model.objects {
        check_object(object, path)?;
    }
    let mut out = OutputDocument::new(&source.0, &asset.model, path, binary);
    if keep_compression {
        out.keep_compression()?;
    } else {
        out.uncompress_views();
    }
    for group in instance_groups(&asset.model, &source.0.instances) {
        out.mesh(asset, &group)?;
    }
    out.skins(asset);
    // Decoded at load (`decode/draco.rs`): the accessors hold plain data.
    let note = uncompress::strip_draco(&mut out.json, &source.0.path);
    out.warnings.extend(note);
    out.prune();
    out.finish_compression();
    out.embed_or_copy_files()?;
    out.write(to)?;
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
type MeshUse = (usize, Vec<(usize, usize)>);

/// Groups the objects by mesh instance (node), then the instances of each mesh by equal
/// results: same triangles, splits, normal and tangent bits.
fn instance_groups(model: &Model, instances: &[Instance]) -> Vec<Group> {
    // mesh -> its uses, in object order.
    let mut by_mesh: BTreeMap<usize, Vec<MeshUse>> = BTreeMap::new();
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
        && a.skin == b.skin
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
struct OutputDocument<'a> {
    source: &'a Source,
    /// The model written (buffer 0's bytes given back at load are its elements).
    model: &'a Model,
    /// The output document: the input's, changed in place.
    json: Value,
    /// Where appended data starts in buffer 0: its input length (or, once pruned, its kept
    /// bytes' length), padded to 4.
    base: usize,
    /// How buffer 0's input bytes were packed by pruning; `None`: kept as they were.
    kept: Option<KeptBytes>,
    /// Appended data, each piece starting at a multiple of 4 bytes from `base`.
    pieces: Vec<Piece<'a>>,
    /// Bytes appended so far (pieces and their padding).
    appended: usize,
    /// Files to copy beside a `.gltf` output: (source, destination).
    copies: Vec<(PathBuf, PathBuf)>,
    path: &'a Path,
    binary: bool,
    warnings: Vec<String>,
    /// Set while a save keeps meshopt compression: new views are encoded.
    keep: Option<Recompression>,
}

impl<'a> OutputDocument<'a> {
    fn new(source: &'a Source, model: &'a Model, path: &'a Path, binary: bool) -> Self {
        let host =
            source.json["buffers"].get(0).and_then(|b| usize_member(b, "byteLength")).unwrap_or(0);
        Self {
            source,
            model,
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
        self.append_piece(Piece::Bytes(bytes))
    }

    /// Appends `piece` to buffer 0 at a multiple of 4; returns its offset in it.
    fn append_piece(&mut self, piece: Piece<'a>) -> usize {
        let offset = self.appended.next_multiple_of(4);
        self.appended = offset + piece.len();
        self.pieces.push(piece);
        self.base + offset
    }

    /// Buffer views the input stored compressed (EXT_ or KHR_meshopt_compression, decoded at load)
    /// become plain data appended to buffer 0, and the report says so
    /// (`uncompress.rs`).
    fn uncompress_views(&mut self) {
        let mut json = std::mem::take(&mut self.json);
        let source = self.source;
        let note =
            uncompress::uncompress_views(&mut json, &source.buffers, &source.path, |bytes| {
                self.append(bytes)
            });
        self.json = json;
        self.warnings.extend(note);
    }

    /// Keeps the input's meshopt compression (`encode.rs`): compressed views stay
    /// as written, and new views are encoded. The report says what was kept, or that the
    /// input had nothing to keep.
    ///
    /// # Errors
    ///
    /// [`IoError::CannotKeepCompression`] for a Draco-compressed input.
    fn keep_compression(&mut self) -> Result<(), IoError> {
        self.keep = Recompression::start(&mut self.json, &self.source.path)?;
        if self.keep.is_none() {
            self.warnings.push(encode::nothing_to_keep(&self.source.path));
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

    /// Adds `accessor` (its JSON, less `bufferView`) over the new data `piece`, laid out as
    /// `layout`; returns its index. The data gets a buffer view of its own in buffer 0, or,
    /// while the compression is kept, joins the new view of its layout
    /// ([`Recompression::gather`]), at the offset the accessor then names.
    fn accessor_over(&mut self, piece: Piece<'a>, layout: Layout, mut accessor: Value) -> usize {
        let mut keep = self.keep.take();
        let gathered =
            keep.as_mut().and_then(|k| k.gather(&piece.bytes(), layout, self.array("bufferViews")));
        self.keep = keep;
        let (view, offset) = gathered.unwrap_or_else(|| (self.view(piece, layout), 0));
        accessor["bufferView"] = json!(view);
        if offset > 0 {
            accessor["byteOffset"] = json!(offset);
        }
        self.accessor(accessor)
    }

    /// Appends `piece` to buffer 0 as a new buffer view laid out as `layout`; returns its
    /// index.
    fn view(&mut self, piece: Piece<'a>, layout: Layout) -> usize {
        let view = self.plain_view(piece, layout);
        let views = self.array("bufferViews");
        views.push(view);
        views.len() - 1
    }

    /// Appends `piece` to buffer 0; returns its buffer view.
    fn plain_view(&mut self, piece: Piece<'a>, layout: Layout) -> Value {
        let length = piece.len();
        let offset = self.append_piece(piece);
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

    /// Drops what only the input's replaced data used (`prune.rs`) and packs
    /// buffer 0's remaining input bytes. Never while the compression is kept: packing would
    /// move compressed bytes that views name by offset (today no meshopt document is
    /// pruned anyway, its extension is not among those `references.rs` knows).
    fn prune(&mut self) {
        if self.keep.is_some() {
            return;
        }
        if let Some(kept) = prune::prune(&self.source.json, &mut self.json, self.base) {
            self.base = kept.length;
            self.kept = Some(kept);
        }
    }

    /// Writes one group: its primitives into the mesh, or into a clone the group's nodes
    /// then point at.
    fn mesh(&mut self, asset: &'a Asset, group: &Group) -> Result<(), IoError> {
        let source = self.source;
        let mut mesh = source.json["meshes"][group.mesh].clone();
        for &(p, object) in &group.objects {
            let primitive = &source.json["meshes"][group.mesh]["primitives"][p];
            let mut written = self.primitive(primitive, &asset.model.objects[object])?;
            if asset.skins_changed.objects.contains(&object) {
                self.influences(&mut written, asset, object);
            }
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
    fn primitive(&mut self, input: &Value, object: &'a Object) -> Result<Value, IoError> {
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
            let layout = Layout::Vertices { element: 12, stride: 12 };
            let accessor = self.accessor_over(
                Piece::Normals(normals),
                layout,
                json!({ "componentType": FLOAT, "count": count, "type": "VEC3" }),
            );
            attributes.insert("NORMAL".to_owned(), json!(accessor));
            if let Some(tangents) = &object.tangents {
                let layout = Layout::Vertices { element: 16, stride: 16 };
                let accessor = self.accessor_over(
                    Piece::Tangents(tangents),
                    layout,
                    json!({ "componentType": FLOAT, "count": count, "type": "VEC4" }),
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
        match self.indices(usize_member(input, "indices"), object) {
            Some(accessor) => primitive["indices"] = json!(accessor),
            None => {
                if let Some(p) = primitive.as_object_mut() {
                    p.remove("indices");
                }
            }
        }
        // A strip or a fan was read as a list of triangles, which the indices now are.
        if primitive.get("mode").is_some() {
            primitive["mode"] = json!(TRIANGLES);
        }
        Ok(primitive)
    }

    /// Replaces a written primitive's `JOINTS_n`/`WEIGHTS_n` with the object's influences
    /// ([`seamlit_asset::match_skin_seams`] changed them): joints as indices into its node's skin
    /// (`UNSIGNED_SHORT`), weights as `FLOAT`, one pair per set.
    fn influences(&mut self, primitive: &mut Value, asset: &Asset, object: usize) {
        let o = &asset.model.objects[object];
        let Some(joints) = seamlit_asset::pose::node_of(asset, object)
            .and_then(|n| asset.nodes[n].skin)
            .and_then(|s| asset.skins.get(s))
            .map(|s| &s.joints)
        else {
            return;
        };
        let Some(attributes) = primitive["attributes"].as_object_mut() else { return };
        attributes.retain(|name, _| !name.starts_with("JOINTS_") && !name.starts_with("WEIGHTS_"));
        let mut added = Vec::new();
        for (set, influences) in o.skin.iter().enumerate() {
            // Every joint an influence names is in the skin (match_skin_seams added it).
            let slot = |node: u32| -> u16 {
                let k = joints.iter().position(|&j| j == node as usize).unwrap_or(0);
                u16::try_from(k).unwrap_or(u16::MAX)
            };
            let bytes: Vec<u8> = influences
                .joints
                .iter()
                .flat_map(|j| j.map(slot))
                .flat_map(u16::to_le_bytes)
                .collect();
            let layout = Layout::Vertices { element: 8, stride: 8 };
            let count = influences.joints.len();
            let joints_accessor = self.accessor_over(
                Piece::Bytes(bytes),
                layout,
                json!({ "componentType": UNSIGNED_SHORT, "count": count, "type": "VEC4" }),
            );
            let bytes: Vec<u8> =
                influences.weights.iter().flatten().flat_map(|w| w.to_le_bytes()).collect();
            let layout = Layout::Vertices { element: 16, stride: 16 };
            let weights_accessor = self.accessor_over(
                Piece::Bytes(bytes),
                layout,
                json!({ "componentType": FLOAT, "count": count, "type": "VEC4" }),
            );
            added.push((format!("JOINTS_{set}"), joints_accessor));
            added.push((format!("WEIGHTS_{set}"), weights_accessor));
        }
        if let Some(attributes) = primitive["attributes"].as_object_mut() {
            attributes.extend(added.into_iter().map(|(n, a)| (n, json!(a))));
        }
    }

    /// The skins that [`seamlit_asset::match_skin_seams`] gave joints: their `joints` and a new
    /// `inverseBindMatrices` accessor, from the asset.
    fn skins(&mut self, asset: &Asset) {
        let nodes = &self.source.nodes;
        for &s in &asset.skins_changed.skins {
            let Some(skin) = asset.skins.get(s) else { continue };
            let joints: Vec<usize> =
                skin.joints.iter().map(|&j| nodes.get(j).copied().unwrap_or(usize::MAX)).collect();
            if joints.contains(&usize::MAX) {
                continue;
            }
            let bytes: Vec<u8> = skin
                .inverse_bind_matrices
                .iter()
                .flat_map(glam::Mat4::to_cols_array)
                .flat_map(f32::to_le_bytes)
                .collect();
            let accessor = self.accessor_over(
                Piece::Bytes(bytes),
                Layout::Bytes,
                json!({ "componentType": FLOAT, "count": joints.len(), "type": "MAT4" }),
            );
            self.json["skins"][s]["joints"] = json!(joints);
            self.json["skins"][s]["inverseBindMatrices"] = json!(accessor);
        }
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
                Piece::Bytes(bytes),
                layout,
                json!({ "componentType": FLOAT, "count": deltas.len(), "type": "VEC3" }),
            );
            out.push((name, accessor));
        }
        out
    }

    /// The object's triangles as a new index accessor, in the input's component type where
    /// every index fits below its restart value, else `UNSIGNED_INT`. `None` for a
    /// non-indexed input whose triangles are still `0, 1, 2, ...`.
    fn indices(&mut self, input: Option<usize>, object: &'a Object) -> Option<usize> {
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
        // Every index fits the component type, checked by `fits`.
        let piece = Piece::Indices { corners, size };
        Some(self.accessor_over(piece, Layout::Triangles { size }, Value::Object(accessor)))
    }

    /// A new accessor holding the input accessor `index`'s elements for the object's
    /// vertices: each input vertex's own, each split vertex a copy of its source's. The
    /// elements keep their bytes (component type, normalisation, min and max as written).
    fn duplicate(&mut self, index: &Value, object: &Object) -> Result<usize, IoError> {
        let source = self.source;
        let Some(index) = integer(index).and_then(|i| usize::try_from(i).ok()) else {
            return Err(IoError::gltf_data(
                source.path.clone(),
                GltfKind::Accessor {
                    accessor: usize::MAX,
                    kind: Box::new(BadAccessor::NotAnAccessor { found: index.to_string() }),
                },
            ));
        };
        let elements = match source.buffers.model_elements(index, object) {
            Some((bytes, size)) => Elements { bytes, size },
            None => read_elements(source, index, object.input_vertex_count())?,
        };
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
        Ok(self.accessor_over(Piece::Bytes(bytes), layout, Value::Object(accessor)))
    }
}
