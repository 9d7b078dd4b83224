//! MikkTSpace tangents over the whole welded model: in parallel, in time linear in the
//! triangles, with a result that does not depend on the number of threads.
//!
//! The algorithm is Morten S. Mikkelsen's: "Simulation of wrinkled surfaces revisited"
//! (master's thesis, University of Copenhagen, 2008), section 3.2 and appendix, as its
//! reference implementation `mikktspace.c` computes it (the code Blender, Substance, xNormal
//! and glTF's sample models use to bake and read normal maps; `bevy_mikktspace` is a line by
//! line port, and this crate's tests check against it). Its steps, as named below:
//!
//! 1. [`face_tangents`]: per triangle, the first-order tangent `s` and bitangent `t` (the
//!    thesis' equations 18 and 19), normalised, signed by the UV orientation; a triangle with
//!    (near) zero UV area or zero `s` or `t` "groups with any" neighbour and adds nothing; a
//!    triangle two of whose corners share a position is degenerate.
//! 2. A *vertex*, in MikkTSpace's sense, is a (position, normal, UV) triple with exact
//!    equality. The positions are the welded ones: every object's copy of a position is the
//!    same position, so a seam corner of one object and its copy in the next are one vertex
//!    when their normal and UV agree ([`Vertex`]).
//! 3. Around each vertex, triangles that share an edge through it and agree in UV
//!    orientation form a *group* (mikktspace.c's `Build4RuleGroups`); a group with-any
//!    triangle takes the orientation of the group that reaches it first
//!    ([`resolve_orientations`]).
//! 4. A group's tangent is the sum, over its triangles, of `s` projected into the vertex's
//!    tangent plane, normalised, weighted by the triangle's angle at the vertex measured in that
//!    plane (`EvalTspace`); triangles whose projected `s` or `t` point exactly opposite are
//!    split into sub-groups first (mikktspace.c's default angular threshold, 180 degrees).
//! 5. A degenerate triangle's corner takes the tangent of the first healthy corner of its
//!    vertex (`DegenEpilogue`).
//!
//! mikktspace.c finds the groups by sorting every edge of the model and walking each group
//! recursively, triangle by triangle; `bevy_mikktspace` also searches every healthy triangle
//! for each degenerate one, so both grow faster than the model (a 1M-triangle teapot with
//! poles took 3.8 s). Here:
//!
//! - each corner's vertex becomes one 64-bit key ([`keys`]): the first vertex of its position
//!   with the same UV (and, where normals are per vertex, the same normal), and a number that
//!   tells the normals at one position apart; keys are computed in corner order, where memory
//!   is read in sequence, so that the steps after compare integers;
//! - the corners are gathered by position with a counting sort on the weld's roots, and each
//!   position's groups are found from its corners alone (two triangles share an edge through
//!   a vertex when the next vertex of one is the previous vertex of the other: keys of the
//!   same triangle), with union-find.
//!
//! Positions are independent, so they run in parallel; every sum runs in corner order, so the
//! result does not depend on the number of threads.
//!
//! Where this differs from mikktspace.c (both documented there as its own choices, and
//! outside what a well-formed model hits): an edge shared by more than two triangles joins
//! them all (mikktspace.c pairs them in sort order); and a group-with-any triangle takes the
//! orientation of its first edge-neighbour in triangle order that has one, rather than of the
//! first group its recursive walk reaches.

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use crate::VAxis;
use crate::index::index;
use crate::weld::union;

/// The model as MikkTSpace sees it, in model space.
pub(crate) struct Surface<'a, N> {
    /// Per vertex, snapped onto its weld root (equal positions, equal roots).
    pub positions: &'a [Vec3],
    /// Per vertex: its weld root.
    pub roots: &'a [u32],
    /// Per vertex (zero for objects without UVs).
    pub uvs: &'a [Vec2],
    /// Every triangle, indexing the vertices.
    pub triangles: &'a [[u32; 3]],
    /// Per object: its first vertex and first triangle, one extra entry at the end (an
    /// object's triangles use its vertices only).
    pub vertex_start: &'a [u32],
    pub triangle_start: &'a [u32],
    /// `normal(corner, vertex)`: the unit normal of corner `triangle * 3 + k` and a key that,
    /// together with `vertex_normals`, tells normals at one position apart: corners of one
    /// position whose normals are bit for bit equal must have equal keys where
    /// `vertex_normals` is `None`.
    pub normal: N,
    /// Where normals are per vertex: those normals (the keys are then 0).
    pub vertex_normals: Option<&'a [Vec3]>,
    /// For glTF (V down) the V coordinate is flipped before MikkTSpace sees it, so that its
    /// bitangent points up the image, as with OBJ's V.
    pub v_axis: VAxis,
}

