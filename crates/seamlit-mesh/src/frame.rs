//! Finishing a tangent frame (the paper's sections 5.3 and 5.4) and moving it between model
//! space and an object's local space.
//!
//! `T = normalize(T - N dot(N, T))` (Gram-Schmidt), and `w = sign(dot(cross(N, T), B))` so
//! that the renderer rebuilds `B = cross(N, T) * w` (glTF convention). Every step has a
//! fallback, so no input, however degenerate, gives a NaN.
//!
//! **Invariant: every tangent leaves here orthogonal to its normal, |N.T| < 1e-5, whatever
//! the UVs** (tests/orthogonal_frames.rs). One Gram-Schmidt step does not ensure it: where the
//! summed tangent lies nearly along the normal (faces whose tangents' parts across the normal
//! cancel: degenerate, repeated or folded-back UVs), removing the normal part leaves mostly
//! rounding error, in any direction, and normalising that gave |N.T| up to 0.95. So
//! [`orthogonal_tangent`] falls back to a surface direction there, and otherwise
//! orthogonalises twice ("twice is enough": the second step removes what the first's rounding
//! left along the normal).

use glam::{Mat3, Vec3, Vec4, Vec4Swizzles};

/// Normalises the summed normal, orthogonalises the summed tangent against it and takes the
/// handedness from the summed bitangent. `fallback` is used when the normal sum vanishes.
#[must_use]
pub(crate) fn finish(n_sum: Vec3, fallback: Vec3, t_sum: Vec3, b_sum: Vec3) -> (Vec3, Vec4) {
    let n = finish_normal(n_sum, fallback);
    let t = orthogonal_tangent(n, t_sum);
    let w = if n.cross(t).dot(b_sum) < 0.0 { -1.0 } else { 1.0 };
    (n, t.extend(w))
}

/// [`finish`]'s normal alone: `n_sum` normalised, or `fallback`, or +Z.
pub(crate) fn finish_normal(n_sum: Vec3, fallback: Vec3) -> Vec3 {
    n_sum.try_normalize().or_else(|| fallback.try_normalize()).unwrap_or(Vec3::Z)
}

/// The unit vector along `t`'s part across the unit normal `n`; where `t` has (nearly) no
/// such part, a direction across `n` from the surface alone (`any_orthonormal_vector`,
/// continuous in `n`, as for faces without usable UVs).
#[must_use]
#[inline(always)]
pub(crate) fn orthogonal_tangent(n: Vec3, t: Vec3) -> Vec3 {
    let across = t - n * n.dot(t);
    // Below a thousandth of |t|, the rounding of `t`'s part along `n` (about 6e-8 |t|) would
    // tilt the direction by more than 6e-5 before the second step.
    if across.length_squared() <= 1e-6 * t.length_squared() || !across.is_finite() {
        return n.any_orthonormal_vector();
    }
    (across - n * n.dot(across)).try_normalize().unwrap_or_else(|| n.any_orthonormal_vector())
}

/// A transform's linear part and what is derived from it, for moving frames.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Linear {
    m: Mat3,
    inverse: Mat3,
}

impl Linear {
    pub fn new(m: Mat3) -> Self {
        Self { m, inverse: m.inverse() }
    }

    /// Model-space frame -> local space: `N_l ~ M^T N`, `T_l ~ M^-1 T`, `B_l ~ M^-1 B`.
    #[must_use]
    #[inline(always)]
    pub fn frame_to_local(&self, n: Vec3, t: Vec4) -> (Vec3, Vec4) {
        let b = n.cross(t.xyz()) * t.w;
        reframe(self.m.transpose() * n, self.inverse * t.xyz(), self.inverse * b, n, t)
    }

    /// Local-space frame -> model space: `N_m ~ M^-T N`, `T_m ~ M T`, `B_m ~ M B`.
    #[must_use]
    pub fn frame_to_model(&self, n: Vec3, t: Vec4) -> (Vec3, Vec4) {
        let b = n.cross(t.xyz()) * t.w;
        reframe(self.inverse.transpose() * n, self.m * t.xyz(), self.m * b, n, t)
    }

    /// A normal only, model -> local: the normal [`Self::frame_to_local`] gives.
    #[must_use]
    pub fn normal_to_local(&self, n: Vec3) -> Vec3 {
        (self.m.transpose() * n).try_normalize().unwrap_or(n)
    }

