//! Skin seams closed on an asset: [`seamlit_mesh::match_skin_seams`] on its model, then every
//! joint an object's influences now name added to its skin, so that writers can store them.

use glam::Mat4;
use seamlit_mesh::SkinMatch;

use crate::asset::Asset;
use crate::pose::{Pose, node_of};

/// Gives every copy of a welded position the same skin influences where the asset's skinned
/// objects disagree there (see [`seamlit_mesh::match_skin_seams`]), and appends to each
/// object's skin the joints it now names but lacked, with the inverse bind matrix another
/// skin gives that joint (else the inverse of the joint's rest transform, the bind pose a
/// skin without one implies). Records what changed in [`Asset::skins_changed`]. `copies`:
/// [`seamlit_mesh::shared_copies`] of the model.
pub fn match_skin_seams(asset: &mut Asset, copies: &[Vec<(u32, u32)>]) -> SkinMatch {
    let matched = seamlit_mesh::match_skin_seams(&mut asset.model, copies);
    let mut rest: Option<Pose> = None;
    for (o, _) in matched.objects.iter().enumerate().filter(|&(_, &changed)| changed) {
        push_unique(&mut asset.skins_changed.objects, o);
        let Some(skin) = node_of(asset, o).and_then(|n| asset.nodes[n].skin) else { continue };
        let mut named: Vec<usize> = asset.model.objects[o]
            .skin
            .iter()
            .flat_map(|set| set.joints.iter().zip(&set.weights))
            .flat_map(|(j, w)| j.iter().zip(w).filter(|&(_, &w)| w > 0.0).map(|(&j, _)| j as usize))
            .collect();
        named.sort_unstable();
        named.dedup();
        for joint in named {
            if asset.skins[skin].joints.contains(&joint) {
                continue;
            }
            let from_other = asset.skins.iter().find_map(|s| {
                let k = s.joints.iter().position(|&j| j == joint)?;
                s.inverse_bind_matrices.get(k).copied()
            });
            let inverse_bind = from_other.unwrap_or_else(|| {
                let rest = rest.get_or_insert_with(|| Pose::rest(asset));
                rest.globals.get(joint).map_or(Mat4::IDENTITY, |g| g.inverse())
            });
            asset.skins[skin].joints.push(joint);
            asset.skins[skin].inverse_bind_matrices.push(inverse_bind);
            push_unique(&mut asset.skins_changed.skins, skin);
        }
    }
    matched
}

fn push_unique(list: &mut Vec<usize>, value: usize) {
    if !list.contains(&value) {
        list.push(value);
    }
}
