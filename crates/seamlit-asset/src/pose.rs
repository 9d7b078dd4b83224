//! An asset posed: its nodes' transforms at a time of an animation (or at rest), the joint
//! matrices of its skins and its morph weights, and each object's vertices moved by them on
//! the CPU.
//!
//! The maths is glTF 2.0's ("Skins", "Morph Targets"), and the renderer's vertex shader does
//! the same (seamlit-render's `deform.wgsl`; the two are tested against each other):
//!
//! 1. morph: `v = base + sum_k w_k * delta_k` (positions, normals, tangents);
//! 2. skin: `M = sum over sets and lanes of weight * global(joint) * inverse_bind(joint)`
//!    (the skinned mesh's own node transform is ignored), the position `M * v`, the normal
//!    `M`'s inverse transpose times `n`, normalised, the tangent's xyz `M * t`, normalised,
//!    its `w` kept; an object that is not skinned is moved by its node's global transform.

use glam::{Mat3, Mat4, Vec3, Vec4};

use crate::animation::Property;
use crate::asset::Asset;

/// The nodes of an asset at one instant.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    /// Per node of [`Asset::nodes`]: its transform to model space.
    pub globals: Vec<Mat4>,
    /// Per node: its mesh's morph target weights (empty: all 0).
    pub weights: Vec<Vec<f32>>,
}

/// One object's vertices in model space, posed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PosedObject {
    /// Positions.
    pub positions: Vec<Vec3>,
    /// Unit normals, where the object has normals.
    pub normals: Option<Vec<Vec3>>,
    /// Unit tangents with their handedness, where the object has tangents.
    pub tangents: Option<Vec<Vec4>>,
}

impl Pose {
    /// The nodes as the file places them, morph weights as the file gives them: the pose
    /// without animation (for a skinned mesh not always its bind pose).
    #[must_use]
    pub fn rest(asset: &Asset) -> Self {
        let locals = asset.nodes.iter().map(|n| n.local_transform).collect();
        let weights = asset.nodes.iter().map(|n| n.weights.clone()).collect();
        Self::from_locals(asset, locals, weights)
    }

    /// The pose at `time` seconds of animation `animation` (an index into
    /// [`Asset::animations`]): each channel sampled (see [`crate::Sampler::sample`]) and
    /// put in place of its property; what no channel moves stays at rest. An index past the
    /// animations gives the rest pose.
    #[must_use]
    pub fn at(asset: &Asset, animation: usize, time: f32) -> Self {
        let Some(animation) = asset.animations.get(animation) else {
            return Self::rest(asset);
        };
        let mut trs: Vec<Option<crate::Trs>> = vec![None; asset.nodes.len()];
        let mut weights: Vec<Vec<f32>> = asset.nodes.iter().map(|n| n.weights.clone()).collect();
        let mut value = Vec::new();
        for channel in &animation.channels {
            let Some(node) = asset.nodes.get(channel.node) else { continue };
            let n = channel.sampler.components();
            if n == 0 {
                continue;
            }
            value.clear();
            value.resize(n, 0.0);
            let rotation = channel.property == Property::Rotation;
            channel.sampler.sample(time, rotation, &mut value);
            let current = trs[channel.node].get_or_insert_with(|| node.local_trs());
            match (channel.property, value.as_slice()) {
                (Property::Translation, &[x, y, z, ..]) => current.translation = Vec3::new(x, y, z),
                (Property::Scale, &[x, y, z, ..]) => current.scale = Vec3::new(x, y, z),
                (Property::Rotation, &[x, y, z, w, ..]) => {
                    current.rotation = glam::Quat::from_xyzw(x, y, z, w).normalize();
                }
                (Property::Weights, values) => weights[channel.node] = values.to_vec(),
                _ => {}
            }
        }
        let locals = asset
            .nodes
            .iter()
            .zip(&trs)
            .map(|(node, trs)| trs.map_or(node.local_transform, |t| t.matrix()))
            .collect();
        Self::from_locals(asset, locals, weights)
    }

    /// Globals from locals, parents first (a parent whose index is not below its child's is
    /// followed up its chain, so any order works; a cycle, which the readers refuse, stops
    /// at the node that closes it).
    fn from_locals(asset: &Asset, locals: Vec<Mat4>, weights: Vec<Vec<f32>>) -> Self {
        let count = asset.nodes.len();
        let mut globals: Vec<Option<Mat4>> = vec![None; count];
        let mut chain = Vec::new();
        for start in 0..count {
            let mut at = Some(start);
            while let Some(i) = at {
                if globals[i].is_some() || chain.len() > count {
                    break;
                }
                chain.push(i);
                at = asset.nodes[i].parent.filter(|&p| p < count);
            }
            while let Some(i) = chain.pop() {
                let parent = asset.nodes[i].parent.and_then(|p| globals.get(p).copied().flatten());
                globals[i] = Some(parent.unwrap_or(Mat4::IDENTITY) * locals[i]);
            }
        }
        Self { globals: globals.into_iter().map(Option::unwrap_or_default).collect(), weights }
    }

    /// The transform that takes a rigid (not skinned) object's vertices to model space: its
    /// node's global transform; for an object no node carries (OBJ), its own transform.
    #[must_use]
    pub fn object_transform(&self, asset: &Asset, object: usize) -> Mat4 {
        match node_of(asset, object) {
            Some(node) => self.globals[node],
            None => asset.model.objects.get(object).map_or(Mat4::IDENTITY, |o| o.model_transform()),
        }
    }

