//! Keeping what the artist authored: which objects keep their normals and tangents, the
//! seam-only repair of kept normals, and tangents for kept normals that came without them.
//! docs/normals.md explains the policies.
//!
//! # The seam-only repair
//!
//! Only positions that vertices of two or more objects share (after the weld) are visited.
//! At each, every vertex (a *copy*) is first judged from its own object's faces there
//! ([`crate::judge`]): its face's normal (an authored hard edge), its object's smooth normal
//! (a seam per-object smoothing made), or neither (custom); copies of objects whose normals
//! were computed are smooth. Then the smooth copies are grouped: two join when their normals
//! lie within the crease angle of each other (connected components, as [`crate::group`]
//! groups faces). A group whose vertices all belong to one object, or whose normals are
//! already bit-equal in model space, is left alone; every other group gets one normal, the
//! weighted average of its corners' normals (each corner weighted by [`crate::Weighting`], in
//! corner order), the same model-space value for every vertex of the group. A kept normal is
//! one value per vertex, so all corners of a vertex fall into one group and the repair never
//! splits a vertex. Where a normal changes, the vertex's tangent (if it has one) is made
//! orthogonal to the new normal, its handedness kept. [`NormalPolicy::SmoothShared`] skips
//! the judgement: every copy is smooth (the rule before it existed).
//!
//! **Invariant:** every vertex not at a shared position, every vertex whose group lies
//! within one object, and every flat or custom copy keeps its normal and tangent bit for bit
//! (`tests/normals.rs`: `the_repair_joins_the_seam_and_nothing_else`,
//! `one_object_with_a_hard_edge_is_left_alone`; `tests/hard_edges.rs`).
//!
//! Cost: the corners at shared positions are gathered and sorted ([`Flat::corners_at`]); each
//! position is settled by one task, its vertices compared pairwise. Nothing is computed for
//! the rest of the model.

use glam::{Vec2, Vec3, Vec4, Vec4Swizzles};
use rayon::prelude::*;

use crate::face::face;
use crate::frame::{Linear, kept_normal_tangent, kept_normal_tangents, orthogonalise};
use crate::group::{Frame, Rules, weight};
use crate::index::{index, low_half};
use crate::judge::{self, Copy, Corner, Kind, Shading};
use crate::out::Out;
use crate::smooth::{self, face_frame};
use crate::validate::Flat;
use crate::weld::union;
use crate::{
    FixOptions, Mode, Model, NormalPolicy, Object, SharedNormals, TangentMethod, Weighting,
};

/// Per object: whether its authored normals and tangents are kept.
pub(crate) struct Authored {
    pub normals: Vec<bool>,
    pub tangents: Vec<bool>,
}

impl Authored {
    /// Which objects keep what they carry under `options`: normals where the policy is not
    /// [`NormalPolicy::Recompute`] and the object has a finite, non-zero normal for every
    /// vertex; tangents where the normals are kept, tangents are wanted, and the object has a
    /// finite tangent with a non-zero direction for every vertex.
    pub fn of(model: &Model, options: &FixOptions) -> Self {
        let keep = options.normals != NormalPolicy::Recompute;
        let normals: Vec<bool> =
            model.objects.iter().map(|o| keep && usable_normals(o.normals.as_deref())).collect();
        let tangents = model
            .objects
            .iter()
            .zip(&normals)
            .map(|(o, &n)| {
                n && options.tangents != TangentMethod::None
                    && usable_tangents(o.tangents.as_deref())
            })
            .collect();
        Self { normals, tangents }
    }

    /// Whether any object keeps its normals.
    pub fn any(&self) -> bool {
        self.normals.iter().any(|&k| k)
    }

    /// Whether every object keeps its normals.
    pub fn all(&self) -> bool {
        self.normals.iter().all(|&k| k)
    }
}

fn usable_normals(normals: Option<&[Vec3]>) -> bool {
    normals.is_some_and(|ns| ns.iter().all(|n| n.is_finite() && *n != Vec3::ZERO))
}

fn usable_tangents(tangents: Option<&[Vec4]>) -> bool {
    tangents.is_some_and(|ts| ts.iter().all(|t| t.is_finite() && t.xyz() != Vec3::ZERO))
}

/// A vertex at a shared position whose normal the repair sets.
struct Update {
    object: usize,
    vertex: u32,
    /// The group's normal, in model space, unit length.
    normal: Vec3,
}

