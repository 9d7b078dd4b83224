//! The OBJ geometry parser: `v`, `vt`, `vn`, `f`, `o`, `g`, `s`, `usemtl`, `mtllib`, in
//! parallel.
//!
//! tobj reads a line at a time on one thread (a `String` per line, a hash lookup per face
//! corner; figures in BENCHMARKS.md, "Loading"). This parser reads the file in
//! blocks of about a megabyte cut at line ends ([`blocks`]), on a thread of its own, while
//! rayon parses the blocks already read ([`statements`], with [`numbers`], [`corners`] and
//! the blanks and words of [`words`]);
//! then it resolves face indices against the running counts (naming the line of one out of
//! range) and builds the objects' vertex arrays in parallel ([`dedup`]). It follows tobj's
//! rules, but for the two marked (*), and tests check that it
//! gives tobj's output on every shared OBJ model and on generated files:
//!
//! - `o` and `g` start a new object when the current one has faces, else rename it; `usemtl`
//!   changing the material inside an object with faces starts a new object of the same name;
//! - faces are triangulated as fans `(a, b, c), (a, c, d), ...` (*: but for polygons that are
//!   not convex, which are ear-clipped, see [`seamlit_asset::polygon`]); faces of fewer than three
//!   corners (points, lines) and `p` statements are ignored, and so are `l` statements (*:
//!   tobj makes a polygon of an `l` of three or more points; a polyline is not a surface);
//! - vertices are the distinct `v/vt/vn` triples of an object, in order of first use; `vt`
//!   and `vn` are kept only where every corner of the object has them (*: the caller warns);
//! - `v x y z w` divides by `w`; `v x y z r g b` and `v x y z r g b a` give vertex colours
//!   (*: tobj reads no alpha), kept where every vertex of the object has one (*: the caller
//!   warns); other counts of numbers are an error;
//! - (*: tobj ignores `s`) `s N` puts the faces that follow in smoothing group `N`, `s off`
//!   and `s 0` in none; a polygon's triangles are in its group. A file without `s` gives no
//!   groups (`Object::smoothing_groups` is `None`); in a file with `s`, faces before the
//!   first are in none (0), the OBJ default.
//!
//! Material libraries are read with tobj (see `mtl.rs`).

use std::io::Read;
use std::path::Path;
use std::sync::mpsc;

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use blocks::{BLOCK, READ_AHEAD, read_blocks};
use corners::{Corner, INVALID, MISSING};
use dedup::{dense_dedup, hashed_dedup};
use seamlit_asset::{IoError, NotText, Syntax};
use statements::parse_chunk;

mod blocks;
mod corners;
mod dedup;
pub(crate) mod names;
mod numbers;
mod statements;
mod words;

/// "No colour" for a `v` without one, among others with one.
const NO_COLOR: Vec4 = Vec4::NAN;

/// A run of an object's triangles: chunk, first and end triangle in it.
type Segment = (usize, usize, usize);

/// An object's part as split at `o`, `g` and `usemtl`: name, `usemtl` name in force,
/// triangles, and whether a `usemtl` (rather than `o` / `g`) started it.
type Part = (String, Option<String>, Vec<Segment>, bool);

/// One object as parsed, before material resolution and conversion.
#[derive(Debug)]
pub(crate) struct ParsedObject {
    pub name: String,
    pub material: Option<usize>,
    pub positions: Vec<Vec3>,
    /// `Some` when every corner has a `vt`; `None` when none has.
    pub uvs: Option<Vec<Vec2>>,
    pub normals: Option<Vec<Vec3>>,
    /// `Some` when every vertex has a colour; `None` when none has.
    pub colors: Option<Vec<Vec4>>,
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle, its smoothing group (0 = off); `None` when the file has no `s`.
    pub smoothing_groups: Option<Vec<u32>>,
    /// Some corners had a `vt` and some did not (texture coordinates dropped).
    pub mixed_uvs: bool,
    /// Some corners had a `vn` and some did not (normals dropped).
    pub mixed_normals: bool,
    /// Some vertices had a colour and some did not (colours dropped).
    pub mixed_colors: bool,
    /// Where the object's triangles come from in the file: runs of consecutive triangles,
    /// each its first triangle counted over the whole file (every face of `n >= 3` corners
    /// gives `n - 2`, in file order) and its length, in the object's order.
    pub runs: Vec<(usize, usize)>,
    /// The polygons ear-clipped rather than fanned: first triangle and corners (see
    /// [`seamlit_asset::polygon::triangulate`]).
    pub clipped: Vec<(usize, Vec<u32>)>,
}