    /// A normal only, local -> model.
    #[must_use]
    pub fn normal_to_model(&self, n: Vec3) -> Vec3 {
        (self.inverse.transpose() * n).try_normalize().unwrap_or(n)
    }

    /// [`Self::frame_to_local`] of four frames at once, a frame a lane, with the same bits: the
    /// same operations in the same order (IEEE 754 rounds each lane's product, sum, quotient
    /// and root as the scalar's), so that the roots and divisions of four frames overlap. A
    /// lane that meets one of the fallbacks (a normal or tangent that vanishes, a tangent
    /// along the normal, a value not finite) is made by [`Self::frame_to_local`] itself.
    #[must_use]
    pub fn frames_to_local(&self, normals: [Vec3; 4], tangents: [Vec4; 4]) -> [(Vec3, Vec4); 4] {
        let (n0, t4) = (Lanes::of(normals), Lanes::of(tangents.map(Vec4::xyz)));
        let w0 = Vec4::from_array(tangents.map(|t| t.w));
        let b = n0.cross(t4).scale(w0);
        let (m, inverse) = (self.m.transpose(), self.inverse);
        let (n, t, b) = (n0.times(&m), t4.times(&inverse), b.times(&inverse));
        // `reframe`, where nothing falls back.
        let (rn, rt) = (n.length_recip(), t.length_recip());
        let (n, t) = (n.scale(rn), t.scale(rt));
        let across = t.minus(n.scale(n.dot(t)));
        let twice = across.minus(n.scale(n.dot(across)));
        let ra = twice.length_recip();
        let tangent = twice.scale(ra);
        let w = Vec4::select(n.cross(tangent).dot(b).cmplt(Vec4::ZERO), -Vec4::ONE, Vec4::ONE);
        // `across` is finite where both normalised (`reframe`'s test of it never fails here).
        let plain = usable(rn)
            & usable(rt)
            & !across.length_squared().cmple(t.length_squared() * 1e-6)
            & usable(ra);
        let (n, tangent) = (n.lanes(), tangent.lanes());
        std::array::from_fn(|i| {
            if plain.test(i) {
                (n[i], tangent[i].extend(w[i]))
            } else {
                self.frame_to_local(normals[i], tangents[i])
            }
        })
    }
}

/// The tangent, with its handedness, of a corner whose vertex keeps its normal `n` (local
/// space, as the file gives it), from the corner's model-space frame `(normal, tangent)`:
/// the frame moved to local space, its tangent made orthogonal to the unit `n` and its
/// handedness taken from the moved frame's bitangent.
#[must_use]
#[inline(always)]
pub(crate) fn kept_normal_tangent(linear: Option<&Linear>, n: Vec3, frame: (Vec3, Vec4)) -> Vec4 {
    let (n0, t0) = match linear {
        Some(l) => l.frame_to_local(frame.0, frame.1),
        None => frame,
    };
    let unit = n.try_normalize().unwrap_or(n0);
    let bitangent = n0.cross(t0.xyz()) * t0.w;
    let t = orthogonalise(t0, unit);
    let w = if unit.cross(t.xyz()).dot(bitangent) < 0.0 { -1.0 } else { 1.0 };
    t.xyz().extend(w)
}

/// [`kept_normal_tangent`] of four corners at once, a corner a lane, with the same bits (as
/// [`Linear::frames_to_local`]); a lane that meets a fallback is made by it alone.
#[must_use]
pub(crate) fn kept_normal_tangents(
    linear: Option<&Linear>,
    n: [Vec3; 4],
    frames: [(Vec3, Vec4); 4],
) -> [Vec4; 4] {
    let moved = match linear {
        Some(l) => l.frames_to_local(frames.map(|f| f.0), frames.map(|f| f.1)),
        None => frames,
    };
    let (n0, t0) = (Lanes::of(moved.map(|f| f.0)), Lanes::of(moved.map(|f| f.1.xyz())));
    let kept = Lanes::of(n);
    let rn = kept.length_recip();
    let unit = kept.scale(rn);
    let bitangent = n0.cross(t0).scale(Vec4::from_array(moved.map(|f| f.1.w)));
    let across = t0.minus(unit.scale(unit.dot(t0)));
    let ra = across.length_recip();
    let t = across.scale(ra);
    let w = Vec4::select(unit.cross(t).dot(bitangent).cmplt(Vec4::ZERO), -Vec4::ONE, Vec4::ONE);
    let plain = usable(rn) & usable(ra);
    let t = t.lanes();
    std::array::from_fn(|i| {
        if plain.test(i) { t[i].extend(w[i]) } else { kept_normal_tangent(linear, n[i], frames[i]) }
    })
}

