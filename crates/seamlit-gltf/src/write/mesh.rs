//! An object as a mesh of one triangle primitive: its vertex attributes, skin influences,
//! indices and morph targets.

use std::collections::{BTreeMap, HashMap};

use glam::Vec3;
use gltf_json as json;
use json::accessor::Type;
use json::mesh::Semantic;
use json::validation::Checked;
use seamlit_mesh::{Object, VAxis};

use super::Writer;
use super::bin::BinPart;
use super::deform::Deform;

/// A primitive's attributes.
type Attributes = BTreeMap<Checked<Semantic>, json::Index<json::Accessor>>;

impl<'a> Writer<'a> {
    /// Object `index` as a mesh of one triangle primitive: its attributes, its influences
    /// where `deform` writes it skinned, its indices, its morph targets (with the node's
    /// default weights and `extras.targetNames`) and its material.
    pub(super) fn mesh(
        &mut self,
        object: &'a Object,
        v_axis: VAxis,
        material_count: usize,
        deform: &Deform,
        index: usize,
    ) -> json::Index<json::Mesh> {
        let mut attributes = self.vertex_attributes(object, v_axis);
        if let Some(joints) = deform.joints_of(index) {
            self.influences(object, joints, &mut attributes);
        }
        let indices = self.indices(object);
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
        self.root.push(json::Mesh {
            extensions: None,
            extras: target_names(object),
            name: Some(object.name.clone()),
            primitives: vec![primitive],
            weights,
        })
    }

    /// POSITION (with its bounds), NORMAL, TANGENT (only with NORMAL), TEXCOORD_0 and _1
    /// (V flipped where the model's runs up) and COLOR_0, in that order.
    fn vertex_attributes(&mut self, object: &'a Object, v_axis: VAxis) -> Attributes {
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
        attributes
    }

    /// JOINTS_n (as u16 indices into the skin's joints, `joints`) and WEIGHTS_n of every
    /// influence set, added to `attributes`.
    fn influences(
        &mut self,
        object: &'a Object,
        joints: &HashMap<u32, u16>,
        attributes: &mut Attributes,
    ) {
        let n = object.positions.len();
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
            let accessor =
                self.push_accessor(view, n, json::accessor::ComponentType::U16, Type::Vec4, None);
            attributes.insert(Checked::Valid(Semantic::Joints(set)), accessor);
            attributes.insert(
                Checked::Valid(Semantic::Weights(set)),
                self.float_accessor(BinPart::Weights(&influences.weights), n, Type::Vec4, None),
            );
        }
    }

    /// The triangles' indices: u16 where every index fits, else u32.
    fn indices(&mut self, object: &'a Object) -> json::Index<json::Accessor> {
        let count = object.triangles.len() * 3;
        let (piece, component) = if object.positions.len() <= usize::from(u16::MAX) {
            (BinPart::Indices16(&object.triangles), json::accessor::ComponentType::U16)
        } else {
            (BinPart::Indices32(&object.triangles), json::accessor::ComponentType::U32)
        };
        self.accessor(
            piece,
            count,
            component,
            Type::Scalar,
            json::buffer::Target::ElementArrayBuffer,
            None,
        )
    }

    /// The morph targets of an object: POSITION deltas (with the bounds the specification
    /// requires), and NORMAL and TANGENT deltas where every target has them (the attributes of
    /// all targets of a primitive are the same).
    pub(super) fn morph_targets(
        &mut self,
        object: &'a Object,
    ) -> Option<Vec<json::mesh::MorphTarget>> {
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
}

/// `extras.targetNames` (glTF has no target names; this is the convention readers know),
/// where any target has a name.
fn target_names(object: &Object) -> Option<Box<serde_json::value::RawValue>> {
    let names: Vec<&str> = object.morph_targets.iter().map(|t| t.name.as_str()).collect();
    names
        .iter()
        .any(|n| !n.is_empty())
        .then(|| serde_json::value::to_raw_value(&serde_json::json!({ "targetNames": names })).ok())
        .flatten()
}