#[derive(Debug)]
enum Event {
    Object(String),
    /// A `usemtl`: the material's name (empty where the file gives none) and the line.
    Material(String, usize),
    Library(String, usize),
}

/// What a block of lines holds.
#[derive(Debug, Default)]
struct Chunk {
    lines: usize,
    positions: Vec<Vec3>,
    /// Per position, its colour or [`NO_COLOR`]; empty when no `v` of the chunk has one.
    colors: Vec<Vec4>,
    uvs: Vec<Vec2>,
    normals: Vec<Vec3>,
    /// A negative (relative) index is resolved later, from `relative`.
    triangles: Vec<[Corner; 3]>,
    /// Corners with a negative index: corner (three per triangle), slot, and the index counted from the chunk's
    /// first element of that kind (negative where it refers to an earlier chunk).
    relative: Vec<(usize, usize, i64)>,
    /// Corners holding [`INVALID`]: corner, slot, and the index as written.
    invalid: Vec<(usize, usize, i64)>,
    /// Where the faces are: one entry per run of faces on consecutive lines (no element
    /// statement between them), for naming the line of a face index out of range.
    face_runs: Vec<FaceRun>,
    /// Events with the chunk-local triangle index they precede.
    events: Vec<(usize, Event)>,
    /// Faces of more than three corners, fan-triangulated here: their first triangle and
    /// their number of corners (see [`seamlit_asset::polygon`]).
    polygons: Vec<(usize, usize)>,
    /// `s` statements: the chunk-local triangle they precede and the group (0 = off).
    smoothing: Vec<(usize, u32)>,
    /// The smoothing group in force at the chunk's first triangle (set in [`assemble`]).
    smoothing_at_start: u32,
    /// The first line of a name that is not UTF-8 (read as Windows-1252, `names.rs`).
    legacy_names: Option<usize>,
}

/// Faces on consecutive lines of a chunk: the first one's first triangle and line, and the
/// chunk's element counts (`v`, `vt`, `vn`) before it, the same for every face of the run.
#[derive(Debug)]
struct FaceRun {
    triangle: usize,
    line: usize,
    counts: [usize; 3],
}

/// The OBJ file's objects and, in order, its `mtllib` statements (name, line).
pub(crate) struct Parsed {
    /// The objects' parts, in file order.
    objects: Vec<Part>,
    pub libraries: Vec<(String, usize)>,
    /// Every material name that a `usemtl` gives, once, with the line of its first use.
    pub materials_used: Vec<(String, usize)>,
    chunks: Vec<Chunk>,
    positions: Vec<Vec3>,
    /// Per position, its colour or [`NO_COLOR`]; empty when no `v` has one.
    colors: Vec<Vec4>,
    uvs: Vec<Vec2>,
    normals: Vec<Vec3>,
    /// Whether the file has an `s` statement.
    has_smoothing: bool,
    /// The first line of a name that is not UTF-8 (read as Windows-1252, `names.rs`).
    pub legacy_names: Option<usize>,
}

