//! The OBJ geometry parser: `v`, `vt`, `vn`, `f`, `o`, `g`, `s`, `usemtl`, `mtllib`, in
//! parallel.
//!
//! tobj reads a 1M-triangle OBJ in about 2.4 s on the project's machine (one thread, a
//! `String` per line, a hash lookup per face corner). This parser reads the file in blocks of
//! about a megabyte cut at line ends, on a thread of its own, while rayon parses the blocks
//! already read (the text is never held whole, and the blocks' buffers are reused); then it
//! resolves face indices against the running counts and builds the objects' vertex arrays in
//! parallel. It follows tobj's rules, but for the two marked (*), and tests check that it
//! gives tobj's output on every shared OBJ model and on generated files:
//!
//! - `o` and `g` start a new object when the current one has faces, else rename it; `usemtl`
//!   changing the material inside an object with faces starts a new object of the same name;
//! - faces are triangulated as fans `(a, b, c), (a, c, d), ...` (*: but for polygons that are
//!   not convex, which are ear-clipped, see [`crate::polygon`]); faces of fewer than three
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
//! Material libraries are read with tobj (see [`crate::obj`]).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::io::Read;
use std::path::Path;
use std::sync::mpsc;

use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

use crate::{IoError, NotText};

/// The UTF-8 byte-order mark, which some editors write before the first line.
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// "No colour" for a `v` without one, among others with one.
const NO_COLOR: Vec4 = Vec4::NAN;

/// "No `vt` / `vn` index" in a corner.
const MISSING: u32 = u32::MAX;

/// An index out of range whatever the file holds (zero, or past `u32`); the index as
/// written is kept in [`Chunk::invalid`].
const INVALID: u32 = u32::MAX - 1;

/// The size of the blocks the file is read and parsed in (each is cut at its last line end).
const BLOCK: usize = 1 << 20;

/// How many blocks the reader may read ahead of the parsers.
const READ_AHEAD: usize = 4;

/// A face corner as `[v, vt, vn]` zero-based indices (or [`MISSING`], [`INVALID`]).
type Corner = [u32; 3];

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
    /// [`crate::polygon::triangulate`]).
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
    /// their number of corners (see [`crate::polygon`]).
    polygons: Vec<(usize, usize)>,
    /// `s` statements: the chunk-local triangle they precede and the group (0 = off).
    smoothing: Vec<(usize, u32)>,
    /// The smoothing group in force at the chunk's first triangle (set in [`assemble`]).
    smoothing_at_start: u32,
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
    let mut parsed = parsed;
    parsed.sort_unstable_by_key(|&(index, _)| index);

    let mut line_base = 0;
    let mut chunks = Vec::with_capacity(parsed.len());
    for (_, result) in parsed {
        match result {
            Ok(chunk) => {
                line_base += chunk.lines;
                chunks.push(chunk);
            }
            Err((line, error)) => {
                return Err(error.into_io(path, line_base + line));
            }
        }
    }
    assemble(chunks, path)
}

/// Reads `file` in blocks cut after their last line end and sends them, numbered, to the
/// parsers; buffers come back through `free` to be reused. A line longer than a block makes
/// its block grow (each byte is read and searched once, however long the line).
fn read_blocks(
    mut file: impl Read,
    blocks: &mpsc::SyncSender<(usize, Vec<u8>)>,
    free: &mpsc::Receiver<Vec<u8>>,
) -> std::io::Result<()> {
    let mut carry: Vec<u8> = Vec::new();
    let mut index = 0;
    loop {
        let mut block = free.try_recv().unwrap_or_else(|_| Vec::with_capacity(BLOCK + 4096));
        block.clear();
        // The end of the previous block's last line, which holds no line end.
        block.append(&mut carry);
        let end = loop {
            let before = block.len();
            let got = (&mut file).take(BLOCK as u64).read_to_end(&mut block)?;
            if got < BLOCK {
                break true;
            }
            if let Some(at) = block[before..].iter().rposition(|&b| b == b'\n') {
                let cut = before + at + 1;
                carry.extend_from_slice(&block[cut..]);
                block.truncate(cut);
                break false;
            }
        };
        if index == 0 && block.starts_with(UTF8_BOM) {
            block.drain(..UTF8_BOM.len());
        }
        if (!block.is_empty() || index == 0) && blocks.send((index, block)).is_err() {
            return Ok(());
        }
        if end {
            return Ok(());
        }
        index += 1;
    }
}

