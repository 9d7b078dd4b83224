//! What deforms a primitive: its skin influences (`JOINTS_n`/`WEIGHTS_n`) and its morph
//! targets' position deltas, read into [`seamlit_mesh::Influences`] and
//! [`seamlit_mesh::MorphTarget`].
//!
//! Joints are read as the accessor holds them (indices into a skin's `joints`), and mapped
//! to node indices per instance by [`map_joints`], since one mesh may be used by nodes with
//! different skins. Morph targets' `NORMAL`/`TANGENT` deltas are not read: `fix` computes
//! them where it computes normals, and the pass-through duplicates the input's otherwise.

use std::path::Path;

use bytes::Bytes;
use glam::Vec3;
use gltf::accessor::{DataType, Dimensions};
use seamlit_mesh::{Influences, MorphTarget};

use super::Reader;
use crate::decode::quantized::read_floats;
use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::GltfKind;

/// How many `JOINTS_n`/`WEIGHTS_n` sets are read (glTF requires support for one; files with
/// more than eight influences per vertex are rare).
const SETS: u32 = 2;

impl Reader<'_> {
    /// The primitive's skin influences (joints as skin-joint indices) and morph targets
    /// (position deltas only), each checked like the base attributes: type, bounds, sparse
    /// indices, count equal to `vertex_count`, finite values.
    pub(super) fn deformation(
        &self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        buffers: &[Bytes],
        vertex_count: usize,
    ) -> Result<(Vec<Influences>, Vec<MorphTarget>), IoError> {
        let skin = self.influences(primitive, buffers, vertex_count)?;
        let targets = self.morph_targets(mesh, primitive, buffers, vertex_count)?;
        Ok((skin, targets))
    }

    /// The `JOINTS_n`/`WEIGHTS_n` sets, up to [`SETS`], until the first `n` without both.
    fn influences(
        &self,
        primitive: &gltf::Primitive<'_>,
        buffers: &[Bytes],
        vertex_count: usize,
    ) -> Result<Vec<Influences>, IoError> {
        let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
        let mut skin = Vec::new();
        for set in 0..SETS {
            let (Some(joints), Some(weights)) = (
                primitive.get(&gltf::Semantic::Joints(set)),
                primitive.get(&gltf::Semantic::Weights(set)),
            ) else {
                break;
            };
            let (jn, wn) = (format!("JOINTS_{set}"), format!("WEIGHTS_{set}"));
            self.checked(&joints, buffers, &[DataType::U8, DataType::U16], &jn, vertex_count)?;
            let weight_types = [DataType::F32, DataType::U8, DataType::U16];
            self.checked(&weights, buffers, &weight_types, &wn, vertex_count)?;
            let weights_index = weights.index();
            // An accessor without a view or sparse data is zeros; the gltf reader gives nothing.
            let joints: Vec<[u32; 4]> = super::lenient::zeros_without_view(
                Some(&joints),
                reader.read_joints(set).map(|it| it.into_u16().map(|j| j.map(u32::from)).collect()),
            )
            .unwrap_or_default();
            let weights: Vec<[f32; 4]> = super::lenient::zeros_without_view(
                Some(&weights),
                reader.read_weights(set).map(|it| it.into_f32().collect()),
            )
            .unwrap_or_default();
            if let Some(bad) = weights.iter().position(|w| !w.iter().all(|x| x.is_finite())) {
                return Err(IoError::gltf_data(
                    self.path.to_path_buf(),
                    GltfKind::AccessorNotFinite {
                        accessor: weights_index,
                        attribute: "WEIGHTS",
                        element: bad,
                    },
                ));
            }
            skin.push(Influences { joints, weights });
        }
        Ok(skin)
    }

    /// The morph targets' position deltas (zeros for a target without `POSITION`), named
    /// after the mesh's `extras.targetNames`.
    fn morph_targets(
        &self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        buffers: &[Bytes],
        vertex_count: usize,
    ) -> Result<Vec<MorphTarget>, IoError> {
        let mut targets = Vec::new();
        let names = target_names(mesh);
        let target_name = |k: usize| names.get(k).cloned().unwrap_or_default();
        for (k, target) in primitive.morph_targets().enumerate() {
            let Some(accessor) = target.positions() else {
                targets.push(MorphTarget {
                    name: target_name(k),
                    position_deltas: vec![Vec3::ZERO; vertex_count],
                    ..MorphTarget::default()
                });
                continue;
            };
            let name = format!("targets[{k}].POSITION");
            self.checked(&accessor, buffers, &[DataType::F32], &name, vertex_count)?;
            // Read from its own accessor: the gltf crate's `read_morph_targets` opens every
            // target's NORMAL and TANGENT accessors too, which seamlit does not read or check
            // (a count of 0 there panics in it).
            let deltas: Vec<Vec3> = super::lenient::zeros_without_view(
                Some(&accessor),
                read_floats::<3>(&accessor, buffers)
                    .map(|v| v.into_iter().map(Vec3::from_array).collect()),
            )
            .unwrap_or_default();
            if let Some(bad) = deltas.iter().position(|d| !d.is_finite()) {
                return Err(IoError::gltf_data(
                    self.path.to_path_buf(),
                    GltfKind::AccessorNotFinite {
                        accessor: accessor.index(),
                        attribute: "morph target POSITION",
                        element: bad,
                    },
                ));
            }
            targets.push(MorphTarget {
                name: target_name(k),
                position_deltas: deltas,
                ..MorphTarget::default()
            });
        }
        Ok(targets)
    }

    /// [`Reader::check_attribute`] for a `VEC3` (positions) or `VEC4` (joints, weights)
    /// accessor of one of `types`.
    fn checked(
        &self,
        accessor: &gltf::Accessor<'_>,
        buffers: &[Bytes],
        types: &[DataType],
        name: &str,
        vertex_count: usize,
    ) -> Result<(), IoError> {
        let dimensions =
            if name.ends_with("POSITION") { Dimensions::Vec3 } else { Dimensions::Vec4 };
        self.check_attribute(accessor, (dimensions, types), name, buffers, vertex_count)
    }
}