/// The seam-only repair (see the module docs): at every position shared by two or more
/// objects, gives the copies that carry their object's smooth normal one normal per group.
/// `flat` holds the model's positions snapped to their `roots` (welded across the whole
/// model); every object has normals, authored where `kept` says so (the others' were
/// computed across the objects: they count as smooth). Returns, per object, how many
/// vertices' normals changed, and what was decided at the shared positions.
pub(crate) fn repair_seams(
    model: &mut Model,
    flat: &Flat,
    roots: &[u32],
    options: &FixOptions,
    kept: &[bool],
) -> (Vec<usize>, SharedNormals) {
    let view: &Model = model;
    let judge = options.normals != NormalPolicy::SmoothShared;
    let linear: Vec<Option<Linear>> = flat.linear.iter().map(|m| m.map(Linear::new)).collect();
    let judged: Vec<bool> = kept.iter().map(|&k| k && judge).collect();
    let positions = judged_positions(view, flat, roots, &linear, options.weighting, &judged);
    let shading = shading(view, flat, &positions);
    let rules = Rules::new(options, false);
    let (updates, shared) = positions
        .par_iter()
        .fold(
            || (Vec::new(), SharedNormals::default()),
            |(mut out, mut shared), position| {
                let class = repair_position(position, &shading, rules.crease_cos, &mut out);
                *class.count(&mut shared) += 1;
                (out, shared)
            },
        )
        .reduce(|| (Vec::new(), SharedNormals::default()), merge);
    (apply(model, &linear, &updates), shared)
}

/// Two partial results of [`repair_seams`] as one.
fn merge(
    (mut a, sa): (Vec<Update>, SharedNormals),
    (b, sb): (Vec<Update>, SharedNormals),
) -> (Vec<Update>, SharedNormals) {
    a.extend(b);
    let shared = SharedNormals {
        repaired: sa.repaired + sb.repaired,
        hard_edges: sa.hard_edges + sb.hard_edges,
        custom: sa.custom + sb.custom,
        agreeing: sa.agreeing + sb.agreeing,
    };
    (a, shared)
}

/// Which copies of the positions that objects share are sides of a seam, as the seam-only
/// repair of `options` judges them: per group of `copies` ([`crate::shared_copies`]), per
/// copy, whether it carries its object's smooth normal (or will: its object's normals are
/// computed). Copies that carry flat or custom normals, which the repair keeps, are not.
/// Under [`NormalPolicy::SmoothShared`] and [`NormalPolicy::Recompute`] every copy is.
///
/// # Errors
///
/// [`MeshError`] where the model is not valid (as [`crate::fix`]).
pub fn seam_copies(
    model: &Model,
    copies: &[Vec<(u32, u32)>],
    options: &FixOptions,
) -> Result<Vec<Vec<bool>>, crate::MeshError> {
    let authored = Authored::of(model, options);
    let judge = !matches!(options.normals, NormalPolicy::SmoothShared | NormalPolicy::Recompute);
    let mut sides: Vec<((u32, u32), bool)> = Vec::new();
    if judge && authored.any() {
        let mut flat = crate::validate::flatten(model)?;
        let tolerance = options.weld_tolerance.absolute(crate::weld::diagonal(&flat));
        let roots = crate::weld::roots(&flat.positions, tolerance);
        crate::weld::snap_to_roots(&mut flat.positions, &roots);
        let linear: Vec<Option<Linear>> = flat.linear.iter().map(|m| m.map(Linear::new)).collect();
        let positions =
            judged_positions(model, &flat, &roots, &linear, options.weighting, &authored.normals);
        let shading = shading(model, &flat, &positions);
        for p in &positions {
            for (v, kind) in p.vertices.iter().zip(resolve(p, &shading)) {
                let object = u32::try_from(v.object).expect("validated: fits u32");
                sides.push(((object, v.vertex), kind == Kind::Smooth));
            }
        }
        sides.sort_unstable_by_key(|&(copy, _)| copy);
    }
    let side = |&(o, v): &(u32, u32)| {
        !judge
            || !authored.normals[o as usize]
            || sides.binary_search_by_key(&(o, v), |&(copy, _)| copy).is_ok_and(|i| sides[i].1)
    };
    Ok(copies.iter().map(|group| group.iter().map(side).collect()).collect())
}

