//! Step 1: each triangle's first-order frame and flags, and its corners seen from a vertex.

use glam::{Vec2, Vec3, Vec4, Vec4Swizzles};

use super::Surface;

/// The triangle's UV mapping preserves orientation (`w = +1`).
pub(super) const ORIENTED: u8 = 1;
/// The triangle has no usable first-order tangent: it takes any neighbour's group.
pub(super) const ANY: u8 = 2;
/// Two of the triangle's corners share a position.
pub(super) const DEGENERATE: u8 = 4;

/// Step 1's result for one triangle.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct FaceTangent {
    /// Unit tangent (towards +U), times the orientation's sign; zero for an `ANY` triangle.
    pub(super) s: Vec3,
    /// Unit bitangent (towards +V), times the orientation's sign.
    pub(super) t: Vec3,
    pub(super) flags: u8,
}

impl FaceTangent {
    pub(super) fn is(&self, flag: u8) -> bool {
        self.flags & flag != 0
    }
}

/// For each corner `k` of the triangle of vertices `tri` (whose first-order frame is `f`),
/// seen in the tangent plane of `normals[k]`: `s` projected and normalised, and the angle between the corner's
/// edges projected.
///
/// The three corners run side by side in SIMD lanes: each `Vec4` below holds one coordinate
/// of one quantity for corners 0, 1 and 2 (lane 3 is padding). Every lane performs the
/// operations `Vec3` would for its corner alone, in the same order (a dot product is
/// `(x * x' + y * y') + z * z'`, as glam's), so a lane gives the bits a lone corner would.
///
/// Always inlined, as [`crate::face::face`] is and for its reason: returned through memory,
/// the 48-byte result was read back in loads that wait on the stores they span. Left to
/// the compiler, it was inlined in one build and not in the next after an unrelated change
/// (the plain fans' pass 15 ms slower on two threads; BENCHMARKS.md).
#[inline(always)]
pub(super) fn corner_terms<N>(
    surface: &Surface<'_, N>,
    f: &FaceTangent,
    tri: [u32; 3],
    normals: [Vec3; 3],
) -> [(Vec3, f32); 3] {
    let p = tri.map(|v| surface.positions[v as usize]);
    let lanes = |c: fn(Vec3) -> f32, v: [Vec3; 3]| Vec4::new(c(v[0]), c(v[1]), c(v[2]), 0.0);
    let coords = |v: [Vec3; 3]| [lanes(|v| v.x, v), lanes(|v| v.y, v), lanes(|v| v.z, v)];
    let [px, py, pz] = coords(p);
    let n = coords(normals);
    let dot = |a: [Vec4; 3], b: [Vec4; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    // `v - n * n.dot(v)`, per lane.
    let across = |v: [Vec4; 3]| {
        let d = dot(n, v);
        [v[0] - n[0] * d, v[1] - n[1] * d, v[2] - n[2] * d]
    };
    // The corner's edges to the next and the previous vertex (lane k: p[k + 1] - p[k] and
    // p[k + 2] - p[k], indices modulo 3).
    let e1 = across([px.yzxw() - px, py.yzxw() - py, pz.yzxw() - pz]);
    let e2 = across([px.zxyw() - px, py.zxyw() - py, pz.zxyw() - pz]);
    // mikktspace.c normalises both edges, then takes their cosine; one root does both.
    let dots = dot(e1, e2);
    let lengths = (dot(e1, e1) * dot(e2, e2)).sqrt();
    let cos = Vec4::select(lengths.cmpgt(Vec4::ZERO), dots / lengths, Vec4::ZERO)
        .clamp(Vec4::NEG_ONE, Vec4::ONE);
    let x = cos.abs();
    let r = (Vec4::ONE - x).sqrt() * crate::face::acos_poly(x);
    let angle = Vec4::select(cos.cmplt(Vec4::ZERO), Vec4::splat(std::f32::consts::PI) - r, r);
    // `s` projected for each corner and normalised as `Vec3::normalize_or_zero` does.
    let s = across([Vec4::splat(f.s.x), Vec4::splat(f.s.y), Vec4::splat(f.s.z)]);
    let rcp = dot(s, s).sqrt().recip();
    std::array::from_fn(|k| {
        let r = rcp[k];
        let s = Vec3::new(s[0][k], s[1][k], s[2][k]);
        (if r.is_finite() && r > 0.0 { s * r } else { Vec3::ZERO }, angle[k])
    })
}

/// Step 1 for the triangle of vertices `tri` and UVs `uv`: its flags, as [`face_tangent`]
/// gives them, and its `s` where it is healthy (its `t` is computed where it is needed:
/// [`face_tangent`]).
#[inline]
pub(super) fn face_flags<N>(surface: &Surface<'_, N>, tri: [u32; 3], uv: [Vec2; 3]) -> FaceTangent {
    let Some(raw) = first_order(surface, tri, uv) else {
        return FaceTangent { flags: DEGENERATE, ..FaceTangent::default() };
    };
    let oriented = raw.area > 0.0;
    if !not_zero(raw.area) {
        return FaceTangent { flags: ANY | u8::from(oriented), ..FaceTangent::default() };
    }
    // Where both lengths are far from zero and the UV area is sane, the magnitudes
    // `|s| / |area|` are surely above f32::MIN_POSITIVE: no root needed for `t`. Otherwise the
    // full test, as face_tangent makes it.
    let sure = |v: Vec3| v.length_squared() > 1e-30 && raw.area.abs() < 1e20;
    if !(sure(raw.s) && sure(raw.t)) {
        return FaceTangent { t: Vec3::ZERO, ..tangent_of(raw) };
    }
    let sign = if oriented { 1.0 } else { -1.0 };
    FaceTangent { s: unit(raw.s, raw.s.length()) * sign, t: Vec3::ZERO, flags: u8::from(oriented) }
}

/// A healthy triangle's first-order tangent and UV area, before normalising.
struct FirstOrder {
    s: Vec3,
    t: Vec3,
    /// Twice the signed UV area.
    area: f32,
}

/// The first-order frame (the thesis' equations 18 and 19) of the triangle of vertices `tri`
/// and UVs `uv`, unnormalised; `None` where two of its corners share a position.
#[inline]
fn first_order<N>(surface: &Surface<'_, N>, tri: [u32; 3], uv: [Vec2; 3]) -> Option<FirstOrder> {
    let r = tri.map(|v| surface.roots[v as usize]);
    if r[0] == r[1] || r[1] == r[2] || r[2] == r[0] {
        return None;
    }
    let v_sign = surface.v_axis.bitangent_sign();
    let p = tri.map(|v| surface.positions[v as usize]);
    let uv = uv.map(|uv| Vec2::new(uv.x, uv.y * v_sign));
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    Some(FirstOrder {
        s: e1 * d2.y - e2 * d1.y,
        t: e2 * d1.x - e1 * d2.x,
        area: d1.x * d2.y - d1.y * d2.x,
    })
}

/// `v` over its length `l`, as `Vec3::normalize_or_zero` makes it.
pub(super) fn unit(v: Vec3, l: f32) -> Vec3 {
    let r = l.recip();
    if r.is_finite() && r > 0.0 { v * r } else { Vec3::ZERO }
}

/// Triangle `t`'s first-order tangent `s` and bitangent `t`, normalised and signed by its UV
/// orientation, and its flags.
pub(super) fn face_tangent<N>(surface: &Surface<'_, N>, t: usize) -> FaceTangent {
    let (tri, uv) = surface.corners(t);
    match first_order(surface, tri, uv) {
        Some(raw) => tangent_of(raw),
        None => FaceTangent { flags: DEGENERATE, ..FaceTangent::default() },
    }
}

/// [`face_tangent`] of a triangle that is not degenerate, from its first-order frame.
fn tangent_of(raw: FirstOrder) -> FaceTangent {
    let oriented = raw.area > 0.0;
    let mut face = FaceTangent { flags: ANY | u8::from(oriented), ..Default::default() };
    if not_zero(raw.area) {
        let sign = if oriented { 1.0 } else { -1.0 };
        // Each length once: for the unit vector and the magnitude.
        let (ls, lt) = (raw.s.length(), raw.t.length());
        face.s = unit(raw.s, ls) * sign;
        face.t = unit(raw.t, lt) * sign;
        if not_zero(ls / raw.area.abs()) && not_zero(lt / raw.area.abs()) {
            face.flags &= !ANY;
        }
    }
    face
}

/// mikktspace.c's test for a usable float.
pub(super) fn not_zero(x: f32) -> bool {
    x.abs() > f32::MIN_POSITIVE
}