/// Resolves the chunks' face indices and splits the triangles into objects.
///
/// # Errors
///
/// [`IoError::ReferenceOutOfRange`] at the first face index out of range.
fn assemble(mut chunks: Vec<Chunk>, path: &Path) -> Result<Parsed, IoError> {
    // Prefix sums of the element counts: where each chunk's elements start.
    let mut bases = Vec::with_capacity(chunks.len());
    let mut totals = [0usize; 3];
    let mut line_bases = Vec::with_capacity(chunks.len());
    let mut lines = 0;
    for chunk in &chunks {
        bases.push(totals);
        line_bases.push(lines);
        totals[0] += chunk.positions.len();
        totals[1] += chunk.uvs.len();
        totals[2] += chunk.normals.len();
        lines += chunk.lines;
    }
    // Resolve every corner to global indices, in parallel; any out-of-range index fails.
    let resolved = chunks.par_iter_mut().zip(bases.par_iter()).all(|(chunk, base)| {
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
    if !resolved {
        let (c, out) = first_out_of_range(&chunks, &bases, totals)
            .expect("a corner failed the range check above");
        return Err(IoError::ReferenceOutOfRange {
            path: path.to_path_buf(),
            line: line_bases[c] + out.line,
            what: ["vertex", "texture coordinate", "normal"][out.slot],
            index: out.index,
            count: bases[c][out.slot] + out.count,
        });
    }

    // Split into objects, following the events in file order.
    let mut objects = Vec::new();
    let mut libraries = Vec::new();
    let mut materials_used: Vec<(String, usize)> = Vec::new();
    let mut seen: std::collections::HashSet<String> = std::collections::HashSet::new();
    let mut name = "unnamed_object".to_owned();
    let mut material: Option<String> = None;
    let mut current: Vec<Segment> = Vec::new();
    let mut by_usemtl = false;
    let add = |current: &mut Vec<Segment>, c: usize, start: usize, end: usize| {
        if end > start {
            current.push((c, start, end));
        }
    };
    for (c, (chunk, line_base)) in chunks.iter_mut().zip(line_bases).enumerate() {
        let mut next = 0;
        for (at, event) in std::mem::take(&mut chunk.events) {
            add(&mut current, c, next, at);
            next = at;
            match event {
                Event::Object(new_name) => {
                    if !current.is_empty() {
                        objects.push((
                            name.clone(),
                            material.clone(),
                            std::mem::take(&mut current),
                            by_usemtl,
                        ));
                    }
                    // A new object, even when it only renames an empty part that a `usemtl`
                    // started (that part must not merge back into the previous object).
                    by_usemtl = false;
                    name = if new_name.is_empty() { "unnamed_object".to_owned() } else { new_name };
                }
                Event::Material(new_material, line) => {
                    if seen.insert(new_material.clone()) {
                        materials_used.push((new_material.clone(), line_base + line));
                    }
                    if material.as_ref() != Some(&new_material) && !current.is_empty() {
                        objects.push((
                            name.clone(),
                            material.clone(),
                            std::mem::take(&mut current),
                            by_usemtl,
                        ));
                        by_usemtl = true;
                    }
                    material = Some(new_material);
                }
                Event::Library(library, line) => libraries.push((library, line_base + line)),
            }
        }
        add(&mut current, c, next, chunk.triangles.len());
    }
    if !current.is_empty() {
        objects.push((name, material, current, by_usemtl));
    }
    // The smoothing group in force where each chunk starts: 0 (off) before any `s`.
    let has_smoothing = chunks.iter().any(|chunk| !chunk.smoothing.is_empty());
    let mut group = 0;
    for chunk in &mut chunks {
        chunk.smoothing_at_start = group;
        group = chunk.smoothing.last().map_or(group, |&(_, g)| g);
    }
    let mut positions = Vec::with_capacity(totals[0]);
    let mut uvs = Vec::with_capacity(totals[1]);
    let mut normals = Vec::with_capacity(totals[2]);
    let mut colors = Vec::new();
    if chunks.iter().any(|chunk| !chunk.colors.is_empty()) {
        colors.reserve_exact(totals[0]);
        for chunk in &mut chunks {
            match chunk.colors.is_empty() {
                true => colors.extend(std::iter::repeat_n(NO_COLOR, chunk.positions.len())),
                false => colors.append(&mut chunk.colors),
            }
        }
    }
    for chunk in &mut chunks {
        positions.extend(std::mem::take(&mut chunk.positions));
        uvs.extend(std::mem::take(&mut chunk.uvs));
        normals.extend(std::mem::take(&mut chunk.normals));
    }
    Ok(Parsed {
        objects,
        libraries,
        materials_used,
        chunks,
        positions,
        colors,
        uvs,
        normals,
        has_smoothing,
    })
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
                    (u32::try_from(global).is_err() || global as usize >= totals[slot])
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
                    return Some((c, chunk.place(at / 3, slot, written)));
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
    fn place(&self, triangle: usize, slot: usize, written: Written) -> OutOfRange {
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
                let clipped = crate::polygon::triangulate(
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

/// The distinct corners in order of first use, and the triangles as indices among them.
type Dedup = (Vec<Corner>, Vec<[u32; 3]>);

/// Deduplicates the corners of `triangles` (`count` of them) with a table indexed by
/// position holding the first vertex at that position (its id, `vt` and `vn`: one memory
/// access for the common case of one vertex per position) and a chain of the others; `None`
/// (try [`hashed_dedup`]) when the positions used are spread too thin for a table or a
/// chain grows long (many `vt` / `vn` per position: a hash map bounds the work of such a
/// file).
fn dense_dedup<'a>(
    triangles: impl Iterator<Item = &'a [Corner; 3]> + Clone,
    count: usize,
) -> Option<Dedup> {
    const NONE: u32 = u32::MAX;
    const LONGEST_CHAIN: usize = 32;
    let (low, high) = triangles
        .clone()
        .flatten()
        .fold((u32::MAX, 0), |(low, high), c| (low.min(c[0]), high.max(c[0])));
    if low > high {
        return Some((Vec::new(), Vec::new()));
    }
    let span = (high - low) as usize + 1;
    if span > 6 * count + 1024 {
        return None;
    }
    // Per position: [first vertex, its vt, its vn].
    let mut first = vec![[NONE; 3]; span];
    let mut keys: Vec<Corner> = Vec::with_capacity(count / 2 + 16);
    // Per vertex: the next vertex at the same position.
    let mut next: Vec<u32> = Vec::with_capacity(count / 2 + 16);
    let mut out: Vec<[u32; 3]> = Vec::with_capacity(count);
    for triangle in triangles {
        let mut indices = [0; 3];
        for (index, &key) in indices.iter_mut().zip(triangle) {
            let head = &mut first[(key[0] - low) as usize];
            if head[0] != NONE && head[1] == key[1] && head[2] == key[2] {
                *index = head[0];
                continue;
            }
            let mut at = if head[0] == NONE { NONE } else { next[head[0] as usize] };
            let mut steps = 0;
            while at != NONE {
                let known = keys[at as usize];
                if known[1] == key[1] && known[2] == key[2] {
                    break;
                }
                at = next[at as usize];
                steps += 1;
                if steps > LONGEST_CHAIN {
                    return None;
                }
            }
            if at == NONE {
                at = keys.len() as u32;
                keys.push(key);
                if head[0] == NONE {
                    *head = [at, key[1], key[2]];
                    next.push(NONE);
                } else {
                    // Second and later vertices at a position: after the first.
                    let second = &mut next[head[0] as usize];
                    let after = *second;
                    *second = at;
                    next.push(after);
                }
            }
            *index = at;
        }
        out.push(indices);
    }
    Some((keys, out))
}

/// Deduplicates the corners of `triangles` (`count` of them) with a hash map.
fn hashed_dedup<'a>(triangles: impl Iterator<Item = &'a [Corner; 3]>, count: usize) -> Dedup {
    let mut map: HashMap<u128, u32, BuildHasherDefault<KeyHasher>> =
        HashMap::with_capacity_and_hasher(count, BuildHasherDefault::default());
    let mut keys: Vec<Corner> = Vec::with_capacity(count);
    let out = triangles
        .map(|triangle| {
            triangle.map(|key| {
                let packed =
                    u128::from(key[0]) | u128::from(key[1]) << 32 | u128::from(key[2]) << 64;
                *map.entry(packed).or_insert_with(|| {
                    keys.push(key);
                    (keys.len() - 1) as u32
                })
            })
        })
        .collect();
    (keys, out)
}

/// A hasher for packed `(v, vt, vn)` keys: two multiplications and shifts (splitmix64's
/// finaliser) instead of SipHash, which took a tenth of the loading time. The keys come
/// from the file, but a collision-heavy file only slows its own loading down.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
    }
    #[expect(clippy::cast_possible_truncation, reason = "splitting the key into its halves")]
    fn write_u128(&mut self, key: u128) {
        let mut h = (key as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ ((key >> 64) as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
        h ^= h >> 29;
        h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
        self.0 = h ^ (h >> 32);
    }
}

/// A blank between words (space, tab, carriage return, form feed).
fn blank(b: u8) -> bool {
    b == b' ' || b == b'\t' || b == b'\r' || b == 0x0c
}

/// A cursor over a block's text that yields the blank-separated words of the current line
/// (`None` at its end) and moves to the next line with [`Cursor::next_line`].
struct Cursor<'a> {
    text: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    /// Skips blanks; whether a word follows on the current line.
    fn skip_blanks(&mut self) -> bool {
        let text = self.text;
        while self.at < text.len() && blank(text[self.at]) {
            self.at += 1;
        }
        self.at < text.len() && text[self.at] != b'\n'
    }

    fn word(&mut self) -> Option<&'a [u8]> {
        if !self.skip_blanks() {
            return None;
        }
        let text = self.text;
        let start = self.at;
        while self.at < text.len() && !end_of_word(text[self.at]) {
            self.at += 1;
        }
        Some(&text[start..self.at])
    }

    /// The next word: read in place as a number when it is a plain decimal.
    fn number(&mut self) -> Option<Number<'a>> {
        if !self.skip_blanks() {
            return None;
        }
        if let Some((value, length)) = fast_f32(&self.text[self.at..]) {
            self.at += length;
            return Some(Number::Plain(value));
        }
        self.word().map(Number::Word)
    }

    /// The rest of the current line (without its line end).
    fn rest(&self) -> &'a [u8] {
        let tail = &self.text[self.at..];
        &tail[..tail.iter().position(|&b| b == b'\n').unwrap_or(tail.len())]
    }

    fn next_line(&mut self) {
        let tail = &self.text[self.at..];
        self.at += tail.iter().position(|&b| b == b'\n').map_or(tail.len(), |n| n + 1);
    }
}