/// The kinds of a position's vertices with the coplanar ones decided by their object's
/// shading next to them (`shading`, per object; [`judge::Shading::smooth_at`]).
fn resolve(position: &Position, shading: &[Option<Shading>]) -> Vec<Kind> {
    let Position { vertices, fans, kinds, .. } = position;
    (0..vertices.len())
        .map(|a| match kinds[a] {
            Kind::Coplanar => {
                let Some(shading) = &shading[vertices[a].object] else { return Kind::Smooth };
                let own = fans.iter().filter(|(copy, ..)| *copy == a);
                let fan = own.flat_map(|(_, t, _)| t.iter().copied());
                if shading.smooth_at(fan.filter(|&v| v != vertices[a].vertex)) {
                    Kind::Smooth
                } else {
                    Kind::Flat
                }
            }
            kind => kind,
        })
        .collect()
}

/// A vertex at one position, as the repair sees it.
struct SeamVertex {
    object: usize,
    vertex: u32,
    /// Its normal in model space, as stored (before normalising): equal bits mean agreement.
    stored: Vec3,
    /// Unit length.
    unit: Vec3,
}

/// One shared position, judged: its vertices, each corner's vertex and weight, and what each
/// vertex's normal is.
struct Position {
    vertices: Vec<SeamVertex>,
    corners: Vec<(usize, f32)>,
    /// Per corner: its vertex, its triangle's vertices (in its object) and unit normal.
    fans: Vec<(usize, [u32; 3], Vec3)>,
    kinds: Vec<Kind>,
}

/// Every position that two or more objects share, its vertices judged ([`judge::judge`])
/// where their object is marked in `judged`, [`Kind::Smooth`] elsewhere.
fn judged_positions(
    model: &Model,
    flat: &Flat,
    roots: &[u32],
    linear: &[Option<Linear>],
    weighting: Weighting,
    judged: &[bool],
) -> Vec<Position> {
    let shared = flat.shared_positions(roots);
    let entries = flat.corners_at(model, roots, |r| shared[r as usize]);
    drop(shared);
    entries
        .par_chunk_by(|a, b| a >> 32 == b >> 32)
        .map(|run| {
            let (vertices, faces) = gather(model, flat, linear, run);
            let corners = faces.iter().map(|c| (c.copy, weight(weighting, &c.face, c.k))).collect();
            let fans = faces.iter().map(|c| (c.copy, c.triangle, c.face.normal)).collect();
            // Copies that agree bit for bit need no judging: nothing is done there.
            let bits = |n: Vec3| n.to_array().map(f32::to_bits);
            let agree = vertices.iter().all(|v| bits(v.stored) == bits(vertices[0].stored));
            let kinds = if !agree && vertices.iter().any(|v| judged[v.object]) {
                let copies: Vec<Copy> =
                    vertices.iter().map(|v| Copy { object: v.object, unit: v.unit }).collect();
                let kinds = judge::judge(&copies, &faces);
                kinds
                    .iter()
                    .zip(&vertices)
                    .map(|(&k, v)| if judged[v.object] { k } else { Kind::Smooth })
                    .collect()
            } else {
                vec![Kind::Smooth; vertices.len()]
            };
            Position { vertices, corners, fans, kinds }
        })
        .collect()
}

/// The vertices at one position (`run`: its corners, `root << 32 | corner`, ascending), in
/// order of first corner, and each corner with its vertex and face.
fn gather(
    model: &Model,
    flat: &Flat,
    linear: &[Option<Linear>],
    run: &[u64],
) -> (Vec<SeamVertex>, Vec<Corner>) {
    let mut vertices: Vec<SeamVertex> = Vec::new();
    let mut corners = Vec::with_capacity(run.len());
    for &e in run {
        let c = low_half(e) as usize;
        let t = c / 3;
        let o = flat.object_of_triangle(t);
        let local = t - flat.triangle_start[o] as usize;
        let object = &model.objects[o];
        let v = object.triangles[local][c % 3];
        let at = vertices.iter().position(|x| x.object == o && x.vertex == v);
        let copy = at.unwrap_or_else(|| {
            let n = object.normals.as_ref().map_or(Vec3::Z, |ns| ns[v as usize]);
            let stored = linear[o].as_ref().map_or(n, |l| l.normal_to_model(n));
            let unit = stored.try_normalize().unwrap_or(Vec3::Z);
            vertices.push(SeamVertex { object: o, vertex: v, stored, unit });
            vertices.len() - 1
        });
        let positions = flat.corners(model, o, local).positions;
        let (face, k) = (face(positions, None, model.v_axis), c % 3);
        let triangle = object.triangles[local];
        let uniform = object.normals.as_deref().is_some_and(|ns| judge::uniform(ns, triangle));
        corners.push(Corner { copy, face, k, triangle, uniform });
    }
    (vertices, corners)
}

