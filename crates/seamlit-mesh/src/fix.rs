//! The fix pipeline: validate and flatten, weld, smooth, then write each object back with its
//! vertices split where one position needs several values; under [`NormalPolicy::Auto`] and
//! [`NormalPolicy::Keep`], objects that carry normals keep them and [`crate::repair`] repairs
//! the seams between objects.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::face::face;
use crate::frame::Linear;
use crate::group::{Frame, Rules};
use crate::index::{index, low_half};
use crate::mikk;
use crate::morph;
use crate::out::Out;
use crate::repair::{self, Authored};
use crate::smooth::{self, Smooth, face_frame};
use crate::validate::{self, Flat};
use crate::weld::{self, Welded, diagonal, roots_for_mode};
use crate::{
    Changes, FixOptions, MeshError, Mode, Model, NormalPolicy, Object, ObjectChanges,
    SharedNormals, TangentMethod,
};

/// Computes seam-free normals and tangents for every object of `model`.
///
/// Returns a copy of the model in which every object has `normals`, and `tangents` where it
/// has UVs (unless `options.tangents` is [`TangentMethod::None`]). Which input normals and
/// tangents are kept is `options.normals`' choice ([`NormalPolicy`]): with
/// [`NormalPolicy::Recompute`] every one is ignored and computed; otherwise objects that carry
/// normals keep them (with [`NormalPolicy::Auto`] in [`Mode::Model`], repaired where objects
/// meet), and the others get them computed. Computed normals are shared by faces only within
/// their smoothing group, where the objects have them ([`Object::smoothing_groups`]). Vertices
/// are split where one position needs several values: at a crease, between smoothing groups,
/// across a change of UV handedness, between tangents further apart than the tangent angle.
/// Split vertices are appended after the object's original vertices, which keep their indices,
/// and recorded in [`Object::split_from`]. Vertices on a boundary between objects get
/// bit-identical normals in model space (up to each object's transform back to its local
/// space) in [`Mode::Model`], unless the policy is [`NormalPolicy::Keep`].
///
/// The result does not depend on the number of threads: every sum runs in a fixed order.
/// Fixing a fixed model changes nothing. [`fix_in_place`] does the same without the copy, and
/// says what it changed.
///
/// # Errors
///
/// A [`MeshError`] naming the object and element for: attribute arrays of the wrong length,
/// indices out of range, a non-finite or singular transform, non-finite positions (after the
/// transform) or UVs, or more than [`crate::MAX_ELEMENTS`] vertices, corners, or both together.
pub fn fix(model: &Model, options: &FixOptions) -> Result<Model, MeshError> {
    let flat = validate::flatten(model)?;
    let authored = Authored::of(model, options);
    let objects = model
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| Object {
            name: o.name.clone(),
            positions: o.positions.clone(),
            uvs: o.uvs.clone(),
            uvs1: o.uvs1.clone(),
            colors: o.colors.clone(),
            // Kept normals are copied; computed objects' vertices that no triangle uses keep
            // their input normal, read from `model` below.
            normals: if authored.normals[i] { o.normals.clone() } else { None },
            tangents: if authored.tangents[i] { o.tangents.clone() } else { None },
            triangles: o.triangles.clone(),
            transform: o.transform,
            material: o.material,
            smoothing_groups: o.smoothing_groups.clone(),
            split_from: o.split_from.clone(),
            skin: o.skin.clone(),
            morph_targets: o.morph_targets.clone(),
        })
        .collect();
    let mut out = Model { objects, v_axis: model.v_axis };
    let plan =
        Plan { options, input: Some(model), authored: &authored, keep_weld: false, given: None };
    let (_, weld) = run(&mut out, flat, plan)?;
    morph::compute_deltas(&mut out, options, &computed(&authored), weld.map(|(r, _)| r))?;
    Ok(out)
}

