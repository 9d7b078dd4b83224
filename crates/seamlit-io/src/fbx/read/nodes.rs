//! The node tree: every ufbx node but the root, parents before children, with its name and
//! its transform relative to its parent (ufbx's `node_to_parent`, pivots resolved; a node
//! below the root takes the root's transform too, which after ufbx's conversion is the
//! identity).

use crate::asset::Node;

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
        tree.nodes.push(Node {
            name: node.element.name.to_string(),
            local_transform: local,
            parent,
            objects: Vec::new(),
        });
        stack.extend(node.children.iter().rev().map(|c| (c.as_ref(), Some(i))));
    }
    tree
}