/// Reads and parses the OBJ text of `file` (UTF-8, opened from `path`; a UTF-8 byte-order
/// mark is skipped).
///
/// # Errors
///
/// [`IoError::Io`] for a read error, and the first error in the file with its line:
/// [`IoError::Syntax`], [`IoError::NotFinite`], [`IoError::NotText`],
/// [`IoError::ReferenceOutOfRange`].
pub(crate) fn read(file: impl Read + Send, path: &Path) -> Result<Parsed, IoError> {
    let (blocks, received) = mpsc::sync_channel::<(usize, Vec<u8>)>(READ_AHEAD);
    let (give_back, free) = mpsc::channel::<Vec<u8>>();
    let parsed: Vec<(usize, ChunkResult)> = std::thread::scope(|s| {
        let reader = s.spawn(move || read_blocks(file, &blocks, &free));
        let parsed = received
            .into_iter()
            .par_bridge()
            .map(|(index, block)| {
                let chunk = parse_chunk(&block);
                // The reader may be gone (it stops at the end or at an error): nothing to do.
                give_back.send(block).ok();
                (index, chunk)
            })
            .collect();
        reader.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)).map(|()| parsed)
    })
    .map_err(|e| IoError::io(path, e))?;
    from_chunks(parsed, path)
}

/// [`read`] of OBJ text already in memory, without the reading thread (a browser has none):
/// the blocks are cut first, then parsed by rayon.
///
/// # Errors
///
/// As [`read`].
pub(crate) fn read_slice(bytes: &[u8], path: &Path) -> Result<Parsed, IoError> {
    // Every block but the last takes a whole block's bytes from the text: this many fit.
    let (blocks, received) = mpsc::sync_channel::<(usize, Vec<u8>)>(bytes.len() / BLOCK + 2);
    let (_unused, free) = mpsc::channel::<Vec<u8>>();
    read_blocks(bytes, &blocks, &free).map_err(|e| IoError::io(path, e))?;
    drop(blocks);
    let blocks: Vec<(usize, Vec<u8>)> = received.into_iter().collect();
    let parsed =
        blocks.into_par_iter().map(|(index, block)| (index, parse_chunk(&block))).collect();
    from_chunks(parsed, path)
}

/// The parsed blocks (by their index) as one [`Parsed`].
fn from_chunks(mut parsed: Vec<(usize, ChunkResult)>, path: &Path) -> Result<Parsed, IoError> {
    parsed.sort_unstable_by_key(|&(index, _)| index);

    let mut line_base = 0;
    let mut chunks = Vec::with_capacity(parsed.len());
    let mut legacy_names = None;
    for (_, result) in parsed {
        match result {
            Ok(chunk) => {
                legacy_names = legacy_names.or(chunk.legacy_names.map(|line| line_base + line));
                line_base += chunk.lines;
                chunks.push(chunk);
            }
            Err((line, error)) => {
                return Err(error.into_io(path, line_base + line));
            }
        }
    }
    let mut parsed = assemble(chunks, path)?;
    parsed.legacy_names = legacy_names;
    Ok(parsed)
}

/// Resolves the chunks' face indices and splits the triangles into objects.
///
/// # Errors
///
/// [`IoError::ReferenceOutOfRange`] at the first face index out of range.
fn assemble(mut chunks: Vec<Chunk>, path: &Path) -> Result<Parsed, IoError> {
    let starts = Starts::of(&chunks);
    resolve_indices(&mut chunks, &starts, path)?;
    let split = split_objects(&mut chunks, &starts.lines);
    let has_smoothing = start_smoothing_groups(&mut chunks);
    let elements = concatenate(&mut chunks, starts.totals);
    Ok(Parsed {
        objects: split.objects,
        libraries: split.libraries,
        materials_used: split.materials_used,
        chunks,
        positions: elements.positions,
        colors: elements.colors,
        uvs: elements.uvs,
        normals: elements.normals,
        has_smoothing,
        legacy_names: None,
    })
}