/// [`fix`], in place: the model's normals and tangents are replaced where they are computed
/// (reusing their memory), and split vertices are appended to its objects. Returns what
/// changed, object by object. On an error the model is unchanged.
///
/// # Errors
///
/// As [`fix`].
pub fn fix_in_place(model: &mut Model, options: &FixOptions) -> Result<Changes, MeshError> {
    fix_in_place_welded(model, options, None).map(|(changes, _)| changes)
}

/// [`fix_in_place`], also returning the weld the fix smoothed over (or repaired and made
/// tangents over), renumbered for the fixed model, where [`crate::report_welded`] can measure
/// the fixed model with it instead of welding it again: in [`Mode::Model`], wherever the fix
/// welded (not where every object keeps normals and tangents and nothing is repaired). The
/// same roots, bit for bit, as welding the fixed model would give (split vertices are copies
/// of their sources, at the same positions); it costs a pass over the vertices, against a
/// sort. Where every object's normals were computed, it carries the report's triangle counts
/// too, counted by the smoothing's pass over the triangles.
///
/// `loaded`, the weld of the model as it is ([`crate::report_with_weld`] of it, measured
/// before the fix), is used instead of welding it again where it fits (the same vertex count
/// and tolerance, in [`Mode::Model`]), and its triangle counts are not made again.
///
/// # Errors
///
/// As [`fix`].
pub fn fix_in_place_welded(
    model: &mut Model,
    options: &FixOptions,
    loaded: Option<&Welded>,
) -> Result<(Changes, Option<Welded>), MeshError> {
    let flat = validate::flatten(model)?;
    let authored = Authored::of(model, options);
    let keep = options.mode == Mode::Model;
    let given = loaded.filter(|_| keep).and_then(|w| {
        let roots = w.roots_for(flat.positions.len(), options.weld_tolerance)?;
        Some(Given { roots, counts: w.counts_for(roots.len(), options.weld_tolerance) })
    });
    let plan = Plan { options, input: None, authored: &authored, keep_weld: keep, given };
    let (changes, weld) = run(model, flat, plan)?;
    // Copied only where the morph targets' deltas need the roots too.
    let morphs = model.objects.iter().any(|o| !o.morph_targets.is_empty());
    let tolerance = options.weld_tolerance;
    let (welded, for_deltas) = match weld {
        Some((r, counts)) if keep && morphs => {
            (Some(Welded::new(r.clone(), tolerance, counts)), Some(r))
        }
        Some((r, counts)) if keep => (Some(Welded::new(r, tolerance, counts)), None),
        weld => (None, weld.map(|(r, _)| r)),
    };
    morph::compute_deltas(model, options, &computed(&authored), for_deltas)?;
    Ok((changes, welded))
}

/// The objects whose normals `fix` computes (the others keep theirs, and their morph
/// targets' deltas).
fn computed(authored: &Authored) -> Vec<bool> {
    authored.normals.iter().map(|&kept| !kept).collect()
}

/// The weld [`run`] gives back: each vertex's root, renumbered for the fixed model, and the
/// report's triangle counts where the fix made them.
type RunWeld = (Vec<u32>, Option<[usize; 3]>);

/// How [`run`] fixes a model: with `options`; `input`, where the model is a copy, the original
/// (see [`compute`]); which objects keep their normals and tangents; whether the report
/// wants the weld back; the weld of the model as loaded, where the caller has it.
#[derive(Clone, Copy)]
struct Plan<'a> {
    options: &'a FixOptions,
    input: Option<&'a Model>,
    authored: &'a Authored,
    keep_weld: bool,
    given: Option<Given<'a>>,
}

/// A weld of the model before the fix, made by the caller (the report as loaded), in
/// [`Mode::Model`]: the roots of its vertices, and its triangle counts where made.
#[derive(Clone, Copy)]
struct Given<'a> {
    roots: &'a [u32],
    counts: Option<[usize; 3]>,
}

