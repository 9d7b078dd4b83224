//! Seams in motion: how far the copies of the positions that objects share come apart, and
//! how far their normals turn from each other, over the time of an animation.

use glam::Vec3;

use crate::asset::Asset;
use crate::pose::{Pose, Poser};

/// The worst of one animation's seams, over its sampled times.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SeamMotion {
    /// The animation's index in [`Asset::animations`].
    pub animation: usize,
    /// Its name (empty where the file gives none).
    pub name: String,
    /// Its length in seconds.
    pub duration: f32,
    /// How many times were sampled, evenly from 0 to the duration.
    pub samples: usize,
    /// The largest distance between two copies of one shared position, model units.
    pub max_gap: f32,
    /// `max_gap` over the diagonal of the model's bounds (bind pose).
    pub max_gap_fraction: f32,
    /// When it happens, seconds.
    pub max_gap_time: f32,
    /// The largest angle between the normals of two copies whose normals agree within the
    /// crease angle in the bind pose (a smooth seam), degrees; `None` where no such pair has
    /// normals.
    pub max_normal_angle_deg: Option<f32>,
    /// When it happens, seconds.
    pub max_normal_angle_time: f32,
}

/// Measures the seams of `asset` in animation `animation` at `samples` times (at least 2:
/// 0 and the duration) (`copies`: [`seamlit_mesh::shared_copies`] of the model; `seams`: per
/// copy, whether it is a side of a seam, [`seamlit_mesh::seam_copies`]; `crease_angle_deg`:
/// pairs of copies whose normals are further apart than this in the bind pose meet at a hard
/// edge and are not compared). Gaps are measured between all copies, normals only between
/// seam sides of different objects: an authored hard edge is no seam, whatever its angle.
///
/// # Panics
///
/// If `copies` names an object or vertex the model lacks, or `seams` is not shaped as
/// `copies`.
#[must_use]
pub fn seam_motion(
    asset: &Asset,
    animation: usize,
    samples: usize,
    copies: &[Vec<(u32, u32)>],
    seams: &[Vec<bool>],
    crease_angle_deg: f32,
) -> SeamMotion {
    let samples = samples.max(2);
    let duration = asset.animations.get(animation).map_or(0.0, crate::Animation::duration);
    let diagonal = bounds_diagonal(asset);
    let objects: Vec<usize> = {
        let mut o: Vec<usize> = copies.iter().flatten().map(|&(o, _)| o as usize).collect();
        o.sort_unstable();
        o.dedup();
        o
    };
    let smooth_pairs = smooth_pairs(asset, copies, seams, crease_angle_deg);
    let mut out = SeamMotion {
        animation,
        name: asset.animations.get(animation).map(|a| a.name.clone()).unwrap_or_default(),
        duration,
        samples,
        ..SeamMotion::default()
    };
    let mut angle: Option<f32> = None;
    // No shared position, nothing to pose: a model of one object moves no seam.
    let posed_at = if copies.is_empty() { 0 } else { samples };
    for s in 0..posed_at {
        let time = duration * s as f32 / (samples - 1) as f32;
        let pose = Pose::at(asset, animation, time);
        let posers: Vec<Option<Poser<'_>>> = (0..asset.model.objects.len())
            .map(|o| objects.binary_search(&o).is_ok().then(|| Poser::new(asset, &pose, o)))
            .collect();
        for (group, pairs) in copies.iter().zip(&smooth_pairs) {
            let posed: Vec<(Vec3, Option<Vec3>)> = group
                .iter()
                .map(|&(o, v)| {
                    let poser = posers[o as usize].as_ref().expect("posed above");
                    let (p, n, _) = poser.vertex(v as usize);
                    (p, n)
                })
                .collect();
            for (i, a) in posed.iter().enumerate() {
                for b in &posed[i + 1..] {
                    let gap = a.0.distance(b.0);
                    if gap > out.max_gap {
                        out.max_gap = gap;
                        out.max_gap_time = time;
                    }
                }
            }
            for &(i, j) in pairs {
                let (Some(a), Some(b)) = (posed[i].1, posed[j].1) else { continue };
                // atan2 of sine and cosine: exact near 0, where acos of a dot product of
                // f32 unit vectors is off by hundredths of a degree.
                let degrees = a.cross(b).length().atan2(a.dot(b)).to_degrees();
                if angle.is_none_or(|worst| degrees > worst) {
                    angle = Some(degrees);
                    out.max_normal_angle_time = time;
                }
            }
        }
    }
    out.max_normal_angle_deg = angle;
    out.max_gap_fraction = if diagonal > 0.0 { out.max_gap / diagonal } else { 0.0 };
    out
}