/// Per object: how the other vertices of its coplanar copies' faces join its faces
/// ([`Shading`]), and where those tell nothing, how the whole object is shaded; `None` for
/// objects without a coplanar copy at a shared position. The vertices at shared positions
/// are known from the positions' corners; the object's triangles are scanned only for a fan
/// that those do not decide.
fn shading(model: &Model, flat: &Flat, positions: &[Position]) -> Vec<Option<Shading>> {
    // Per object: each coplanar copy's fan (the other vertices of its faces), and how the
    // copies at shared positions join their faces.
    let mut fans: Vec<Vec<Vec<u32>>> = vec![Vec::new(); model.objects.len()];
    let mut known: Vec<Vec<(u32, Vec<Vec3>)>> = vec![Vec::new(); model.objects.len()];
    for p in positions {
        for (a, (v, kind)) in p.vertices.iter().zip(&p.kinds).enumerate() {
            let own = || p.fans.iter().filter(move |(copy, ..)| *copy == a);
            known[v.object].push((v.vertex, own().map(|&(.., n)| n).collect()));
            if *kind == Kind::Coplanar {
                let fan = own().flat_map(|(_, t, _)| *t).filter(|&u| u != v.vertex);
                fans[v.object].push(fan.collect());
            }
        }
    }
    fans.into_par_iter()
        .zip(known)
        .enumerate()
        .map(|(o, (fans, known))| {
            if fans.is_empty() {
                return None;
            }
            // A curved vertex decides a fan; otherwise its vertices away from the shared
            // positions may still be: scan for those fans.
            let at_shared = Shading::known(known);
            let open: Vec<&Vec<u32>> = fans
                .iter()
                .filter(|fan| at_shared.near(fan.iter().copied()) != Some(true))
                .collect();
            if open.is_empty() {
                return Some(at_shared);
            }
            let object = &model.objects[o];
            let normal =
                |t: usize| face(flat.corners(model, o, t).positions, None, model.v_axis).normal;
            let mut asked: Vec<u32> = open.iter().copied().flatten().copied().collect();
            asked.sort_unstable();
            asked.dedup();
            let (triangles, n) = (&object.triangles, object.vertex_count());
            let near = Shading::of(triangles, normal, &asked, n, false);
            let whole = open.iter().any(|fan| near.near(fan.iter().copied()).is_none());
            let scanned =
                if whole { Shading::of(triangles, normal, &asked, n, true) } else { near };
            Some(scanned.or(at_shared))
        })
        .collect()
}

/// What was decided at one shared position (see [`SharedNormals`]).
#[derive(Clone, Copy)]
enum Class {
    Repaired,
    HardEdge,
    Custom,
    Agreeing,
}

impl Class {
    fn count(self, shared: &mut SharedNormals) -> &mut usize {
        match self {
            Self::Repaired => &mut shared.repaired,
            Self::HardEdge => &mut shared.hard_edges,
            Self::Custom => &mut shared.custom,
            Self::Agreeing => &mut shared.agreeing,
        }
    }
}

