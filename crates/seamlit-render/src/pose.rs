//! Animation on the GPU: each object's skin influences and morph target deltas, uploaded once
//! with its geometry, and the pose ([`ObjectPose`]: transform, joint palette, morph weights)
//! written each time [`crate::GpuScene::set_pose`] is called. `deform.wgsl` applies them in
//! the vertex stage of the scene and shadow passes.
//!
//! Invariant: a scene without a pose draws as before animation existed (the uniforms say zero
//! skin sets and zero morph targets, so `deform` returns the vertex as it is); setting a pose
//! changes only the uniforms and the two pose buffers, never the geometry.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use seamlit_mesh::Object;
use wgpu::util::DeviceExt;

use crate::{GpuContext, RenderError};

/// The pose of one object for [`crate::GpuScene::set_pose`]: where it is and how it is bent.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjectPose {
    /// The model matrix, which replaces the object's own transform.
    pub transform: Mat4,
    /// For a skinned object, the palette of model-space joint matrices (each a joint's global
    /// transform times its inverse bind matrix), indexed by the values in the object's
    /// `skin[set].joints`; `None` draws the object unskinned (its bind pose). Ignored for an
    /// object without a skin.
    pub joints: Option<Vec<Mat4>>,
    /// One weight per morph target, in order; missing trailing weights are zero.
    pub morph_weights: Vec<f32>,
}

/// One set of skin influences of one vertex as `deform.wgsl` reads it (`SkinVertex`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct SkinRaw {
    pub joints: [u32; 4],
    pub weights: [f32; 4],
}

/// Floats per vertex and morph target in the delta buffer: position, normal and tangent
/// deltas, each a vec4 (w unused) so that the shader loads each at once.
const MORPH_STRIDE: usize = 12;

/// An object's skin and morph data on the GPU, and what [`crate::GpuScene::set_pose`] needs
/// to check a pose and bound the posed object.
#[derive(Debug)]
pub(crate) struct Deform {
    /// `SkinRaw`s, set by set (the shared empty buffer when the object has no skin).
    pub skin: Option<wgpu::Buffer>,
    /// Morph deltas, target by target, [`MORPH_STRIDE`] floats a vertex.
    pub morph: Option<wgpu::Buffer>,
    /// The joint palette, `joint_count` matrices (skinned objects only).
    pub palette: Option<wgpu::Buffer>,
    /// The morph weights, one per target (morphed objects only).
    pub weights: Option<wgpu::Buffer>,
    pub skin_sets: u32,
    pub morph_targets: u32,
    /// One more than the largest joint index of any influence: the palette's length.
    pub joint_count: usize,
    /// The joints that carry weight somewhere, for the posed bounds.
    used_joints: Vec<usize>,
    /// The object's bounds in its own space, unposed.
    local_bounds: (Vec3, Vec3),
    /// Per target, the bounds of its position deltas.
    delta_bounds: Vec<(Vec3, Vec3)>,
}

