//! [`face_flags`] of four triangles at once, a triangle per SSE lane, for the report's pass
//! that counts them (`report.rs`): one triangle at a time, its three square roots and three
//! divisions waited on each other. Every lane makes [`face_flags`]' operations in its order
//! (glam's `Vec3A` products and dot products, component by component: `(x + y) + z`), and
//! square roots and divisions are correctly rounded in lanes as alone, so the flags are the
//! same, bit for bit (tested against [`face_flags`]).

use glam::{BVec4A, Vec2, Vec3, Vec4};

use super::{DEGENERATE, DEGENERATE_UV, EPS, MIRRORED, NO_UV, face_flags};
use crate::VAxis;

/// Three components, a triangle per lane.
#[derive(Clone, Copy)]
struct Lanes3 {
    x: Vec4,
    y: Vec4,
    z: Vec4,
}

impl Lanes3 {
    fn of(v: [Vec3; 4]) -> Self {
        Self {
            x: Vec4::new(v[0].x, v[1].x, v[2].x, v[3].x),
            y: Vec4::new(v[0].y, v[1].y, v[2].y, v[3].y),
            z: Vec4::new(v[0].z, v[1].z, v[2].z, v[3].z),
        }
    }

    fn sub(self, o: Self) -> Self {
        Self { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }

    fn scale(self, s: Vec4) -> Self {
        Self { x: self.x * s, y: self.y * s, z: self.z * s }
    }

    /// As `Vec3A::dot`: `(x + y) + z` of the products.
    fn dot(self, o: Self) -> Vec4 {
        (self.x * o.x + self.y * o.y) + self.z * o.z
    }

    /// As `Vec3A::cross`: `a.y b.z - b.y a.z`, and so on.
    fn cross(self, o: Self) -> Self {
        Self {
            x: self.y * o.z - o.y * self.z,
            y: self.z * o.x - o.z * self.x,
            z: self.x * o.y - o.x * self.y,
        }
    }
}

/// Whether each lane is above zero and finite: can be divided by.
fn usable(v: Vec4) -> BVec4A {
    v.cmpgt(Vec4::ZERO) & v.is_finite_mask()
}

/// What [`face_flags`] decides on, a triangle per lane, each made by its operations.
#[derive(Clone, Copy, Debug)]
struct Measures {
    /// Twice the area, and the bound it must exceed (`EPS` times the two edges' squares).
    area2: Vec4,
    area_bound: Vec4,
    /// Twice the signed UV area, and the bound its magnitude must exceed.
    det: Vec4,
    det_bound: Vec4,
    /// The lengths of the tangent and bitangent projected into the face's plane.
    lt: Vec4,
    lb: Vec4,
    /// The unit frame's handedness: below zero where the UV mapping is mirrored.
    handedness: Vec4,
}

/// [`Measures`] of four triangles; without UVs, those of the area alone (the rest zero).
fn measures(p: [[Vec3; 3]; 4], uvs: Option<[[Vec2; 3]; 4]>, v_axis: VAxis) -> Measures {
    let corner = |k: usize| Lanes3::of([p[0][k], p[1][k], p[2][k], p[3][k]]);
    let (p0, p1, p2) = (corner(0), corner(1), corner(2));
    let (e1, e2) = (p1.sub(p0), p2.sub(p0));
    let cross = e1.cross(e2);
    let (area2, area_bound) =
        (cross.dot(cross).sqrt(), Vec4::splat(EPS) * (e1.dot(e1) + e2.dot(e2)));
    let Some(uvs) = uvs else {
        let zero = Vec4::ZERO;
        return Measures {
            area2,
            area_bound,
            det: zero,
            det_bound: zero,
            lt: zero,
            lb: zero,
            handedness: zero,
        };
    };
    let normal = cross.scale(area2.recip());
    let uv = |k: usize, c: fn(Vec2) -> f32| {
        Vec4::new(c(uvs[0][k]), c(uvs[1][k]), c(uvs[2][k]), c(uvs[3][k]))
    };
    let (d1x, d1y) = (uv(1, |v| v.x) - uv(0, |v| v.x), uv(1, |v| v.y) - uv(0, |v| v.y));
    let (d2x, d2y) = (uv(2, |v| v.x) - uv(0, |v| v.x), uv(2, |v| v.y) - uv(0, |v| v.y));
    let det = d1x * d2y - d2x * d1y;
    let det_bound = Vec4::splat(EPS) * ((d1x * d1x + d1y * d1y) + (d2x * d2x + d2y * d2y));
    let sign = Vec4::select(det.cmplt(Vec4::ZERO), Vec4::NEG_ONE, Vec4::ONE);
    let t = e1.scale(d2y).sub(e2.scale(d1y)).scale(sign);
    let b = e2.scale(d1x).sub(e1.scale(d2x)).scale(sign * v_axis.bitangent_sign());
    let t = t.sub(normal.scale(normal.dot(t)));
    let b = b.sub(normal.scale(normal.dot(b)));
    let (lt, lb) = (t.dot(t).sqrt(), b.dot(b).sqrt());
    let handedness = normal.cross(t.scale(lt.recip())).dot(b.scale(lb.recip()));
    Measures { area2, area_bound, det, det_bound, lt, lb, handedness }
}

/// [`face_flags`] of four triangles (their corners' positions and, where the object has
/// them, UVs).
pub(crate) fn face_flags4(
    p: [[Vec3; 3]; 4],
    uvs: Option<[[Vec2; 3]; 4]>,
    v_axis: VAxis,
) -> [u8; 4] {
    let m = measures(p, uvs, v_axis);
    let solid = m.area2.cmpgt(m.area_bound) & m.area2.is_finite_mask();
    if uvs.is_none() {
        return lanes(solid, |_| DEGENERATE_UV | NO_UV, DEGENERATE | DEGENERATE_UV | NO_UV);
    }
    let spans = m.det.abs().cmpgt(m.det_bound) & m.det.is_finite_mask();
    let frame = (spans & usable(m.lt) & usable(m.lb)).bitmask();
    let mirrored = m.handedness.cmplt(Vec4::ZERO).bitmask();
    lanes(
        solid,
        |i| match (frame >> i & 1 != 0, mirrored >> i & 1 != 0) {
            (false, _) => DEGENERATE_UV,
            (true, true) => MIRRORED,
            (true, false) => 0,
        },
        DEGENERATE | DEGENERATE_UV,
    )
}

/// Per lane: `solid`'s flags where the triangle has area, `degenerate` where not.
fn lanes(solid: BVec4A, flags: impl Fn(u32) -> u8, degenerate: u8) -> [u8; 4] {
    let solid = solid.bitmask();
    let mut out = [degenerate; 4];
    for (i, flag) in (0..4).zip(&mut out) {
        if solid >> i & 1 != 0 {
            *flag = flags(i);
        }
    }
    out
}

/// [`face_flags`] of every triangle of `triangles` (vertex indices into `positions` and
/// `uvs`), four at a time, passed to `each` in order.
pub(crate) fn each_face_flags(
    positions: &[Vec3],
    uvs: Option<&[Vec2]>,
    triangles: &[[u32; 3]],
    v_axis: VAxis,
    mut each: impl FnMut(u8),
) {
    let (fours, rest) = triangles.as_chunks::<4>();
    for four in fours {
        let p = four.map(|tri| tri.map(|i| positions[i as usize]));
        let uv = uvs.map(|uvs| four.map(|tri| tri.map(|i| uvs[i as usize])));
        face_flags4(p, uv, v_axis).into_iter().for_each(&mut each);
    }
    for tri in rest {
        let p = tri.map(|i| positions[i as usize]);
        each(face_flags(p, uvs.map(|uvs| tri.map(|i| uvs[i as usize])), v_axis));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random value: a quarter of the time one of a small set that reaches every test of
    /// [`face_flags`] (zero and its sign, tiny and huge magnitudes, near neighbours), else one
    /// in [-8, 8) in steps of 1/4096.
    fn value(state: &mut u64) -> f32 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        const VALUES: [f32; 12] =
            [0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 1e-20, -3e-19, 1e19, 1.000_000_1, 0.25, -7.5];
        let pick = VALUES[usize::try_from(*state % 12).unwrap()];
        let step = f32::from(u16::try_from(*state >> 20 & 0xFFFF).unwrap());
        if *state >> 40 & 3 == 0 { pick } else { step / 4096.0 - 8.0 }
    }

    /// A triangle's third corner near the line of the first two (`toward` times `along`,
    /// moved by `off` times a millionth): slivers at the edge of the degenerate tests.
    fn sliver<V: std::ops::Mul<f32, Output = V> + std::ops::Add<Output = V> + Copy>(
        toward: V,
        along: f32,
        off: V,
    ) -> V {
        toward * along + off * 1e-6
    }

    /// Four lanes give [`face_flags`]' flags, bit for bit, on random triangles of values that
    /// reach each of its tests (degenerate, UVs without area, usable frames, mirrored), half
    /// of them slivers at the edge of the area tests (where a sum made in another order
    /// would land on the other side), with and without UVs, both V axes; each flag turns up.
    #[test]
    fn four_lanes_are_face_flags() {
        let mut state = 0x9E37_79B9_7F4A_7C15;
        let mut seen = 0u8;
        for round in 0..200_000 {
            let mut v3 = || Vec3::new(value(&mut state), value(&mut state), value(&mut state));
            let mut p: [[Vec3; 3]; 4] = std::array::from_fn(|_| [v3(), v3(), v3()]);
            let mut v2 = || Vec2::new(value(&mut state), value(&mut state));
            let mut uv: [[Vec2; 3]; 4] = std::array::from_fn(|_| [v2(), v2(), v2()]);
            if round % 2 == 1 {
                for t in 0..4 {
                    let along = value(&mut state);
                    p[t][2] = p[t][0] + sliver(p[t][1] - p[t][0], along, p[t][2]);
                    uv[t][2] = uv[t][0] + sliver(uv[t][1] - uv[t][0], along, uv[t][2]);
                }
            }
            let uvs = (round % 5 != 0).then_some(uv);
            let v_axis = if round % 4 < 2 { VAxis::Up } else { VAxis::Down };
            let lanes = face_flags4(p, uvs, v_axis);
            for t in 0..4 {
                let alone = face_flags(p[t], uvs.map(|u| u[t]), v_axis);
                assert_eq!(
                    lanes[t],
                    alone,
                    "round {round}, lane {t}: {:?} {:?}",
                    p[t],
                    uvs.map(|u| u[t])
                );
                seen |= alone;
            }
        }
        assert_eq!(seen, DEGENERATE | DEGENERATE_UV | MIRRORED | NO_UV, "every flag reached");
    }

    /// Each lane's measures are those `face.rs` makes of its triangle with `Vec3A`, bit for
    /// bit: the same operations in the same order (a sum or product taken in another order
    /// fails this, where it would change a flag only at the edge of a test).
    #[test]
    fn four_lanes_measure_as_vec3a() {
        use glam::Vec3A;
        let mut state = 0x2545_F491_4F6C_DD1D;
        for round in 0..20_000 {
            let mut v3 = || Vec3::new(value(&mut state), value(&mut state), value(&mut state));
            let p: [[Vec3; 3]; 4] = std::array::from_fn(|_| [v3(), v3(), v3()]);
            let mut v2 = || Vec2::new(value(&mut state), value(&mut state));
            let uv: [[Vec2; 3]; 4] = std::array::from_fn(|_| [v2(), v2(), v2()]);
            let v_axis = if round % 2 == 0 { VAxis::Up } else { VAxis::Down };
            let m = measures(p, Some(uv), v_axis);
            for k in 0..4 {
                let [p0, p1, p2] = p[k].map(Vec3A::from);
                let (e1, e2) = (p1 - p0, p2 - p0);
                let cross = e1.cross(e2);
                let area2 = cross.length_squared().sqrt();
                let area_bound = EPS * (e1.length_squared() + e2.length_squared());
                let normal = Vec3A::from(Vec3::from(cross * area2.recip()));
                let (d1, d2) = (uv[k][1] - uv[k][0], uv[k][2] - uv[k][0]);
                let det = d1.x * d2.y - d2.x * d1.y;
                let det_bound = EPS * (d1.length_squared() + d2.length_squared());
                let sign = if det < 0.0 { -1.0 } else { 1.0 };
                let t = (e1 * d2.y - e2 * d1.y) * sign;
                let b = (e2 * d1.x - e1 * d2.x) * (sign * v_axis.bitangent_sign());
                let (t, b) = (t - normal * normal.dot(t), b - normal * normal.dot(b));
                let (lt, lb) = (t.length_squared().sqrt(), b.length_squared().sqrt());
                let handedness = normal.cross(t * lt.recip()).dot(b * lb.recip());
                let alone = [area2, area_bound, det, det_bound, lt, lb, handedness];
                let lane = [m.area2, m.area_bound, m.det, m.det_bound, m.lt, m.lb, m.handedness];
                for (what, (a, l)) in alone.iter().zip(lane).enumerate() {
                    let l = l.to_array()[k];
                    assert!(
                        a.to_bits() == l.to_bits() || a.is_nan() && l.is_nan(),
                        "round {round}, lane {k}, measure {what}: {a} alone, {l} in lanes"
                    );
                }
            }
        }
    }
}