/// Groups the smooth vertices at one position and pushes an [`Update`] for every vertex of
/// every group that needs one normal; says what was decided there.
fn repair_position(
    position: &Position,
    shading: &[Option<Shading>],
    crease_cos: Option<f32>,
    out: &mut Vec<Update>,
) -> Class {
    let Position { vertices, corners, .. } = position;
    // A coplanar vertex is as its object is shaded.
    let kinds = resolve(position, shading);

    // Groups: smooth vertices whose normals lie within the crease angle, joined transitively.
    let k = vertices.len();
    let mut parent: Vec<u32> = (0..index(k)).collect();
    for a in (0..k).filter(|&a| kinds[a] == Kind::Smooth) {
        for b in (a + 1..k).filter(|&b| kinds[b] == Kind::Smooth) {
            if crease_cos.is_none_or(|cos| vertices[a].unit.dot(vertices[b].unit) >= cos) {
                union(&mut parent, index(a), index(b));
            }
        }
    }
    for a in 0..k {
        // Roots are the smallest members: one pass points every vertex at its root.
        parent[a] = parent[parent[a] as usize];
    }

    // One normal per group that spans objects and does not agree already.
    let bits = |n: Vec3| n.to_array().map(f32::to_bits);
    let mut repaired = false;
    for g in 0..k {
        if parent[g] as usize != g {
            continue;
        }
        let members = || (0..k).filter(|&a| parent[a] as usize == g);
        let first = &vertices[g];
        let spans_objects = members().any(|a| vertices[a].object != first.object);
        let agrees = members().all(|a| bits(vertices[a].stored) == bits(first.stored));
        if !spans_objects || agrees {
            continue;
        }
        let mut sum = Vec3::ZERO;
        for &(a, w) in corners {
            if parent[a] as usize == g {
                sum += vertices[a].unit * w;
            }
        }
        let normal = sum
            .try_normalize()
            .or_else(|| members().map(|a| vertices[a].unit).sum::<Vec3>().try_normalize())
            .unwrap_or(first.unit);
        out.extend(members().map(|a| Update {
            object: vertices[a].object,
            vertex: vertices[a].vertex,
            normal,
        }));
        repaired = true;
    }
    if repaired {
        Class::Repaired
    } else if vertices.iter().all(|v| v.unit.dot(vertices[0].unit) >= judge::noise_cos()) {
        // Equal but for rounding (coplanar faces of two objects): nothing to tell apart.
        Class::Agreeing
    } else if kinds.contains(&Kind::Flat) || !kinds.contains(&Kind::Custom) {
        Class::HardEdge
    } else {
        Class::Custom
    }
}

/// Writes the repaired normals into the objects (in each object's local space), with their
/// tangents made orthogonal to them; returns, per object, the vertices whose normal changed.
fn apply(model: &mut Model, linear: &[Option<Linear>], updates: &[Update]) -> Vec<usize> {
    let mut changed = vec![0; model.objects.len()];
    for u in updates {
        let (o, v) = (u.object, u.vertex as usize);
        let object = &mut model.objects[o];
        let Some(normals) = object.normals.as_mut() else { continue };
        let n = linear[o].as_ref().map_or(u.normal, |l| l.normal_to_local(u.normal));
        if normals[v].to_array().map(f32::to_bits) == n.to_array().map(f32::to_bits) {
            continue;
        }
        normals[v] = n;
        changed[o] += 1;
        if let Some(tangents) = object.tangents.as_mut() {
            tangents[v] = orthogonalise(tangents[v], n.try_normalize().unwrap_or(Vec3::Z));
        }
    }
    changed
}

/// Computes tangents for the objects marked in `which` (objects whose normals were kept and
/// that have UVs but no tangents to keep), against their normals as they are: each corner
/// takes the tangent the generator of `options` gives it, made orthogonal to the vertex's
/// normal, its handedness taken against that normal; a vertex whose corners get different
/// tangents is split. `flat` holds the model's positions (snapped to `roots` where the mode
/// welds; `roots` is `None` in [`Mode::Flat`]).
///
/// The generator's model-space frame of every corner: face frames in [`Mode::Flat`],
/// MikkTSpace over the whole model with the model's normals, or seamlit's smoothed frames.
/// Each is made triangle by triangle as its object is written, not kept for the whole model
/// (32 bytes a corner: 100 MB of a 1M-triangle model).
///
/// With `count`, where a generator passes over every triangle of the welded model
/// (MikkTSpace's, seamlit's), returns the report's triangle counts over `flat`'s positions
/// (see [`crate::face::count`]); else `None`.
pub(crate) fn compute_tangents(
    model: &mut Model,
    flat: &Flat,
    roots: Option<Vec<u32>>,
    options: &FixOptions,
    which: &[bool],
    count: bool,
) -> Option<[usize; 3]> {
    if !which.iter().any(|&w| w) {
        return None;
    }
    match (options.mode, options.tangents, roots) {
        (Mode::Flat, ..) | (_, _, None) => {
            let v_axis = model.v_axis;
            let each = vec![(); model.objects.len()];
            write_each(model, flat, which, each, |o, (), _, tri, uvs| {
                let base = flat.vertex_start[o];
                let p = tri.map(|i| flat.positions[(base + i) as usize]);
                [CornerFrame::own(face_frame(&face(p, uvs, v_axis))); 3]
            });
            None
        }
        (_, TangentMethod::Mikktspace, Some(roots)) => {
            mikk_tangents(model, flat, &roots, which, count)
        }
        (_, _, Some(roots)) => {
            let smooth = smooth::smooth(model, flat, roots, Rules::new(options, true), count);
            let each = vec![(); model.objects.len()];
            write_each(model, flat, which, each, |o, (), t, tri, _| {
                let triangle = flat.triangle_start[o] as usize + t;
                let base = flat.vertex_start[o] as usize;
                std::array::from_fn(|k| {
                    let v = base + tri[k] as usize;
                    match smooth.simple_frame(v) {
                        Some(frame) => CornerFrame { frame, whole_vertex: true },
                        None => CornerFrame::own(smooth.corner_frame(index(triangle * 3 + k), v)),
                    }
                })
            });
            smooth.counts
        }
    }
}