/// Where each chunk starts in the file: prefix sums of the element counts and lines.
struct Starts {
    /// Per chunk, the file's `v`, `vt` and `vn` before it.
    elements: Vec<[usize; 3]>,
    /// Per chunk, the file's lines before it.
    lines: Vec<usize>,
    /// The file's `v`, `vt` and `vn`.
    totals: [usize; 3],
}

impl Starts {
    fn of(chunks: &[Chunk]) -> Self {
        let mut starts = Self {
            elements: Vec::with_capacity(chunks.len()),
            lines: Vec::with_capacity(chunks.len()),
            totals: [0; 3],
        };
        let mut lines = 0;
        for chunk in chunks {
            starts.elements.push(starts.totals);
            starts.lines.push(lines);
            starts.totals[0] += chunk.positions.len();
            starts.totals[1] += chunk.uvs.len();
            starts.totals[2] += chunk.normals.len();
            lines += chunk.lines;
        }
        starts
    }
}

/// Resolves every corner to the file's indices, in parallel.
///
/// # Errors
///
/// [`IoError::ReferenceOutOfRange`] at the first face index out of range.
fn resolve_indices(chunks: &mut [Chunk], starts: &Starts, path: &Path) -> Result<(), IoError> {
    let totals = starts.totals;
    let resolved = chunks.par_iter_mut().zip(starts.elements.par_iter()).all(|(chunk, base)| {
        let in_range = chunk.triangles.as_flattened().iter().all(|corner| {
            corner.iter().zip(totals).all(|(&index, total)| {
                index == MISSING || (index != INVALID && (index as usize) < total)
            })
        });
        in_range
            && chunk.relative.iter().all(|&(at, slot, local)| {
                let global = base[slot] as i64 + local;
                match u32::try_from(global) {
                    Ok(global) if (global as usize) < totals[slot] => {
                        chunk.triangles.as_flattened_mut()[at][slot] = global;
                        true
                    }
                    _ => false,
                }
            })
    });
    if resolved {
        return Ok(());
    }
    let (c, out) = first_out_of_range(chunks, &starts.elements, totals)
        .expect("a corner failed the range check above");
    Err(IoError::ReferenceOutOfRange {
        path: path.to_path_buf(),
        line: starts.lines[c] + out.line,
        what: ["vertex", "texture coordinate", "normal"][out.slot],
        index: out.index,
        count: starts.elements[c][out.slot] + out.count,
    })
}

/// The objects' parts and the libraries and materials the file names, in file order.
#[derive(Default)]
struct Split {
    objects: Vec<Part>,
    libraries: Vec<(String, usize)>,
    materials_used: Vec<(String, usize)>,
}

/// The part being gathered while [`split_objects`] follows the events.
struct Current {
    name: String,
    material: Option<String>,
    segments: Vec<Segment>,
    by_usemtl: bool,
}

impl Current {
    /// Ends the part (if it has triangles) and adds it to `objects`.
    fn close(&mut self, objects: &mut Vec<Part>) {
        if !self.segments.is_empty() {
            let segments = std::mem::take(&mut self.segments);
            objects.push((self.name.clone(), self.material.clone(), segments, self.by_usemtl));
        }
    }

    /// Adds a chunk's triangles `start..end` (if any).
    fn add(&mut self, c: usize, start: usize, end: usize) {
        if end > start {
            self.segments.push((c, start, end));
        }
    }
}