/// Where a reciprocal length lets `try_normalize` normalise: finite and above zero.
fn usable(rcp: Vec4) -> glam::BVec4A {
    rcp.abs().cmplt(Vec4::INFINITY) & rcp.cmpgt(Vec4::ZERO)
}

/// Four `Vec3`s, a lane each, with glam's `Vec3` arithmetic in glam's order of operations.
#[derive(Clone, Copy)]
struct Lanes {
    x: Vec4,
    y: Vec4,
    z: Vec4,
}

impl Lanes {
    fn of(v: [Vec3; 4]) -> Self {
        let lane = |k: usize| Vec4::from_array(v.map(|v| v[k]));
        Self { x: lane(0), y: lane(1), z: lane(2) }
    }

    fn lanes(self) -> [Vec3; 4] {
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        std::array::from_fn(|i| Vec3::new(x[i], y[i], z[i]))
    }

    fn dot(self, r: Self) -> Vec4 {
        (self.x * r.x) + (self.y * r.y) + (self.z * r.z)
    }

    fn cross(self, r: Self) -> Self {
        Self {
            x: self.y * r.z - r.y * self.z,
            y: self.z * r.x - r.z * self.x,
            z: self.x * r.y - r.x * self.y,
        }
    }

    fn scale(self, s: Vec4) -> Self {
        Self { x: self.x * s, y: self.y * s, z: self.z * s }
    }

    fn minus(self, r: Self) -> Self {
        Self { x: self.x - r.x, y: self.y - r.y, z: self.z - r.z }
    }

    fn length_squared(self) -> Vec4 {
        self.dot(self)
    }

    /// `1 / |v|`, as `Vec3::length_recip`.
    fn length_recip(self) -> Vec4 {
        Vec4::ONE / self.length_squared().sqrt()
    }

    /// `m * v`, as `Mat3::mul_vec3`: the columns scaled by `v`'s components, summed in order.
    fn times(self, m: &Mat3) -> Self {
        let row = |k: usize| {
            let c = |axis: Vec3| Vec4::splat(axis[k]);
            c(m.x_axis) * self.x + c(m.y_axis) * self.y + c(m.z_axis) * self.z
        };
        Self { x: row(0), y: row(1), z: row(2) }
    }
}

/// Gram-Schmidt: `t` made orthogonal to the unit normal `n`, unit length, its `w` kept (any
/// vector orthogonal to `n` where `t` is parallel to it).
#[must_use]
pub(crate) fn orthogonalise(t: Vec4, n: Vec3) -> Vec4 {
    let xyz = t.xyz();
    let xyz = (xyz - n * n.dot(xyz)).try_normalize().unwrap_or_else(|| n.any_orthonormal_vector());
    xyz.extend(t.w)
}

