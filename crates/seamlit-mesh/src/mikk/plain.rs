//! Plain positions: the fans whose tangent is one group's sum, found and summed in one pass
//! per object without the grouping, with step 1 (each triangle's flags) in the same pass.

use glam::{Vec2, Vec3, Vec4, Vec4Swizzles};
use rayon::prelude::*;

use super::Surface;
use super::face::{ANY, DEGENERATE, ORIENTED, corner_terms, face_flags};

/// What the corners at a vertex tell [`plain_positions`].
pub(super) const HAS_ORIENTED: u8 = 1;
pub(super) const HAS_REVERSED: u8 = 2;
/// With-any or degenerate triangles, or several normals at the position, or another vertex
/// of the position with the same key.
pub(super) const IRREGULAR: u8 = 4;
/// Its triangles do not close around it (see [`gather_object`]'s closures).
const OPEN: u8 = 8;

/// Mixes a key into 64 well-spread bits (splitmix64's finaliser): sums of these tell whether
/// two multisets of keys are equal, but for a 2^-64 chance.
pub(super) fn spread(key: u64) -> u64 {
    let mut z = key.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// What one pass over the triangles gathers per vertex, for [`plain_fans`], as two arrays
/// (of 16 and 1 bytes a vertex: at a million triangles these are fresh pages the kernel
/// clears, a good part of the pass's cost).
struct Gathered {
    /// Per object, per vertex: the sum of its corners' projected `s` times angle (healthy
    /// triangles, in triangle order), `w` zero. Per object, and as wide as a tangent, so that
    /// each object's sums can become its tangents in place ([`Fans`]).
    sums: Vec<Vec<Vec4>>,
    /// `HAS_ORIENTED`, `HAS_REVERSED`, `IRREGULAR`, `OPEN`.
    flags: Vec<u8>,
}

/// One object's part of [`Gathered`] and of the triangles' flags.
struct ObjectPart<'x> {
    o: usize,
    sums: &'x mut Vec<Vec4>,
    flags: &'x mut [u8],
    faces: &'x mut [u8],
}

/// Step 1 and the plain fans, in one pass over each object's triangles.
pub(super) struct PlainFans {
    /// Per triangle: its flags (see [`face_tangent`](super::face::face_tangent)).
    pub(super) faces: Vec<u8>,
    /// Per root vertex: whether its position is plain (see [`plain_fans`]).
    pub(super) plain: Vec<bool>,
    /// Per vertex at a plain position: the fan's sum, whose part across the normal is the
    /// tangent of all its corners (see [`Fans::tangent_of`]).
    pub(super) fans: Fans,
    /// The report's triangle counts where [`Surface::count`] asks (else zeros).
    pub(super) counts: [usize; 3],
}

/// The sums of the plain fans.
pub(super) struct Fans {
    /// Per object, per vertex: the sum (`xyz`; see [`Gathered::sums`]). Empty once taken.
    pub(super) sums: Vec<Vec<Vec4>>,
    /// Per vertex.
    flags: Vec<u8>,
}

impl Fans {
    /// The tangent of every corner of vertex `v`, at a plain position, whose corners' normal
    /// is `normal`, from the vertex's `sum`: the sum made orthogonal to it, `w` its triangles'
    /// orientation (zero for a vertex no triangle uses).
    pub(super) fn tangent_of(&self, v: usize, normal: Vec3, sum: Vec4) -> Vec4 {
        let w = match self.flags[v] & (HAS_ORIENTED | HAS_REVERSED) {
            HAS_ORIENTED => 1.0,
            HAS_REVERSED => -1.0,
            _ => return Vec4::ZERO,
        };
        crate::frame::orthogonal_tangent(normal, sum.xyz()).extend(w)
    }
}

/// Every triangle's flags, and per root vertex whether every vertex of its position is
/// *plain*, one MikkTSpace group whose tangent is summed here in the same pass: its corners
/// share one normal (a simple position) and it shares its key with no other vertex (`shared`);
/// its triangles are healthy (none with-any, none degenerate) and of one orientation; and
/// they close around it (every triangle's next vertex is another's previous one: the sums of
/// their spread keys agree). Such a fan is one group, and its tangent is the sum over its
/// corners in triangle order, as [`Position`](super::position) sums a group. The rest
/// (boundaries of objects and UV islands, mirror lines, creases, poles) go through the
/// grouping, position by position.
///
/// One case a closed fan does not rule out: two closed fans pinched at one vertex with one
/// UV, two groups for MikkTSpace; they are summed as one here.
pub(super) fn plain_fans<N>(surface: &Surface<'_, N>, shared: &[bool]) -> PlainFans
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    let n = surface.roots.len();
    let mut faces = vec![0u8; surface.triangle_count()];
    let objects = surface.vertex_start.len() - 1;
    let sums = (0..objects).map(|_| Vec::new()).collect();
    let mut gathered = Gathered { sums, flags: vec![0; n] };
    let counts = split_by_object(surface, &mut gathered, &mut faces)
        .into_par_iter()
        .map(|part| gather_object(surface, part))
        .reduce(|| [0; 3], crate::face::add_counts);
    let plain = plain_positions(surface, &gathered, shared);
    let Gathered { sums, flags, .. } = gathered;
    PlainFans { faces, plain, fans: Fans { sums, flags }, counts }
}

/// What [`gather_object`] learns of one triangle before it adds it to its vertices.
#[derive(Clone, Copy, Default)]
struct Told {
    /// `HAS_ORIENTED`, `HAS_REVERSED` or `IRREGULAR`, per corner (`IRREGULAR` where the corner's
    /// normal is not its position's one).
    bits: [u8; 3],
    /// Per corner, its projected `s` times its angle, where the triangle is healthy.
    terms: Option<[Vec3; 3]>,
}