/// Fixes `model` as `plan` says (flattened into `flat`) under the normal policy. Objects
/// marked in `authored` carry their input normals (and tangents
/// where marked), the others none or their input ones, which are replaced. Returns what
/// changed and the weld renumbered for the fixed model: where `keep_weld` asks for it (the
/// report's), and where every object's normals were computed and the morph targets' deltas
/// ask for it; with the report's triangle counts where every object's normals were computed
/// and `keep_weld` asked. `given` is used instead of welding the model again (its counts
/// instead of counting).
fn run(
    model: &mut Model,
    flat: Flat,
    plan: Plan<'_>,
) -> Result<(Changes, Option<RunWeld>), MeshError> {
    let Plan { options, input, authored, keep_weld, given } = plan;
    if !authored.any() {
        return Ok(run_computed(model, flat, plan));
    }
    let vertices: Vec<usize> = model.objects.iter().map(Object::vertex_count).collect();
    let given_roots = given.map(|g| g.roots);
    let given_counts = given.and_then(|g| g.counts);
    // 1. Missing normals (and their tangents), computed as `recompute` computes them; the
    //    objects that keep theirs are left as they are. Vertices may have been split since
    //    the model was flattened: flatten it again.
    let (flat, mut changed, welded) = if authored.all() {
        (flat, vec![0; model.objects.len()], None)
    } else {
        let (changed, roots, _) =
            compute(model, flat, options, input, &authored.normals, false, given_roots);
        (validate::flatten(model)?, changed, roots)
    };
    let mut flat = flat;
    // 2. Authored tangents that are not kept go (they are computed in step 5).
    for (o, object) in model.objects.iter_mut().enumerate() {
        if authored.normals[o] && !authored.tangents[o] {
            object.tangents = None;
        }
    }
    let wants_tangents = |o: usize| {
        authored.normals[o]
            && !authored.tangents[o]
            && options.tangents != TangentMethod::None
            && model.objects[o].uvs.is_some()
    };
    let tangents_needed: Vec<bool> = (0..model.objects.len()).map(wants_tangents).collect();
    let repairs = matches!(options.normals, NormalPolicy::Auto | NormalPolicy::SmoothShared)
        && options.mode == Mode::Model;
    let mut shared = SharedNormals::default();
    // 3. The weld, where the repair or the tangents need it: step 1's or the given one,
    //    renumbered past step 1's splits, where there is one (the same roots: split vertices
    //    are copies at their sources' positions).
    let at_weld: Vec<usize> = model.objects.iter().map(Object::vertex_count).collect();
    let roots =
        (options.mode != Mode::Flat && (repairs || tangents_needed.contains(&true))).then(|| {
            let roots = match welded.as_deref().or(given_roots) {
                Some(r) => morph::roots_after_splits(r, &vertices, model),
                None => {
                    let tolerance = options.weld_tolerance.absolute(diagonal(&flat));
                    roots_for_mode(&flat, tolerance, options.mode)
                }
            };
            weld::snap_to_roots(&mut flat.positions, &roots);
            roots
        });
    // 4. The seam-only repair.
    if repairs && let Some(roots) = &roots {
        let (repaired, decided) =
            repair::repair_seams(model, &flat, roots, options, &authored.normals);
        for (o, n) in repaired.into_iter().enumerate() {
            changed[o] += n;
        }
        shared = decided;
    }
    // 5. Tangents where kept normals came without them; the report's triangle counts made by
    //    their pass over the triangles where the report wants the weld and has no counts.
    let kept = roots.as_ref().filter(|_| keep_weld).cloned();
    let count = keep_weld && given_counts.is_none();
    let counted = repair::compute_tangents(model, &flat, roots, options, &tangents_needed, count);
    let mut changes = tally(model, &vertices, &changed, authored);
    changes.shared = shared;
    // The weld, for the report, as in the first branch.
    let counts = given_counts.or(counted);
    let weld = kept.map(|r| (morph::roots_after_splits(&r, &at_weld, model), counts));
    Ok((changes, weld))
}

