//! glTF 2.0 and GLB out, through gltf-json.
//!
//! Each object becomes a mesh of one triangle primitive (POSITION with min/max, NORMAL,
//! TANGENT, TEXCOORD_0 and _1, COLOR_0 as RGBA floats, indices as u16 where every index fits
//! below 65535, else u32, and the morph targets' POSITION, NORMAL and TANGENT deltas) named
//! after the object. The node hierarchy of the asset is rebuilt when it is consistent with
//! the objects' transforms (a node carrying several objects gets one child node per object);
//! otherwise each object gets a root node with its transform. Materials and the textures
//! they use are carried through: embedded in a GLB, written beside a `.gltf` (whose buffer
//! goes to `NAME.bin` beside it too).
//!
//! The glTF validator rejects non-unit normals and tangents and tangent signs other than
//! +-1: such values (only such) are normalised on the way out, a zero vector becoming +Z
//! (normal) or +X (tangent). Texture coordinates are flipped (`v' = 1 - v`) when the model's V
//! runs up (OBJ, Newell), since glTF's runs down.

use std::collections::{BTreeMap, HashMap};
use std::io::Write;
use std::path::Path;

use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use gltf_json as json;
use json::validation::{Checked, USize64};
use seamlit_mesh::{Object, VAxis};

use crate::animation::{Interpolation, Property};
use crate::asset::{Asset, Material, TextureRef, UvTransform};
use crate::check::{check_object, unit_normal, unit_tangent};
use crate::error::{InvalidAsset, IoError};
use crate::files::safe_name;
use crate::texture::encoded;

/// Writes `asset` as `.glb` (`binary`) or `.gltf` (+ `.bin` and images beside it).
///
/// The binary buffer is never assembled in memory: the JSON is built first with every buffer
/// view's offset computed from the lengths, then the vertex and index data are streamed from
/// the objects to the file (after the JSON chunk in a GLB, into `NAME.bin` beside a `.gltf`).
pub(crate) fn save(asset: &Asset, path: &Path, binary: bool) -> Result<(), IoError> {
    for object in &asset.model.objects {
        check_object(object, path)?;
    }
    // glTF's indices are 32-bit: the nodes written (the asset's, or one per object) too.
    let nodes = asset.nodes.len() + asset.model.objects.len();
    if nodes >= u32::MAX as usize {
        return Err(IoError::TooManyElements {
            path: path.to_path_buf(),
            what: "the asset's nodes and objects".to_owned(),
            limit: u32::MAX as usize - 1,
            actual: nodes,
        });
    }
    let stem =
        path.file_stem().map_or_else(|| "model".to_owned(), |s| safe_name(&s.to_string_lossy()));
    let mut writer = Writer {
        root: json::Root::default(),
        pieces: Vec::new(),
        bin_len: 0,
        side_files: Vec::new(),
        path,
        binary,
        stem,
    };
    writer.root.asset = json::Asset {
        generator: Some("seamlit".to_owned()),
        version: "2.0".to_owned(),
        ..Default::default()
    };

    let textures = writer.textures(asset)?;
    for material in &asset.materials {
        let m = writer.material(material, &textures);
        writer.root.push(m);
    }
    let hierarchy = hierarchy_matches(asset);
    let deform = Deform::of(asset, hierarchy);
    let meshes: Vec<json::Index<json::Mesh>> = asset
        .model
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| writer.mesh(o, asset.model.v_axis, asset.materials.len(), &deform, i))
        .collect();
    let written = writer.nodes(asset, &meshes, hierarchy);
    if hierarchy {
        writer.skins(asset, &written);
        writer.animations(asset, &written, &deform);
    }

    let bin_uri = (!binary && writer.bin_len > 0).then(|| format!("{}.bin", writer.stem));
    if writer.bin_len > 0 {
        let buffer = json::Buffer {
            byte_length: USize64::from(writer.bin_len),
            name: None,
            uri: bin_uri.clone(),
            extensions: None,
            extras: Default::default(),
        };
        writer.root.push(buffer);
    }
    let json_bytes =
        serde_json::to_vec_pretty(&writer.root).map_err(|e| IoError::InvalidAsset {
            path: path.to_path_buf(),
            object: String::new(),
            kind: InvalidAsset::Json { source: e },
        })?;
    let folder = path.parent().unwrap_or(Path::new(""));
    for (name, bytes) in &writer.side_files {
        crate::files::write(&folder.join(name), bytes)?;
    }
    if let Some(uri) = bin_uri {
        crate::files::write_with(&folder.join(uri), |out| writer.write_bin(out))?;
    }
    if !binary {
        return crate::files::write(path, &json_bytes);
    }
    let bin = (writer.bin_len > 0).then_some(writer.bin_len);
    crate::gltf::glb::write(path, json_bytes, bin, |out| writer.write_bin(out))
}