/// [`compute_tangents`] with MikkTSpace: over the whole model, against each object's
/// normals in model space. With `count`, returns the report's triangle counts.
fn mikk_tangents(
    model: &mut Model,
    flat: &Flat,
    roots: &[u32],
    which: &[bool],
    count: bool,
) -> Option<[usize; 3]> {
    let linear: Vec<Option<Linear>> = flat.linear.iter().map(|m| m.map(Linear::new)).collect();
    // Per vertex: the object's normal in model space (+Z where it has none).
    let vertex_normals: Vec<Vec3> = (0..flat.positions.len())
        .into_par_iter()
        .map(|v| {
            let o = crate::index::part_of(&flat.vertex_start, v);
            let n = model.objects[o]
                .normals
                .as_ref()
                .map_or(Vec3::Z, |ns| ns[v - flat.vertex_start[o] as usize]);
            linear[o].as_ref().map_or(n, |l| l.normal_to_model(n)).normalize_or(Vec3::Z)
        })
        .collect();
    let uvs: Vec<Option<&[Vec2]>> = model.objects.iter().map(|o| o.uvs.as_deref()).collect();
    let local: Vec<&[[u32; 3]]> = model.objects.iter().map(|o| &o.triangles[..]).collect();
    let surface = crate::mikk::Surface {
        positions: &flat.positions,
        roots,
        uvs: &uvs,
        triangles: &local,
        vertex_start: &flat.vertex_start,
        triangle_start: &flat.triangle_start,
        normal: |_, v: usize| (vertex_normals[v], 0),
        vertex_normals: Some(&vertex_normals),
        v_axis: model.v_axis,
        count,
    };
    let mut tangents = crate::mikk::tangents(&surface);
    let counts = tangents.counts();
    drop((uvs, local));
    // Each plain vertex's tangent once, not once a corner, in its fan's sum's place.
    let mut fans = tangents.take_sums();
    fans.par_iter_mut().enumerate().filter(|(o, _)| which[*o]).for_each(|(o, sums)| {
        let base = flat.vertex_start[o] as usize;
        sums.par_iter_mut().enumerate().for_each(|(i, sum)| {
            let (v, root) = (base + i, roots[base + i] as usize);
            *sum = tangents.fan_of(v, root, vertex_normals[v], *sum).unwrap_or_default();
        });
    });
    let tangents = &tangents;
    let vertex_normals = &vertex_normals;
    // Per object: its fans' tangents, its corners at positions that are not plain (in corner
    // order) with their tangents, and how far it is through them.
    let each = fans
        .into_iter()
        .enumerate()
        .map(|(o, fans)| {
            let corners =
                flat.triangle_start[o] as usize * 3..flat.triangle_start[o + 1] as usize * 3;
            (fans, tangents.others(corners), 0)
        })
        .collect();
    type Each<'a> = (Vec<Vec4>, &'a [(u32, Vec4)], usize);
    write_each(model, flat, which, each, |o, (fans, others, next): &mut Each<'_>, t, tri, _| {
        let base = flat.vertex_start[o] as usize;
        std::array::from_fn(|k| {
            let v = base + tri[k] as usize;
            let normal = vertex_normals[v];
            if tangents.is_plain(roots[v] as usize) {
                let frame = Frame { normal, tangent: fans[tri[k] as usize] };
                return CornerFrame { frame, whole_vertex: true };
            }
            let (c, tangent) = others[*next];
            debug_assert_eq!(c as usize, (flat.triangle_start[o] as usize + t) * 3 + k);
            *next += 1;
            CornerFrame::own(Frame { normal, tangent })
        })
    });
    counts
}