/// [`run`] where no object keeps its normals: [`compute`] over the whole model.
fn run_computed(model: &mut Model, flat: Flat, plan: Plan<'_>) -> (Changes, Option<RunWeld>) {
    let Plan { options, input, authored, keep_weld, given } = plan;
    let vertices: Vec<usize> = model.objects.iter().map(Object::vertex_count).collect();
    let given_counts = given.and_then(|g| g.counts);
    let count = keep_weld && given_counts.is_none();
    let (changed, roots, counts) =
        compute(model, flat, options, input, &authored.normals, count, given.map(|g| g.roots));
    let counts = counts.or(given_counts);
    // The weld, for the morph targets' deltas (the fix made no other change) and the report:
    // renumbering every vertex is a pass over them, not asked for otherwise.
    let morphs = model.objects.iter().any(|o| !o.morph_targets.is_empty());
    let weld = roots
        .filter(|_| morphs || keep_weld)
        .map(|r| (morph::roots_after_splits(&r, &vertices, model), counts));
    (tally(model, &vertices, &changed, authored), weld)
}

/// The [`Changes`]: `vertices` and `changed` per object, before the fix.
fn tally(model: &Model, vertices: &[usize], changed: &[usize], authored: &Authored) -> Changes {
    let objects = model
        .objects
        .iter()
        .enumerate()
        .map(|(o, object)| ObjectChanges {
            name: object.name.clone(),
            kept_normals: authored.normals[o],
            kept_tangents: authored.tangents[o],
            vertices: vertices[o],
            normals_changed: changed[o].min(vertices[o]),
            vertices_split: object.vertex_count() - vertices[o],
        })
        .collect();
    Changes { objects, shared: SharedNormals::default() }
}

/// Computes the normals and tangents of every object not marked in `skip` (objects marked
/// are not written), from the faces of all objects: the paper's way, and the whole fix under
/// [`NormalPolicy::Recompute`]. `input`, where the model is a copy, is the original (for the
/// normals of vertices no triangle uses). Returns, per object, how many of its vertices'
/// normals are not the input ones, each vertex's weld root (where it welded) and, where
/// `count` asks and it welded, the report's triangle counts over the snapped positions
/// (counted by the smoothing's pass over the triangles). `given`: the model's weld, where the
/// caller has it (in [`Mode::Model`]).
fn compute(
    model: &mut Model,
    mut flat: Flat,
    options: &FixOptions,
    input: Option<&Model>,
    skip: &[bool],
    count: bool,
    given: Option<&[u32]>,
) -> (Vec<usize>, Option<Vec<u32>>, Option<[usize; 3]>) {
    let writing = Writing { skip, want_tangents: options.tangents != TangentMethod::None, input };
    if options.mode == Mode::Flat {
        // Flat shading: each corner takes its face's frame.
        let (v_axis, flat) = (model.v_axis, &flat);
        let each = vec![(); model.objects.len()];
        let changed = write_objects(model, writing, each, |o, object, tangents, input, ()| {
            write_corners(o, object, flat, tangents, input, |_, p, uv| {
                [face_frame(&face(p, uv, v_axis)); 3]
            })
        });
        return (changed, None, None);
    }

    let roots = match given {
        Some(roots) => roots.to_vec(),
        None => {
            let tolerance = options.weld_tolerance.absolute(diagonal(&flat));
            roots_for_mode(&flat, tolerance, options.mode)
        }
    };
    weld::snap_to_roots(&mut flat.positions, &roots);
    let rules = Rules::new(options, options.tangents == TangentMethod::Seamlit);
    let smooth = smooth::smooth(model, &flat, roots, rules, count);
    let counts = smooth.counts;
    let changed = if options.tangents == TangentMethod::Mikktspace {
        write_with_mikk(model, flat, &smooth, writing)
    } else {
        let (flat, smooth) = (&without_positions(flat), &smooth);
        let each = vec![(); model.objects.len()];
        write_objects(model, writing, each, |o, object, tangents, input, ()| {
            write_smooth(o, object, flat, smooth, tangents, input)
        })
    };
    (changed, Some(smooth.into_roots()), counts)
}

