//! Per-face geometry: normal, area, corner angles, and the tangent frame from edge and UV
//! deltas (the paper's section 4.2), with the guards the paper lacks.
//!
//! The paper solves `E1 = dU1 T + dV1 B`, `E2 = dU2 T + dV2 B` with
//! `r = 1 / (dU1 dV2 - dU2 dV1)`, which divides by zero when the UVs of a triangle are
//! collinear. Here such a triangle gets a tangent from the surface instead (a direction
//! perpendicular to its normal, continuous in the normal, from `Vec3::any_orthonormal_vector`),
//! is flagged, and does not take part in tangent averaging unless no face at the vertex has
//! usable UVs.

mod lanes;

use glam::{Vec2, Vec3, Vec3A, Vec4};

pub(crate) use lanes::each_face_flags;

use crate::VAxis;

/// The triangle has (near) zero area: no normal, contributes nothing.
pub(crate) const DEGENERATE: u8 = 1;
/// The triangle's UVs span (near) zero area, or it has none: its tangent is a fallback.
pub(crate) const DEGENERATE_UV: u8 = 2;
/// The triangle's UV mapping is mirrored (handedness -1).
pub(crate) const MIRRORED: u8 = 4;
/// The triangle's object has no UVs.
pub(crate) const NO_UV: u8 = 8;

/// What the algorithms need to know about one triangle.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Face {
    /// Unit normal (counter-clockwise front), zero for a degenerate triangle.
    pub normal: Vec3,
    /// Twice the area.
    pub area2: f32,
    /// Interior angles at the three corners, radians (zero for a degenerate triangle).
    pub angles: [f32; 3],
    /// Unit tangent (toward +U), perpendicular to the normal.
    pub tangent: Vec3,
    /// Unit bitangent (toward the normal map's +Y).
    pub bitangent: Vec3,
    /// `DEGENERATE | DEGENERATE_UV | MIRRORED | NO_UV`.
    pub flags: u8,
}

impl Face {
    pub fn is(&self, flag: u8) -> bool {
        self.flags & flag != 0
    }

    /// +1 or -1: the handedness of the face's UV mapping.
    pub fn sign(&self) -> f32 {
        if self.is(MIRRORED) { -1.0 } else { 1.0 }
    }
}

/// Relative threshold below which a triangle (in space or in UV) counts as degenerate:
/// `|cross| <= EPS * (|e1|^2 + |e2|^2)`, i.e. its smallest angle is below about 1e-6 rad.
const EPS: f32 = 1e-6;

/// The polynomial of Abramowitz and Stegun's 4.4.46, lane by lane: `acos(x) = sqrt(1 - x)
/// poly(x)` for `x` in [0, 1], absolute error below 2e-8: several times cheaper than `acos`,
/// and exact to f32 precision for what it is used for, weights.
#[expect(
    clippy::excessive_precision,
    reason = "the published coefficients, kept as printed in Abramowitz and Stegun"
)]
pub(crate) fn acos_poly(x: Vec4) -> Vec4 {
    // Horner's scheme with separate multiplies and adds: `mul_add` is a library call on CPUs
    // without FMA in the baseline target (x86-64), several times slower.
    ((((((Vec4::splat(-0.001_262_491_1) * x + 0.006_670_090_1) * x - 0.017_088_125_6) * x
        + 0.030_891_881_0)
        * x
        - 0.050_174_304_6)
        * x
        + 0.088_978_987_4)
        * x
        - 0.214_598_801_6)
        * x
        + 1.570_796_305_0
}

