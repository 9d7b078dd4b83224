//! Skins: a skinned mesh's clusters as the joints of an [`seamlit_asset::Skin`], each with its
//! binding (ufbx's `geometry_to_bone`) as the inverse bind matrix from bind-pose model space; the vertices' weights as
//! [`Influences`] sets of four (joints as [`seamlit_asset::Asset::nodes`] indices, weights summing
//! to 1); the vertices moved into bind-pose model space (the object has no transform, as a
//! skinned glTF mesh is placed by its joints only).
//!
//! A vertex that no cluster weighs (a half-skinned mesh) follows its mesh's node: that node
//! is one more joint, bound where the mesh was bound.

use glam::{Mat3, Mat4};
use seamlit_mesh::{Influences, Object};

use super::scene::{f32_of, mat4};
use seamlit_asset::Skin;

/// A mesh instance's skin, and the geometry-to-model matrix its vertices were bound with.
pub(super) struct Bound {
    pub skin: Skin,
    /// Geometry space to model space at bind time: the vertices go through it.
    pub bind: Mat4,
    /// Per cluster: its joint's index in `skin.joints`.
    clusters: Vec<u32>,
    /// The joint (index in `skin.joints`) of vertices no cluster weighs, where there are
    /// such vertices.
    own: Option<u32>,
}

/// The skin of a mesh instance whose mesh has a skin deformer (the first, as glTF has one
/// skin per mesh), or `None`. `joint_of` gives a ufbx node's index in the asset's nodes;
/// `node` is the instance's own index there.
pub(super) fn bound(
    node: &ufbx::Node,
    mesh: &ufbx::Mesh,
    node_index: usize,
    joint_of: impl Fn(&ufbx::Node) -> Option<usize>,
) -> Option<Bound> {
    let deformer = mesh.skin_deformers.first()?;
    // The geometry's world transform at bind time: a bone's bind pose times the binding
    // from the geometry to it (ufbx's cluster `geometry_to_world` is the current pose's).
    let bind = deformer.clusters.first().map_or_else(
        || mat4(&node.geometry_to_world),
        |c| mat4(&c.bind_to_world) * mat4(&c.geometry_to_bone),
    );
    let to_geometry = bind.inverse();
    let mut joints: Vec<usize> = Vec::new();
    let mut inverse_bind_matrices = Vec::new();
    let mut clusters = Vec::new();
    let mut joint = |n: usize, inverse_bind: Mat4| -> u32 {
        // One joint per node: two clusters of one bone share it.
        let at = joints.iter().position(|&j| j == n).unwrap_or_else(|| {
            joints.push(n);
            inverse_bind_matrices.push(inverse_bind);
            joints.len() - 1
        });
        u32::try_from(at).unwrap_or(u32::MAX)
    };
    for cluster in deformer.clusters.iter() {
        let n = cluster.bone_node.as_ref().and_then(|b| joint_of(b)).unwrap_or(node_index);
        // Bind-pose model space to the bone: back to the geometry, then ufbx's binding.
        clusters.push(joint(n, mat4(&cluster.geometry_to_bone) * to_geometry));
    }
    // The mesh's node, bound where its geometry was (bind = node_to_world * geometry_to_node),
    // only where a vertex needs it (a joint outside the skeleton's tree is not always valid).
    let unweighted = deformer.vertices.iter().any(|v| v.num_weights == 0);
    let node_at_bind = bind * mat4(&node.geometry_to_node).inverse();
    let own = unweighted.then(|| joint(node_index, node_at_bind.inverse()));
    let skin = Skin { name: deformer.element.name.to_string(), joints, inverse_bind_matrices };
    Some(Bound { skin, bind, clusters, own })
}

impl Bound {
    /// Moves an object (geometry space) into bind-pose model space and gives it its
    /// influences: `corners[v]` is vertex `v`'s face corner in the mesh.
    pub(super) fn apply(&self, object: &mut Object, mesh: &ufbx::Mesh, corners: &[u32]) {
        let Some(deformer) = mesh.skin_deformers.first() else { return };
        let linear = Mat3::from_mat4(self.bind);
        let normal_matrix = linear.inverse().transpose();
        for p in &mut object.positions {
            *p = self.bind.transform_point3(*p);
        }
        for n in object.normals.iter_mut().flatten() {
            *n = (normal_matrix * *n).normalize_or_zero();
        }
        for t in object.tangents.iter_mut().flatten() {
            *t = (linear * t.truncate()).normalize_or_zero().extend(t.w);
        }
        for target in &mut object.morph_targets {
            for d in &mut target.position_deltas {
                *d = linear * *d;
            }
        }
        object.transform = None;
        // Per vertex, its (joint, weight) pairs, heaviest first, summing to 1.
        let weighted: Vec<Vec<(u32, f32)>> = corners
            .iter()
            .map(|&c| {
                let vertex = mesh.vertex_indices.get(c as usize).copied().unwrap_or(0);
                let mut pairs: Vec<(u32, f32)> = deformer
                    .vertices
                    .get(vertex as usize)
                    .map(|v| {
                        let begin = v.weight_begin as usize;
                        let end = begin + v.num_weights as usize;
                        deformer.weights.get(begin..end).unwrap_or_default()
                    })
                    .unwrap_or_default()
                    .iter()
                    .filter_map(|w| {
                        let joint = *self.clusters.get(w.cluster_index as usize)?;
                        let weight = f32_of(w.weight);
                        (weight > 0.0 && weight.is_finite()).then_some((joint, weight))
                    })
                    .collect();
                pairs.sort_by(|a, b| b.1.total_cmp(&a.1));
                let total: f32 = pairs.iter().map(|p| p.1).sum();
                if total > 0.0 {
                    pairs.iter_mut().for_each(|p| p.1 /= total);
                } else {
                    pairs = vec![(self.own.unwrap_or(0), 1.0)];
                }
                pairs
            })
            .collect();
        let sets = weighted.iter().map(Vec::len).max().unwrap_or(1).div_ceil(4).max(1);
        object.skin = (0..sets)
            .map(|set| {
                let mut influences = Influences {
                    joints: Vec::with_capacity(weighted.len()),
                    weights: Vec::with_capacity(weighted.len()),
                };
                for pairs in &weighted {
                    let mut joints = [0u32; 4];
                    let mut weights = [0f32; 4];
                    for (k, &(joint, weight)) in pairs.iter().skip(4 * set).take(4).enumerate() {
                        let node = self.skin.joints.get(joint as usize).copied().unwrap_or(0);
                        joints[k] = u32::try_from(node).unwrap_or(u32::MAX);
                        weights[k] = weight;
                    }
                    influences.joints.push(joints);
                    influences.weights.push(weights);
                }
                influences
            })
            .collect();
    }
}