/// Makes MikkTSpace's tangents over the smoothed model and writes every object with them
/// ([`write_mikk`]); returns each object's count of changed normals.
fn write_with_mikk(
    model: &mut Model,
    flat: Flat,
    smooth: &Smooth,
    writing: Writing<'_>,
) -> Vec<usize> {
    let triangles: Vec<&[[u32; 3]]> = model.objects.iter().map(|o| &o.triangles[..]).collect();
    let uvs: Vec<Option<&[Vec2]>> = model.objects.iter().map(|o| o.uvs.as_deref()).collect();
    let surface = mikk::Surface {
        positions: &flat.positions,
        roots: smooth.roots(),
        uvs: &uvs,
        triangles: &triangles,
        vertex_start: &flat.vertex_start,
        triangle_start: &flat.triangle_start,
        normal: |c: usize, v: usize| smooth.corner_normal(index(c), v),
        vertex_normals: None,
        v_axis: model.v_axis,
        // The smoothing's pass counted them.
        count: false,
    };
    let mut tangents = mikk::tangents(&surface);
    drop((uvs, triangles));
    let flat = &without_positions(flat);
    // Each object's fan sums become its tangents in place.
    let sums = tangents.take_sums();
    let tangents = &tangents;
    write_objects(model, writing, sums, |o, object, wanted, input, sums| {
        write_mikk(o, object, flat, Mikk { smooth, tangents, sums }, wanted, input)
    })
}

/// `flat` without its positions: the smoothed frames are known, and writing the objects
/// needs only the layout and the transforms. Freed before the objects' new normals and
/// tangents are made, the peak of the fix's memory (a copy of every position: 6 MB of the
/// 1M teapot's 91 MiB).
fn without_positions(mut flat: Flat) -> Flat {
    flat.positions = Vec::new();
    flat
}

/// How [`write_objects`] writes a model's objects: those marked in `skip` not at all; with
/// tangents where they are wanted (and the object has UVs); `input`, where the model is a
/// copy, the original (for the input normals).
#[derive(Clone, Copy)]
struct Writing<'a> {
    skip: &'a [bool],
    want_tangents: bool,
    input: Option<&'a Model>,
}

/// Writes every object as `writing` says with `write(o, object, tangents wanted, input
/// normals, its item of each)`, in parallel; returns each one's count of changed normals (0
/// for those skipped).
fn write_objects<T: Send>(
    model: &mut Model,
    writing: Writing<'_>,
    each: Vec<T>,
    write: impl Fn(usize, &mut Object, bool, Option<&[Vec3]>, T) -> usize + Sync,
) -> Vec<usize> {
    model
        .objects
        .par_iter_mut()
        .zip(each)
        .enumerate()
        .map(|(o, (object, item))| {
            if writing.skip[o] {
                return 0;
            }
            let tangents = writing.want_tangents && object.uvs.is_some();
            let input = writing.input.and_then(|m| m.objects[o].normals.as_deref());
            write(o, object, tangents, input, item)
        })
        .collect()
}

/// Writes one object corner by corner, `frames(t, positions, uvs)` giving the model-space
/// frames of triangle `t`'s corners (from its model-space positions and UVs). `input_normals`:
/// see [`Out`]. Returns how many input vertices' normals changed.
fn write_corners(
    o: usize,
    object: &mut Object,
    flat: &Flat,
    tangents: bool,
    input_normals: Option<&[Vec3]>,
    frames: impl Fn(usize, [Vec3; 3], Option<[Vec2; 3]>) -> [Frame; 3],
) -> usize {
    let base = flat.vertex_start[o];
    let mut triangles = std::mem::take(&mut object.triangles);
    let (mut normals, mut out_tangents) = (None, None);
    let mut out = Out::new(object, flat.linear[o].map(Linear::new), tangents, input_normals);
    for (t, tri) in triangles.iter_mut().enumerate() {
        let p = tri.map(|i| flat.positions[(base + i) as usize]);
        let uv = out.uvs.as_ref().map(|uvs| tri.map(|i| uvs[i as usize]));
        let f = frames(t, p, uv);
        for k in 0..3 {
            tri[k] = out.put(tri[k], f[k]);
        }
    }
    let changed = out.changed;
    out.finish(&mut normals, &mut out_tangents);
    (object.normals, object.tangents, object.triangles) = (normals, out_tangents, triangles);
    changed
}

