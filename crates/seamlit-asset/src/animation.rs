//! Skins and animations as glTF 2.0 defines them, and the sampling of an animation channel.
//!
//! Format-neutral: the glTF reader fills them from `skins` and `animations`, the FBX reader
//! from clusters and baked animation stacks. Nodes are indices into
//! [`crate::Asset::nodes`]; [`crate::pose`] turns them into a pose.

use glam::{Mat4, Quat, Vec3};

/// A skin: the joints that move a mesh and the matrices that take its vertices from the
/// mesh's space (the bind pose) to each joint's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skin {
    /// The skin's name, empty when the file gives none.
    pub name: String,
    /// The joints, as indices into [`crate::Asset::nodes`], in the skin's order (the order
    /// the file's joint indices refer to).
    pub joints: Vec<usize>,
    /// One per joint: mesh space to the joint's space at bind time (the identity where the
    /// file gives none).
    pub inverse_bind_matrices: Vec<Mat4>,
}

/// What [`crate::match_skin_seams`] changed, for the writers: the objects whose influences are new
/// and the skins that gained joints. Empty after loading.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SkinsChanged {
    /// Objects (indices into the model's objects) whose influences changed.
    pub objects: Vec<usize>,
    /// Skins (indices into [`crate::Asset::skins`]) that gained joints.
    pub skins: Vec<usize>,
}

/// A node's transform as translation, rotation and scale (`T * R * S`): what animation
/// channels replace, one property at a time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trs {
    /// Translation.
    pub translation: Vec3,
    /// Rotation, a unit quaternion.
    pub rotation: Quat,
    /// Scale.
    pub scale: Vec3,
}

impl Trs {
    /// The identity transform.
    pub const IDENTITY: Self =
        Self { translation: Vec3::ZERO, rotation: Quat::IDENTITY, scale: Vec3::ONE };

    /// `T * R * S` as a matrix.
    #[must_use]
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// A named animation: channels, each moving one property of one node.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Animation {
    /// The animation's name, empty when the file gives none.
    pub name: String,
    /// The channels, in file order.
    pub channels: Vec<Channel>,
}

/// One animated property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The node, an index into [`crate::Asset::nodes`].
    pub node: usize,
    /// What the channel moves.
    pub property: Property,
    /// Key times and values.
    pub sampler: Sampler,
}

/// The node property a channel moves (glTF `target.path`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    /// `translation`: three values per key.
    Translation,
    /// `rotation`: a quaternion `(x, y, z, w)` per key.
    Rotation,
    /// `scale`: three values per key.
    Scale,
    /// `weights`: one morph target weight per target, per key.
    Weights,
}

/// How values between keys are found (glTF `sampler.interpolation`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Interpolation {
    /// The value of the key at or before the time.
    Step,
    /// Linear between keys; spherical linear for rotations.
    #[default]
    Linear,
    /// Cubic Hermite spline; each key holds an in-tangent, a value and an out-tangent.
    CubicSpline,
}

/// Key times and values of one channel.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sampler {
    /// How values between keys are found.
    pub interpolation: Interpolation,
    /// Key times in seconds, increasing.
    pub times: Vec<f32>,
    /// The keys' values, flat: per key `components` floats, or for
    /// [`Interpolation::CubicSpline`] three such groups (in-tangent, value, out-tangent), as
    /// glTF stores them.
    pub values: Vec<f32>,
}

impl Animation {
    /// The time of the last key of any channel, 0 for an animation without keys.
    #[must_use]
    pub fn duration(&self) -> f32 {
        self.channels.iter().filter_map(|c| c.sampler.times.last().copied()).fold(0.0, f32::max)
    }
}

impl Sampler {
    /// How many floats one value has: the values' length over the keys (and the three
    /// groups of a cubic spline). 0 for a sampler without keys.
    #[must_use]
    pub fn components(&self) -> usize {
        let groups = if self.interpolation == Interpolation::CubicSpline { 3 } else { 1 };
        match self.times.len() * groups {
            0 => 0,
            n => self.values.len() / n,
        }
    }

