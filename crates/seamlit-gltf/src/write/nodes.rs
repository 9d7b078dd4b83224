//! The node hierarchy: the asset's own where it matches the objects, else one root node per
//! object.

use glam::{Mat4, Quat, Vec3};
use gltf_json as json;

use super::Writer;
use super::deform::skins_lack_a_common_root;
use seamlit_asset::Asset;

impl Writer<'_> {
    /// The node hierarchy: the asset's own when it matches the objects (`hierarchy`), else
    /// flat. Returns where the asset's nodes went (empty when flat).
    pub(super) fn nodes(
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
pub(super) struct Written {
    /// Per asset node, its written node (empty when the hierarchy was written flat).
    pub(super) nodes: Vec<json::Index<json::Node>>,
    /// Per asset node, the written nodes that carry its meshes (the node itself for one
    /// object, a child per object for several).
    pub(super) meshes: Vec<Vec<json::Index<json::Node>>>,
}

/// Whether the asset's nodes describe its objects: every object carried by exactly one node,
/// parents before children, and each object's transform the composition of its node chain
/// (a skinned node's objects have none: they are placed by their joints).
pub(super) fn hierarchy_matches(asset: &Asset) -> bool {
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
