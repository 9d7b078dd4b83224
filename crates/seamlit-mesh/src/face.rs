//! Per-face geometry: normal, area, corner angles, and the tangent frame from edge and UV
//! deltas (the paper's section 4.2), with the guards the paper lacks.
//!
//! The paper solves `E1 = dU1 T + dV1 B`, `E2 = dU2 T + dV2 B` with
//! `r = 1 / (dU1 dV2 - dU2 dV1)`, which divides by zero when the UVs of a triangle are
//! collinear. Here such a triangle gets a tangent from the surface instead (a direction
//! perpendicular to its normal, continuous in the normal, from `Vec3::any_orthonormal_vector`),
//! is flagged, and does not take part in tangent averaging unless no face at the vertex has
//! usable UVs.

use glam::{Vec2, Vec3, Vec3A};
use rayon::prelude::*;

use crate::validate::Flat;
use crate::{Model, VAxis};

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

/// The angle between two non-zero vectors, radians.
///
/// `acos` of the normalised dot product through Abramowitz and Stegun's 4.4.46 polynomial
/// (absolute error below 2e-8 on [0, 1]): several times cheaper than `atan2`, and exact to f32
/// precision for what it is used for, weights.
#[expect(
    clippy::excessive_precision,
    reason = "the published coefficients, kept as printed in Abramowitz and Stegun"
)]
fn angle_between(a: Vec3A, b: Vec3A) -> f32 {
    let d = (a.dot(b) / (a.length_squared() * b.length_squared()).sqrt()).clamp(-1.0, 1.0);
    let x = d.abs();
    // Horner's scheme with separate multiplies and adds: `mul_add` is a library call on CPUs
    // without FMA in the baseline target (x86-64), several times slower.
    let poly = ((((((-0.001_262_491_1_f32 * x + 0.006_670_090_1) * x - 0.017_088_125_6) * x
        + 0.030_891_881_0)
        * x
        - 0.050_174_304_6)
        * x
        + 0.088_978_987_4)
        * x
        - 0.214_598_801_6)
        * x
        + 1.570_796_305_0;
    let r = (1.0 - x).sqrt() * poly;
    if d < 0.0 { std::f32::consts::PI - r } else { r }
}

/// Computes one face, with its corner angles. `uvs` is `None` when the object has no UVs.
pub(crate) fn face(p: [Vec3; 3], uvs: Option<[Vec2; 3]>, v_axis: VAxis) -> Face {
    let mut f = face_without_angles(p, uvs, v_axis);
    if !f.is(DEGENERATE) {
        let [p0, p1, p2] = p.map(Vec3A::from);
        let (e1, e2, e3) = (p1 - p0, p2 - p0, p2 - p1);
        let a0 = angle_between(e1, e2);
        let a1 = angle_between(-e1, e3);
        let a2 = (std::f32::consts::PI - a0 - a1).max(0.0);
        f.angles = [a0, a1, a2];
    }
    f
}

/// Computes one face, except its corner angles (left zero): what is needed where the
/// weighting does not use them. Every other field is bit-identical to [`face`]'s.
///
/// The arithmetic runs on `Vec3A` (SSE lanes on x86-64): a third of the instructions of
/// scalar `Vec3` code, on the hottest function of the pipeline.
pub(crate) fn face_without_angles(p: [Vec3; 3], uvs: Option<[Vec2; 3]>, v_axis: VAxis) -> Face {
    let [p0, p1, p2] = p.map(Vec3A::from);
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let cross = e1.cross(e2);
    let area2 = cross.length();
    let scale = e1.length_squared() + e2.length_squared();
    let mut flags = 0;
    let normal = if area2 > EPS * scale && area2.is_finite() {
        cross / area2
    } else {
        flags |= DEGENERATE;
        Vec3A::ZERO
    };

    let from_uv = uvs.and_then(|uv| {
        let d1 = uv[1] - uv[0];
        let d2 = uv[2] - uv[0];
        let det = d1.x * d2.y - d2.x * d1.y;
        let uv_scale = d1.length_squared() + d2.length_squared();
        if det.abs() <= EPS * uv_scale || !det.is_finite() || flags & DEGENERATE != 0 {
            return None;
        }
        let r = 1.0 / det;
        let t = (e1 * d2.y - e2 * d1.y) * r;
        let b = (e2 * d1.x - e1 * d2.x) * (r * v_axis.bitangent_sign());
        // Project into the face's plane (they lie in it up to rounding) and normalise.
        let t = (t - normal * normal.dot(t)).try_normalize()?;
        let b = (b - normal * normal.dot(b)).try_normalize()?;
        Some((t, b))
    });
    let (tangent, bitangent) = match from_uv {
        Some((t, b)) => {
            if normal.cross(t).dot(b) < 0.0 {
                flags |= MIRRORED;
            }
            (t, b)
        }
        None => {
            flags |= DEGENERATE_UV;
            if uvs.is_none() {
                flags |= NO_UV;
            }
            let n = if flags & DEGENERATE != 0 { Vec3::Z } else { Vec3::from(normal) };
            let t = n.any_orthonormal_vector();
            (t.into(), n.cross(t).into())
        }
    };
    Face {
        normal: normal.into(),
        area2,
        angles: [0.0; 3],
        tangent: tangent.into(),
        bitangent: bitangent.into(),
        flags,
    }
}

/// Computes every face of the model, in parallel (the reference's and small models' way).
pub(crate) fn faces(model: &Model, flat: &Flat) -> Vec<Face> {
    (0..flat.triangle_start.last().map_or(0, |&n| n as usize))
        .into_par_iter()
        .map(|t| {
            let o = flat.object_of_triangle(t);
            let c = flat.corners(model, o, t - flat.triangle_start[o] as usize);
            face(c.positions, c.uvs, model.v_axis)
        })
        .collect()
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
mod angle_tests {
    use super::*;

    #[test]
    fn polynomial_acos_matches_the_library() {
        for i in 0..=2000 {
            let t = i as f32 / 2000.0 * std::f32::consts::PI;
            let a = Vec3::new(1.0, 0.0, 0.0);
            let b = Vec3::new(t.cos(), t.sin(), 0.0) * 3.0;
            // The true angle between the two f32 vectors, in f64.
            let bd = b.as_dvec3();
            let exact = (bd.x / bd.length()).clamp(-1.0, 1.0).acos() as f32;
            // Near 0 and pi, acos of an f32 dot product is limited by the dot's rounding.
            let tolerance = if !(0.05..=3.09).contains(&t) { 1e-4 } else { 2e-6 };
            let got = angle_between(a.into(), b.into());
            assert!((got - exact).abs() < tolerance, "{t}: {got} vs {exact}");
        }
    }
}