    /// The value at `time` (glTF 2.0, "Animations" and Appendix C), written into `out`
    /// (`components` floats): times before the first key take the first value, after the
    /// last the last. A rotation (`rotation` true) is interpolated spherically (linear) or
    /// normalised (cubic). Leaves `out` as it is for a sampler without keys.
    pub fn sample(&self, time: f32, rotation: bool, out: &mut [f32]) {
        let n = self.components();
        let keys = self.times.len();
        if n == 0 || keys == 0 || out.len() < n {
            return;
        }
        let cubic = self.interpolation == Interpolation::CubicSpline;
        // The value group of key k.
        let value = |k: usize| -> &[f32] {
            let start = if cubic { (3 * k + 1) * n } else { k * n };
            &self.values[start..start + n]
        };
        let out = &mut out[..n];
        let last = keys - 1;
        // Before the first key (or NaN) and at or after the last: the end values.
        if time.is_nan() || time <= self.times[0] {
            out.copy_from_slice(value(0));
            return;
        }
        if time >= self.times[last] {
            out.copy_from_slice(value(last));
            return;
        }
        // times[k] <= time < times[k + 1].
        let k = self.times.partition_point(|&t| t <= time) - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let dt = t1 - t0;
        let s = if dt > 0.0 { (time - t0) / dt } else { 0.0 };
        match self.interpolation {
            Interpolation::Step => out.copy_from_slice(value(k)),
            Interpolation::Linear if rotation && n == 4 => {
                let q = |v: &[f32]| Quat::from_xyzw(v[0], v[1], v[2], v[3]);
                let r = q(value(k)).slerp(q(value(k + 1)), s);
                out.copy_from_slice(&r.to_array());
            }
            Interpolation::Linear => {
                let (a, b) = (value(k), value(k + 1));
                for (o, (a, b)) in out.iter_mut().zip(a.iter().zip(b)) {
                    *o = a + (b - a) * s;
                }
            }
            Interpolation::CubicSpline => {
                let group = |k: usize, g: usize| &self.values[(3 * k + g) * n..(3 * k + g + 1) * n];
                let (v0, b0, a1, v1) = (group(k, 1), group(k, 2), group(k + 1, 0), group(k + 1, 1));
                let (s2, s3) = (s * s, s * s * s);
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = (s3 - 2.0 * s2 + s) * dt;
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = (s3 - s2) * dt;
                for (i, o) in out.iter_mut().enumerate() {
                    *o = h00 * v0[i] + h10 * b0[i] + h01 * v1[i] + h11 * a1[i];
                }
                if rotation && n == 4 {
                    let q = Quat::from_xyzw(out[0], out[1], out[2], out[3]).normalize();
                    out.copy_from_slice(&q.to_array());
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sampler(interpolation: Interpolation, times: &[f32], values: &[f32]) -> Sampler {
        Sampler { interpolation, times: times.to_vec(), values: values.to_vec() }
    }

    #[test]
    fn linear_step_and_the_ends() {
        let s = sampler(Interpolation::Linear, &[1.0, 3.0], &[0.0, 10.0, 4.0, 20.0]);
        let mut out = [0.0; 2];
        s.sample(2.0, false, &mut out);
        assert_eq!(out, [2.0, 15.0]);
        s.sample(0.0, false, &mut out);
        assert_eq!(out, [0.0, 10.0]);
        s.sample(9.0, false, &mut out);
        assert_eq!(out, [4.0, 20.0]);
        let step = Sampler { interpolation: Interpolation::Step, ..s };
        step.sample(2.9, false, &mut out);
        assert_eq!(out, [0.0, 10.0]);
        step.sample(3.0, false, &mut out);
        assert_eq!(out, [4.0, 20.0]);
    }

    #[test]
    fn linear_rotations_are_spherical() {
        let a = Quat::IDENTITY;
        let b = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
        let values: Vec<f32> = a.to_array().into_iter().chain(b.to_array()).collect();
        let s = sampler(Interpolation::Linear, &[0.0, 1.0], &values);
        let mut out = [0.0; 4];
        s.sample(0.5, true, &mut out);
        let half = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
        let got = Quat::from_array(out);
        assert!(got.angle_between(half) < 1e-5, "{got:?}");
        // Componentwise lerp would give a quaternion of length cos(22.5 deg) / ... != 1.
        assert!((got.length() - 1.0).abs() < 1e-6);
    }

    /// The specification's formula (glTF 2.0, Appendix C), written out for one scalar:
    /// p(t) = (2s^3 - 3s^2 + 1) v_k + td (s^3 - 2s^2 + s) b_k + (-2s^3 + 3s^2) v_k+1
    ///        + td (s^3 - s^2) a_k+1.
    #[test]
    fn cubic_spline_follows_the_specification() {
        // Keys at t = 2 and t = 6 (td = 4): (a, v, b) = (9, 1, 0.5) and (-0.25, 3, 7).
        let s = sampler(Interpolation::CubicSpline, &[2.0, 6.0], &[9.0, 1.0, 0.5, -0.25, 3.0, 7.0]);
        let mut out = [0.0];
        // s = 0.25: h00 = 0.84375, h10 = 0.140625 * 4, h01 = 0.15625, h11 = -0.046875 * 4.
        s.sample(3.0, false, &mut out);
        let expected = 0.84375 * 1.0 + 0.5625 * 0.5 + 0.15625 * 3.0 + (-0.1875) * -0.25;
        assert!((out[0] - expected).abs() < 1e-6, "{} != {expected}", out[0]);
        // The keys themselves are the values, not the tangents.
        s.sample(2.0, false, &mut out);
        assert_eq!(out[0], 1.0);
        s.sample(6.0, false, &mut out);
        assert_eq!(out[0], 3.0);
    }

    #[test]
    fn duration_is_the_last_key() {
        let channel = |t: &[f32]| Channel {
            node: 0,
            property: Property::Translation,
            sampler: sampler(Interpolation::Linear, t, &vec![0.0; 3 * t.len()]),
        };
        let a = Animation {
            name: "a".into(),
            channels: vec![channel(&[0.0, 1.5]), channel(&[0.5, 2.5])],
        };
        assert_eq!(a.duration(), 2.5);
        assert_eq!(Animation::default().duration(), 0.0);
    }
}