/// Computes one face. `uvs` is `None` when the object has no UVs.
///
/// The hottest function of the pipeline, so its square roots and divisions are batched into
/// SSE lanes (`Vec4`, `Vec3A`): one `sqrt` and one division give the area, the normal and the
/// two corner cosines; a second pair gives the unit tangent, the unit bitangent and the
/// corner angles. That shortens the chain of slow operations from a dozen to four.
///
/// Always inlined: returned through memory, the 56-byte `Face` was stored field by field and
/// read back in 16-byte loads, each waiting for the stores it spans (a failed store-to-load
/// forward); the smoothing's pass over the 1M teapot's triangles took 50 ms on two threads
/// instead of 33 (BENCHMARKS.md).
#[inline(always)]
pub(crate) fn face(p: [Vec3; 3], uvs: Option<[Vec2; 3]>, v_axis: VAxis) -> Face {
    let [p0, p1, p2] = p.map(Vec3A::from);
    let (e1, e2, e3) = (p1 - p0, p2 - p0, p2 - p1);
    let cross = e1.cross(e2);
    let (l1, l2, l3) = (e1.length_squared(), e2.length_squared(), e3.length_squared());
    // Lanes: |cross| = twice the area, and the denominators of the cosines at corners 0, 1.
    let roots = Vec4::new(cross.length_squared(), l1 * l2, l1 * l3, 1.0).sqrt();
    let area2 = roots.x;
    if !(area2 > EPS * (l1 + l2) && area2.is_finite()) {
        return degenerate(area2, uvs);
    }
    let inv = roots.recip();
    let normal = cross * inv.x;
    let cos = Vec4::new(e1.dot(e2) * inv.y, -e1.dot(e3) * inv.z, 0.0, 0.0)
        .clamp(Vec4::NEG_ONE, Vec4::ONE);
    let x = cos.abs();

    let solve = uvs.and_then(|uv| uv_directions(normal, e1, e2, uv, v_axis));
    let (t, b) = solve.unwrap_or((Vec3A::ZERO, Vec3A::ZERO));
    // Lanes: sqrt(1 - |cos|) for the two angles (lined up with `x`), |t| and |b|.
    let roots = Vec4::new(1.0 - x.x, 1.0 - x.y, t.length_squared(), b.length_squared()).sqrt();
    let r = roots * acos_poly(x);
    let angle = Vec4::select(cos.cmplt(Vec4::ZERO), Vec4::splat(std::f32::consts::PI) - r, r);
    let angles = [angle.x, angle.y, (std::f32::consts::PI - angle.x - angle.y).max(0.0)];

    let mut flags = 0;
    let (tangent, bitangent) = if solve.is_some() && usable(roots.z) && usable(roots.w) {
        let inv = Vec4::new(roots.z, roots.w, 1.0, 1.0).recip();
        let (t, b) = (t * inv.x, b * inv.y);
        if is_mirrored(normal, t, b) {
            flags |= MIRRORED;
        }
        (Vec3::from(t), Vec3::from(b))
    } else {
        flags |= DEGENERATE_UV | if uvs.is_none() { NO_UV } else { 0 };
        fallback_frame(normal.into())
    };
    Face { normal: normal.into(), area2, angles, tangent, bitangent, flags }
}

/// The paper's solution for the tangent and bitangent times the UV determinant (its sign
/// kept), projected into the face's plane (they lie there up to rounding): to be normalised,
/// so the scale does not matter. `None` where the UVs span (near) zero area.
#[inline]
fn uv_directions(
    normal: Vec3A,
    e1: Vec3A,
    e2: Vec3A,
    uv: [Vec2; 3],
    v_axis: VAxis,
) -> Option<(Vec3A, Vec3A)> {
    let d1 = uv[1] - uv[0];
    let d2 = uv[2] - uv[0];
    let det = d1.x * d2.y - d2.x * d1.y;
    if !(det.abs() > EPS * (d1.length_squared() + d2.length_squared()) && det.is_finite()) {
        return None;
    }
    let sign = if det < 0.0 { -1.0 } else { 1.0 };
    let t = (e1 * d2.y - e2 * d1.y) * sign;
    let b = (e2 * d1.x - e1 * d2.x) * (sign * v_axis.bitangent_sign());
    Some((t - normal * normal.dot(t), b - normal * normal.dot(b)))
}

/// Whether a tangent or bitangent length can be divided by.
fn usable(length: f32) -> bool {
    length > 0.0 && length.is_finite()
}

/// Whether the unit frame `(t, b)` of a face with unit `normal` is left-handed: a mirrored UV
/// mapping.
#[inline]
fn is_mirrored(normal: Vec3A, t: Vec3A, b: Vec3A) -> bool {
    normal.cross(t).dot(b) < 0.0
}

/// [`face`]'s flags alone, for counting (the report): the same tests on the same values, bit
/// for bit, without the corner angles, the unit frame or the fallback frame.
#[inline]
pub(crate) fn face_flags(p: [Vec3; 3], uvs: Option<[Vec2; 3]>, v_axis: VAxis) -> u8 {
    let [p0, p1, p2] = p.map(Vec3A::from);
    let (e1, e2) = (p1 - p0, p2 - p0);
    let cross = e1.cross(e2);
    let (l1, l2) = (e1.length_squared(), e2.length_squared());
    // As `face` computes them in lanes: square roots and divisions are correctly rounded either way.
    let area2 = cross.length_squared().sqrt();
    let no_uv = if uvs.is_none() { NO_UV } else { 0 };
    if !(area2 > EPS * (l1 + l2) && area2.is_finite()) {
        return DEGENERATE | DEGENERATE_UV | no_uv;
    }
    uv_flags(p, (cross * area2.recip()).into(), uvs, v_axis)
}