/// Triangles [`gather_object`] works out before it adds them to their vertices: the work of
/// one triangle does not wait on the previous one's sums, so the processor overlaps several.
const BLOCK: usize = 32;

/// [`plain_fans`]' pass over one object's triangles: their flags into `faces` (the object's
/// part), and what their corners tell into the object's part of [`Gathered`]. Returns the
/// report's counts of its triangles where [`Surface::count`] asks (else zeros).
fn gather_object<N>(surface: &Surface<'_, N>, part: ObjectPart<'_>) -> [usize; 3]
where
    N: Fn(usize, usize) -> (Vec3, u32) + Sync,
{
    let ObjectPart { o, sums, flags: vertex_flags, faces } = part;
    // Allocated here, by the object's task: its pages are first touched by the thread that
    // fills them.
    *sums = vec![Vec4::ZERO; vertex_flags.len()];
    // Per vertex, the sum over its corners of the spread next vertex minus the spread
    // previous one: zero where its triangles close around it. Only that is kept (`OPEN`),
    // so these 8 bytes a vertex live while one object is gathered, not the whole model.
    let mut closures = vec![0u64; vertex_flags.len()];
    let b = surface.vertex_start[o];
    let first = surface.triangle_start[o] as usize;
    let uvs = surface.uvs[o];
    let mut told = [Told::default(); BLOCK];
    let mut counts = [0; 3];
    for (block, (faces, locals)) in
        faces.chunks_mut(BLOCK).zip(surface.triangles[o].chunks(BLOCK)).enumerate()
    {
        for (i, (flags, local)) in faces.iter_mut().zip(locals).enumerate() {
            let t = first + block * BLOCK + i;
            let uv = match uvs {
                Some(uvs) => {
                    [uvs[local[0] as usize], uvs[local[1] as usize], uvs[local[2] as usize]]
                }
                None => [Vec2::ZERO; 3],
            };
            let tri = [local[0] + b, local[1] + b, local[2] + b];
            if surface.count {
                let p = tri.map(|v| surface.positions[v as usize]);
                let flags = crate::face::face_flags(p, uvs.map(|_| uv), surface.v_axis);
                crate::face::count(&mut counts, flags);
            }
            let face = face_flags(surface, tri, uv);
            *flags = face.flags;
            let bits = if face.is(ANY | DEGENERATE) {
                IRREGULAR
            } else if face.is(ORIENTED) {
                HAS_ORIENTED
            } else {
                HAS_REVERSED
            };
            let normals: [(Vec3, u32); 3] =
                std::array::from_fn(|k| (surface.normal)(t * 3 + k, tri[k] as usize));
            let terms = (bits != IRREGULAR).then(|| {
                corner_terms(surface, &face, tri, normals.map(|n| n.0)).map(|(s, a)| s * a)
            });
            told[i] = Told {
                bits: std::array::from_fn(|k| bits | if normals[k].1 != 0 { IRREGULAR } else { 0 }),
                terms,
            };
        }
        for (local, told) in locals.iter().zip(&told) {
            // Vertices, not keys: a fan closed by vertex is closed by key (at a simple
            // position the corners of one vertex across an edge share a normal group); one
            // closed only through another vertex with the same key is not plain.
            let spreads = local.map(|v| spread((v + b).into()));
            for (k, &v) in local.iter().enumerate() {
                let v = v as usize;
                vertex_flags[v] |= told.bits[k];
                let (next, prev) = (spreads[(k + 1) % 3], spreads[(k + 2) % 3]);
                closures[v] = closures[v].wrapping_add(next).wrapping_sub(prev);
                if let Some(terms) = &told.terms {
                    sums[v] += terms[k].extend(0.0);
                }
            }
        }
    }
    for (flags, &closure) in vertex_flags.iter_mut().zip(&closures) {
        if closure != 0 {
            *flags |= OPEN;
        }
    }
    counts
}

/// Per root vertex: whether every vertex of its position is plain, from what
/// [`gather_object`] gathered.
fn plain_positions<N>(surface: &Surface<'_, N>, gathered: &Gathered, shared: &[bool]) -> Vec<bool> {
    let n = gathered.flags.len();
    let not_plain: Vec<u32> = (0..n)
        .into_par_iter()
        .filter(|&v| {
            let f = gathered.flags[v];
            let mixed = f & (HAS_ORIENTED | HAS_REVERSED) == HAS_ORIENTED | HAS_REVERSED;
            f & (IRREGULAR | OPEN) != 0 || mixed || shared[v]
        })
        .map(|v| surface.roots[v])
        .collect();
    let mut plain = vec![true; n];
    for r in not_plain {
        plain[r as usize] = false;
    }
    plain
}

/// [`Gathered`] (one entry per vertex) and `faces` (one per triangle) cut into each object's
/// part.
fn split_by_object<'x, N>(
    surface: &Surface<'_, N>,
    gathered: &'x mut Gathered,
    faces: &'x mut [u8],
) -> Vec<ObjectPart<'x>> {
    let objects = surface.vertex_start.len() - 1;
    let mut parts = Vec::with_capacity(objects);
    let mut sums = gathered.sums.iter_mut();
    let mut flags = &mut gathered.flags[..];
    let mut faces = faces;
    for o in 0..objects {
        let vertices = (surface.vertex_start[o + 1] - surface.vertex_start[o]) as usize;
        let triangles = (surface.triangle_start[o + 1] - surface.triangle_start[o]) as usize;
        let s = sums.next().expect("one sum array per object");
        let (f, rest_f) = flags.split_at_mut(vertices);
        let (t, rest_t) = faces.split_at_mut(triangles);
        parts.push(ObjectPart { o, sums: s, flags: f, faces: t });
        (flags, faces) = (rest_f, rest_t);
    }
    parts
}