/// A word read by [`Cursor::number`].
enum Number<'a> {
    /// A plain decimal, read (always finite).
    Plain(f32),
    /// Any other word, for `str::parse`.
    Word(&'a [u8]),
}

/// A byte that ends a word: a blank or a line end.
fn end_of_word(b: u8) -> bool {
    blank(b) || b == b'\n'
}

/// Text of the file (its invalid UTF-8 replaced, as when the whole file is read as text).
fn text(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(bytes)
}

/// A parsed chunk, or an error and its chunk-local line.
type ChunkResult = Result<Chunk, (usize, ChunkError)>;

/// An error found while parsing a chunk, placed at a chunk-local line by the caller.
#[derive(Debug)]
enum ChunkError {
    Syntax(String),
    NotFinite(&'static str, String),
    NotText(NotText),
}

impl ChunkError {
    fn into_io(self, path: &Path, line: usize) -> IoError {
        match self {
            Self::Syntax(reason) => IoError::Syntax { path: path.to_path_buf(), line, reason },
            Self::NotFinite(what, text) => {
                IoError::NotFinite { path: path.to_path_buf(), line, what, text }
            }
            Self::NotText(problem) => IoError::NotText { path: path.to_path_buf(), line, problem },
        }
    }
}

/// Powers of ten exact in `f64` (up to 1e22; a number of 15 digits needs 1e15 at most).
const POWERS: [f64; 16] =
    [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15];

/// `str::parse::<f32>` of a plain decimal (`-12.375`) at the start of `text`, up to the end
/// of its word, faster: the value and the word's length. `None` for any other word (the
/// caller asks `str::parse`, which gives the same value for what this accepts).
///
/// The digits, at most 15, make an integer `m` exact in `f64`, and the fraction digits a
/// power `10^k` exact in `f64` (k <= 15), so `m / 10^k` is the `f64` nearest the decimal
/// (Clinger's fast path). Rounding that to `f32` gives the `f32` nearest the decimal unless
/// the `f64` lies exactly halfway between two `f32`s (no `f32` midpoint lies between the
/// decimal and its nearest `f64`, as midpoints are `f64`s); that case goes to `str::parse`.
/// Fraction digits are read eight at a time where eight follow.
fn fast_f32(text: &[u8]) -> Option<(f32, usize)> {
    const MOST: usize = 15;
    let (negative, mut at) = match text.first()? {
        b'-' => (true, 1),
        b'+' => (false, 1),
        _ => (false, 0),
    };
    let mut mantissa: u64 = 0;
    let mut count = 0;
    while let Some(&b) = text.get(at).filter(|b| b.is_ascii_digit()) {
        if count == MOST {
            return None;
        }
        mantissa = mantissa * 10 + u64::from(b - b'0');
        count += 1;
        at += 1;
    }
    let mut fraction = 0;
    if text.get(at) == Some(&b'.') {
        at += 1;
        while let Some(digits) = text.get(at..at + 8).and_then(eight_digits) {
            if count + 8 > MOST {
                return None;
            }
            mantissa = mantissa * 100_000_000 + digits;
            count += 8;
            fraction += 8;
            at += 8;
        }
        while let Some(&b) = text.get(at).filter(|b| b.is_ascii_digit()) {
            if count == MOST {
                return None;
            }
            mantissa = mantissa * 10 + u64::from(b - b'0');
            count += 1;
            fraction += 1;
            at += 1;
        }
    }
    if count == 0 || text.get(at).is_some_and(|&b| !end_of_word(b)) {
        return None;
    }
    #[expect(clippy::cast_precision_loss, reason = "at most 15 digits: exact")]
    let value = mantissa as f64 / POWERS[fraction];
    // 29 bits of the f64 significand are rounded off; exactly 1000...0 is a tie.
    if value.to_bits() & 0x1FFF_FFFF == 0x1000_0000 {
        return None;
    }
    #[expect(clippy::cast_possible_truncation, reason = "rounding to f32 is the point")]
    let value = value as f32;
    Some((if negative { -value } else { value }, at))
}

/// The value of eight ASCII digits (`None` if any byte is not a digit), with a few
/// multiplications instead of eight dependent steps (the technique of fast_float and
/// simdjson, `parse_eight_digits_unrolled`).
fn eight_digits(bytes: &[u8]) -> Option<u64> {
    let word = u64::from_le_bytes(bytes.try_into().ok()?);
    // Every byte 0x30..=0x39: high nibble 3, and still 3 after adding 6.
    let all_digits = word & 0xF0F0_F0F0_F0F0_F0F0 == 0x3030_3030_3030_3030
        && word.wrapping_add(0x0606_0606_0606_0606) & 0xF0F0_F0F0_F0F0_F0F0
            == 0x3030_3030_3030_3030;
    if !all_digits {
        return None;
    }
    // The first digit is the lowest byte: pairs, then quadruples, then the eight.
    let digits = word - 0x3030_3030_3030_3030;
    let pairs = digits.wrapping_mul(10).wrapping_add(digits >> 8);
    let mask = 0x0000_00FF_0000_00FF;
    let value = ((pairs & mask).wrapping_mul(100 + (1_000_000 << 32))
        + ((pairs >> 16) & mask).wrapping_mul(1 + (10_000 << 32)))
        >> 32;
    Some(value)
}

/// A number word as `str::parse::<f32>` reads it.
fn float(word: &[u8]) -> Option<f32> {
    match fast_f32(word) {
        Some((value, _)) => Some(value),
        None => text(word).parse().ok(),
    }
}

fn numbers<const N: usize>(
    words: &mut Cursor<'_>,
    keyword: &str,
    what: &'static str,
) -> Result<[f32; N], ChunkError> {
    let mut out = [0.0; N];
    for (k, slot) in out.iter_mut().enumerate() {
        let value = match words.number() {
            None => {
                return Err(ChunkError::Syntax(format!(
                    "`{keyword}` needs {N} numbers, found {k}"
                )));
            }
            Some(Number::Plain(value)) => value,
            Some(Number::Word(word)) => {
                let value: f32 = text(word).parse().map_err(|_| {
                    ChunkError::Syntax(format!(
                        "`{keyword}`: expected a number, found {:?}",
                        text(word)
                    ))
                })?;
                if !value.is_finite() {
                    return Err(ChunkError::NotFinite(what, text(word).into_owned()));
                }
                value
            }
        };
        *slot = value;
    }
    Ok(out)
}

/// The rest of a statement's line after its keyword, trimmed (names may hold spaces).
fn rest_of(words: &Cursor<'_>) -> String {
    text(words.rest()).trim().to_owned()
}

/// The group of an `s` statement from its first word: a number, 0 and `off` for none.
fn smoothing_group(word: Option<&[u8]>) -> Result<u32, ChunkError> {
    let word = text(word.unwrap_or_default());
    match &*word {
        "off" => Ok(0),
        _ => word.parse().map_err(|_| {
            ChunkError::Syntax(format!(
                "`s` needs a smoothing group number (0 to {}) or `off`, found {word:?}",
                u32::MAX
            ))
        }),
    }
}

/// Parses a block of whole lines: its statements, and the first error among them or among
/// its lines that are not text (whichever comes first).
fn parse_chunk(block: &[u8]) -> ChunkResult {
    let parsed = parse_statements(block);
    match (first_line_not_text(block), parsed) {
        (Some(bad), Err(error)) if error.0 < bad.0 => Err(error),
        (Some(bad), _) => Err(bad),
        (None, parsed) => parsed,
    }
}

/// The first statement line (not a comment) of `block` that holds a NUL byte or invalid
/// UTF-8, with what is wrong. A block of ASCII without NUL (nearly every OBJ file) is seen
/// to have none in one pass that vectorises; others are searched line by line.
fn first_line_not_text(block: &[u8]) -> Option<(usize, ChunkError)> {
    // Bit 7 of `b | (b - 1)` is set for NUL (0 - 1 = 0xFF) and for every byte above 127.
    let ascii = |chunk: &[u8]| chunk.iter().fold(0, |any, &b| any | b | b.wrapping_sub(1)) < 0x80;
    if block.chunks(64).all(ascii) {
        return None;
    }
    block.split(|&b| b == b'\n').enumerate().find_map(|(i, line)| {
        let start = line.iter().position(|&b| !blank(b)).unwrap_or(line.len());
        let problem = if line[start..].starts_with(b"#") {
            return None;
        } else if line.contains(&0) {
            NotText::Nul
        } else if std::str::from_utf8(line).is_err() {
            NotText::InvalidUtf8
        } else {
            return None;
        };
        Some((i + 1, ChunkError::NotText(problem)))
    })
}

/// Parses the statements of a block of whole lines.
fn parse_statements(block: &[u8]) -> ChunkResult {
    let mut chunk = Chunk::default();
    let mut face: Vec<(Corner, [Option<i64>; 3])> = Vec::with_capacity(8);
    let mut words = Cursor { text: block, at: 0 };
    let mut line = 0;
    // The line of the last face that gave triangles.
    let mut last_face = 0;
    while words.at < block.len() {
        line += 1;
        let fail = |e| (line, e);
        if let Some(keyword) = words.word() {
            match keyword {
                b"v" => {
                    let [x, y, z] =
                        numbers::<3>(&mut words, "v", "vertex position").map_err(fail)?;
                    let mut p = Vec3::new(x, y, z);
                    // `v x y z w`: divide by w; `v x y z r g b [a]`: a colour.
                    match more_numbers(&mut words).map_err(fail)? {
                        (1, [w, ..]) => {
                            if w == 0.0 {
                                return Err(fail(ChunkError::Syntax(format!(
                                    "`v`: w = {w} cannot scale a position"
                                ))));
                            }
                            p /= w;
                        }
                        (3, [r, g, b, _]) => chunk.add_color(Vec4::new(r, g, b, 1.0)),
                        (4, [r, g, b, a]) => chunk.add_color(Vec4::new(r, g, b, a)),
                        (0, _) => {}
                        (count, _) => {
                            return Err(fail(ChunkError::Syntax(format!(
                                "`v` needs 3 numbers, 4 (x y z w), 6 (x y z r g b) or 7 \
                                 (x y z r g b a), found {}",
                                3 + count
                            ))));
                        }
                    }
                    chunk.positions.push(p);
                }
                b"vt" => {
                    let [u, v] =
                        numbers::<2>(&mut words, "vt", "texture coordinate").map_err(fail)?;
                    chunk.uvs.push(Vec2::new(u, v));
                }
                b"vn" => {
                    let [x, y, z] =
                        numbers::<3>(&mut words, "vn", "vertex normal").map_err(fail)?;
                    chunk.normals.push(Vec3::new(x, y, z));
                }
                b"f" => {
                    face.clear();
                    let mut any_kept = false;
                    while words.skip_blanks() {
                        if let Some((corner, length)) = simple_corner(&block[words.at..]) {
                            words.at += length;
                            face.push((corner, [None; 3]));
                            continue;
                        }
                        let Some(word) = words.word() else { break };
                        let (corner, kept) = corner(word).map_err(fail)?;
                        any_kept |= kept != [None; 3];
                        face.push((corner, kept));
                    }
                    if face.len() >= 3 {
                        chunk.note_face(line, &mut last_face);
                    }
                    // Fan triangulation; polygons that are not convex are triangulated
                    // again once their positions are known (`crate::polygon`).
                    if face.len() > 3 {
                        chunk.polygons.push((chunk.triangles.len(), face.len()));
                    }
                    for k in 1..face.len().saturating_sub(1) {
                        let triangle = [face[0], face[k], face[k + 1]];
                        if any_kept {
                            chunk.keep_indices(&triangle);
                        }
                        chunk.triangles.push(triangle.map(|(corner, _)| corner));
                    }
                }
                b"o" | b"g" => {
                    let name = rest_of(&words);
                    chunk.events.push((chunk.triangles.len(), Event::Object(name)));
                }
                b"usemtl" => {
                    // An empty name is the name of a material `newmtl` left unnamed.
                    let name = rest_of(&words);
                    chunk.events.push((chunk.triangles.len(), Event::Material(name, line)));
                }
                b"s" => {
                    let group = smoothing_group(words.word()).map_err(fail)?;
                    chunk.smoothing.push((chunk.triangles.len(), group));
                }
                b"mtllib" => {
                    let name = rest_of(&words);
                    chunk.events.push((chunk.triangles.len(), Event::Library(name, line)));
                }
                _ => {}
            }
        }
        words.next_line();
    }
    chunk.lines = line;
    if !chunk.colors.is_empty() {
        chunk.colors.resize(chunk.positions.len(), NO_COLOR);
    }
    Ok(chunk)
}

impl Chunk {
    /// Starts a run of faces at a face on `line` unless the last face was on the line before.
    fn note_face(&mut self, line: usize, last_face: &mut usize) {
        if self.face_runs.is_empty() || line != *last_face + 1 {
            self.face_runs.push(FaceRun {
                triangle: self.triangles.len(),
                line,
                counts: [self.positions.len(), self.uvs.len(), self.normals.len()],
            });
        }
        *last_face = line;
    }