/// [`face_flags`] of a triangle that is not [`DEGENERATE`], given its unit `normal` as
/// [`face`] computes it (with or without UVs: the normal does not depend on them): the UV
/// tests alone, for a pass that has the face already (the smoothing, [`crate::smooth`]).
#[inline]
pub(crate) fn uv_flags(p: [Vec3; 3], normal: Vec3, uvs: Option<[Vec2; 3]>, v_axis: VAxis) -> u8 {
    let [p0, p1, p2] = p.map(Vec3A::from);
    let normal = Vec3A::from(normal);
    let Some((t, b)) = uvs.and_then(|uv| uv_directions(normal, p1 - p0, p2 - p0, uv, v_axis))
    else {
        return DEGENERATE_UV | if uvs.is_none() { NO_UV } else { 0 };
    };
    let (lt, lb) = (t.length_squared().sqrt(), b.length_squared().sqrt());
    if !(usable(lt) && usable(lb)) {
        return DEGENERATE_UV;
    }
    if is_mirrored(normal, t * lt.recip(), b * lb.recip()) { MIRRORED } else { 0 }
}

/// Adds a triangle of `flags` (as [`face_flags`] gives them) to the report's counts: degenerate
/// triangles, degenerate-UV triangles of objects with UVs (degenerate ones aside), mirrored
/// triangles.
#[inline]
pub(crate) fn count(counts: &mut [usize; 3], flags: u8) {
    counts[0] += usize::from(flags & DEGENERATE != 0);
    counts[1] += usize::from(flags & (DEGENERATE_UV | NO_UV | DEGENERATE) == DEGENERATE_UV);
    counts[2] += usize::from(flags & MIRRORED != 0);
}