/// The triangle's UV mapping preserves orientation (`w = +1`).
const ORIENTED: u8 = 1;
/// The triangle has no usable first-order tangent: it takes any neighbour's group.
const ANY: u8 = 2;
/// Two of the triangle's corners share a position.
const DEGENERATE: u8 = 4;

/// Step 1's result for one triangle.
#[derive(Clone, Copy, Debug, Default)]
struct FaceTangent {
    /// Unit tangent (towards +U), times the orientation's sign; zero for an `ANY` triangle.
    s: Vec3,
    /// Unit bitangent (towards +V), times the orientation's sign.
    t: Vec3,
    flags: u8,
}

impl FaceTangent {
    fn is(&self, flag: u8) -> bool {
        self.flags & flag != 0
    }
}

/// MikkTSpace's tangent of every corner of a [`Surface`]: see [`Tangents::get`].
pub(crate) fn tangents<N>(surface: &Surface<'_, N>) -> Tangents
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    tangents_with(surface, false)
}

/// [`tangents`], optionally sending every position through the grouping (for tests: both
/// paths must give the same bits).
fn tangents_with<N>(surface: &Surface<'_, N>, all_grouped: bool) -> Tangents
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    let mut faces = face_flags(surface);
    let first = first_equal_vertex(surface);
    let mut plain = plain_positions(surface, &faces, &shared(&first));
    if all_grouped {
        plain.fill(false);
    }
    let keys = Keys::of(surface, &first, &plain);
    drop(first);
    let by_position = ByPosition::gather(surface, &plain);
    resolve_orientations(surface, &keys, &by_position, &mut faces);
    let raw = by_position.evaluate(surface, &keys, &faces);
    drop(keys);
    let mut rest: Vec<(u32, Vec4)> = by_position.corners.iter().copied().zip(raw).collect();
    rest.par_sort_unstable_by_key(|&(c, _)| c);
    let fans = plain_fans(surface, &plain);
    Tangents { plain, fans, rest }
}

/// The result of [`tangents`].
pub(crate) struct Tangents {
    /// Per root vertex: whether its position is plain (see [`plain_positions`]).
    plain: Vec<bool>,
    /// Per vertex at a plain position: the tangent of all its corners.
    fans: Vec<Vec4>,
    /// The tangent of every corner at the other positions, sorted by corner.
    rest: Vec<(u32, Vec4)>,
}

impl Tangents {
    /// The tangent of every corner of vertex `v` (whose root is `root`), where its position
    /// is plain: all its corners have one.
    pub fn fan(&self, v: usize, root: usize) -> Option<Vec4> {
        self.plain[root].then(|| self.fans[v])
    }

    /// The corners in `corners` at positions that are not plain, ascending, with their
    /// tangents.
    pub fn others(&self, corners: std::ops::Range<usize>) -> &[(u32, Vec4)] {
        let at = |c: usize| self.rest.partition_point(|&(e, _)| (e as usize) < c);
        &self.rest[at(corners.start)..at(corners.end)]
    }

    /// The tangent of corner `c` (`triangle * 3 + k`) at vertex `v` whose root is `root`:
    /// MikkTSpace's, made orthogonal to the corner's normal (it is, up to rounding), `w` the
    /// handedness. A corner MikkTSpace leaves without a tangent space (a degenerate triangle
    /// whose vertex has no healthy one) gets a direction across its normal, `w = +1`.
    pub fn get(&self, c: usize, v: usize, root: usize) -> Vec4 {
        if self.plain[root] {
            return self.fans[v];
        }
        let i = self.rest.partition_point(|&(e, _)| (e as usize) < c);
        self.rest[i].1
    }
}

/// What the corners at a vertex tell [`plain_positions`].
const HAS_ORIENTED: u8 = 1;
const HAS_REVERSED: u8 = 2;
/// With-any or degenerate triangles, or several normals at the position, or another vertex
/// of the position with the same key.
const IRREGULAR: u8 = 4;