/// The frame `(n, t)` given the moved normal, tangent and bitangent, with `(n0, t0)` (the
/// frame before the move) where they vanish.
///
/// Always inlined, as [`orthogonal_tangent`] and [`Linear::frame_to_local`] are: the writing
/// of a fixed model calls them for every vertex of an object with a transform, and a frame
/// returned through memory is read back in loads that wait on the stores they span (the fix
/// of the 1M teapot, whose objects are rotated, 3 to 5 ms faster on two threads).
#[inline(always)]
fn reframe(n: Vec3, t: Vec3, b: Vec3, n0: Vec3, t0: Vec4) -> (Vec3, Vec4) {
    let n = n.try_normalize().unwrap_or(n0);
    // Orthogonal in theory (`N^T M M^-1 T = N.T`), up to the rounding of a stretched transform.
    let t = orthogonal_tangent(n, t.try_normalize().unwrap_or(t0.xyz()));
    let w = if n.cross(t).dot(b) < 0.0 { -1.0 } else { 1.0 };
    (n, t.extend(w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn finish_orthogonalises_and_signs() {
        let (n, t) = finish(Vec3::new(0.0, 0.0, 2.0), Vec3::Y, Vec3::new(1.0, 0.0, 1.0), -Vec3::Y);
        assert_eq!(n, Vec3::Z);
        assert_eq!(t, Vec4::new(1.0, 0.0, 0.0, -1.0));
    }

    #[test]
    fn finish_never_gives_nan() {
        let (n, t) = finish(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
        assert!(n.is_finite() && t.is_finite());
        assert!((n.length() - 1.0).abs() < 1e-6 && n.dot(t.xyz()).abs() < 1e-6);
    }

    /// A coordinate: mostly plain, sometimes one that makes a fallback (vanishing, tiny,
    /// overflowing, not finite).
    fn coordinate() -> impl Strategy<Value = f32> {
        let special = prop::sample::select(vec![0.0, -0.0, 1e-30, 3e38, f32::INFINITY, f32::NAN]);
        prop_oneof![12 => -1.0f32..1.0, 1 => special]
    }

    fn vector() -> impl Strategy<Value = Vec3> {
        [coordinate(), coordinate(), coordinate()].prop_map(Vec3::from_array)
    }

    /// Rotations, any matrix, mirrors with a stretch, and a stretch across 40 orders.
    fn transform() -> impl Strategy<Value = Mat3> {
        let angle = -3.2f32..3.2;
        prop_oneof![
            (angle.clone(), angle.clone(), angle).prop_map(|(x, y, z)| Mat3::from_euler(
                glam::EulerRot::XYZ,
                x,
                y,
                z
            )),
            prop::array::uniform9(-3.0f32..3.0).prop_map(|m| Mat3::from_cols_array(&m)),
            (0.1f32..4.0).prop_map(|s| Mat3::from_diagonal(Vec3::new(-2.0, s, 0.5))),
            Just(Mat3::from_diagonal(Vec3::new(1e-20, 1.0, 1e20))),
        ]
    }

    /// A frame; with `along`, its tangent lies along its normal (the Gram-Schmidt fallback).
    fn frame() -> impl Strategy<Value = (Vec3, Vec4)> {
        (vector(), vector(), any::<bool>(), prop::bool::weighted(0.2)).prop_map(
            |(n, t, left, along)| {
                let t = if along { n * 2.0 } else { t };
                (n, t.extend(if left { -1.0 } else { 1.0 }))
            },
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

        /// The four-lane move gives every lane the scalar's bits, fallbacks included.
        #[test]
        fn four_frames_move_as_one_does(m in transform(), frames in prop::array::uniform4(frame())) {
            let bits = |(n, t): (Vec3, Vec4)| {
                (n.to_array().map(f32::to_bits), t.to_array().map(f32::to_bits))
            };
            let linear = Linear::new(m);
            let four = linear.frames_to_local(frames.map(|f| f.0), frames.map(|f| f.1));
            for (i, (n, t)) in frames.into_iter().enumerate() {
                let one = linear.frame_to_local(n, t);
                prop_assert_eq!(bits(four[i]), bits(one), "lane {} of {:?}", i, frames);
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

        /// The four-lane tangents for kept normals have every lane's scalar bits, with and
        /// without a transform, fallbacks included.
        #[test]
        fn four_kept_normal_tangents_are_one_by_one(
            m in prop::option::of(transform()),
            kept in prop::array::uniform4(vector()),
            frames in prop::array::uniform4(frame()),
        ) {
            let linear = m.map(Linear::new);
            let four = kept_normal_tangents(linear.as_ref(), kept, frames);
            for i in 0..4 {
                let one = kept_normal_tangent(linear.as_ref(), kept[i], frames[i]);
                let bits = |t: Vec4| t.to_array().map(f32::to_bits);
                prop_assert_eq!(bits(four[i]), bits(one), "lane {} of {:?} {:?}", i, kept, frames);
            }
        }
    }

    #[test]
    fn local_model_round_trip_with_mirror() {
        let l = Linear::new(Mat3::from_diagonal(Vec3::new(-2.0, 1.0, 3.0)));
        let (n, t) = (Vec3::new(0.0, 0.6, 0.8), Vec4::new(1.0, 0.0, 0.0, 1.0));
        let (nm, tm) = l.frame_to_model(n, t);
        let (nl, tl) = l.frame_to_local(nm, tm);
        assert!(nl.abs_diff_eq(n, 1e-6) && tl.abs_diff_eq(t, 1e-6), "{nl} {tl}");
    }
}