/// A part of the binary buffer, written from the asset when the file is written.
enum BinPart<'a> {
    /// Vertex positions (and morph targets' deltas), as they are.
    Positions(&'a [Vec3]),
    /// Normals, made unit length ([`unit_normal`]).
    Normals(&'a [Vec3]),
    /// Tangents, made unit length with w = +-1 ([`unit_tangent`]).
    Tangents(&'a [Vec4]),
    /// Vertex colours, linear RGBA, as they are.
    Colors(&'a [Vec4]),
    /// Texture coordinates, V flipped (`1 - v`) when `flip` is set.
    Uvs { uvs: &'a [Vec2], flip: bool },
    /// Skin joints as u16 (indices into the object's skin's joints).
    Joints(Vec<[u16; 4]>),
    /// Skin weights, as they are.
    Weights(&'a [[f32; 4]]),
    /// Floats, as they are: inverse bind matrices, animation times and values.
    Floats(Vec<f32>),
    /// Triangle indices as u16 (every index is below 65535).
    Indices16(&'a [[u32; 3]]),
    /// Triangle indices as u32.
    Indices32(&'a [[u32; 3]]),
    /// An encoded image.
    Bytes(Vec<u8>),
}

impl BinPart<'_> {
    /// Bytes this piece takes.
    fn len(&self) -> usize {
        match self {
            Self::Positions(v) | Self::Normals(v) => v.len() * 12,
            Self::Tangents(v) | Self::Colors(v) => v.len() * 16,
            Self::Uvs { uvs, .. } => uvs.len() * 8,
            Self::Joints(j) => j.len() * 8,
            Self::Weights(w) => w.len() * 16,
            Self::Floats(f) => f.len() * 4,
            Self::Indices16(t) => t.len() * 6,
            Self::Indices32(t) => t.len() * 12,
            Self::Bytes(b) => b.len(),
        }
    }

    /// Writes the piece, little-endian.
    fn write(&self, out: &mut dyn Write) -> std::io::Result<()> {
        fn floats<const N: usize>(out: &mut dyn Write, v: [f32; N]) -> std::io::Result<()> {
            let mut bytes = [[0u8; 4]; N];
            for (b, x) in bytes.iter_mut().zip(v) {
                *b = x.to_le_bytes();
            }
            out.write_all(bytes.as_flattened())
        }
        match self {
            Self::Positions(v) => v.iter().try_for_each(|p| floats(out, p.to_array())),
            Self::Normals(v) => v.iter().try_for_each(|&n| floats(out, unit_normal(n).to_array())),
            Self::Tangents(v) => {
                v.iter().try_for_each(|&t| floats(out, unit_tangent(t).to_array()))
            }
            Self::Colors(v) => v.iter().try_for_each(|c| floats(out, c.to_array())),
            Self::Uvs { uvs, flip } => {
                uvs.iter().try_for_each(|t| floats(out, [t.x, if *flip { 1.0 - t.y } else { t.y }]))
            }
            Self::Joints(joints) => joints
                .iter()
                .try_for_each(|j| out.write_all(j.map(u16::to_le_bytes).as_flattened())),
            Self::Weights(weights) => weights.iter().try_for_each(|w| floats(out, *w)),
            Self::Floats(values) => values.iter().try_for_each(|x| out.write_all(&x.to_le_bytes())),
            Self::Indices16(triangles) => triangles.iter().try_for_each(|t| {
                // Every index is below 65535, checked by the caller.
                #[expect(clippy::cast_possible_truncation, reason = "below 65535, checked")]
                let [[a0, a1], [b0, b1], [c0, c1]] = t.map(|i| (i as u16).to_le_bytes());
                out.write_all(&[a0, a1, b0, b1, c0, c1])
            }),
            Self::Indices32(triangles) => triangles
                .iter()
                .try_for_each(|t| out.write_all(t.map(u32::to_le_bytes).as_flattened())),
            Self::Bytes(bytes) => out.write_all(bytes),
        }
    }
}

struct Writer<'a> {
    root: json::Root,
    /// The binary buffer's contents in order, each starting at a multiple of 4 bytes.
    pieces: Vec<BinPart<'a>>,
    /// The binary buffer's length so far.
    bin_len: usize,
    /// Files to write beside a `.gltf`: (file name, bytes).
    side_files: Vec<(String, Vec<u8>)>,
    path: &'a Path,
    binary: bool,
    stem: String,
}

impl<'a> Writer<'a> {
    /// Appends a piece to the binary buffer (4-byte aligned) as a buffer view.
    fn view(
        &mut self,
        piece: BinPart<'a>,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        let offset = self.bin_len.next_multiple_of(4);
        let length = piece.len();
        self.bin_len = offset + length;
        self.pieces.push(piece);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(length),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Checked::Valid),
            extensions: None,
            extras: Default::default(),
        })
    }

    /// Writes the binary buffer: every piece, each padded with zeros to a multiple of 4.
    fn write_bin(&self, out: &mut dyn Write) -> std::io::Result<()> {
        let mut written = 0usize;
        for piece in &self.pieces {
            let padding = written.next_multiple_of(4) - written;
            out.write_all(&[0; 3][..padding])?;
            piece.write(out)?;
            written += padding + piece.len();
        }
        debug_assert_eq!(written, self.bin_len);
        Ok(())
    }

    fn accessor(
        &mut self,
        piece: BinPart<'a>,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        target: json::buffer::Target,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(piece, Some(target));
        self.push_accessor(view, count, component, type_, min_max)
    }

    /// Floats that are not vertex attributes (inverse bind matrices, animation times and
    /// values): a view without a target.
    fn data_accessor(
        &mut self,
        values: Vec<f32>,
        count: usize,
        type_: json::accessor::Type,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(BinPart::Floats(values), None);
        self.push_accessor(view, count, json::accessor::ComponentType::F32, type_, min_max)
    }

    /// An accessor of a whole view.
    fn push_accessor(
        &mut self,
        view: json::Index<json::buffer::View>,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        let (min, max) = match min_max {
            Some((min, max)) => (
                Some(json::Value::from(min.iter().map(|&x| f64::from(x)).collect::<Vec<_>>())),
                Some(json::Value::from(max.iter().map(|&x| f64::from(x)).collect::<Vec<_>>())),
            ),
            None => (None, None),
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Checked::Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Checked::Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// A float vertex attribute of `count` elements.
    fn float_accessor(
        &mut self,
        piece: BinPart<'a>,
        count: usize,
        type_: json::accessor::Type,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        self.accessor(
            piece,
            count,
            json::accessor::ComponentType::F32,
            type_,
            json::buffer::Target::ArrayBuffer,
            min_max,
        )
    }

    fn mesh(
        &mut self,
        object: &'a Object,
        v_axis: VAxis,
        material_count: usize,
        deform: &Deform,
        index: usize,
    ) -> json::Index<json::Mesh> {
        use json::accessor::Type;
        use json::mesh::Semantic;
        let mut attributes = BTreeMap::new();
        let n = object.positions.len();
        let (min, max) = object
            .positions
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let bounds = Some((min.to_array().to_vec(), max.to_array().to_vec()));
        attributes.insert(
            Checked::Valid(Semantic::Positions),
            self.float_accessor(BinPart::Positions(&object.positions), n, Type::Vec3, bounds),
        );
        if let Some(normals) = &object.normals {
            attributes.insert(
                Checked::Valid(Semantic::Normals),
                self.float_accessor(BinPart::Normals(normals), n, Type::Vec3, None),
            );
            // TANGENT requires NORMAL.
            if let Some(tangents) = &object.tangents {
                attributes.insert(
                    Checked::Valid(Semantic::Tangents),
                    self.float_accessor(BinPart::Tangents(tangents), n, Type::Vec4, None),
                );
            }
        }
        for (set, uvs) in [(0, &object.uvs), (1, &object.uvs1)] {
            if let Some(uvs) = uvs {
                let piece = BinPart::Uvs { uvs, flip: v_axis == VAxis::Up };
                attributes.insert(
                    Checked::Valid(Semantic::TexCoords(set)),
                    self.float_accessor(piece, n, Type::Vec2, None),
                );
            }
        }
        if let Some(colors) = &object.colors {
            attributes.insert(
                Checked::Valid(Semantic::Colors(0)),
                self.float_accessor(BinPart::Colors(colors), n, Type::Vec4, None),
            );
        }
        if let Some(joints) = deform.joints_of(index) {
            for (set, influences) in object.skin.iter().enumerate() {
                let Ok(set) = u32::try_from(set) else { break };
                let remapped: Vec<[u16; 4]> = influences
                    .joints
                    .iter()
                    .zip(&influences.weights)
                    .map(|(j, w)| {
                        // A joint the skin lacks can only carry no weight (checked by
                        // `Deform::of`); it is written as joint 0.
                        std::array::from_fn(|k| {
                            if w[k] > 0.0 { joints.get(&j[k]).copied().unwrap_or(0) } else { 0 }
                        })
                    })
                    .collect();
                let view =
                    self.view(BinPart::Joints(remapped), Some(json::buffer::Target::ArrayBuffer));
                let accessor = self.push_accessor(
                    view,
                    n,
                    json::accessor::ComponentType::U16,
                    Type::Vec4,
                    None,
                );
                attributes.insert(Checked::Valid(Semantic::Joints(set)), accessor);
                attributes.insert(
                    Checked::Valid(Semantic::Weights(set)),
                    self.float_accessor(BinPart::Weights(&influences.weights), n, Type::Vec4, None),
                );
            }
        }
        let count = object.triangles.len() * 3;
        let (piece, component) = if n <= usize::from(u16::MAX) {
            (BinPart::Indices16(&object.triangles), json::accessor::ComponentType::U16)
        } else {
            (BinPart::Indices32(&object.triangles), json::accessor::ComponentType::U32)
        };
        let indices = self.accessor(
            piece,
            count,
            component,
            Type::Scalar,
            json::buffer::Target::ElementArrayBuffer,
            None,
        );
        let primitive = json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: object
                .material
                .filter(|&m| m < material_count)
                .and_then(|m| u32::try_from(m).ok())
                .map(json::Index::new),
            mode: Checked::Valid(json::mesh::Mode::Triangles),
            targets: self.morph_targets(object),
        };
        let targets = object.morph_targets.len();
        let weights = deform.weights[index].clone().filter(|w| targets > 0 && w.len() == targets);
        // glTF has no target names; `extras.targetNames` is the convention readers know.
        let names: Vec<&str> = object.morph_targets.iter().map(|t| t.name.as_str()).collect();
        let extras = names
            .iter()
            .any(|n| !n.is_empty())
            .then(|| {
                serde_json::value::to_raw_value(&serde_json::json!({ "targetNames": names })).ok()
            })
            .flatten();
        self.root.push(json::Mesh {
            extensions: None,
            extras,
            name: Some(object.name.clone()),
            primitives: vec![primitive],
            weights,
        })
    }

    /// The morph targets of an object: POSITION deltas (with the bounds the specification
    /// requires), and NORMAL and TANGENT deltas where every target has them (the attributes of
    /// all targets of a primitive are the same).
    fn morph_targets(&mut self, object: &'a Object) -> Option<Vec<json::mesh::MorphTarget>> {
        use json::accessor::Type;
        let targets = &object.morph_targets;
        if targets.is_empty() {
            return None;
        }
        let normals = object.normals.is_some() && targets.iter().all(|t| t.normal_deltas.is_some());
        let tangents = normals
            && object.tangents.is_some()
            && targets.iter().all(|t| t.tangent_deltas.is_some());
        let n = object.positions.len();
        let mut deltas = |values: Option<&'a [Vec3]>, wanted: bool, bounded: bool| {
            let values = values.filter(|_| wanted)?;
            let bounds = bounded.then(|| {
                let (min, max) =
                    values.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
                        (lo.min(p), hi.max(p))
                    });
                (min.to_array().to_vec(), max.to_array().to_vec())
            });
            Some(self.float_accessor(BinPart::Positions(values), n, Type::Vec3, bounds))
        };
        let out = targets
            .iter()
            .map(|target| json::mesh::MorphTarget {
                positions: deltas(Some(&target.position_deltas), n > 0, true),
                normals: deltas(target.normal_deltas.as_deref(), normals, false),
                tangents: deltas(target.tangent_deltas.as_deref(), tangents, false),
            })
            .collect();
        Some(out)
    }

    /// The node hierarchy: the asset's own when it matches the objects (`hierarchy`), else
    /// flat. Returns where the asset's nodes went (empty when flat).
    fn nodes(
        &mut self,
        asset: &Asset,
        meshes: &[json::Index<json::Mesh>],
        hierarchy: bool,
    ) -> Written {
        let mut roots = Vec::new();
        let mut written = Written { nodes: Vec::new(), meshes: Vec::new() };
        if hierarchy {
            let base = self.root.nodes.len();
            for node in &asset.nodes {
                let mut json_node = node_with_transform(node.local_transform);
                json_node.name = (!node.name.is_empty()).then(|| node.name.clone());
                if let [object] = node.objects[..] {
                    // Named after the object, so that it reads back under the same name.
                    json_node.name = Some(asset.model.objects[object].name.clone());
                    json_node.mesh = Some(meshes[object]);
                }
                let index = self.root.push(json_node);
                written.nodes.push(index);
                written.meshes.push(if node.objects.len() == 1 { vec![index] } else { Vec::new() });
            }
            let mut children: Vec<Vec<json::Index<json::Node>>> =
                vec![Vec::new(); asset.nodes.len()];
            for (i, node) in asset.nodes.iter().enumerate() {
                #[expect(
                    clippy::cast_possible_truncation,
                    reason = "fewer nodes than u32::MAX, checked in `save`"
                )]
                let index = json::Index::new((base + i) as u32);
                match node.parent {
                    Some(parent) => children[parent].push(index),
                    None => roots.push(index),
                }
                if node.objects.len() > 1 {
                    for &object in &node.objects {
                        let mut child = node_with_transform(Mat4::IDENTITY);
                        child.name = Some(asset.model.objects[object].name.clone());
                        child.mesh = Some(meshes[object]);
                        let child = self.root.push(child);
                        children[i].push(child);
                        written.meshes[i].push(child);
                    }
                }
            }
            for (i, list) in children.into_iter().enumerate() {
                if !list.is_empty() {
                    self.root.nodes[base + i].children = Some(list);
                }
            }
            if skins_lack_a_common_root(asset) {
                // glTF wants a skin's joints below one node: one above every root (the
                // identity) gives them one where they lie in different trees (the bones and
                // the node of a half-skinned mesh, whose unweighted vertices follow it).
                let mut top = node_with_transform(Mat4::IDENTITY);
                top.children = Some(std::mem::take(&mut roots));
                roots.push(self.root.push(top));
            }
        } else {
            for (object, &mesh) in asset.model.objects.iter().zip(meshes) {
                let mut node = node_with_transform(object.model_transform());
                node.name = Some(object.name.clone());
                node.mesh = Some(mesh);
                roots.push(self.root.push(node));
            }
        }
        let scene = self.root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            name: None,
            nodes: roots,
        });
        self.root.scene = Some(scene);
        written
    }

    /// The asset's skins whose joints are all written nodes: joints and inverse bind
    /// matrices; each set on the nodes that carry its meshes.
    fn skins(&mut self, asset: &Asset, written: &Written) {
        for (k, skin) in asset.skins.iter().enumerate() {
            if !skin_writable(asset, k) {
                continue;
            }
            let joints: Vec<json::Index<json::Node>> =
                skin.joints.iter().map(|&j| written.nodes[j]).collect();
            let matrices: Vec<f32> =
                skin.inverse_bind_matrices.iter().flat_map(Mat4::to_cols_array).collect();
            let accessor =
                self.data_accessor(matrices, joints.len(), json::accessor::Type::Mat4, None);
            let index = self.root.push(json::Skin {
                extensions: None,
                extras: Default::default(),
                inverse_bind_matrices: Some(accessor),
                joints,
                name: (!skin.name.is_empty()).then(|| skin.name.clone()),
                skeleton: None,
            });
            for (i, node) in asset.nodes.iter().enumerate() {
                if node.skin == Some(k) {
                    for &mesh_node in &written.meshes[i] {
                        self.root.nodes[mesh_node.value()].skin = Some(index);
                    }
                }
            }
        }
    }

    /// The asset's animations: one sampler per channel (times with their bounds, values as
    /// the channel holds them), aimed at the written node; a `Weights` channel at every
    /// written node of the node's meshes, where each mesh has that many morph targets.
    /// Channels that cannot be written so are left out (a malformed sampler, a node without
    /// meshes for weights).
    fn animations(&mut self, asset: &Asset, written: &Written, deform: &Deform) {
        use json::accessor::Type;
        use json::animation::{Interpolation as Interp, Property as Path};
        for animation in &asset.animations {
            let mut samplers = Vec::new();
            let mut channels = Vec::new();
            for channel in &animation.channels {
                let sampler = &channel.sampler;
                let keys = sampler.times.len();
                let components = sampler.components();
                let groups =
                    if sampler.interpolation == Interpolation::CubicSpline { 3 } else { 1 };
                if keys == 0
                    || components == 0
                    || sampler.values.len() != keys * groups * components
                    || !sampler.times.windows(2).all(|t| t[0] < t[1])
                    || !sampler.times.iter().chain(&sampler.values).all(|x| x.is_finite())
                {
                    continue;
                }
                let Some(&node) = written.nodes.get(channel.node) else { continue };
                let (path, type_, targets) = match channel.property {
                    Property::Translation if components == 3 => {
                        (Path::Translation, Type::Vec3, vec![node])
                    }
                    Property::Rotation if components == 4 => {
                        (Path::Rotation, Type::Vec4, vec![node])
                    }
                    Property::Scale if components == 3 => (Path::Scale, Type::Vec3, vec![node]),
                    Property::Weights
                        if deform.morph_targets_of(asset, channel.node) == Some(components) =>
                    {
                        (
                            Path::MorphTargetWeights,
                            Type::Scalar,
                            written.meshes[channel.node].clone(),
                        )
                    }
                    _ => continue,
                };
                if targets.is_empty() {
                    continue;
                }
                let count =
                    if type_ == Type::Scalar { keys * groups * components } else { keys * groups };
                let (first, last) = (sampler.times[0], sampler.times[keys - 1]);
                let input = self.data_accessor(
                    sampler.times.clone(),
                    keys,
                    Type::Scalar,
                    Some((vec![first], vec![last])),
                );
                let output = self.data_accessor(sampler.values.clone(), count, type_, None);
                let interpolation = match sampler.interpolation {
                    Interpolation::Step => Interp::Step,
                    Interpolation::Linear => Interp::Linear,
                    Interpolation::CubicSpline => Interp::CubicSpline,
                };
                #[expect(clippy::cast_possible_truncation, reason = "one sampler per channel")]
                let index = json::Index::new(samplers.len() as u32);
                samplers.push(json::animation::Sampler {
                    extensions: None,
                    extras: Default::default(),
                    input,
                    interpolation: Checked::Valid(interpolation),
                    output,
                });
                for node in targets {
                    channels.push(json::animation::Channel {
                        sampler: index,
                        target: json::animation::Target {
                            extensions: None,
                            extras: Default::default(),
                            node,
                            path: Checked::Valid(path),
                        },
                        extensions: None,
                        extras: Default::default(),
                    });
                }
            }
            if !channels.is_empty() {
                self.root.push(json::Animation {
                    extensions: None,
                    extras: Default::default(),
                    channels,
                    name: (!animation.name.is_empty()).then(|| animation.name.clone()),
                    samplers,
                });
            }
        }
    }

    /// Images, textures and one sampler for the textures that materials use and whose bytes
    /// are available; returns, per asset texture, its glTF texture index.
    fn textures(
        &mut self,
        asset: &'a Asset,
    ) -> Result<Vec<Option<json::Index<json::Texture>>>, IoError> {
        let used: Vec<bool> = (0..asset.textures.len())
            .map(|i| {
                asset.materials.iter().any(|m| {
                    [&m.base_color_texture, &m.normal_texture]
                        .into_iter()
                        .flatten()
                        .any(|r| r.texture == i)
                })
            })
            .collect();
        let mut out = vec![None; asset.textures.len()];
        let mut sampler = None;
        let mut names: HashMap<String, usize> = HashMap::new();
        for (i, texture) in asset.textures.iter().enumerate() {
            if !used[i] {
                continue;
            }
            let Some((bytes, mime)) = encoded(texture, self.path)? else { continue };
            let image = if self.binary {
                let view = self.view(BinPart::Bytes(bytes), None);
                json::Image {
                    buffer_view: Some(view),
                    mime_type: Some(json::image::MimeType(mime.to_owned())),
                    name: Some(texture.name.clone()),
                    uri: None,
                    extensions: None,
                    extras: Default::default(),
                }
            } else {
                let extension = if mime == "image/png" { "png" } else { "jpg" };
                let base = Path::new(&texture.name)
                    .file_stem()
                    .map_or_else(|| format!("texture{i}"), |s| s.to_string_lossy().into_owned());
                let base = format!("{}_{}", self.stem, safe_name(&base));
                let n = names.entry(base.clone()).or_default();
                let file = if *n == 0 {
                    format!("{base}.{extension}")
                } else {
                    format!("{base}_{n}.{extension}")
                };
                *n += 1;
                self.side_files.push((file.clone(), bytes));
                json::Image {
                    buffer_view: None,
                    mime_type: None,
                    name: Some(texture.name.clone()),
                    uri: Some(file),
                    extensions: None,
                    extras: Default::default(),
                }
            };
            let image = self.root.push(image);
            let sampler = *sampler.get_or_insert_with(|| {
                self.root.push(json::texture::Sampler {
                    mag_filter: Some(Checked::Valid(json::texture::MagFilter::Linear)),
                    min_filter: Some(Checked::Valid(json::texture::MinFilter::LinearMipmapLinear)),
                    ..Default::default()
                })
            });
            out[i] = Some(self.root.push(json::Texture {
                name: None,
                sampler: Some(sampler),
                source: image,
                extensions: None,
                extras: Default::default(),
            }));
        }
        Ok(out)
    }

    fn material(
        &mut self,
        m: &Material,
        textures: &[Option<json::Index<json::Texture>>],
    ) -> json::Material {
        fn lookup<'r>(
            r: &'r Option<TextureRef>,
            textures: &[Option<json::Index<json::Texture>>],
        ) -> Option<(json::Index<json::Texture>, &'r TextureRef)> {
            r.as_ref().and_then(|r| textures.get(r.texture).copied().flatten().map(|t| (t, r)))
        }
        let base_color_texture = lookup(&m.base_color_texture, textures).map(|(index, r)| {
            let extensions = r.transform.map(|t| {
                self.use_extension("KHR_texture_transform");
                json::extensions::texture::Info {
                    texture_transform: Some(texture_transform(t, r.tex_coord)),
                    others: Default::default(),
                }
            });
            json::texture::Info {
                index,
                tex_coord: r.tex_coord,
                extensions,
                extras: Default::default(),
            }
        });
        let normal_texture = lookup(&m.normal_texture, textures).map(|(index, r)| {
            let extensions = r.transform.map(|t| {
                self.use_extension("KHR_texture_transform");
                let mut others = serde_json::Map::new();
                others.insert("KHR_texture_transform".to_owned(), serde_json::json!({ "offset": t.offset, "rotation": t.rotation, "scale": t.scale }));
                json::extensions::material::NormalTexture { others }
            });
            json::material::NormalTexture { index, scale: m.normal_scale, tex_coord: r.tex_coord, extensions, extras: Default::default() }
        });
        let alpha = m.base_color[3];
        json::Material {
            alpha_mode: Checked::Valid(if alpha < 1.0 {
                json::material::AlphaMode::Blend
            } else {
                json::material::AlphaMode::Opaque
            }),
            double_sided: m.double_sided,
            name: Some(m.name.clone()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(
                    m.base_color.map(|c| c.clamp(0.0, 1.0)),
                ),
                base_color_texture,
                metallic_factor: json::material::StrengthFactor(m.metallic.clamp(0.0, 1.0)),
                roughness_factor: json::material::StrengthFactor(m.roughness.clamp(0.0, 1.0)),
                ..Default::default()
            },
            normal_texture,
            ..Default::default()
        }
    }

    fn use_extension(&mut self, name: &str) {
        if !self.root.extensions_used.iter().any(|e| e == name) {
            self.root.extensions_used.push(name.to_owned());
        }
    }
}