/// Mixes a key into 64 well-spread bits (splitmix64's finaliser): sums of these tell whether
/// two multisets of keys are equal, but for a 2^-64 chance.
fn spread(key: u64) -> u64 {
    let mut z = key.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Per root vertex: whether every vertex of its position is *plain*, one MikkTSpace group
/// whose tangent [`plain_fans`] sums in one pass: its corners share one normal (a simple
/// position) and it shares its key with no other vertex; its triangles are healthy (none
/// with-any, none degenerate) and of one orientation; and they close around it (every
/// triangle's next vertex is another's previous one: the sums of their spread keys agree).
/// Such a fan is one group. The rest (boundaries of objects and UV islands, mirror lines,
/// creases, poles) go through the grouping, position by position.
///
/// One case a closed fan does not rule out: two closed fans pinched at one vertex with one
/// UV, two groups for MikkTSpace; they are summed as one here.
fn plain_positions<N>(surface: &Surface<'_, N>, faces: &[u8], shared: &[bool]) -> Vec<bool>
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    let n = surface.roots.len();
    let mut flags = vec![0u8; n];
    let mut fans = vec![0u64; n];
    let parts = split_by_object(surface, &mut flags, &mut fans);
    parts.into_par_iter().for_each(|(o, (flags, fans))| {
        let base = surface.vertex_start[o] as usize;
        let triangles = surface.triangle_start[o] as usize..surface.triangle_start[o + 1] as usize;
        for t in triangles {
            let face = faces[t];
            let bits = if face & (ANY | DEGENERATE) != 0 {
                IRREGULAR
            } else if face & ORIENTED != 0 {
                HAS_ORIENTED
            } else {
                HAS_REVERSED
            };
            let tri = surface.triangles[t];
            for (k, &v) in tri.iter().enumerate() {
                let normal =
                    if (surface.normal)(t * 3 + k, v as usize).1 != 0 { IRREGULAR } else { 0 };
                let v = v as usize - base;
                flags[v] |= bits | normal;
                // Vertices, not keys: a fan closed by vertex is closed by key (at a simple
                // position the corners of one vertex across an edge share a normal group);
                // one closed only through another vertex with the same key is not plain.
                let (next, prev) =
                    (spread(tri[(k + 1) % 3].into()), spread(tri[(k + 2) % 3].into()));
                fans[v] = fans[v].wrapping_add(next).wrapping_sub(prev);
            }
        }
    });
    let mut plain = vec![true; n];
    for v in 0..n {
        let f = flags[v];
        let mixed = f & (HAS_ORIENTED | HAS_REVERSED) == HAS_ORIENTED | HAS_REVERSED;
        if f & IRREGULAR != 0 || mixed || fans[v] != 0 || shared[v] {
            plain[surface.roots[v] as usize] = false;
        }
    }
    plain
}

/// One object's part of two per-vertex arrays, with the object's number.
type ObjectPart<'x, A, B> = (usize, (&'x mut [A], &'x mut [B]));

/// `a` and `b` (one entry per vertex) cut into each object's part, numbered.
fn split_by_object<'x, N, A, B>(
    surface: &Surface<'_, N>,
    mut a: &'x mut [A],
    mut b: &'x mut [B],
) -> Vec<ObjectPart<'x, A, B>> {
    let mut parts = Vec::with_capacity(surface.vertex_start.len());
    for (o, w) in surface.vertex_start.windows(2).enumerate() {
        let len = (w[1] - w[0]) as usize;
        let (pa, ra) = a.split_at_mut(len);
        let (pb, rb) = b.split_at_mut(len);
        parts.push((o, (pa, pb)));
        (a, b) = (ra, rb);
    }
    parts
}

/// Per vertex at a plain position (see [`plain_positions`]): the tangent of its one group,
/// summed over its corners in triangle order, as [`Position`] sums a group.
fn plain_fans<N>(surface: &Surface<'_, N>, plain: &[bool]) -> Vec<Vec4>
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    let n = surface.roots.len();
    let mut sums = vec![Vec4::ZERO; n];
    let mut normals = vec![Vec3::ZERO; n];
    let parts = split_by_object(surface, &mut sums, &mut normals);
    parts.into_par_iter().for_each(|(o, (sums, normals))| {
        let base = surface.vertex_start[o] as usize;
        let triangles = surface.triangle_start[o] as usize..surface.triangle_start[o + 1] as usize;
        for t in triangles {
            let tri = surface.triangles[t];
            let is_plain = tri.map(|v| plain[surface.roots[v as usize] as usize]);
            if is_plain == [false; 3] {
                continue;
            }
            let n: [Vec3; 3] =
                std::array::from_fn(|k| (surface.normal)(t * 3 + k, tri[k] as usize).0);
            let face = plain_tangent(surface, t);
            let terms = corner_terms(surface, &face, t, n);
            let w = if face.is(ORIENTED) { 1.0 } else { -1.0 };
            for k in 0..3 {
                if is_plain[k] {
                    let v = tri[k] as usize - base;
                    let (s, angle) = terms[k];
                    sums[v] += (s * angle).extend(0.0);
                    sums[v].w = w;
                    normals[v] = n[k];
                }
            }
        }
        for (sum, n) in sums.iter_mut().zip(normals.iter()) {
            if sum.w != 0.0 {
                *sum = crate::frame::orthogonal_tangent(*n, sum.truncate()).extend(sum.w);
            }
        }
    });
    sums
}