impl Deform {
    /// Checks the object's influences and deltas against its vertex count and uploads them.
    pub(crate) fn upload(ctx: &GpuContext, object: &Object) -> Result<Self, RenderError> {
        let bad = |what: String| RenderError::BadObject { object: object.name.clone(), what };
        let max_binding = ctx.device().limits().max_storage_buffer_binding_size;
        let buffer = |what: &str, bytes: &[u8]| {
            if bytes.len() as u64 > max_binding {
                return Err(bad(format!(
                    "its {what} take {} bytes, more than the device's storage binding limit \
                     ({max_binding})",
                    bytes.len()
                )));
            }
            Ok(ctx.device().create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&object.name),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            }))
        };
        let skin = skin_influences(object)?;
        let joint_count = skin.iter().flat_map(|s| s.joints).max().map_or(0, |j| j as usize + 1);
        let mut used = vec![false; joint_count];
        for s in &skin {
            for (j, w) in s.joints.iter().zip(s.weights) {
                if w != 0.0 {
                    used[*j as usize] = true;
                }
            }
        }
        let used_joints = used.iter().enumerate().filter(|(_, u)| **u).map(|(j, _)| j).collect();
        let morph = morph_deltas(object)?;
        let delta_bounds = object
            .morph_targets
            .iter()
            .map(|t| bounds_of(t.position_deltas.iter().copied()).unwrap_or_default())
            .collect();
        let pose_buffer = |label: &str, size: usize| {
            ctx.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let too_many = |what: &str| bad(format!("too many {what}"));
        Ok(Self {
            skin: (!skin.is_empty())
                .then(|| buffer("skin influences", bytemuck::cast_slice(&skin)))
                .transpose()?,
            morph: (!morph.is_empty())
                .then(|| buffer("morph target deltas", bytemuck::cast_slice(&morph)))
                .transpose()?,
            palette: (joint_count > 0)
                .then(|| pose_buffer("seamlit joint palette", joint_count * size_of::<Mat4>())),
            weights: (!object.morph_targets.is_empty()).then(|| {
                pose_buffer("seamlit morph weights", object.morph_targets.len() * size_of::<f32>())
            }),
            skin_sets: u32::try_from(object.skin.len()).map_err(|_| too_many("skin sets"))?,
            morph_targets: u32::try_from(object.morph_targets.len())
                .map_err(|_| too_many("morph targets"))?,
            joint_count,
            used_joints,
            local_bounds: bounds_of(object.positions.iter().copied())
                .unwrap_or((Vec3::ZERO, Vec3::ZERO)),
            delta_bounds,
        })
    }

    /// Checks `pose` against this object: a palette that covers every joint its influences
    /// name, no more weights than targets, finite numbers.
    pub(crate) fn check(&self, name: &str, pose: &ObjectPose) -> Result<(), RenderError> {
        let bad = |what: String| RenderError::BadPose { object: name.to_owned(), what };
        if !pose.transform.is_finite() {
            return Err(bad("its transform is not finite".into()));
        }
        if self.joint_count > 0
            && let Some(joints) = &pose.joints
        {
            if joints.len() < self.joint_count {
                return Err(bad(format!(
                    "its palette has {} joint matrices, its influences name joint {}",
                    joints.len(),
                    self.joint_count - 1
                )));
            }
            if let Some(j) = joints[..self.joint_count].iter().position(|m| !m.is_finite()) {
                return Err(bad(format!("joint matrix {j} is not finite")));
            }
        }
        if pose.morph_weights.len() > self.morph_targets as usize {
            return Err(bad(format!(
                "{} morph weights for {} morph targets",
                pose.morph_weights.len(),
                self.morph_targets
            )));
        }
        if let Some(k) = pose.morph_weights.iter().position(|w| !w.is_finite()) {
            return Err(bad(format!("morph weight {k} is not finite")));
        }
        Ok(())
    }

    /// Whether the pose skins the object: it has influences and the pose a palette.
    pub(crate) fn skinned(&self, pose: &ObjectPose) -> bool {
        self.joint_count > 0 && pose.joints.is_some()
    }

    /// Writes the pose's palette and weights (checked with [`Deform::check`]).
    pub(crate) fn write(&self, ctx: &GpuContext, pose: &ObjectPose) {
        if let (Some(buffer), Some(joints)) = (&self.palette, &pose.joints) {
            let palette: Vec<[[f32; 4]; 4]> =
                joints[..self.joint_count].iter().map(Mat4::to_cols_array_2d).collect();
            ctx.queue().write_buffer(buffer, 0, bytemuck::cast_slice(&palette));
        }
        if let Some(buffer) = &self.weights {
            let mut weights = pose.morph_weights.clone();
            weights.resize(self.morph_targets as usize, 0.0);
            ctx.queue().write_buffer(buffer, 0, bytemuck::cast_slice(&weights));
        }
    }

    /// Bounds of the posed object in world space: the unposed bounds widened by each
    /// weighted target's delta bounds, then, skinned, the union of those bounds under every
    /// joint that carries weight (a blend of joint matrices with weights that sum to one puts
    /// a point in the convex hull of its images under each), then the pose's transform.
    pub(crate) fn posed_bounds(&self, pose: &ObjectPose) -> (Vec3, Vec3) {
        let (mut lo, mut hi) = self.local_bounds;
        for (&w, &(dlo, dhi)) in pose.morph_weights.iter().zip(&self.delta_bounds) {
            lo += (dlo * w).min(dhi * w);
            hi += (dlo * w).max(dhi * w);
        }
        let boxes: Vec<(Vec3, Vec3)> = match &pose.joints {
            Some(joints) if self.skinned(pose) && !self.used_joints.is_empty() => {
                self.used_joints.iter().map(|&j| transform_bounds(joints[j], lo, hi)).collect()
            }
            _ => vec![(lo, hi)],
        };
        let (lo, hi) =
            boxes.into_iter().reduce(|(a, b), (c, d)| (a.min(c), b.max(d))).unwrap_or((lo, hi));
        transform_bounds(pose.transform, lo, hi)
    }
}

