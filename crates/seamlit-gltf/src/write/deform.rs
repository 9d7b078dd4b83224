//! Which skins and morph weights the writer gives each object.

use std::collections::HashMap;

use seamlit_asset::Asset;

/// What skins and morph weights the writer gives each object.
pub(super) struct Deform {
    /// Per skin: each joint node's index in the skin's joints.
    pub(super) joints: Vec<HashMap<u32, u16>>,
    /// Per object: the skin its JOINTS index, where it is written with one.
    pub(super) skin: Vec<Option<usize>>,
    /// Per object: its node's default morph weights, where the node gives some.
    pub(super) weights: Vec<Option<Vec<f32>>>,
}

impl Deform {
    /// Objects are written skinned where the hierarchy is written, their node names a
    /// writable skin (see [`skin_writable`]) and every joint they weigh is one of its joints.
    pub(super) fn of(asset: &Asset, hierarchy: bool) -> Self {
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
    pub(super) fn joints_of(&self, o: usize) -> Option<&HashMap<u32, u16>> {
        self.skin[o].map(|k| &self.joints[k])
    }

    /// The number of morph targets every object of node `node` has, where they agree and
    /// are not zero.
    pub(super) fn morph_targets_of(&self, asset: &Asset, node: usize) -> Option<usize> {
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
pub(super) fn skins_lack_a_common_root(asset: &Asset) -> bool {
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
pub(super) fn skin_writable(asset: &Asset, k: usize) -> bool {
    asset.skins.get(k).is_some_and(|skin| {
        !skin.joints.is_empty()
            && skin.joints.len() <= usize::from(u16::MAX)
            && skin.joints.iter().all(|&j| j < asset.nodes.len())
            && skin.inverse_bind_matrices.len() == skin.joints.len()
            && skin.inverse_bind_matrices.iter().all(|m| m.is_finite())
    })
}
