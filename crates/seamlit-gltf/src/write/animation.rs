//! Skins and animations, written where the asset's node hierarchy is.

use glam::Mat4;
use gltf_json as json;
use json::accessor::Type;
use json::animation::{Interpolation as Interp, Property as Path};
use json::validation::Checked;

use super::Writer;
use super::deform::{Deform, skin_writable};
use super::nodes::Written;
use seamlit_asset::Asset;
use seamlit_asset::{Channel, Interpolation, Property, Sampler};

impl Writer<'_> {
    /// The asset's skins whose joints are all written nodes: joints and inverse bind
    /// matrices; each set on the nodes that carry its meshes.
    pub(super) fn skins(&mut self, asset: &Asset, written: &Written) {
        for (k, skin) in asset.skins.iter().enumerate() {
            if !skin_writable(asset, k) {
                continue;
            }
            let joints: Vec<json::Index<json::Node>> =
                skin.joints.iter().map(|&j| written.nodes[j]).collect();
            let matrices: Vec<f32> =
                skin.inverse_bind_matrices.iter().flat_map(Mat4::to_cols_array).collect();
            let accessor = self.data_accessor(matrices, joints.len(), Type::Mat4, None);
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
    pub(super) fn animations(&mut self, asset: &Asset, written: &Written, deform: &Deform) {
        for animation in &asset.animations {
            let mut samplers = Vec::new();
            let mut channels = Vec::new();
            for channel in &animation.channels {
                let Some((path, type_, targets)) = target(asset, channel, written, deform) else {
                    continue;
                };
                #[expect(clippy::cast_possible_truncation, reason = "one sampler per channel")]
                let index = json::Index::new(samplers.len() as u32);
                samplers.push(self.sampler(&channel.sampler, type_));
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

    /// A channel's sampler: its times (with their bounds) and values (of `type_`) as data
    /// accessors, its interpolation.
    fn sampler(&mut self, sampler: &Sampler, type_: Type) -> json::animation::Sampler {
        let keys = sampler.times.len();
        let groups = if sampler.interpolation == Interpolation::CubicSpline { 3 } else { 1 };
        let components = sampler.components();
        let count = if type_ == Type::Scalar { keys * groups * components } else { keys * groups };
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
        json::animation::Sampler {
            extensions: None,
            extras: Default::default(),
            input,
            interpolation: Checked::Valid(interpolation),
            output,
        }
    }
}

/// Where a channel is written: its path, the type of its values and the written nodes it
/// moves; `None` when it cannot be (see [`writable`]; its node not written; a `Weights`
/// channel whose node's meshes do not all have as many targets as it has values per key, or
/// no written mesh node).
fn target(
    asset: &Asset,
    channel: &Channel,
    written: &Written,
    deform: &Deform,
) -> Option<(Path, Type, Vec<json::Index<json::Node>>)> {
    let components = channel.sampler.components();
    if !writable(&channel.sampler) {
        return None;
    }
    let &node = written.nodes.get(channel.node)?;
    let (path, type_, targets) = match channel.property {
        Property::Translation if components == 3 => (Path::Translation, Type::Vec3, vec![node]),
        Property::Rotation if components == 4 => (Path::Rotation, Type::Vec4, vec![node]),
        Property::Scale if components == 3 => (Path::Scale, Type::Vec3, vec![node]),
        Property::Weights if deform.morph_targets_of(asset, channel.node) == Some(components) => {
            (Path::MorphTargetWeights, Type::Scalar, written.meshes[channel.node].clone())
        }
        _ => return None,
    };
    (!targets.is_empty()).then_some((path, type_, targets))
}

/// Whether a sampler can be written: keys, a whole number of values per key, times
/// increasing, everything finite.
fn writable(sampler: &Sampler) -> bool {
    let keys = sampler.times.len();
    let components = sampler.components();
    let groups = if sampler.interpolation == Interpolation::CubicSpline { 3 } else { 1 };
    keys > 0
        && components > 0
        && sampler.values.len() == keys * groups * components
        && sampler.times.windows(2).all(|t| t[0] < t[1])
        && sampler.times.iter().chain(&sampler.values).all(|x| x.is_finite())
}