    /// Keeps the indices of the triangle about to be pushed that [`corner`] gave as written:
    /// negative ones, counted from the chunk's first element, in `relative`; those out of
    /// range whatever the file holds in `invalid`.
    fn keep_indices(&mut self, triangle: &[(Corner, [Option<i64>; 3]); 3]) {
        let at = 3 * self.triangles.len();
        let counts = [self.positions.len(), self.uvs.len(), self.normals.len()];
        for (i, (corner, kept)) in triangle.iter().enumerate() {
            for (slot, index) in kept.iter().enumerate() {
                match *index {
                    Some(index) if corner[slot] == INVALID => {
                        self.invalid.push((at + i, slot, index));
                    }
                    Some(index) => self.relative.push((at + i, slot, counts[slot] as i64 + index)),
                    None => {}
                }
            }
        }
    }

    /// Gives the position about to be pushed a colour (the ones before without get
    /// [`NO_COLOR`]).
    fn add_color(&mut self, color: Vec4) {
        self.colors.resize(self.positions.len(), NO_COLOR);
        self.colors.push(color);
    }
}

/// The numbers after a `v`'s position (w, or a colour's r g b and a), and how many there
/// are (5 for more than four).
fn more_numbers(words: &mut Cursor<'_>) -> Result<(usize, [f32; 4]), ChunkError> {
    let mut values = [0.0; 4];
    let mut count = 0;
    while let Some(word) = words.word() {
        if count == values.len() {
            return Ok((count + 1, values));
        }
        values[count] = float(word).filter(|v| v.is_finite()).ok_or_else(|| {
            ChunkError::Syntax(format!(
                "`v`: expected a number (w, or a colour's r g b [a]), found {:?}",
                text(word)
            ))
        })?;
        count += 1;
    }
    Ok((count, values))
}

/// The common corners `v`, `v/vt`, `v//vn` and `v/vt/vn` with indices of 1 to 9 digits,
/// not 0, at the start of `text`, in one pass: the corner and its length. `None` for
/// anything else (which [`corner`] reads the long way).
fn simple_corner(text: &[u8]) -> Option<(Corner, usize)> {
    let mut corner = [MISSING; 3];
    let mut slot = 0;
    let mut value = 0u32;
    let mut digits = 0;
    let mut length = text.len();
    for (i, &b) in text.iter().enumerate() {
        match b {
            b'0'..=b'9' => {
                digits += 1;
                if digits > 9 {
                    return None;
                }
                value = value * 10 + u32::from(b - b'0');
            }
            b'/' => {
                if digits > 0 {
                    corner[slot] = value.checked_sub(1)?;
                } else if slot != 1 {
                    // Only `vt` may be left out between separators (`v//vn`).
                    return None;
                }
                slot += 1;
                if slot > 2 {
                    return None;
                }
                value = 0;
                digits = 0;
            }
            b if end_of_word(b) => {
                length = i;
                break;
            }
            _ => return None,
        }
    }
    if digits == 0 {
        return None;
    }
    corner[slot] = value.checked_sub(1)?;
    Some((corner, length))
}

/// A face index as `str::parse::<i64>` reads it.
fn integer(field: &[u8]) -> Option<i64> {
    let (negative, digits) = match field.first()? {
        b'-' => (true, &field[1..]),
        b'+' => (false, &field[1..]),
        _ => (false, field),
    };
    if digits.is_empty() || digits.len() > 18 {
        return text(field).parse().ok();
    }
    let mut value: i64 = 0;
    for &b in digits {
        if !b.is_ascii_digit() {
            return None;
        }
        value = value * 10 + i64::from(b - b'0');
    }
    Some(if negative { -value } else { value })
}

/// Parses a face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`: the corner, and per slot the
/// index as written where the corner cannot hold it: a negative index (the corner holds 0
/// until it is resolved) and one out of range whatever the file holds (the corner holds
/// [`INVALID`]).
fn corner(word: &[u8]) -> Result<(Corner, [Option<i64>; 3]), ChunkError> {
    let mut c = [MISSING; 3];
    let mut kept = [None; 3];
    let mut rest = word;
    // A fourth slot only to report a corner of four indices.
    for slot in 0..4 {
        if rest.is_empty() && slot > 0 {
            break;
        }
        let (field, tail) = match rest.iter().position(|&b| b == b'/') {
            Some(at) => (&rest[..at], &rest[at + 1..]),
            None => (rest, &[][..]),
        };
        // `v/vt/` or `v//`: a trailing separator with nothing after it.
        let ends = tail.is_empty() && field.len() < rest.len();
        rest = tail;
        if slot > 2 {
            return Err(ChunkError::Syntax(format!(
                "face corner {:?} has more than three indices",
                text(word)
            )));
        }
        if field.is_empty() && slot > 0 {
            if ends {
                break;
            }
            continue;
        }
        let index = integer(field).ok_or_else(|| {
            ChunkError::Syntax(format!(
                "face corner {:?}: expected an index, found {:?}",
                text(word),
                text(field)
            ))
        })?;
        c[slot] = match index {
            i if i < 0 => 0,
            // Zero, or past `u32`: out of range whatever the file holds.
            i => u32::try_from(i - 1).map_or(INVALID, |i| i.min(INVALID)),
        };
        // Resolved (or found out of range) in `assemble`.
        if index < 0 || c[slot] == INVALID {
            kept[slot] = Some(index);
        }
    }
    Ok((c, kept))
}

#[cfg(test)]
mod tests {
    use super::{eight_digits, fast_f32, float, simple_corner};

