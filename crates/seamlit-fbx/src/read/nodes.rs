//! The node tree: every ufbx node but the root, parents before children, with its name and
//! its transform relative to its parent (ufbx's `node_to_parent`, pivots resolved; a node
//! below the root takes the root's transform too, which after ufbx's conversion is the
//! identity), also as translation, rotation and scale where it is one.

use glam::{DQuat, DVec3};

use seamlit_asset::Node;
use seamlit_asset::Trs;

use super::scene::mat4;

/// The converted tree, and where each ufbx node went.
pub(super) struct Tree {
    /// The nodes, parents before children (depth first, in the file's child order).
    pub nodes: Vec<Node>,
    /// Per ufbx node (by `typed_id`): its index in `nodes`, `None` for the root.
    pub index: Vec<Option<usize>>,
    /// Per entry of `nodes`: the ufbx node's `typed_id`.
    pub typed: Vec<usize>,
}

/// The scene's nodes in depth-first order from the root's children.
pub(super) fn tree(scene: &ufbx::Scene) -> Tree {
    let mut tree =
        Tree { nodes: Vec::new(), index: vec![None; scene.nodes.len()], typed: Vec::new() };
    // (node, parent index); a stack, children pushed in reverse so they come out in order.
    let mut stack: Vec<(&ufbx::Node, Option<usize>)> =
        scene.root_node.children.iter().rev().map(|c| (c.as_ref(), None)).collect();
    while let Some((node, parent)) = stack.pop() {
        let typed = node.element.typed_id as usize;
        if tree.index.get(typed).is_none_or(Option::is_some) {
            continue; // Out of range or seen: ufbx gives a tree, this only guards.
        }
        let local = match parent {
            Some(_) => mat4(&node.node_to_parent),
            None => mat4(&node.node_to_world),
        };
        let i = tree.nodes.len();
        tree.index[typed] = Some(i);
        tree.typed.push(typed);
        let t = &node.local_transform;
        let trs = Trs {
            translation: DVec3::new(t.translation.x, t.translation.y, t.translation.z).as_vec3(),
            rotation: DQuat::from_xyzw(t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w)
                .as_quat()
                .normalize(),
            scale: DVec3::new(t.scale.x, t.scale.y, t.scale.z).as_vec3(),
        };
        tree.nodes.push(Node {
            name: node.element.name.to_string(),
            local_transform: local,
            parent,
            objects: Vec::new(),
            // What baked animation channels replace (ufbx bakes `local_transform`), where it
            // is the matrix (no shear from a non-uniform scale above a rotation).
            trs: trs
                .matrix()
                .abs_diff_eq(
                    local,
                    1e-5 * local.abs().to_cols_array().iter().fold(1.0, |a: f32, &x| a.max(x)),
                )
                .then_some(trs),
            skin: None,
            weights: Vec::new(),
        });
        stack.extend(node.children.iter().rev().map(|c| (c.as_ref(), Some(i))));
    }
    tree
}