/// Corner `c`'s triangle (whose first-order frame is `f`) in the tangent plane of the vertex
/// normal `n`: its `s` and `t` projected and normalised, and its angle at the vertex between
/// its edges projected (mikktspace.c's `EvalTspace`).
fn frame<N>(surface: &Surface<'_, N>, f: &FaceTangent, c: usize, n: Vec3) -> Projected {
    let (s, angle) = corner_terms(surface, f, c / 3, [n; 3])[c % 3];
    Projected { s, t: (f.t - n * n.dot(f.t)).normalize_or_zero(), angle }
}

/// For each corner `k` of triangle `t` (whose first-order frame is `f`), seen in the tangent
/// plane of `normals[k]`: `s` projected and normalised, and the angle between the corner's
/// edges projected. The three corners' square roots, divisions and arc cosines run side by
/// side in SIMD lanes (a lane gives the bits a lone corner would).
fn corner_terms<N>(
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
fn face_flags<N: Sync>(surface: &Surface<'_, N>) -> Vec<u8> {
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
struct FirstOrder {
    s: Vec3,
    t: Vec3,
    /// Twice the signed UV area.
    area: f32,
}

/// Triangle `t`'s first-order frame (the thesis' equations 18 and 19) unnormalised; `None`
/// where two of its corners share a position.
fn first_order<N>(surface: &Surface<'_, N>, t: usize) -> Option<FirstOrder> {
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
fn unit(v: Vec3, l: f32) -> Vec3 {
    let r = l.recip();
    if r.is_finite() && r > 0.0 { v * r } else { Vec3::ZERO }
}

/// Triangle `t`'s first-order tangent `s` and bitangent `t`, normalised and signed by its UV
/// orientation, and its flags.
fn face_tangent<N>(surface: &Surface<'_, N>, t: usize) -> FaceTangent {
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
fn plain_tangent<N>(surface: &Surface<'_, N>, t: usize) -> FaceTangent {
    let Some(raw) = first_order(surface, t) else {
        return FaceTangent { flags: DEGENERATE, ..FaceTangent::default() };
    };
    let oriented = raw.area > 0.0;
    let sign = if oriented { 1.0 } else { -1.0 };
    FaceTangent { s: unit(raw.s, raw.s.length()) * sign, t: Vec3::ZERO, flags: u8::from(oriented) }
}

/// mikktspace.c's test for a usable float.
fn not_zero(x: f32) -> bool {
    x.abs() > f32::MIN_POSITIVE
}

/// The bits of `x`, with `-0.0` read as `0.0` (mikktspace.c compares with `==`).
fn bits(x: f32) -> u32 {
    (x + 0.0).to_bits()
}

/// Step 2: per corner of every triangle that touches a position that is not plain, its
/// MikkTSpace vertex as a key: equal keys at one position are one vertex
/// (equal position, UV and normal). The high half is the first vertex of the position with
/// the vertex's UV (and normal, where normals are per vertex), the low half the normal's key.
struct Keys {
    /// The triangles that touch a position that is not plain, ascending.
    triangles: Vec<u32>,
    /// Three keys per triangle of `triangles`.
    keys: Vec<[u64; 3]>,
}

impl Keys {
    fn of<N>(surface: &Surface<'_, N>, first: &[u32], plain: &[bool]) -> Self
    where
        N: Fn(usize, usize) -> (Vec3, u32) + Sync,
    {
        let triangles: Vec<u32> = (0..surface.triangles.len())
            .into_par_iter()
            .filter(|&t| {
                surface.triangles[t].iter().any(|&v| !plain[surface.roots[v as usize] as usize])
            })
            .map(index)
            .collect();
        let keys = triangles
            .par_iter()
            .map(|&t| {
                let (t, tri) = (t as usize, surface.triangles[t as usize]);
                std::array::from_fn(|k| {
                    let normal = (surface.normal)(t * 3 + k, tri[k] as usize).1;
                    (u64::from(first[tri[k] as usize]) << 32) | u64::from(normal)
                })
            })
            .collect();
        Self { triangles, keys }
    }

    /// The keys of the corners of triangle `t`, which touches a position that is not plain.
    fn of_triangle(&self, t: usize) -> [u64; 3] {
        let i = self.triangles.partition_point(|&e| (e as usize) < t);
        debug_assert_eq!(self.triangles[i] as usize, t);
        self.keys[i]
    }
}

/// Per vertex: whether another vertex of its position has the same first vertex (see
/// [`first_equal_vertex`]), so that the two may share a MikkTSpace vertex.
fn shared(first: &[u32]) -> Vec<bool> {
    let mut shared = vec![false; first.len()];
    for (v, &f) in first.iter().enumerate() {
        if f as usize != v {
            (shared[v], shared[f as usize]) = (true, true);
        }
    }
    shared
}

/// Per vertex: the first vertex of its position with the same UV bits (and normal bits, where
/// normals are per vertex). A counting sort of the vertices by root, then a comparison within
/// each position.
fn first_equal_vertex<N>(surface: &Surface<'_, N>) -> Vec<u32> {
    let roots = surface.roots;
    let n = roots.len();
    let mut offsets = vec![0u32; n + 1];
    for &r in roots {
        offsets[r as usize + 1] += 1;
    }
    for r in 0..n {
        offsets[r + 1] += offsets[r];
    }
    let mut next = offsets.clone();
    let mut members = vec![0u32; n];
    for (v, &r) in roots.iter().enumerate() {
        members[next[r as usize] as usize] = index(v);
        next[r as usize] += 1;
    }
    let same = |a: usize, b: usize| {
        let (ua, ub) = (surface.uvs[a], surface.uvs[b]);
        let uv = bits(ua.x) == bits(ub.x) && bits(ua.y) == bits(ub.y);
        uv && surface.vertex_normals.is_none_or(|ns| {
            let (na, nb) = (ns[a], ns[b]);
            bits(na.x) == bits(nb.x) && bits(na.y) == bits(nb.y) && bits(na.z) == bits(nb.z)
        })
    };
    let mut first: Vec<u32> = (0..index(n)).collect();
    for r in 0..n {
        let at = &members[offsets[r] as usize..offsets[r + 1] as usize];
        if at.len() < 2 {
            continue;
        }
        for (i, &v) in at.iter().enumerate() {
            if let Some(&u) = at[..i].iter().find(|&&u| same(u as usize, v as usize)) {
                first[v as usize] = first[u as usize];
            }
        }
    }
    first
}

/// The corners of the positions that are not plain, sorted by position (weld root), in corner
/// order within each.
struct ByPosition {
    /// Per root vertex `r`: its corners are `corners[offsets[r]..offsets[r + 1]]`.
    offsets: Vec<u32>,
    corners: Vec<u32>,
}

impl ByPosition {
    /// A counting sort by their vertex's root of the corners at positions that are not
    /// `plain`.
    fn gather<N>(surface: &Surface<'_, N>, plain: &[bool]) -> Self {
        let roots = surface.roots;
        let corners = surface.triangles.as_flattened();
        let mut offsets = vec![0u32; roots.len() + 1];
        for &v in corners {
            let r = roots[v as usize] as usize;
            offsets[r + 1] += u32::from(!plain[r]);
        }
        for r in 0..roots.len() {
            offsets[r + 1] += offsets[r];
        }
        let mut next = offsets.clone();
        let mut sorted = vec![0u32; offsets[roots.len()] as usize];
        for (c, &v) in corners.iter().enumerate() {
            let r = roots[v as usize] as usize;
            if !plain[r] {
                sorted[next[r] as usize] = index(c);
                next[r] += 1;
            }
        }
        Self { offsets, corners: sorted }
    }

    /// The corners at root `r`.
    fn at(&self, r: usize) -> &[u32] {
        &self.corners[self.offsets[r] as usize..self.offsets[r + 1] as usize]
    }

    /// Steps 3 to 5 for every position, in parallel: each corner's tangent, in the order of
    /// `corners`.
    fn evaluate<N>(&self, surface: &Surface<'_, N>, keys: &Keys, faces: &[u8]) -> Vec<Vec4>
    where
        N: Fn(usize, usize) -> (Vec3, u32) + Sync,
    {
        let mut raw = vec![Vec4::ZERO; self.corners.len()];
        // Blocks of positions, cut where a position ends, about this many corners each.
        const BLOCK: usize = 1 << 14;
        let roots = self.offsets.len() - 1;
        let mut blocks = Vec::new();
        let mut rest: &mut [Vec4] = &mut raw;
        let mut start = 0;
        while start < roots {
            let mut end = start + 1;
            while end < roots && (self.offsets[end] - self.offsets[start]) as usize <= BLOCK {
                end += 1;
            }
            let len = (self.offsets[end] - self.offsets[start]) as usize;
            let (block, tail) = rest.split_at_mut(len);
            blocks.push((start..end, block));
            rest = tail;
            start = end;
        }
        blocks.into_par_iter().for_each_init(Scratch::default, |scratch, (range, out)| {
            let base = self.offsets[range.start] as usize;
            for r in range {
                let (lo, hi) = (self.offsets[r] as usize, self.offsets[r + 1] as usize);
                if lo < hi {
                    let at = Position { surface, keys, faces, corners: &self.corners[lo..hi] };
                    at.evaluate(scratch, &mut out[lo - base..hi - base]);
                }
            }
        });
        raw
    }
}

/// Scratch space for one position, reused from one to the next.
#[derive(Default)]
struct Scratch {
    /// Per local corner: its key, and the keys of the vertices after and before it in its
    /// triangle.
    key: Vec<u64>,
    next: Vec<u64>,
    prev: Vec<u64>,
    /// Local corners sorted by key (then corner).
    order: Vec<u32>,
    /// The healthy corners of one vertex (local indices), in corner order.
    members: Vec<u32>,
    /// Union-find over `members`.
    parent: Vec<u32>,
    /// `members` sorted by their previous vertex's key.
    by_prev: Vec<u32>,
    /// `members`' indices sorted by group.
    by_group: Vec<u32>,
    /// One group's local corners, in corner order.
    group: Vec<u32>,
    /// Per corner of `group`: its triangle seen from the vertex (`None`: a with-any one).
    frames: Vec<Option<Projected>>,
    /// Sub-groups of one group: their member lists and results.
    sub_members: Vec<Vec<u32>>,
    sub_result: Vec<Vec4>,
}

/// The corners at one position.
struct Position<'a, 'b, N> {
    surface: &'a Surface<'b, N>,
    keys: &'a Keys,
    /// Per triangle: its flags.
    faces: &'a [u8],
    /// Global corner indices, ascending.
    corners: &'a [u32],
}

impl<N> Position<'_, '_, N>
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    /// The flags of local corner `a`'s triangle.
    fn flags(&self, a: usize) -> u8 {
        self.faces[self.corners[a] as usize / 3]
    }

    /// Writes the tangent of every corner at this position into `out` (aligned with
    /// `self.corners`).
    fn evaluate(&self, s: &mut Scratch, out: &mut [Vec4]) {
        let k = self.corners.len();
        s.key.clear();
        s.next.clear();
        s.prev.clear();
        for &c in self.corners {
            let c = c as usize;
            let k = c % 3;
            let keys = self.keys.of_triangle(c / 3);
            s.key.push(keys[k]);
            s.next.push(keys[(k + 1) % 3]);
            s.prev.push(keys[(k + 2) % 3]);
        }
        s.order.clear();
        s.order.extend(0..index(k));
        if k > 1 {
            let key = &s.key;
            s.order.sort_unstable_by_key(|&a| (key[a as usize], a));
        }
        let mut i = 0;
        while i < k {
            let key = s.key[s.order[i] as usize];
            let mut j = i + 1;
            while j < k && s.key[s.order[j] as usize] == key {
                j += 1;
            }
            self.one_vertex(s, i..j, out);
            i = j;
        }
    }

    /// Steps 3 to 5 for the corners `s.order[range]`, which share one vertex.
    fn one_vertex(&self, s: &mut Scratch, range: std::ops::Range<usize>, out: &mut [Vec4]) {
        // Healthy corners only take part in the groups.
        s.members.clear();
        let order = &s.order[range.clone()];
        s.members
            .extend(order.iter().copied().filter(|&a| !self.flags(a as usize) & DEGENERATE != 0));
        let n = self.normal_of(s.order[range.start] as usize);
        // Corners no group reaches get a direction across the normal, w = +1.
        let none = n.any_orthonormal_vector().extend(1.0);
        for &a in order {
            out[a as usize] = none;
        }
        if !s.members.is_empty() {
            self.groups(s);
            self.group_tangents(s, n, out);
        }
        // Step 5: a degenerate triangle's corner copies the first healthy corner's result.
        let first_healthy = s.members.first().map(|&a| out[a as usize]);
        for &a in &s.order[range] {
            if self.flags(a as usize) & DEGENERATE != 0 {
                out[a as usize] = first_healthy.unwrap_or(none);
            }
        }
    }

    /// Step 3: union-find over `s.members` (into `s.parent`, every entry its root): two
    /// triangles join where they share an edge through the vertex and agree in orientation.
    fn groups(&self, s: &mut Scratch) {
        let m = s.members.len();
        s.parent.clear();
        s.parent.extend(0..index(m));
        if m == 1 {
            return;
        }
        let members = &s.members;
        s.by_prev.clear();
        s.by_prev.extend(0..index(m));
        let prev = |b: u32| s.prev[members[b as usize] as usize];
        s.by_prev.sort_unstable_by_key(|&b| (prev(b), b));
        for a in 0..m {
            let next = s.next[members[a] as usize];
            let from = s.by_prev.partition_point(|&b| prev(b) < next);
            for &b in s.by_prev[from..].iter().take_while(|&&b| prev(b) == next) {
                let (fa, fb) =
                    (self.flags(members[a] as usize), self.flags(members[b as usize] as usize));
                if (fa ^ fb) & ORIENTED == 0 {
                    union(&mut s.parent, index(a), b);
                }
            }
        }
        for a in 0..m {
            s.parent[a] = s.parent[s.parent[a] as usize];
        }
    }

    /// Step 4: each group's tangent, written for its members (`n` is the vertex's normal);
    /// corners of groups made only of with-any triangles keep what they have.
    fn group_tangents(&self, s: &mut Scratch, n: Vec3, out: &mut [Vec4]) {
        let m = s.members.len();
        // The members by group (root), in corner order within each.
        s.by_group.clear();
        s.by_group.extend(0..index(m));
        if m > 1 {
            s.by_group.sort_unstable_by_key(|&a| (s.parent[a as usize], a));
        }
        let mut i = 0;
        while i < m {
            let root = s.parent[s.by_group[i] as usize];
            let mut j = i + 1;
            while j < m && s.parent[s.by_group[j] as usize] == root {
                j += 1;
            }
            s.group.clear();
            s.group.extend(s.by_group[i..j].iter().map(|&a| s.members[a as usize]));
            self.one_group(s, n, out);
            i = j;
        }
    }

    /// Step 4 for the local corners `s.group`, one group.
    fn one_group(&self, s: &mut Scratch, n: Vec3, out: &mut [Vec4]) {
        let Some(&seed) = s.group.iter().find(|&&a| self.flags(a as usize) & ANY == 0) else {
            return;
        };
        let w = if self.flags(seed as usize) & ORIENTED != 0 { 1.0 } else { -1.0 };
        let finish = |sum: Vec3| crate::frame::orthogonal_tangent(n, sum).extend(w);
        s.frames.clear();
        for &a in &s.group {
            let a = a as usize;
            s.frames.push(if self.flags(a) & ANY != 0 { None } else { Some(self.frame(a, n)) });
        }
        if !splits(&s.frames) {
            let tangent = finish(s.frames.iter().flatten().map(|f| f.s * f.angle).sum());
            for &a in &s.group {
                out[a as usize] = tangent;
            }
            return;
        }
        // mikktspace.c's sub-groups: each member's set of similar members (with-any triangles
        // are similar to all) names its sub-group; equal sets share one result.
        s.sub_members.clear();
        s.sub_result.clear();
        for (i, &a) in s.group.iter().enumerate() {
            let similar: Vec<u32> = (0..s.group.len())
                .filter(|&j| similar(s.frames[i], s.frames[j]))
                .map(index)
                .collect();
            let l = s.sub_members.iter().position(|g| *g == similar).unwrap_or_else(|| {
                let sum: Vec3 = similar
                    .iter()
                    .filter_map(|&j| s.frames[j as usize])
                    .map(|f| f.s * f.angle)
                    .sum();
                s.sub_members.push(similar);
                s.sub_result.push(finish(sum));
                s.sub_members.len() - 1
            });
            out[a as usize] = s.sub_result[l];
        }
    }

    /// The normal of local corner `a`.
    fn normal_of(&self, a: usize) -> Vec3 {
        let c = self.corners[a] as usize;
        (self.surface.normal)(c, self.surface.triangles[c / 3][c % 3] as usize).0
    }

    /// Local corner `a`'s triangle seen from the vertex: see [`frame`].
    fn frame(&self, a: usize, n: Vec3) -> Projected {
        let c = self.corners[a] as usize;
        frame(self.surface, &face_tangent(self.surface, c / 3), c, n)
    }
}

/// One healthy triangle of a group, seen from the vertex: see [`Position::frame`].
#[derive(Clone, Copy, Debug)]
struct Projected {
    s: Vec3,
    t: Vec3,
    angle: f32,
}

/// Whether members `a` and `b` of a group are similar at mikktspace.c's default threshold
/// (180 degrees: a cosine above -1); with-any triangles (`None`) are similar to all.
fn similar(a: Option<Projected>, b: Option<Projected>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => a.s.dot(b.s) > -1.0 && a.t.dot(b.t) > -1.0,
        _ => true,
    }
}

/// Whether a group needs sub-groups: two of its members are not similar.
fn splits(frames: &[Option<Projected>]) -> bool {
    frames.iter().enumerate().any(|(i, &a)| frames[i + 1..].iter().any(|&b| !similar(a, b)))
}

/// Step 3's one order dependency: a with-any triangle takes an orientation from a neighbour.
/// In triangle order, each takes that of its first edge-neighbour (in corner order around
/// each of its vertices) that is healthy or already resolved; one without keeps its own.
fn resolve_orientations<N>(
    surface: &Surface<'_, N>,
    keys: &Keys,
    by_position: &ByPosition,
    faces: &mut [u8],
) {
    let is = |flags: u8, flag: u8| flags & flag != 0;
    let any: Vec<usize> =
        (0..faces.len()).filter(|&f| is(faces[f], ANY) && !is(faces[f], DEGENERATE)).collect();
    let mut resolved = vec![false; faces.len()];
    for f in any {
        let mut found = None;
        let own = keys.of_triangle(f);
        'corners: for k in 0..3 {
            let (next, prev) = (own[(k + 1) % 3], own[(k + 2) % 3]);
            let r = surface.roots[surface.triangles[f][k] as usize] as usize;
            for &b in by_position.at(r) {
                let (g, kb) = (b as usize / 3, b as usize % 3);
                let fb = faces[g];
                if g == f || is(fb, DEGENERATE) || (is(fb, ANY) && !resolved[g]) {
                    continue;
                }
                let theirs = keys.of_triangle(g);
                if theirs[kb] != own[k] {
                    continue;
                }
                if theirs[(kb + 2) % 3] == next || theirs[(kb + 1) % 3] == prev {
                    found = Some(fb & ORIENTED);
                    break 'corners;
                }
            }
        }
        if let Some(oriented) = found {
            faces[f] = (faces[f] & !ORIENTED) | oriented;
        }
        resolved[f] = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wavy grid of `n` x `n` quads whose right half has mirrored U, in one object, with
    /// per-vertex normals (the grid's up, tilted by the waves).
    fn wavy(n: u32) -> (Vec<Vec3>, Vec<Vec2>, Vec<[u32; 3]>, Vec<Vec3>) {
        let (mut p, mut uv, mut normals, mut tris) = (vec![], vec![], vec![], vec![]);
        for j in 0..=n {
            for i in 0..=n {
                let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
                let y = (x * 7.0).sin() * 0.1 + (z * 5.0).cos() * 0.1;
                p.push(Vec3::new(x, y, z));
                let u = if x > 0.5 { 1.0 - x } else { x };
                uv.push(Vec2::new(u, z));
                normals.push(
                    Vec3::new(-(x * 7.0).cos() * 0.7, 1.0, (z * 5.0).sin() * 0.5).normalize(),
                );
            }
        }
        let w = n + 1;
        for j in 0..n {
            for i in 0..n {
                let a = j * w + i;
                tris.push([a, a + w, a + w + 1]);
                tris.push([a, a + w + 1, a + 1]);
            }
        }
        (p, uv, tris, normals)
    }

    #[test]
    fn plain_fans_give_the_bits_of_the_grouping() {
        let (positions, uvs, triangles, normals) = wavy(24);
        let roots: Vec<u32> = (0..index(positions.len())).collect();
        let (vertex_start, triangle_start) =
            ([0, index(positions.len())], [0, index(triangles.len())]);
        let surface = Surface {
            positions: &positions,
            roots: &roots,
            uvs: &uvs,
            triangles: &triangles,
            vertex_start: &vertex_start,
            triangle_start: &triangle_start,
            normal: |_, v: usize| (normals[v], 0),
            vertex_normals: Some(&normals),
            v_axis: VAxis::Up,
        };
        let (fast, grouped) = (tangents_with(&surface, false), tangents_with(&surface, true));
        let plain = fast.plain.iter().filter(|&&p| p).count();
        assert!(plain > positions.len() / 2, "{plain} plain positions");
        for (c, &v) in triangles.as_flattened().iter().enumerate() {
            let (a, b) =
                (fast.get(c, v as usize, v as usize), grouped.get(c, v as usize, v as usize));
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits),
                "corner {c}"
            );
        }
    }
}
