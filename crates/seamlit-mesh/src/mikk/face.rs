//! Step 1: each triangle's first-order frame and flags, and its corners seen from a vertex.

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

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

/// For each corner `k` of triangle `t` (whose first-order frame is `f`), seen in the tangent
/// plane of `normals[k]`: `s` projected and normalised, and the angle between the corner's
/// edges projected. The three corners' square roots, divisions and arc cosines run side by
/// side in SIMD lanes (a lane gives the bits a lone corner would).
pub(super) fn corner_terms<N>(
    surface: &Surface<'_, N>,
    f: &FaceTangent,
    t: usize,
    normals: [Vec3; 3],
) -> [(Vec3, f32); 3] {
    let p = surface.triangles[t].map(|v| surface.positions[v as usize]);
    let (mut dots, mut lengths) = (Vec4::ZERO, Vec4::ONE);
    for k in 0..3 {
        let n = normals[k];
        let across = |v: Vec3| v - n * n.dot(v);
        let (e1, e2) = (across(p[(k + 1) % 3] - p[k]), across(p[(k + 2) % 3] - p[k]));
        // mikktspace.c normalises both edges, then takes their cosine; one root does both.
        dots[k] = e1.dot(e2);
        lengths[k] = e1.length_squared() * e2.length_squared();
    }
    let lengths = lengths.sqrt();
    let cos = Vec4::select(lengths.cmpgt(Vec4::ZERO), dots / lengths, Vec4::ZERO)
        .clamp(Vec4::NEG_ONE, Vec4::ONE);
    let x = cos.abs();
    let r = (Vec4::ONE - x).sqrt() * crate::face::acos_poly(x);
    let angle = Vec4::select(cos.cmplt(Vec4::ZERO), Vec4::splat(std::f32::consts::PI) - r, r);
    // `s` projected for each corner and normalised as `Vec3::normalize_or_zero` does, the
    // three square roots and reciprocals side by side.
    let across: [Vec3; 3] = std::array::from_fn(|k| f.s - normals[k] * normals[k].dot(f.s));
    let squares = Vec4::new(
        across[0].length_squared(),
        across[1].length_squared(),
        across[2].length_squared(),
        1.0,
    );
    let rcp = squares.sqrt().recip();
    std::array::from_fn(|k| {
        let r = rcp[k];
        (if r.is_finite() && r > 0.0 { across[k] * r } else { Vec3::ZERO }, angle[k])
    })
}

/// Step 1: every triangle's flags (its first-order frame is computed where it is needed:
/// [`face_tangent`]).
pub(super) fn face_flags<N: Sync>(surface: &Surface<'_, N>) -> Vec<u8> {
    (0..surface.triangles.len())
        .into_par_iter()
        .map(|t| {
            let Some(raw) = first_order(surface, t) else { return DEGENERATE };
            let oriented = u8::from(raw.area > 0.0);
            if !not_zero(raw.area) {
                return ANY | oriented;
            }
            // Where both lengths are far from zero and the UV area is sane, the magnitudes
            // `|s| / |area|` are surely above f32::MIN_POSITIVE: no root needed. Otherwise the
            // full test, as face_tangent makes it.
            let sure = |v: Vec3| v.length_squared() > 1e-30 && raw.area.abs() < 1e20;
            if sure(raw.s) && sure(raw.t) { oriented } else { face_tangent(surface, t).flags }
        })
        .collect()
}

/// A healthy triangle's first-order tangent and UV area, before normalising.
pub(super) struct FirstOrder {
    s: Vec3,
    t: Vec3,
    /// Twice the signed UV area.
    area: f32,
}

/// Triangle `t`'s first-order frame (the thesis' equations 18 and 19) unnormalised; `None`
/// where two of its corners share a position.
pub(super) fn first_order<N>(surface: &Surface<'_, N>, t: usize) -> Option<FirstOrder> {
    let tri = surface.triangles[t];
    let r = tri.map(|v| surface.roots[v as usize]);
    if r[0] == r[1] || r[1] == r[2] || r[2] == r[0] {
        return None;
    }
    let v_sign = surface.v_axis.bitangent_sign();
    let p = tri.map(|v| surface.positions[v as usize]);
    let uv = tri.map(|v| {
        let uv = surface.uvs[v as usize];
        Vec2::new(uv.x, uv.y * v_sign)
    });
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
    let Some(raw) = first_order(surface, t) else {
        return FaceTangent { flags: DEGENERATE, ..FaceTangent::default() };
    };
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

/// The `s` of [`face_tangent`] (and whether the triangle is oriented) for a triangle of a
/// plain fan, which is healthy: its `t` is not needed there.
pub(super) fn plain_tangent<N>(surface: &Surface<'_, N>, t: usize) -> FaceTangent {
    let Some(raw) = first_order(surface, t) else {
        return FaceTangent { flags: DEGENERATE, ..FaceTangent::default() };
    };
    let oriented = raw.area > 0.0;
    let sign = if oriented { 1.0 } else { -1.0 };
    FaceTangent { s: unit(raw.s, raw.s.length()) * sign, t: Vec3::ZERO, flags: u8::from(oriented) }
}

/// mikktspace.c's test for a usable float.
pub(super) fn not_zero(x: f32) -> bool {
    x.abs() > f32::MIN_POSITIVE
}