/// A corner's model-space frame from the tangent generator, and whether it is its vertex's
/// one frame: every corner of the vertex gets the same (a plain or simple position), so the
/// vertex's first corner writes it for all.
#[derive(Clone, Copy)]
struct CornerFrame {
    frame: Frame,
    whole_vertex: bool,
}

impl CornerFrame {
    /// A frame of this corner's own.
    fn own(frame: Frame) -> Self {
        Self { frame, whole_vertex: false }
    }
}

/// Writes the tangents of every object marked in `which`, in parallel: `frames(o, its item
/// of each, t, triangle, its UVs)` gives the model-space frames of the corners of object
/// `o`'s triangle `t` (its input vertices, before any split), in triangle order.
fn write_each<S: Send>(
    model: &mut Model,
    flat: &Flat,
    which: &[bool],
    each: Vec<S>,
    frames: impl Fn(usize, &mut S, usize, [u32; 3], Option<[Vec2; 3]>) -> [CornerFrame; 3] + Sync,
) {
    let objects = model.objects.par_iter_mut().zip(each).enumerate();
    objects.filter(|(o, _)| which[*o]).for_each(|(o, (object, mut item))| {
        let linear = flat.linear[o].map(Linear::new);
        write_tangents(object, linear, |t, tri, uvs| frames(o, &mut item, t, tri, uvs));
    });
}

/// Writes one object's tangents from its corners' model-space frames, `frames(t, triangle,
/// its UVs)` for its triangle `t`, keeping its normals. The corners are placed in order, a
/// [`Corners`] batch at a time.
fn write_tangents(
    object: &mut Object,
    linear: Option<Linear>,
    mut frames: impl FnMut(usize, [u32; 3], Option<[Vec2; 3]>) -> [CornerFrame; 3],
) {
    let mut triangles = std::mem::take(&mut object.triangles);
    let mut out = Out::keeping_normals(object);
    let mut batch = Corners::default();
    for t in 0..triangles.len() {
        let tri = triangles[t];
        let uvs = out.uvs.as_ref().map(|uvs| tri.map(|i| uvs[i as usize]));
        let f = frames(t, tri, uvs);
        for k in 0..3 {
            let CornerFrame { frame, whole_vertex } = f[k];
            if whole_vertex && (out.is_set[tri[k] as usize] || batch.has_vertex(tri[k])) {
                // Its vertex's first corner wrote (or, in the batch, will write) this frame:
                // the vertex keeps its normal, and the same inputs give the same bits. The
                // corner stays on the vertex.
                continue;
            }
            if batch.push(index(t * 3 + k), tri[k], frame) {
                batch.place(&mut out, linear.as_ref(), &mut triangles);
            }
        }
    }
    batch.place(&mut out, linear.as_ref(), &mut triangles);
    let (mut normals, mut tangents) = (None, None);
    out.finish(&mut normals, &mut tangents);
    (object.normals, object.tangents, object.triangles) = (normals, tangents, triangles);
}

/// The corners [`Corners`] holds.
const CORNERS: usize = 32;

/// Corners of [`write_tangents`] waiting to be placed: their tangents are made four at once
/// ([`kept_normal_tangents`]) before any is placed, so that the processor works on several
/// (each a chain of dependent roots and divisions) rather than one after the other behind
/// the placing of the last. Placed in the order they came, as one by one.
struct Corners {
    /// Each corner: `triangle * 3 + k`.
    corner: [u32; CORNERS],
    vertex: [u32; CORNERS],
    frame: [(Vec3, Vec4); CORNERS],
    len: usize,
}

impl Default for Corners {
    fn default() -> Self {
        Self {
            corner: [0; CORNERS],
            vertex: [0; CORNERS],
            frame: [(Vec3::ZERO, Vec4::ZERO); CORNERS],
            len: 0,
        }
    }
}

impl Corners {
    /// Whether a corner of vertex `v` is waiting.
    fn has_vertex(&self, v: u32) -> bool {
        self.vertex[..self.len].contains(&v)
    }

    /// Adds a corner; returns whether the batch is full.
    fn push(&mut self, corner: u32, vertex: u32, frame: Frame) -> bool {
        let i = self.len;
        (self.corner[i], self.vertex[i]) = (corner, vertex);
        self.frame[i] = (frame.normal, frame.tangent);
        self.len += 1;
        self.len == CORNERS
    }