/// Splits the chunks' triangles into objects, following the events in file order
/// (`line_bases`: the file's lines before each chunk).
fn split_objects(chunks: &mut [Chunk], line_bases: &[usize]) -> Split {
    let mut split = Split::default();
    let mut seen: std::collections::HashSet<String> = std::collections::HashSet::new();
    let mut current = Current {
        name: "unnamed_object".to_owned(),
        material: None,
        segments: Vec::new(),
        by_usemtl: false,
    };
    for (c, (chunk, &line_base)) in chunks.iter_mut().zip(line_bases).enumerate() {
        let mut next = 0;
        for (at, event) in std::mem::take(&mut chunk.events) {
            current.add(c, next, at);
            next = at;
            match event {
                Event::Object(new_name) => {
                    current.close(&mut split.objects);
                    // A new object, even when it only renames an empty part that a `usemtl`
                    // started (that part must not merge back into the previous object).
                    current.by_usemtl = false;
                    current.name =
                        if new_name.is_empty() { "unnamed_object".to_owned() } else { new_name };
                }
                Event::Material(new_material, line) => {
                    if seen.insert(new_material.clone()) {
                        split.materials_used.push((new_material.clone(), line_base + line));
                    }
                    if current.material.as_ref() != Some(&new_material)
                        && !current.segments.is_empty()
                    {
                        current.close(&mut split.objects);
                        current.by_usemtl = true;
                    }
                    current.material = Some(new_material);
                }
                Event::Library(library, line) => split.libraries.push((library, line_base + line)),
            }
        }
        current.add(c, next, chunk.triangles.len());
    }
    current.close(&mut split.objects);
    split
}

/// Sets the smoothing group in force where each chunk starts (0, off, before any `s`);
/// whether the file has an `s` statement.
fn start_smoothing_groups(chunks: &mut [Chunk]) -> bool {
    let mut group = 0;
    for chunk in chunks.iter_mut() {
        chunk.smoothing_at_start = group;
        group = chunk.smoothing.last().map_or(group, |&(_, g)| g);
    }
    chunks.iter().any(|chunk| !chunk.smoothing.is_empty())
}

/// The file's elements, moved out of the chunks in order.
struct Elements {
    positions: Vec<Vec3>,
    /// Per position, its colour or [`NO_COLOR`]; empty when no `v` has one.
    colors: Vec<Vec4>,
    uvs: Vec<Vec2>,
    normals: Vec<Vec3>,
}

/// Moves the chunks' elements into arrays for the whole file (`totals` of each kind).
fn concatenate(chunks: &mut [Chunk], totals: [usize; 3]) -> Elements {
    let mut all = Elements {
        positions: Vec::with_capacity(totals[0]),
        colors: Vec::new(),
        uvs: Vec::with_capacity(totals[1]),
        normals: Vec::with_capacity(totals[2]),
    };
    if chunks.iter().any(|chunk| !chunk.colors.is_empty()) {
        all.colors.reserve_exact(totals[0]);
        for chunk in chunks.iter_mut() {
            match chunk.colors.is_empty() {
                true => all.colors.extend(std::iter::repeat_n(NO_COLOR, chunk.positions.len())),
                false => all.colors.append(&mut chunk.colors),
            }
        }
    }
    for chunk in chunks.iter_mut() {
        all.positions.extend(std::mem::take(&mut chunk.positions));
        all.uvs.extend(std::mem::take(&mut chunk.uvs));
        all.normals.extend(std::mem::take(&mut chunk.normals));
    }
    all
}

/// A face index out of range, placed in its chunk: the chunk-local line, the slot (`v`,
/// `vt`, `vn`), the index as written and the chunk's count of that element before the face.
struct OutOfRange {
    line: usize,
    slot: usize,
    index: i64,
    count: usize,
}

/// The first face index of the file out of range, in file order (corner by corner, slot by
/// slot, as the face is written: a fan's triangles meet its corners in order): its chunk and
/// where it is there. `bases` are the chunks' first elements, `totals` the file's counts.
fn first_out_of_range(
    chunks: &[Chunk],
    bases: &[[usize; 3]],
    totals: [usize; 3],
) -> Option<(usize, OutOfRange)> {
    chunks.iter().zip(bases).enumerate().find_map(|(c, (chunk, base))| {
        let mut relative = chunk.relative.iter().peekable();
        let mut invalid = chunk.invalid.iter().peekable();
        for (at, corner) in chunk.triangles.as_flattened().iter().enumerate() {
            for (slot, &value) in corner.iter().enumerate() {
                let out = if let Some(&(_, _, local)) =
                    relative.next_if(|&&(a, s, _)| (a, s) == (at, slot))
                {
                    let global = base[slot] as i64 + local;
                    u32::try_from(global)
                        .ok()
                        .is_none_or(|global| global as usize >= totals[slot])
                        .then_some(Written::Relative(local))
                } else if let Some(&(_, _, index)) =
                    invalid.next_if(|&&(a, s, _)| (a, s) == (at, slot))
                {
                    Some(Written::Index(index))
                } else {
                    (value != MISSING && value as usize >= totals[slot])
                        .then(|| Written::Index(i64::from(value) + 1))
                };
                if let Some(written) = out {
                    return Some((c, chunk.out_of_range(at / 3, slot, written)));
                }
            }
        }
        None
    })
}