/// The names of the primitive's morph targets: its mesh's `extras.targetNames` (the
/// convention of Blender, three.js and the Khronos samples), empty where the file has none.
fn target_names(mesh: &gltf::Mesh<'_>) -> Vec<String> {
    let Some(extras) = mesh.extras().as_ref() else { return Vec::new() };
    let Ok(value) = serde_json::from_str::<serde_json::Value>(extras.get()) else {
        return Vec::new();
    };
    value["targetNames"]
        .as_array()
        .map(|names| names.iter().map(|n| n.as_str().unwrap_or_default().to_owned()).collect())
        .unwrap_or_default()
}

/// The influences `read` (joints as indices into a skin's `joints`) with their joints mapped
/// to node indices through `node`'s skin. A node without a skin gets none (glTF ignores
/// influences there).
///
/// # Errors
///
/// [`IoError::Gltf`] naming the node's skin when a joint index is past its `joints`.
pub(super) fn joint_nodes(
    read: &[Influences],
    node: &gltf::Node<'_>,
    path: &Path,
) -> Result<Vec<Influences>, IoError> {
    let Some(skin) = node.skin() else {
        return Ok(Vec::new());
    };
    let mut nodes = Vec::new();
    for joint in skin.joints() {
        // Influences name joints by 32-bit node indices.
        let Ok(node) = u32::try_from(joint.index()) else {
            return Err(IoError::TooManyElements {
                path: path.to_path_buf(),
                what: format!("the nodes that skins[{}].joints names", skin.index()),
                limit: u32::MAX as usize,
                actual: joint.index(),
            });
        };
        nodes.push(node);
    }
    let mut mapped = read.to_vec();
    for (set, influences) in mapped.iter_mut().enumerate() {
        for (v, joints) in influences.joints.iter_mut().enumerate() {
            for j in joints.iter_mut() {
                let Some(&node) = nodes.get(*j as usize) else {
                    return Err(IoError::Gltf {
                        path: path.to_path_buf(),
                        place: format!("skins[{}].joints", skin.index()),
                        kind: GltfKind::JointOutOfRange {
                            set,
                            vertex: v,
                            joint: *j,
                            joints: nodes.len(),
                        },
                    });
                };
                *j = node;
            }
        }
    }
    Ok(mapped)
}
