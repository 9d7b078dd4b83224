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

    #[test]
    fn local_model_round_trip_with_mirror() {
        let l = Linear::new(Mat3::from_diagonal(Vec3::new(-2.0, 1.0, 3.0)));
        let (n, t) = (Vec3::new(0.0, 0.6, 0.8), Vec4::new(1.0, 0.0, 0.0, 1.0));
        let (nm, tm) = l.frame_to_model(n, t);
        let (nl, tl) = l.frame_to_local(nm, tm);
        assert!(nl.abs_diff_eq(n, 1e-6) && tl.abs_diff_eq(t, 1e-6), "{nl} {tl}");
    }
}