/// KHR_texture_transform of a texture read through `tex_coord`. The extension's own
/// `texCoord` repeats the texture info's: gltf-json 1.4.1 writes `None` as `null`, which the
/// validator rejects.
fn texture_transform(
    t: UvTransform,
    tex_coord: u32,
) -> json::extensions::texture::TextureTransform {
    json::extensions::texture::TextureTransform {
        offset: json::extensions::texture::TextureTransformOffset(t.offset),
        rotation: json::extensions::texture::TextureTransformRotation(t.rotation),
        scale: json::extensions::texture::TextureTransformScale(t.scale),
        tex_coord: Some(tex_coord),
        extras: Default::default(),
    }
}

/// A node with the transform as translation / rotation / scale where it decomposes, else as
/// a matrix; the identity writes nothing.
fn node_with_transform(m: Mat4) -> json::Node {
    let mut node = json::Node::default();
    if m == Mat4::IDENTITY {
        return node;
    }
    let (s, r, t) = m.to_scale_rotation_translation();
    let r = r.normalize();
    let tolerance = 1e-5 * m.to_cols_array().iter().fold(1.0f32, |a, &x| a.max(x.abs()));
    if Mat4::from_scale_rotation_translation(s, r, t).abs_diff_eq(m, tolerance)
        && s.is_finite()
        && r.is_finite()
    {
        if t != Vec3::ZERO {
            node.translation = Some(t.to_array());
        }
        if r != Quat::IDENTITY {
            node.rotation = Some(json::scene::UnitQuaternion(r.to_array()));
        }
        if s != Vec3::ONE {
            node.scale = Some(s.to_array());
        }
    } else {
        node.matrix = Some(m.to_cols_array());
    }
    node
}