/// What [`write_mikk`] writes one object from: the smoothed normals, MikkTSpace's tangents,
/// and the object's fan sums taken from them ([`mikk::Tangents::take_sums`]), which become
/// its tangents.
struct Mikk<'a> {
    smooth: &'a Smooth,
    tangents: &'a mikk::Tangents,
    sums: Vec<glam::Vec4>,
}

/// Writes one object from the smoothed normals and MikkTSpace's tangents: every vertex at a
/// plain position takes its one frame, its tangent made from its fan's sum where the sum
/// lies (the tangent's own memory); the corners of other positions are placed one by one, in
/// corner order. Returns how many input vertices' normals changed.
fn write_mikk(
    o: usize,
    object: &mut Object,
    flat: &Flat,
    mikk: Mikk<'_>,
    tangents_wanted: bool,
    input_normals: Option<&[Vec3]>,
) -> usize {
    let Mikk { smooth, tangents, sums } = mikk;
    let base = flat.vertex_start[o] as usize;
    let first = flat.triangle_start[o] as usize * 3;
    let others = tangents.others(first..flat.triangle_start[o + 1] as usize * 3);
    let mut triangles = std::mem::take(&mut object.triangles);
    let (mut normals, mut out_tangents) = (None, None);
    let linear = flat.linear[o].map(Linear::new);
    let mut out = Out::over_tangents(object, linear, tangents_wanted, input_normals, sums);
    out.set_each(|out, v| {
        let g = base + v;
        let frame = smooth.is_used(g).then(|| smooth.simple_frame(g)).flatten()?;
        let root = smooth.roots()[g] as usize;
        let tangent = tangents.fan_of(g, root, frame.normal, out.tangent(index(v)))?;
        Some(Frame { normal: frame.normal, tangent })
    });
    for &(c, tangent) in others {
        let local = c as usize - first;
        let corner = &mut triangles[local / 3][local % 3];
        let normal = smooth.corner_normal(c, base + *corner as usize).0;
        *corner = out.put(*corner, Frame { normal, tangent });
    }
    let changed = out.changed;
    out.finish(&mut normals, &mut out_tangents);
    (object.normals, object.tangents, object.triangles) = (normals, out_tangents, triangles);
    changed
}

/// Writes one object from the smoothed frames: every vertex at a simple position takes its
/// position's frame; the corners of complex positions are placed one by one, in corner order.
/// Returns how many input vertices' normals changed.
fn write_smooth(
    o: usize,
    object: &mut Object,
    flat: &Flat,
    smooth: &Smooth,
    tangents: bool,
    input_normals: Option<&[Vec3]>,
) -> usize {
    let base = flat.vertex_start[o] as usize;
    let first = flat.triangle_start[o];
    let complex = &smooth.complex[smooth.complex_range(first..flat.triangle_start[o + 1])];
    let mut triangles = std::mem::take(&mut object.triangles);
    let (mut normals, mut out_tangents) = (None, None);
    let mut out = Out::new(object, flat.linear[o].map(Linear::new), tangents, input_normals);
    out.set_each(|_, v| smooth.is_used(base + v).then(|| smooth.simple_frame(base + v)).flatten());
    for &e in complex {
        let c = (e >> 32) as usize - first as usize * 3;
        let corner = &mut triangles[c / 3][c % 3];
        *corner = out.put(*corner, smooth.frames[low_half(e) as usize]);
    }
    let changed = out.changed;
    out.finish(&mut normals, &mut out_tangents);
    (object.normals, object.tangents, object.triangles) = (normals, out_tangents, triangles);
    changed
}