    /// splitmix64, for reproducible test inputs.
    fn next(state: &mut u64) -> u64 {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Where the fast path reads a number, it reads the whole word and the value
    /// `str::parse` gives, bit for bit.
    fn agrees(word: &str) -> bool {
        let Some((value, length)) = fast_f32(word.as_bytes()) else { return false };
        assert_eq!(length, word.len(), "{word}");
        let expected: f32 = word.parse().unwrap();
        assert_eq!(value.to_bits(), expected.to_bits(), "{word}: {value} vs {expected}");
        true
    }

    #[test]
    fn the_fast_path_gives_what_str_parse_gives() {
        let mut state = 1;
        let mut fast = 0;
        for _ in 0..200_000 {
            let x = f32::from_bits(next(&mut state) as u32);
            if !x.is_finite() {
                continue;
            }
            // Shortest round trip, fixed digits, and scaled to exporters' magnitudes.
            let scaled = x / 2f32.powi(x.abs().log2().floor() as i32 - 4);
            for word in [
                format!("{x}"),
                format!("{scaled}"),
                format!("{scaled:.6}"),
                format!("{:.9}", scaled / 7.0),
                format!("{:.3}", scaled * 1000.0),
                format!("{}", f64::from(scaled) / 3.0),
            ] {
                fast += usize::from(agrees(&word));
            }
        }
        // Random digit strings: signs, points anywhere, leading zeros, up to 20 digits.
        for _ in 0..200_000 {
            let r = next(&mut state);
            let digits = 1 + (r % 20) as usize;
            let mut word: String = match (r >> 8) % 3 {
                0 => "-".into(),
                1 => "+".into(),
                _ => String::new(),
            };
            let point = (r >> 16) as usize % (digits + 2);
            for k in 0..digits {
                if k == point {
                    word.push('.');
                }
                word.push(char::from(b'0' + (next(&mut state) % 10) as u8));
            }
            fast += usize::from(agrees(&word));
        }
        assert!(fast > 900_000, "only {fast} words took the fast path");
    }

    #[test]
    fn ties_and_other_words_are_left_to_str_parse() {
        // 16777217 = 2^24 + 1 lies halfway between the f32s 2^24 and 2^24 + 2.
        assert_eq!(fast_f32(b"16777217"), None);
        assert_eq!(float(b"16777217"), Some(16_777_216.0));
        for word in ["", "-", "+", ".", "-.", "1e5", "1.5e3", "inf", "nan", "1.2.3", "0x10", "1_0"]
        {
            assert_eq!(fast_f32(word.as_bytes()), None, "{word}");
        }
        // Sixteen digits or more.
        assert_eq!(fast_f32(b"1.234567890123456"), None);
        assert_eq!(fast_f32(b"0.000000000000001"), None);
        // A word ends at a blank or a line end, not at other bytes.
        assert_eq!(fast_f32(b"2.5 7"), Some((2.5, 3)));
        assert_eq!(fast_f32(b"-0.25\r\n"), Some((-0.25, 5)));
        assert_eq!(fast_f32(b"1.5/2"), None);
        assert_eq!(fast_f32(b"-0").map(|(v, _)| v.to_bits()), Some((-0.0f32).to_bits()));
        assert_eq!(fast_f32(b"5."), Some((5.0, 2)));
        assert_eq!(fast_f32(b".5"), Some((0.5, 2)));
    }

    #[test]
    fn eight_digits_at_once() {
        assert_eq!(eight_digits(b"12345678"), Some(12_345_678));
        assert_eq!(eight_digits(b"00000000"), Some(0));
        assert_eq!(eight_digits(b"99999999"), Some(99_999_999));
        assert_eq!(eight_digits(b"00000001"), Some(1));
        for bad in [b"1234567a", b"/2345678", b"1234:678", b"12 45678", b"1234567\n"] {
            assert_eq!(eight_digits(bad), None, "{bad:?}");
        }
        assert_eq!(eight_digits(b"1234567"), None);
    }

    #[test]
    fn simple_corners() {
        let m = u32::MAX;
        assert_eq!(simple_corner(b"7"), Some(([6, m, m], 1)));
        assert_eq!(simple_corner(b"7/8"), Some(([6, 7, m], 3)));
        assert_eq!(simple_corner(b"7//9 1"), Some(([6, m, 8], 4)));
        assert_eq!(simple_corner(b"7/8/9\n"), Some(([6, 7, 8], 5)));
        // Left to the general reader: zero, negative, empty, too many or too long.
        for word in ["0", "-1", "1/-1", "/1", "1/", "1//", "1/2/", "1/2/3/4", "1234567890", "1x"] {
            assert_eq!(simple_corner(word.as_bytes()), None, "{word}");
        }
    }
}
