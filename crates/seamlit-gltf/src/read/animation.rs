//! Skins and animations: read after the scene walk, with their nodes renumbered from the
//! document's to [`Asset::nodes`]' (the walk's order), and the objects' skin influences with
//! them.

use std::collections::HashMap;

use bytes::Bytes;
use glam::Mat4;
use gltf::accessor::{DataType, Dimensions};
use gltf::animation::util::ReadOutputs;
use gltf::json::validation::Checked;

use super::Reader;
use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::GltfKind;
use seamlit_asset::{Animation, Channel, Interpolation, Property, Sampler, Skin};
use seamlit_asset::{Asset, Node};

impl Reader<'_> {
    /// Renumbers the objects' joints (document nodes, as `deform::joint_nodes` maps them)
    /// into [`Asset::nodes`], reads the skins (every joint the scene walk did not reach is
    /// added as a root node without objects, with a warning) and the animations (a channel
    /// that cannot be played, its node missing or outside the scene or its path not one of
    /// glTF's four, is dropped, with one warning per animation). `json` is the document as
    /// written, which warnings follow.
    ///
    /// # Errors
    ///
    /// [`IoError::Gltf`] for an accessor outside its data, of the wrong type, holding NaN or
    /// infinity, or with fewer elements than it must have; key times not increasing.
    pub(super) fn skins_and_animations(
        &self,
        (document, json): (&gltf::Document, &serde_json::Value),
        buffers: &[Bytes],
        nodes: &mut HashMap<usize, usize>,
        asset: &mut Asset,
        warnings: &mut Vec<String>,
    ) -> Result<(), IoError> {
        // Joints outside the scene: roots of their own, so that every influence has a node.
        for skin in document.skins() {
            for joint in skin.joints() {
                if let std::collections::hash_map::Entry::Vacant(entry) = nodes.entry(joint.index())
                {
                    warnings.push(format!(
                        "{}: skins[{}] joint nodes[{}] is not in the scene; it is placed as a root",
                        self.path.display(),
                        skin.index(),
                        joint.index()
                    ));
                    entry.insert(asset.nodes.len());
                    let local = Mat4::from_cols_array_2d(&joint.transform().matrix());
                    asset.nodes.push(Node::new(joint.name().unwrap_or_default(), local, None));
                }
            }
        }
        for object in &mut asset.model.objects {
            for set in &mut object.skin {
                for joints in &mut set.joints {
                    for j in joints {
                        // Every joint of a skin is in `nodes` now.
                        let node = nodes.get(&(*j as usize)).and_then(|&n| u32::try_from(n).ok());
                        *j = node.unwrap_or(*j);
                    }
                }
            }
        }
        for skin in document.skins() {
            asset.skins.push(self.skin(&skin, buffers, nodes)?);
        }
        let documents = (document.as_json(), json);
        for animation in document.animations() {
            asset.animations.push(self.animation(&animation, documents, buffers, nodes, warnings)?);
        }
        Ok(())
    }

    fn skin(
        &self,
        skin: &gltf::Skin<'_>,
        buffers: &[Bytes],
        nodes: &HashMap<usize, usize>,
    ) -> Result<Skin, IoError> {
        let joints: Vec<usize> = skin.joints().map(|j| nodes[&j.index()]).collect();
        let mut inverse_bind_matrices = vec![Mat4::IDENTITY; joints.len()];
        if let Some(accessor) = skin.inverse_bind_matrices() {
            let name = format!("skins[{}].inverseBindMatrices", skin.index());
            self.check_accessor(&accessor, Dimensions::Mat4, &[DataType::F32], &name)?;
            self.check_sparse_indices(&accessor, buffers)?;
            let reader = skin.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
            let read: Vec<Mat4> = if without_data(&accessor) {
                vec![Mat4::ZERO; accessor.count()]
            } else {
                reader
                    .read_inverse_bind_matrices()
                    .map(|it| it.map(|m| Mat4::from_cols_array_2d(&m)).collect())
                    .unwrap_or_default()
            };
            if read.len() < joints.len() {
                return Err(self.animation_error(
                    format!("skins[{}]", skin.index()),
                    format!(
                        "inverseBindMatrices has {} matrices, the skin has {} joints",
                        read.len(),
                        joints.len()
                    ),
                ));
            }
            if let Some(bad) = read.iter().position(|m| !m.is_finite()) {
                return Err(IoError::gltf_data(
                    self.path.to_path_buf(),
                    GltfKind::AccessorNotFinite {
                        accessor: accessor.index(),
                        attribute: "inverseBindMatrices",
                        element: bad,
                    },
                ));
            }
            inverse_bind_matrices.copy_from_slice(&read[..joints.len()]);
        }
        Ok(Skin { name: skin.name().unwrap_or_default().to_owned(), joints, inverse_bind_matrices })
    }

    /// One animation: each channel whose target can be played (see [`target`]) with its
    /// sampler read and checked; the others are skipped, named in one warning for the
    /// animation. Warnings give the file's channel indices (see [`file_channels`]).
    fn animation(
        &self,
        animation: &gltf::Animation<'_>,
        (root, json): (&gltf::json::Root, &serde_json::Value),
        buffers: &[Bytes],
        nodes: &HashMap<usize, usize>,
        warnings: &mut Vec<String>,
    ) -> Result<Animation, IoError> {
        let mut channels = Vec::new();
        let mut skipped = Vec::new();
        let (file_channels, without_node) = file_channels(json, animation.index());
        for channel in animation.channels() {
            let in_file = file_channels.get(channel.index()).copied().unwrap_or(channel.index());
            match target(root, animation.index(), channel.index(), nodes) {
                Ok((node, property)) => {
                    let sampler = self.sampler(animation, &channel, property, buffers)?;
                    channels.push(Channel { node, property, sampler });
                }
                Err(reason) => skipped.push(format!("channel {in_file}: {reason}")),
            }
        }
        if without_node > 0 {
            skipped.push(format!(
                "{without_node} channel(s) without a target node (KHR_animation_pointer's pointers are not played)"
            ));
        }
        if !skipped.is_empty() {
            warnings.push(format!(
                "{}: animations[{}]{}: not played: {}",
                self.path.display(),
                animation.index(),
                animation.name().map(|n| format!(" ({n:?})")).unwrap_or_default(),
                skipped.join("; ")
            ));
        }
        Ok(Animation { name: animation.name().unwrap_or_default().to_owned(), channels })
    }

    /// A channel's sampler: its interpolation, key times and values, read from accessors
    /// checked first (type, extent, sparse indices) and then checked themselves
    /// ([`Self::check_keys`]).
    fn sampler(
        &self,
        animation: &gltf::Animation<'_>,
        channel: &gltf::animation::Channel<'_>,
        property: Property,
        buffers: &[Bytes],
    ) -> Result<Sampler, IoError> {
        let sampler = channel.sampler();
        let place = format!("animations[{}].samplers[{}]", animation.index(), sampler.index());
        let interpolation = match sampler.interpolation() {
            gltf::animation::Interpolation::Step => Interpolation::Step,
            gltf::animation::Interpolation::Linear => Interpolation::Linear,
            gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
        };
        let (input, output) = (sampler.input(), sampler.output());
        self.check_accessor(
            &input,
            Dimensions::Scalar,
            &[DataType::F32],
            &format!("{place}.input"),
        )?;
        self.check_sparse_indices(&input, buffers)?;
        let (dimensions, output_types): (Dimensions, &[DataType]) = match property {
            Property::Translation | Property::Scale => (Dimensions::Vec3, &[DataType::F32]),
            Property::Rotation => (Dimensions::Vec4, &NORMALIZED_OR_FLOAT),
            Property::Weights => (Dimensions::Scalar, &NORMALIZED_OR_FLOAT),
        };
        self.check_accessor(&output, dimensions, output_types, &format!("{place}.output"))?;
        self.check_sparse_indices(&output, buffers)?;
        let reader = channel.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
        // An accessor without a view or sparse data is zeros; the gltf reader gives nothing.
        let times: Vec<f32> = if without_data(&input) {
            vec![0.0; input.count()]
        } else {
            reader.read_inputs().map(Iterator::collect).unwrap_or_default()
        };
        let values: Vec<f32> = match reader.read_outputs().filter(|_| !without_data(&output)) {
            Some(ReadOutputs::Translations(it)) => it.flatten().collect(),
            Some(ReadOutputs::Scales(it)) => it.flatten().collect(),
            Some(ReadOutputs::Rotations(it)) => it.into_f32().flatten().collect(),
            Some(ReadOutputs::MorphTargetWeights(it)) => it.into_f32().collect(),
            None if without_data(&output) => {
                vec![0.0; output.count() * output.dimensions().multiplicity()]
            }
            None => Vec::new(),
        };
        let sampler = Sampler { interpolation, times, values };
        self.check_keys(&sampler, property, &place)?;
        Ok(sampler)
    }

    /// Key times finite and increasing, values finite and a whole number per key.
    fn check_keys(
        &self,
        sampler: &Sampler,
        property: Property,
        place: &str,
    ) -> Result<(), IoError> {
        let error = |problem: String| self.animation_error(place.to_owned(), problem);
        if let Some(k) = sampler.times.iter().position(|t| !t.is_finite()) {
            return Err(error(format!("key time {k} is not finite")));
        }
        if let Some(k) = sampler.times.windows(2).position(|w| w[1] < w[0]) {
            return Err(error(format!(
                "key times must increase: key {} is at {}, key {} at {}",
                k,
                sampler.times[k],
                k + 1,
                sampler.times[k + 1]
            )));
        }
        if let Some(k) = sampler.values.iter().position(|v| !v.is_finite()) {
            return Err(error(format!("output value {k} is not finite")));
        }
        let groups = if sampler.interpolation == Interpolation::CubicSpline { 3 } else { 1 };
        let keys = sampler.times.len() * groups;
        let per_key = match property {
            Property::Translation | Property::Scale => Some(3),
            Property::Rotation => Some(4),
            Property::Weights => None,
        };
        let fits = keys > 0
            && sampler.values.len().is_multiple_of(keys)
            && per_key.is_none_or(|n| sampler.values.len() == n * keys);
        if !fits {
            return Err(error(format!(
                "{} output values do not fit {} keys{}",
                sampler.values.len(),
                sampler.times.len(),
                if groups == 3 { " of a cubic spline (three values each)" } else { "" }
            )));
        }
        Ok(())
    }

    fn animation_error(&self, place: String, problem: String) -> IoError {
        IoError::Gltf {
            path: self.path.to_path_buf(),
            place,
            kind: GltfKind::Animation { problem },
        }
    }
}