/// The axis-aligned bounds of the box `lo..hi` after `m`.
pub(crate) fn transform_bounds(m: Mat4, lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
    bounds_of((0..8).map(|c| {
        let pick = |bit: u32, a: f32, b: f32| if c & bit == 0 { a } else { b };
        m.transform_point3(Vec3::new(pick(1, lo.x, hi.x), pick(2, lo.y, hi.y), pick(4, lo.z, hi.z)))
    }))
    .unwrap_or((lo, hi))
}

fn bounds_of(points: impl Iterator<Item = Vec3>) -> Option<(Vec3, Vec3)> {
    points.fold(None, |b, p| match b {
        None => Some((p, p)),
        Some((lo, hi)) => Some((lo.min(p), hi.max(p))),
    })
}

/// Every influence set of the object, set after set, checked against its vertex count.
fn skin_influences(object: &Object) -> Result<Vec<SkinRaw>, RenderError> {
    let n = object.positions.len();
    let mut out = Vec::with_capacity(object.skin.len() * n);
    for (s, set) in object.skin.iter().enumerate() {
        if set.joints.len() != n || set.weights.len() != n {
            return Err(RenderError::BadObject {
                object: object.name.clone(),
                what: format!(
                    "skin set {s} has {} joints and {} weights for {n} positions",
                    set.joints.len(),
                    set.weights.len()
                ),
            });
        }
        out.extend(
            set.joints
                .iter()
                .zip(&set.weights)
                .map(|(&joints, &weights)| SkinRaw { joints, weights }),
        );
    }
    Ok(out)
}

/// Every morph target's deltas, target after target, [`MORPH_STRIDE`] floats a vertex
/// (zeros where a target has no normal or tangent deltas, and in each vec4's w), checked
/// against the vertex count.
fn morph_deltas(object: &Object) -> Result<Vec<f32>, RenderError> {
    let n = object.positions.len();
    let mut out = vec![0.0; object.morph_targets.len() * n * MORPH_STRIDE];
    for (k, target) in object.morph_targets.iter().enumerate() {
        let slot = &mut out[k * n * MORPH_STRIDE..(k + 1) * n * MORPH_STRIDE];
        let columns = [
            ("position", Some(&target.position_deltas), 0),
            ("normal", target.normal_deltas.as_ref(), 4),
            ("tangent", target.tangent_deltas.as_ref(), 8),
        ];
        for (what, deltas, at) in columns {
            let Some(deltas) = deltas else { continue };
            if deltas.len() != n {
                return Err(RenderError::BadObject {
                    object: object.name.clone(),
                    what: format!(
                        "morph target {k} has {} {what} deltas for {n} positions",
                        deltas.len()
                    ),
                });
            }
            for (v, d) in deltas.iter().enumerate() {
                slot[v * MORPH_STRIDE + at..v * MORPH_STRIDE + at + 3]
                    .copy_from_slice(&d.to_array());
            }
        }
    }
    Ok(out)
}