/// Where the asset's nodes went in the written document.
struct Written {
    /// Per asset node, its written node (empty when the hierarchy was written flat).
    nodes: Vec<json::Index<json::Node>>,
    /// Per asset node, the written nodes that carry its meshes (the node itself for one
    /// object, a child per object for several).
    meshes: Vec<Vec<json::Index<json::Node>>>,
}

/// What skins and morph weights the writer gives each object.
struct Deform {
    /// Per skin: each joint node's index in the skin's joints.
    joints: Vec<HashMap<u32, u16>>,
    /// Per object: the skin its JOINTS index, where it is written with one.
    skin: Vec<Option<usize>>,
    /// Per object: its node's default morph weights, where the node gives some.
    weights: Vec<Option<Vec<f32>>>,
}

impl Deform {
    /// Objects are written skinned where the hierarchy is written, their node names a
    /// writable skin (see [`skin_writable`]) and every joint they weigh is one of its joints.
    fn of(asset: &Asset, hierarchy: bool) -> Self {
        let joints: Vec<HashMap<u32, u16>> = asset
            .skins
            .iter()
            .map(|skin| {
                skin.joints
                    .iter()
                    .enumerate()
                    .filter_map(|(k, &j)| Some((u32::try_from(j).ok()?, u16::try_from(k).ok()?)))
                    .collect()
            })
            .collect();
        let n = asset.model.objects.len();
        let mut deform = Self { joints, skin: vec![None; n], weights: vec![None; n] };
        for node in &asset.nodes {
            for &o in node.objects.iter().filter(|&&o| o < n) {
                deform.weights[o] = (!node.weights.is_empty()).then(|| node.weights.clone());
                let Some(k) = node.skin.filter(|&k| hierarchy && skin_writable(asset, k)) else {
                    continue;
                };
                let object = &asset.model.objects[o];
                let known = object.skin.iter().all(|set| {
                    set.joints.iter().zip(&set.weights).all(|(j, w)| {
                        (0..4).all(|i| w[i] <= 0.0 || deform.joints[k].contains_key(&j[i]))
                    })
                });
                if known && !object.skin.is_empty() {
                    deform.skin[o] = Some(k);
                }
            }
        }
        deform
    }