/// The component types of rotations and morph weights: floats, or normalised integers.
const NORMALIZED_OR_FLOAT: [DataType; 5] =
    [DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16];

/// The node (in [`Asset::nodes`]) and property that channel `c` of animation `a` moves, read
/// from the document's JSON before the gltf crate would unwrap them: gltf-json's validation
/// leaves channel targets unchecked, and `Target::node` and `Target::property` panic on a
/// node that does not exist and a path outside glTF's four. `Err` says why the channel
/// cannot be played: its node does not exist or is outside the scene, or its path is not
/// `translation`, `rotation`, `scale` or `weights` (as KHR_animation_pointer's `"pointer"`,
/// which belongs on a channel without a node).
fn target(
    root: &gltf::json::Root,
    a: usize,
    c: usize,
    nodes: &HashMap<usize, usize>,
) -> Result<(usize, Property), String> {
    let Some(target) = root.animations.get(a).and_then(|a| a.channels.get(c)).map(|c| &c.target)
    else {
        return Err("it is not in the document".to_owned());
    };
    let node = target.node.value();
    if node >= root.nodes.len() {
        return Err(format!(
            "its target node {node} does not exist (the file has {} nodes)",
            root.nodes.len()
        ));
    }
    let property = match target.path {
        Checked::Valid(gltf::animation::Property::Translation) => Property::Translation,
        Checked::Valid(gltf::animation::Property::Rotation) => Property::Rotation,
        Checked::Valid(gltf::animation::Property::Scale) => Property::Scale,
        Checked::Valid(gltf::animation::Property::MorphTargetWeights) => Property::Weights,
        Checked::Invalid => {
            return Err("its target path is not translation, rotation, scale or weights".to_owned());
        }
    };
    match nodes.get(&node) {
        Some(&node) => Ok((node, property)),
        None => Err(format!("its target nodes[{node}] is not in the scene")),
    }
}

/// Per channel of animation `a` as gltf-json parsed it, its index in the file (`json`, the
/// document as written): the file's channels that have a target node, in order, since
/// `lenient.rs` drops the others (KHR_animation_pointer's) before the typed parse; and how
/// many it dropped.
fn file_channels(json: &serde_json::Value, a: usize) -> (Vec<usize>, usize) {
    let Some(channels) = json["animations"][a]["channels"].as_array() else {
        return (Vec::new(), 0);
    };
    let with_node: Vec<usize> = channels
        .iter()
        .enumerate()
        .filter(|(_, c)| c.get("target").is_none_or(|t| t.get("node").is_some()))
        .map(|(i, _)| i)
        .collect();
    let dropped = channels.len() - with_node.len();
    (with_node, dropped)
}

/// An accessor with neither a buffer view nor sparse data: its elements are zeros (glTF 2.0,
/// "Accessors"), where the gltf crate's reader gives none.
fn without_data(accessor: &gltf::Accessor<'_>) -> bool {
    accessor.view().is_none() && accessor.sparse().is_none()
}