/// A face index out of range as [`first_out_of_range`] finds it.
enum Written {
    /// A negative index, counted from the chunk's first element.
    Relative(i64),
    /// The index as written.
    Index(i64),
}

impl Chunk {
    /// The line of `triangle`'s face and the index as written, from the run of faces it
    /// belongs to: each face of a run is a line, of as many triangles as its corners less two.
    fn out_of_range(&self, triangle: usize, slot: usize, written: Written) -> OutOfRange {
        let run = &self.face_runs[self.face_runs.partition_point(|r| r.triangle <= triangle) - 1];
        let (mut first, mut line) = (run.triangle, run.line);
        let mut polygon = self.polygons.partition_point(|&(f, _)| f < first);
        loop {
            let size = match self.polygons.get(polygon) {
                Some(&(f, corners)) if f == first => {
                    polygon += 1;
                    corners - 2
                }
                _ => 1,
            };
            if triangle < first + size {
                break;
            }
            first += size;
            line += 1;
        }
        let count = run.counts[slot];
        let index = match written {
            Written::Relative(local) => local - count as i64,
            Written::Index(index) => index,
        };
        OutOfRange { line, slot, index, count }
    }
}

impl Parsed {
    /// The triangle corners of the whole file: a bound on the vertices of any one object.
    pub(crate) fn corner_count(&self) -> usize {
        self.chunks.iter().map(|chunk| chunk.triangles.len() * 3).sum()
    }

    /// Builds the objects' vertex arrays (in parallel), resolving `usemtl` names with
    /// `material` (a name unknown to it gives no material; equal results do not split).
    pub(crate) fn into_objects(
        self,
        material: impl Fn(&str) -> Option<usize> + Sync,
    ) -> Vec<ParsedObject> {
        // tobj splits an object at `usemtl` only where the resolved material changes: merge
        // such a part back when its material resolves like the previous part's.
        let mut merged: Vec<(String, Option<usize>, Vec<Segment>)> =
            Vec::with_capacity(self.objects.len());
        for (name, material_name, segments, by_usemtl) in self.objects {
            let resolved = material_name.as_deref().and_then(&material);
            match merged.last_mut() {
                Some(last) if by_usemtl && last.1 == resolved => last.2.extend(segments),
                _ => merged.push((name, resolved, segments)),
            }
        }
        let (chunks, positions, uvs, normals, colors) =
            (&self.chunks, &self.positions, &self.uvs, &self.normals, &self.colors);
        let has_smoothing = self.has_smoothing;
        // Where each chunk's triangles start among the file's.
        let chunk_bases: Vec<usize> = chunks
            .iter()
            .scan(0, |next, chunk| {
                let base = *next;
                *next += chunk.triangles.len();
                Some(base)
            })
            .collect();
        merged
            .into_par_iter()
            .map(|(name, material, segments)| {
                let triangles = || {
                    segments.iter().flat_map(|&(c, start, end)| &chunks[c].triangles[start..end])
                };
                let count: usize = segments.iter().map(|&(_, start, end)| end - start).sum();
                let (keys, mut triangles) = dense_dedup(triangles(), count)
                    .unwrap_or_else(|| hashed_dedup(triangles(), count));
                let with_vt = keys.iter().filter(|k| k[1] != MISSING).count();
                let with_vn = keys.iter().filter(|k| k[2] != MISSING).count();
                let all = keys.len();
                let positions: Vec<Vec3> = keys.iter().map(|k| positions[k[0] as usize]).collect();
                let clipped = seamlit_asset::polygon::triangulate(
                    &mut triangles,
                    &positions,
                    polygons(chunks, &segments),
                );
                let runs =
                    segments.iter().map(|&(c, start, end)| (chunk_bases[c] + start, end - start));
                let with_color = match colors.is_empty() {
                    true => 0,
                    false => keys.iter().filter(|k| !colors[k[0] as usize].x.is_nan()).count(),
                };
                ParsedObject {
                    name,
                    material,
                    positions,
                    uvs: (with_vt == all && all > 0)
                        .then(|| keys.iter().map(|k| uvs[k[1] as usize]).collect()),
                    normals: (with_vn == all && all > 0)
                        .then(|| keys.iter().map(|k| normals[k[2] as usize]).collect()),
                    colors: (with_color == all && all > 0)
                        .then(|| keys.iter().map(|k| colors[k[0] as usize]).collect()),
                    triangles,
                    smoothing_groups: has_smoothing.then(|| smoothing_groups(chunks, &segments)),
                    mixed_uvs: with_vt != 0 && with_vt != all,
                    mixed_normals: with_vn != 0 && with_vn != all,
                    mixed_colors: with_color != 0 && with_color != all,
                    runs: runs.collect(),
                    clipped,
                }
            })
            .collect()
    }
}