    /// The joint indices of object `o`'s skin, where it is written skinned.
    fn joints_of(&self, o: usize) -> Option<&HashMap<u32, u16>> {
        self.skin[o].map(|k| &self.joints[k])
    }

    /// The number of morph targets every object of node `node` has, where they agree and
    /// are not zero.
    fn morph_targets_of(&self, asset: &Asset, node: usize) -> Option<usize> {
        let objects = &asset.nodes.get(node)?.objects;
        let counts: Vec<usize> = objects
            .iter()
            .filter_map(|&o| asset.model.objects.get(o))
            .map(|o| o.morph_targets.len())
            .collect();
        let first = *counts.first()?;
        (first > 0 && counts.iter().all(|&c| c == first)).then_some(first)
    }
}

/// Whether a writable skin has joints in more than one tree of the node hierarchy.
fn skins_lack_a_common_root(asset: &Asset) -> bool {
    let top = |mut n: usize| {
        // Parents come before children (checked by `hierarchy_matches`): this ends.
        while let Some(p) = asset.nodes[n].parent {
            n = p;
        }
        n
    };
    (0..asset.skins.len()).filter(|&k| skin_writable(asset, k)).any(|k| {
        let joints = &asset.skins[k].joints;
        joints.iter().any(|&j| top(j) != top(joints[0]))
    })
}

