//! Animation stacks as [`Animation`]s: each stack baked by ufbx at the file's frame rate
//! (`ufbx::bake_anim`: layers blended, Euler rotations and pivots resolved into translation,
//! rotation quaternion and scale per node, keys where the curves have them and resampled
//! between), each node's three properties a linear channel; and blend channels' weights as
//! a mesh node's `Weights` channel.

use std::collections::HashMap;

use seamlit_asset::{Animation, Channel, Interpolation, Property, Sampler};

use super::mesh::blend_shapes;
use super::scene::f32_of;

/// The scene's animation stacks, in file order; `node_of` gives a ufbx node's index in the
/// asset's nodes. A stack ufbx cannot bake gets a warning instead.
pub(super) fn animations(
    scene: &ufbx::Scene,
    node_of: impl Fn(&ufbx::Node) -> Option<usize>,
    path: &std::path::Path,
    warnings: &mut Vec<String>,
) -> Vec<Animation> {
    let rate = scene.settings.frames_per_second;
    let rate = if rate.is_finite() && rate > 0.0 { rate } else { 30.0 };
    let mut out = Vec::new();
    for stack in scene.anim_stacks.iter() {
        let options =
            ufbx::BakeOpts { resample_rate: rate, minimum_sample_rate: rate, ..Default::default() };
        let baked = match ufbx::bake_anim(scene, &stack.anim, options) {
            Ok(baked) => baked,
            Err(error) => {
                warnings.push(format!(
                    "{}: animation {:?} is not read: ufbx cannot bake it: {}",
                    path.display(),
                    stack.element.name.as_ref() as &str,
                    error.description.as_ref() as &str
                ));
                continue;
            }
        };
        let mut channels = Vec::new();
        for baked_node in baked.nodes.iter() {
            let Some(ufbx_node) = scene.nodes.get(baked_node.typed_id as usize) else { continue };
            let Some(node) = node_of(ufbx_node) else { continue };
            let vec3 = |keys: &ufbx::List<ufbx::BakedVec3>| Sampler {
                interpolation: Interpolation::Linear,
                times: keys.iter().map(|k| f32_of(k.time)).collect(),
                values: keys
                    .iter()
                    .flat_map(|k| [k.value.x, k.value.y, k.value.z].map(f32_of))
                    .collect(),
            };
            let rotation = Sampler {
                interpolation: Interpolation::Linear,
                times: baked_node.rotation_keys.iter().map(|k| f32_of(k.time)).collect(),
                values: baked_node
                    .rotation_keys
                    .iter()
                    .flat_map(|k| [k.value.x, k.value.y, k.value.z, k.value.w].map(f32_of))
                    .collect(),
            };
            let samplers = [
                (Property::Translation, vec3(&baked_node.translation_keys)),
                (Property::Rotation, rotation),
                (Property::Scale, vec3(&baked_node.scale_keys)),
            ];
            for (property, sampler) in samplers {
                if !sampler.times.is_empty() {
                    channels.push(Channel { node, property, sampler });
                }
            }
        }
        channels.extend(weights(scene, &baked, &node_of));
        out.push(Animation { name: stack.element.name.to_string(), channels });
    }
    out
}

/// Per mesh node whose blend channels are animated: a `Weights` channel over the union of
/// their key times, every target's weight at each (a channel's baked `DeformPercent`, in
/// percent, sampled linearly; a channel without keys keeps its weight).
fn weights(
    scene: &ufbx::Scene,
    baked: &ufbx::BakedAnim,
    node_of: &impl Fn(&ufbx::Node) -> Option<usize>,
) -> Vec<Channel> {
    let by_element: HashMap<u32, &ufbx::BakedElement> =
        baked.elements.iter().map(|e| (e.element_id, e)).collect();
    let mut out = Vec::new();
    for ufbx_node in scene.nodes.iter() {
        let (Some(mesh), Some(node)) = (ufbx_node.mesh.as_ref(), node_of(ufbx_node)) else {
            continue;
        };
        let keys: Vec<Option<&ufbx::List<ufbx::BakedVec3>>> = blend_shapes(mesh)
            .map(|(channel, _)| {
                by_element.get(&channel.element.element_id).and_then(|e| {
                    e.props.iter().find(|p| &*p.name == "DeformPercent").map(|p| &p.keys)
                })
            })
            .collect();
        if keys.iter().all(Option::is_none) {
            continue;
        }
        let mut times: Vec<f64> =
            keys.iter().flatten().flat_map(|k| k.iter().map(|k| k.time)).collect();
        times.sort_by(f64::total_cmp);
        times.dedup();
        let defaults: Vec<f64> = blend_shapes(mesh).map(|(c, _)| c.weight).collect();
        let mut values = Vec::with_capacity(times.len() * keys.len());
        for &t in &times {
            for (k, channel_keys) in keys.iter().enumerate() {
                let value = match channel_keys {
                    Some(list) if !list.is_empty() => ufbx::evaluate_baked_vec3(list, t).x / 100.0,
                    _ => defaults[k],
                };
                values.push(f32_of(value));
            }
        }
        out.push(Channel {
            node,
            property: Property::Weights,
            sampler: Sampler {
                interpolation: Interpolation::Linear,
                times: times.into_iter().map(f32_of).collect(),
                values,
            },
        });
    }
    out
}