/// The polygons (faces of more than three corners) of an object made of `segments`: their
/// first triangle in the object and their number of corners, ascending.
fn polygons<'a>(
    chunks: &'a [Chunk],
    segments: &'a [Segment],
) -> impl Iterator<Item = (usize, usize)> + 'a {
    let mut base = 0;
    segments.iter().flat_map(move |&(c, start, end)| {
        let all = &chunks[c].polygons;
        let from = all.partition_point(|&(first, _)| first < start);
        let to = all.partition_point(|&(first, _)| first < end);
        let offset = base;
        base += end - start;
        all[from..to].iter().map(move |&(first, corners)| (offset + first - start, corners))
    })
}

/// The smoothing group of each triangle of an object made of `segments`, in order.
fn smoothing_groups(chunks: &[Chunk], segments: &[Segment]) -> Vec<u32> {
    let mut groups = Vec::new();
    for &(c, start, end) in segments {
        let chunk = &chunks[c];
        // The statements at or before `start` decide the first triangle's group.
        let mut next = chunk.smoothing.partition_point(|&(at, _)| at <= start);
        let mut group =
            next.checked_sub(1).map_or(chunk.smoothing_at_start, |i| chunk.smoothing[i].1);
        for t in start..end {
            while let Some(&(at, g)) = chunk.smoothing.get(next)
                && at <= t
            {
                group = g;
                next += 1;
            }
            groups.push(group);
        }
    }
    groups
}

/// A parsed chunk, or an error and its chunk-local line.
type ChunkResult = Result<Chunk, (usize, ChunkError)>;

/// An error found while parsing a chunk, placed at a chunk-local line by the caller.
#[derive(Debug)]
enum ChunkError {
    Syntax(Syntax),
    NotFinite(&'static str, String),
    NotText(NotText),
}

impl ChunkError {
    fn into_io(self, path: &Path, line: usize) -> IoError {
        match self {
            Self::Syntax(kind) => IoError::Syntax { path: path.to_path_buf(), line, kind },
            Self::NotFinite(what, text) => {
                IoError::NotFinite { path: path.to_path_buf(), line, what, text }
            }
            Self::NotText(problem) => IoError::NotText { path: path.to_path_buf(), line, problem },
        }
    }
}