    /// Places every waiting corner: its vertex, or the copy with its frame.
    fn place(&mut self, out: &mut Out<'_>, linear: Option<&Linear>, triangles: &mut [[u32; 3]]) {
        let n = self.len;
        let mut kept = [Vec3::ZERO; CORNERS];
        for (k, &v) in kept.iter_mut().zip(&self.vertex[..n]) {
            *k = out.normal(v);
        }
        let mut tangents = [Vec4::ZERO; CORNERS];
        let (quads, _) = self.frame[..n].as_chunks::<4>();
        let (kept4, _) = kept[..n].as_chunks::<4>();
        for ((t, &frames), &kept) in
            tangents.as_chunks_mut::<4>().0.iter_mut().zip(quads).zip(kept4)
        {
            *t = kept_normal_tangents(linear, kept, frames);
        }
        for i in quads.len() * 4..n {
            tangents[i] = kept_normal_tangent(linear, kept[i], self.frame[i]);
        }
        for i in 0..n {
            let (c, v) = (self.corner[i] as usize, self.vertex[i]);
            triangles[c / 3][c % 3] = out.put_local(v, kept[i], tangents[i]);
        }
        self.len = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What [`write_tangents`] did before its corners were batched: each corner placed as it
    /// came, its tangent made alone.
    fn one_by_one(
        object: &mut Object,
        linear: Option<Linear>,
        frames: impl Fn(usize, [u32; 3]) -> [CornerFrame; 3],
    ) {
        let mut triangles = std::mem::take(&mut object.triangles);
        let mut out = Out::keeping_normals(object);
        for (t, tri) in triangles.iter_mut().enumerate() {
            let f = frames(t, *tri);
            for k in 0..3 {
                let CornerFrame { frame, whole_vertex } = f[k];
                if whole_vertex && out.is_set[tri[k] as usize] {
                    continue;
                }
                let n = out.normal(tri[k]);
                let tangent =
                    kept_normal_tangent(linear.as_ref(), n, (frame.normal, frame.tangent));
                tri[k] = out.put_local(tri[k], n, tangent);
            }
        }
        let (mut normals, mut tangents) = (None, None);
        out.finish(&mut normals, &mut tangents);
        (object.normals, object.tangents, object.triangles) = (normals, tangents, triangles);
    }

    /// Batched, the corners land where they did one by one: the same vertices, copies and
    /// tangents, over batches that end inside triangles, vertices whose first corner waits
    /// in the batch, and corners of one vertex with different frames (copies).
    #[test]
    fn batched_corners_land_as_one_by_one() {
        // A strip of 200 triangles over 202 vertices; the last vertex is used by none.
        let n = 203;
        let positions = (0..n).map(|i| Vec3::new(i as f32, (i % 2) as f32, 0.0)).collect();
        let triangles: Vec<[u32; 3]> = (0..200).map(|i| [i, i + 1, i + 2]).collect();
        let mut object = Object::new("strip", positions, triangles);
        object.normals = Some((0..n).map(|i| Vec3::new(0.1 * (i % 3) as f32, 0.0, 1.0)).collect());
        let frames = |t: usize, tri: [u32; 3]| {
            std::array::from_fn(|k| {
                let v = tri[k] as usize;
                let tangent = Vec4::new(1.0, 0.05 * (v % 4) as f32, 0.0, 1.0);
                // Every fifth vertex's corners are its own: each triangle gives another frame.
                if v.is_multiple_of(5) {
                    let tangent = Vec4::new(1.0, 0.1 * (t % 3) as f32, 0.0, -1.0);
                    CornerFrame::own(Frame { normal: Vec3::Z, tangent })
                } else {
                    CornerFrame { frame: Frame { normal: Vec3::Z, tangent }, whole_vertex: true }
                }
            })
        };
        for linear in [None, Some(Linear::new(glam::Mat3::from_rotation_z(0.7)))] {
            let (mut batched, mut alone) = (object.clone(), object.clone());
            write_tangents(&mut batched, linear, |t, tri, _| frames(t, tri));
            one_by_one(&mut alone, linear, frames);
            assert!(alone.positions.len() > n, "the frames make copies: {}", alone.positions.len());
            assert_eq!(batched, alone);
        }
    }
}