/// Per group of `copies`, the pairs of copies whose normals are compared: seam sides (see
/// `seams`) of different objects whose normals lie within the crease angle in the bind pose.
fn smooth_pairs(
    asset: &Asset,
    copies: &[Vec<(u32, u32)>],
    seams: &[Vec<bool>],
    crease_angle_deg: f32,
) -> Vec<Vec<(usize, usize)>> {
    let cos_crease = crease_angle_deg.to_radians().cos();
    let bind_normal = |(o, v): (u32, u32)| -> Option<Vec3> {
        let object = &asset.model.objects[o as usize];
        let n = *object.normals.as_ref()?.get(v as usize)?;
        let linear = glam::Mat3::from_mat4(object.model_transform());
        Some((crate::pose::normal_matrix(linear) * n).normalize_or_zero())
    };
    copies
        .iter()
        .zip(seams)
        .map(|(group, seam)| {
            let mut pairs = Vec::new();
            for i in (0..group.len()).filter(|&i| seam[i]) {
                for j in (i + 1..group.len()).filter(|&j| seam[j] && group[i].0 != group[j].0) {
                    let (Some(a), Some(b)) = (bind_normal(group[i]), bind_normal(group[j])) else {
                        continue;
                    };
                    if a.dot(b) >= cos_crease {
                        pairs.push((i, j));
                    }
                }
            }
            pairs
        })
        .collect()
}

/// The diagonal of the model's bounds in model space (bind pose).
fn bounds_diagonal(asset: &Asset) -> f32 {
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for object in &asset.model.objects {
        let m = object.model_transform();
        for &p in &object.positions {
            let p = m.transform_point3(p);
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    if lo.x > hi.x { 0.0 } else { lo.distance(hi) }
}

/// Morph targets whose deltas differ between the copies of a shared position (a seam that
/// opens while the target is active): per target (by index; named by the first object
/// that names it, else `target K`), how many shared positions.
#[must_use]
pub fn morph_seams(asset: &Asset, copies: &[Vec<(u32, u32)>]) -> Vec<(String, usize)> {
    let objects = &asset.model.objects;
    let targets = objects.iter().map(|o| o.morph_targets.len()).max().unwrap_or(0);
    if targets == 0 {
        return Vec::new();
    }
    let tolerance = 1e-6 * bounds_diagonal(asset).max(f32::MIN_POSITIVE);
    let delta = |o: u32, v: u32, k: usize| -> Vec3 {
        let object = &objects[o as usize];
        let d = object.morph_targets.get(k).map_or(Vec3::ZERO, |t| t.position_deltas[v as usize]);
        object.model_transform().transform_vector3(d)
    };
    let mut out: Vec<(String, usize)> = (0..targets)
        .map(|k| {
            let name = objects
                .iter()
                .find_map(|o| {
                    o.morph_targets.get(k).map(|t| t.name.clone()).filter(|n| !n.is_empty())
                })
                .unwrap_or_else(|| format!("target {k}"));
            (name, 0)
        })
        .collect();
    for group in copies {
        for (k, (_, count)) in out.iter_mut().enumerate() {
            let first = delta(group[0].0, group[0].1, k);
            if group[1..].iter().any(|&(o, v)| delta(o, v, k).distance(first) > tolerance) {
                *count += 1;
            }
        }
    }
    out.retain(|&(_, count)| count > 0);
    out
}

/// The copies of the positions an asset's objects share ([`seamlit_mesh::shared_copies`]),
/// where something can pull them apart (skins, morph targets or animations), and which of
/// them are sides of a seam as `fix` judges them, from the normals the file carries
/// ([`seamlit_mesh::seam_copies`]); none otherwise, which costs nothing. The input vertices
/// keep their indices through the fix (split copies are appended), so one `Copies` serves the
/// measures before and after the fix, and [`crate::match_skin_seams`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Copies {
    /// Per shared position, its copies (object, vertex).
    pub copies: Vec<Vec<(u32, u32)>>,
    /// Per copy, whether it is a side of a seam (not an authored hard edge, not custom).
    pub seams: Vec<Vec<bool>>,
}

impl Copies {
    /// The copies of `asset`'s shared positions, welded and judged with `options`.
    ///
    /// # Errors
    /// The [`seamlit_mesh::MeshError`] of bad geometry (a non-finite position, an index out
    /// of range).
    pub fn of(
        asset: &Asset,
        options: &seamlit_mesh::FixOptions,
    ) -> Result<Self, seamlit_mesh::MeshError> {
        let moves = !asset.animations.is_empty()
            || asset
                .model
                .objects
                .iter()
                .any(|o| !o.skin.is_empty() || !o.morph_targets.is_empty());
        if !moves {
            return Ok(Self::default());
        }
        let copies = seamlit_mesh::shared_copies(&asset.model, options.weld_tolerance)?;
        let seams = seamlit_mesh::seam_copies(&asset.model, &copies, options)?;
        Ok(Self { copies, seams })
    }

    /// The seams of `asset` in each of `animations` (indices into [`Asset::animations`]),
    /// `samples` times each, at these copies, with the crease of `options`.
    #[must_use]
    pub fn measure(
        &self,
        asset: &Asset,
        animations: &[usize],
        samples: u32,
        options: &seamlit_mesh::FixOptions,
    ) -> Vec<SeamMotion> {
        animations
            .iter()
            .map(|&a| {
                seam_motion(
                    asset,
                    a,
                    samples as usize,
                    &self.copies,
                    &self.seams,
                    options.crease_angle_deg,
                )
            })
            .collect()
    }
}