    /// For a skinned object: its joint matrices, indexed as [`seamlit_mesh::Influences`]
    /// name joints (by [`Asset::nodes`] index): `global(joint) * inverse_bind(joint)`, the
    /// identity for nodes that are not its skin's joints. `None` for an object that is not
    /// skinned (no skin on its node, or no influences).
    #[must_use]
    pub fn joint_matrices(&self, asset: &Asset, object: usize) -> Option<Vec<Mat4>> {
        let o = asset.model.objects.get(object)?;
        if o.skin.is_empty() {
            return None;
        }
        let skin = asset.skins.get(asset.nodes[node_of(asset, object)?].skin?)?;
        let mut palette = vec![Mat4::IDENTITY; asset.nodes.len()];
        // A joint listed twice keeps its first matrix, as the readers map influences to it.
        for (j, &node) in skin.joints.iter().enumerate().rev() {
            if let Some(slot) = palette.get_mut(node) {
                let inverse_bind = skin.inverse_bind_matrices.get(j).copied();
                *slot = self.globals[node] * inverse_bind.unwrap_or(Mat4::IDENTITY);
            }
        }
        Some(palette)
    }

    /// The morph target weights of an object (its node's), empty when it has none.
    #[must_use]
    pub fn morph_weights(&self, asset: &Asset, object: usize) -> &[f32] {
        node_of(asset, object).map_or(&[], |n| &self.weights[n])
    }
}

/// The node that carries `object`, if any.
#[must_use]
pub fn node_of(asset: &Asset, object: usize) -> Option<usize> {
    asset.nodes.iter().position(|n| n.objects.contains(&object))
}

/// Object `object` of `asset` in `pose`, in model space (see the module's documentation for
/// the maths).
///
/// # Panics
///
/// If `object` is not an index into `asset.model.objects`.
#[must_use]
pub fn posed_object(asset: &Asset, pose: &Pose, object: usize) -> PosedObject {
    let poser = Poser::new(asset, pose, object);
    let o = poser.object;
    let count = o.positions.len();
    let mut out = PosedObject {
        positions: Vec::with_capacity(count),
        normals: o.normals.as_ref().map(|_| Vec::with_capacity(count)),
        tangents: o.tangents.as_ref().map(|_| Vec::with_capacity(count)),
    };
    for v in 0..count {
        let (p, n, t) = poser.vertex(v);
        out.positions.push(p);
        if let (Some(out), Some(n)) = (&mut out.normals, n) {
            out.push(n);
        }
        if let (Some(out), Some(t)) = (&mut out.tangents, t) {
            out.push(t);
        }
    }
    out
}

/// One object in one pose, ready to move its vertices one at a time.
pub struct Poser<'a> {
    object: &'a seamlit_mesh::Object,
    /// The morph targets with a weight other than 0: (target, weight).
    active: Vec<(usize, f32)>,
    /// The joint matrices of a skinned object.
    palette: Option<Vec<Mat4>>,
    /// The transform of a rigid one.
    rigid: Mat4,
}

impl<'a> Poser<'a> {
    /// Object `object` of `asset` in `pose`.
    ///
    /// # Panics
    ///
    /// If `object` is not an index into `asset.model.objects`.
    #[must_use]
    pub fn new(asset: &'a Asset, pose: &Pose, object: usize) -> Self {
        let o = &asset.model.objects[object];
        let active = pose
            .morph_weights(asset, object)
            .iter()
            .copied()
            .enumerate()
            .filter(|&(k, w)| w != 0.0 && k < o.morph_targets.len())
            .collect();
        Self {
            object: o,
            active,
            palette: pose.joint_matrices(asset, object),
            rigid: pose.object_transform(asset, object),
        }
    }

    /// The matrix that moves vertex `v`: its blend of joint matrices, or the rigid transform.
    fn matrix(&self, v: usize) -> Mat4 {
        let Some(palette) = &self.palette else { return self.rigid };
        let mut m = Mat4::ZERO;
        for set in &self.object.skin {
            for (joint, weight) in set.joints[v].into_iter().zip(set.weights[v]) {
                if weight != 0.0 {
                    m += palette.get(joint as usize).copied().unwrap_or(Mat4::IDENTITY) * weight;
                }
            }
        }
        m
    }

    /// Vertex `v` posed: its position, and its unit normal and tangent where the object has
    /// them.
    ///
    /// # Panics
    ///
    /// If `v` is not one of the object's vertices.
    #[must_use]
    pub fn vertex(&self, v: usize) -> (Vec3, Option<Vec3>, Option<Vec4>) {
        let o = self.object;
        let m = self.matrix(v);
        let mut p = o.positions[v];
        for &(k, w) in &self.active {
            p += o.morph_targets[k].position_deltas[v] * w;
        }
        let linear = Mat3::from_mat4(m);
        let normal = o.normals.as_ref().map(|base| {
            let mut n = base[v];
            for &(k, w) in &self.active {
                if let Some(d) = &o.morph_targets[k].normal_deltas {
                    n += d[v] * w;
                }
            }
            (normal_matrix(linear) * n).normalize_or_zero()
        });
        let tangent = o.tangents.as_ref().map(|base| {
            let mut t = base[v].truncate();
            for &(k, w) in &self.active {
                if let Some(d) = &o.morph_targets[k].tangent_deltas {
                    t += d[v] * w;
                }
            }
            (linear * t).normalize_or_zero().extend(base[v].w)
        });
        (m.transform_point3(p), normal, tangent)
    }
}

/// The matrix that moves normals as `m` moves points: `m`'s inverse transpose up to a
/// positive factor (its cofactor matrix, signed by its determinant), defined where `m` is
/// singular too. Normalise what it gives.
#[must_use]
pub fn normal_matrix(m: Mat3) -> Mat3 {
    let (a, b, c) = (m.x_axis, m.y_axis, m.z_axis);
    let cofactor = Mat3::from_cols(b.cross(c), c.cross(a), a.cross(b));
    if m.determinant() < 0.0 { -cofactor } else { cofactor }
}