/// Whether skin `k` can be written: joints that are nodes of the asset, no more than JOINTS'
/// u16 can index, one inverse bind matrix each, all finite.
fn skin_writable(asset: &Asset, k: usize) -> bool {
    asset.skins.get(k).is_some_and(|skin| {
        !skin.joints.is_empty()
            && skin.joints.len() <= usize::from(u16::MAX)
            && skin.joints.iter().all(|&j| j < asset.nodes.len())
            && skin.inverse_bind_matrices.len() == skin.joints.len()
            && skin.inverse_bind_matrices.iter().all(|m| m.is_finite())
    })
}

/// Whether the asset's nodes describe its objects: every object carried by exactly one node,
/// parents before children, and each object's transform the composition of its node chain
/// (a skinned node's objects have none: they are placed by their joints).
fn hierarchy_matches(asset: &Asset) -> bool {
    if asset.nodes.is_empty() {
        return false;
    }
    let mut carried = vec![0usize; asset.model.objects.len()];
    let mut globals: Vec<Mat4> = Vec::with_capacity(asset.nodes.len());
    for (i, node) in asset.nodes.iter().enumerate() {
        let parent = match node.parent {
            Some(p) if p < i => globals[p],
            Some(_) => return false,
            None => Mat4::IDENTITY,
        };
        let global = parent * node.local_transform;
        globals.push(global);
        for &object in &node.objects {
            let Some(o) = asset.model.objects.get(object) else { return false };
            carried[object] += 1;
            if node.skin.is_some() && o.transform.is_none() {
                continue;
            }
            let tolerance =
                1e-5 * global.to_cols_array().iter().fold(1.0f32, |a, &x| a.max(x.abs()));
            if !o.model_transform().abs_diff_eq(global, tolerance) {
                return false;
            }
        }
    }
    carried.iter().all(|&n| n == 1)
}