/// The sum of two [`count`]s.
pub(crate) fn add_counts(a: [usize; 3], b: [usize; 3]) -> [usize; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// The face of a triangle with (near) zero area.
fn degenerate(area2: f32, uvs: Option<[Vec2; 3]>) -> Face {
    let (tangent, bitangent) = fallback_frame(Vec3::Z);
    Face {
        normal: Vec3::ZERO,
        area2,
        angles: [0.0; 3],
        tangent,
        bitangent,
        flags: DEGENERATE | DEGENERATE_UV | if uvs.is_none() { NO_UV } else { 0 },
    }
}

/// A tangent and bitangent from the surface alone, continuous in the normal.
fn fallback_frame(n: Vec3) -> (Vec3, Vec3) {
    let t = n.any_orthonormal_vector();
    (t, n.cross(t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_right_triangle() {
        let f =
            face([Vec3::ZERO, Vec3::X, Vec3::Y], Some([Vec2::ZERO, Vec2::X, Vec2::Y]), VAxis::Up);
        assert_eq!(f.normal, Vec3::Z);
        assert_eq!(f.area2, 1.0);
        assert_eq!(f.tangent, Vec3::X);
        assert_eq!(f.bitangent, Vec3::Y);
        assert_eq!(f.flags, 0);
        assert!((f.angles[0] - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        assert!((f.angles[1] - std::f32::consts::FRAC_PI_4).abs() < 1e-6);
        assert!((f.angles[2] - std::f32::consts::FRAC_PI_4).abs() < 1e-6);
    }

    #[test]
    fn v_down_flips_the_bitangent_and_the_handedness() {
        let f =
            face([Vec3::ZERO, Vec3::X, Vec3::Y], Some([Vec2::ZERO, Vec2::X, Vec2::Y]), VAxis::Down);
        assert_eq!(f.bitangent, -Vec3::Y);
        assert!(f.is(MIRRORED));
    }

    #[test]
    fn mirrored_u_is_flagged() {
        let f = face(
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            Some([Vec2::X, Vec2::ZERO, Vec2::new(1.0, 1.0)]),
            VAxis::Up,
        );
        assert_eq!(f.tangent, -Vec3::X);
        assert!(f.is(MIRRORED));
    }

    #[test]
    fn degenerate_inputs_give_finite_output() {
        let f = face([Vec3::ZERO, Vec3::X, Vec3::X * 2.0], Some([Vec2::ZERO; 3]), VAxis::Up);
        assert!(f.is(DEGENERATE) && f.is(DEGENERATE_UV));
        assert!(f.tangent.is_finite() && f.bitangent.is_finite());
        let g = face([Vec3::ZERO, Vec3::X, Vec3::Y], Some([Vec2::ONE; 3]), VAxis::Up);
        assert!(!g.is(DEGENERATE) && g.is(DEGENERATE_UV));
        assert!(g.tangent.dot(g.normal).abs() < 1e-6);
    }
}

#[cfg(test)]
mod flag_tests {
    use super::*;

    /// `face_flags` gives `face`'s flags on triangles of every kind: random ones (most
    /// healthy, half mirrored), slivers down to degenerate, collinear and repeated UVs, huge
    /// and tiny coordinates, and no UVs.
    #[test]
    fn face_flags_are_faces_flags() {
        let mut state = 0x2545_F491_4F6C_DD1D_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
        };
        let mut seen = [0usize; 16];
        for i in 0..200_000 {
            let scale = [1.0, 1e-3, 1e4, 1e-7][i % 4];
            let mut p: [Vec3; 3] =
                std::array::from_fn(|_| Vec3::new(next(), next(), next()) * scale);
            let mut uv: [Vec2; 3] = std::array::from_fn(|_| Vec2::new(next(), next()));
            match i % 7 {
                // A sliver: the third corner on the first edge, nudged.
                1 => p[2] = p[0].lerp(p[1], 0.5) + Vec3::splat(next() * 1e-7 * scale),
                2 => p[2] = p[1],
                // Collinear or repeated UVs.
                3 => uv[2] = uv[0].lerp(uv[1], next()),
                4 => uv = [uv[0]; 3],
                5 => uv[2] = uv[0] + (uv[1] - uv[0]) * 0.5 + Vec2::splat(next() * 1e-7),
                _ => {}
            }
            let uvs = (i % 11 != 0).then_some(uv);
            for v_axis in [VAxis::Up, VAxis::Down] {
                let f = face(p, uvs, v_axis);
                assert_eq!(face_flags(p, uvs, v_axis), f.flags, "{p:?} {uvs:?} {v_axis:?}");
                // The smoothing's way: the face without its UVs, then the UV tests.
                let bare = face(p, None, v_axis);
                if !bare.is(DEGENERATE) {
                    assert_eq!(uv_flags(p, bare.normal, uvs, v_axis), f.flags, "{p:?} {uvs:?}");
                }
                seen[f.flags as usize] += 1;
            }
        }
        // Every kind the counts tell apart came up.
        for flags in [0, MIRRORED, DEGENERATE_UV, DEGENERATE_UV | NO_UV, DEGENERATE | DEGENERATE_UV]
        {
            assert!(seen[usize::from(flags)] > 100, "{flags}: {seen:?}");
        }
    }
}

#[cfg(test)]
mod angle_tests {
    use super::*;

    #[test]
    fn polynomial_acos_matches_the_library() {
        for i in 1..2000 {
            let t = i as f32 / 2000.0 * std::f32::consts::PI;
            let a = Vec3::new(1.0, 0.0, 0.0);
            let b = Vec3::new(t.cos(), t.sin(), 0.0) * 3.0;
            let got = face([Vec3::ZERO, a, b], None, VAxis::Up).angles;
            // The true angles of the f32 triangle, in f64.
            let angle = |u: glam::DVec3, w: glam::DVec3| {
                (u.dot(w) / (u.length() * w.length())).clamp(-1.0, 1.0).acos()
            };
            let exact0 = angle(a.as_dvec3(), b.as_dvec3());
            let exact1 = angle(-a.as_dvec3(), (b - a).as_dvec3());
            // Near 0 and pi, acos of an f32 dot product is limited by the dot's rounding.
            let tolerance = if !(0.05..=3.09).contains(&t) { 1e-4 } else { 2e-6 };
            let error = |k: usize, exact: f64| (f64::from(got[k]) - exact).abs();
            assert!(error(0, exact0) < tolerance, "{t}: {got:?} vs {exact0}");
            assert!(error(1, exact1) < 1e-4, "{t}: {got:?} vs {exact1}");
            let sum = got.iter().sum::<f32>();
            assert!((sum - std::f32::consts::PI).abs() < 1e-5, "{t}: {got:?}");
        }
    }
}
