//! The OBJ geometry parser: `v`, `vt`, `vn`, `f`, `o`, `g`, `usemtl`, `mtllib`, in parallel.
//!
//! tobj reads a 1M-triangle OBJ in about 2.4 s on the project's machine (one thread, a
//! `String` per line, a hash lookup per face corner); this parser splits the text into chunks
//! at line ends, parses the chunks in parallel (rayon), resolves face indices against the
//! running counts, and builds the objects' vertex arrays in parallel. It follows tobj's rules
//! exactly, and a test checks that it gives tobj's output on every shared OBJ model:
//!
//! - `o` and `g` start a new object when the current one has faces, else rename it; `usemtl`
//!   changing the material inside an object with faces starts a new object of the same name;
//! - faces are triangulated as fans `(a, b, c), (a, c, d), ...`; faces of fewer than three
//!   corners (points, lines) and `l` / `p` statements are ignored;
//! - vertices are the distinct `v/vt/vn` triples of an object, in order of first use;
//! - `v x y z w` divides by `w`; further values (vertex colours) are ignored.
//!
//! Material libraries are read with tobj (see [`crate::obj`]).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::path::Path;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::IoError;

/// "No `vt` / `vn` index" in a corner.
const MISSING: u32 = u32::MAX;

/// A triangle as three `[v, vt, vn]` global indices.
type Triangle = [[u32; 3]; 3];

/// An object's part as split at `o`, `g` and `usemtl`: name, `usemtl` name in force,
/// triangles, and whether a `usemtl` (rather than `o` / `g`) started it.
type Part = (String, Option<String>, Vec<Triangle>, bool);

/// One object as parsed, before material resolution and conversion.
#[derive(Debug)]
pub(crate) struct ParsedObject {
    pub name: String,
    pub material: Option<usize>,
    pub positions: Vec<Vec3>,
    /// `Some` when every corner has a `vt`; `None` when none has.
    pub uvs: Option<Vec<Vec2>>,
    pub normals: Option<Vec<Vec3>>,
    pub triangles: Vec<[u32; 3]>,
    /// Some corners had a `vt` and some did not (texture coordinates dropped).
    pub mixed_uvs: bool,
    /// Some corners had a `vn` and some did not (normals dropped).
    pub mixed_normals: bool,
}

/// A face corner: `[v, vt, vn]`, each either an absolute zero-based index or, where
/// `relative` has the slot's bit, an index relative to the chunk's first element.
#[derive(Clone, Copy, Debug)]
struct Corner {
    index: [i64; 3],
    relative: u8,
}

#[derive(Debug)]
enum Event {
    Object(String),
    Material(String),
    Library(String, usize),
}

#[derive(Debug, Default)]
struct Chunk {
    lines: usize,
    positions: Vec<Vec3>,
    uvs: Vec<Vec2>,
    normals: Vec<Vec3>,
    /// Three per triangle.
    corners: Vec<Corner>,
    /// Events with the chunk-local triangle index they precede.
    events: Vec<(usize, Event)>,
}

/// The OBJ text's objects and, in order, its `mtllib` statements (name, line).
pub(crate) struct Parsed {
    /// The objects' parts, in file order.
    objects: Vec<Part>,
    pub libraries: Vec<(String, usize)>,
    positions: Vec<Vec3>,
    uvs: Vec<Vec2>,
    normals: Vec<Vec3>,
}

/// Parses OBJ text. Index errors are reported by the caller's diagnostic pass; this returns
/// `Err(None)` for them, `Err(Some(error))` for errors it can place itself.
pub(crate) fn parse(text: &str, path: &Path) -> Result<Parsed, Option<IoError>> {
    let chunks = split(text, 1 << 20);
    let parsed: Vec<Result<Chunk, (usize, ChunkError)>> =
        chunks.par_iter().map(|c| parse_chunk(c)).collect();
    let mut line_base = 0;
    let mut done = Vec::with_capacity(parsed.len());
    for result in parsed {
        match result {
            Ok(chunk) => {
                line_base += chunk.lines;
                done.push(chunk);
            }
            Err((line, error)) => return Err(Some(error.into_io(path, line_base + line))),
        }
    }
    // Prefix sums of the element counts: where each chunk's elements start.
    let mut bases = Vec::with_capacity(done.len());
    let mut totals = [0usize; 3];
    let mut line_bases = Vec::with_capacity(done.len());
    let mut lines = 0;
    for chunk in &done {
        bases.push(totals);
        line_bases.push(lines);
        totals[0] += chunk.positions.len();
        totals[1] += chunk.uvs.len();
        totals[2] += chunk.normals.len();
        lines += chunk.lines;
    }
    // Resolve every corner to global indices, in parallel; any out-of-range index fails.
    let resolved: Vec<Option<Vec<[[u32; 3]; 3]>>> = done
        .par_iter()
        .zip(&bases)
        .map(|(chunk, base)| {
            chunk
                .corners
                .chunks_exact(3)
                .map(|t| {
                    let mut tri = [[0u32; 3]; 3];
                    for (k, corner) in t.iter().enumerate() {
                        for slot in 0..3 {
                            let raw = corner.index[slot];
                            if raw == i64::from(MISSING) {
                                tri[k][slot] = MISSING;
                                continue;
                            }
                            let global = if corner.relative & (1 << slot) != 0 {
                                base[slot] as i64 + raw
                            } else {
                                raw
                            };
                            if global < 0 || global >= totals[slot] as i64 {
                                return None;
                            }
                            tri[k][slot] = u32::try_from(global).ok()?;
                        }
                    }
                    Some(tri)
                })
                .collect()
        })
        .collect();

    // Split into objects, following the events in file order.
    let mut objects = Vec::new();
    let mut libraries = Vec::new();
    let mut name = "unnamed_object".to_owned();
    let mut material: Option<String> = None;
    let mut current: Vec<[[u32; 3]; 3]> = Vec::new();
    let mut by_usemtl = false;
    for ((chunk, triangles), line_base) in done.iter_mut().zip(resolved).zip(line_bases) {
        let Some(triangles) = triangles else { return Err(None) };
        let mut next = 0;
        for (at, event) in std::mem::take(&mut chunk.events) {
            current.extend_from_slice(&triangles[next..at]);
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
                        by_usemtl = false;
                    }
                    name = if new_name.is_empty() { "unnamed_object".to_owned() } else { new_name };
                }
                Event::Material(new_material) => {
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
        current.extend_from_slice(&triangles[next..]);
    }
    if !current.is_empty() {
        objects.push((name, material, current, by_usemtl));
    }
    let mut positions = Vec::with_capacity(totals[0]);
    let mut uvs = Vec::with_capacity(totals[1]);
    let mut normals = Vec::with_capacity(totals[2]);
    for chunk in done {
        positions.extend(chunk.positions);
        uvs.extend(chunk.uvs);
        normals.extend(chunk.normals);
    }
    Ok(Parsed { objects, libraries, positions, uvs, normals })
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
        let mut merged: Vec<(String, Option<usize>, Vec<Triangle>)> =
            Vec::with_capacity(self.objects.len());
        for (name, material_name, triangles, by_usemtl) in self.objects {
            let resolved = material_name.as_deref().and_then(&material);
            match merged.last_mut() {
                Some(last) if by_usemtl && last.1 == resolved => last.2.extend(triangles),
                _ => merged.push((name, resolved, triangles)),
            }
        }
        let (positions, uvs, normals) = (&self.positions, &self.uvs, &self.normals);
        merged
            .into_par_iter()
            .map(|(name, material, triangles)| {
                let mut map: HashMap<u128, u32, BuildHasherDefault<KeyHasher>> =
                    HashMap::with_capacity_and_hasher(
                        triangles.len(),
                        BuildHasherDefault::default(),
                    );
                let mut keys: Vec<[u32; 3]> = Vec::with_capacity(triangles.len());
                let indices: Vec<[u32; 3]> = triangles
                    .iter()
                    .map(|t| {
                        t.map(|key| {
                            let packed = u128::from(key[0])
                                | u128::from(key[1]) << 32
                                | u128::from(key[2]) << 64;
                            *map.entry(packed).or_insert_with(|| {
                                keys.push(key);
                                (keys.len() - 1) as u32
                            })
                        })
                    })
                    .collect();
                let with_vt = keys.iter().filter(|k| k[1] != MISSING).count();
                let with_vn = keys.iter().filter(|k| k[2] != MISSING).count();
                let all = keys.len();
                ParsedObject {
                    name,
                    material,
                    positions: keys.iter().map(|k| positions[k[0] as usize]).collect(),
                    uvs: (with_vt == all && all > 0)
                        .then(|| keys.iter().map(|k| uvs[k[1] as usize]).collect()),
                    normals: (with_vn == all && all > 0)
                        .then(|| keys.iter().map(|k| normals[k[2] as usize]).collect()),
                    triangles: indices,
                    mixed_uvs: with_vt != 0 && with_vt != all,
                    mixed_normals: with_vn != 0 && with_vn != all,
                }
            })
            .collect()
    }
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

/// The blank-separated words of a line (spaces, tabs, carriage returns): a byte loop, as
/// `split_ascii_whitespace` called its predicate through a pointer for every byte.
struct Words<'a>(&'a str);

impl<'a> Iterator for Words<'a> {
    type Item = &'a str;

    fn next(&mut self) -> Option<&'a str> {
        let bytes = self.0.as_bytes();
        let blank = |b: u8| b == b' ' || b == b'\t' || b == b'\r' || b == 0x0c;
        let start = bytes.iter().position(|&b| !blank(b))?;
        let end = bytes[start..].iter().position(|&b| blank(b)).map_or(bytes.len(), |n| start + n);
        let word = &self.0[start..end];
        self.0 = &self.0[end..];
        Some(word)
    }
}

/// Splits `text` into pieces of about `size` bytes, each ending at a line end.
fn split(text: &str, size: usize) -> Vec<&str> {
    let mut pieces = Vec::with_capacity(text.len() / size + 1);
    let mut rest = text;
    while rest.len() > size {
        let cut = rest.as_bytes()[size..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(rest.len(), |i| size + i + 1);
        let (piece, tail) = rest.split_at(cut);
        pieces.push(piece);
        rest = tail;
    }
    if !rest.is_empty() || pieces.is_empty() {
        pieces.push(rest);
    }
    pieces
}

/// An error found while parsing a chunk, placed at a chunk-local line by the caller.
#[derive(Debug)]
enum ChunkError {
    Syntax(String),
    NotFinite(&'static str, String),
}

impl ChunkError {
    fn into_io(self, path: &Path, line: usize) -> IoError {
        match self {
            Self::Syntax(reason) => IoError::Syntax { path: path.to_path_buf(), line, reason },
            Self::NotFinite(what, text) => {
                IoError::NotFinite { path: path.to_path_buf(), line, what, text }
            }
        }
    }
}

fn numbers<const N: usize>(
    words: &mut Words<'_>,
    keyword: &str,
    what: &'static str,
) -> Result<[f32; N], ChunkError> {
    let mut out = [0.0; N];
    for (k, slot) in out.iter_mut().enumerate() {
        let Some(word) = words.next() else {
            return Err(ChunkError::Syntax(format!("`{keyword}` needs {N} numbers, found {k}")));
        };
        let value: f32 = word.parse().map_err(|_| {
            ChunkError::Syntax(format!("`{keyword}`: expected a number, found {word:?}"))
        })?;
        if !value.is_finite() {
            return Err(ChunkError::NotFinite(what, word.to_owned()));
        }
        *slot = value;
    }
    Ok(out)
}

/// The rest of a statement's line after its keyword, trimmed (names may hold spaces).
fn rest_of(line: &str, keyword: &str) -> String {
    line.trim_start()[keyword.len()..].trim().to_owned()
}

fn parse_chunk(text: &str) -> Result<Chunk, (usize, ChunkError)> {
    let mut chunk = Chunk::default();
    let mut face: Vec<Corner> = Vec::with_capacity(8);
    for (i, line) in text.lines().enumerate() {
        let fail = |e| (i + 1, e);
        chunk.lines = i + 1;
        let mut words = Words(line);
        let Some(keyword) = words.next() else { continue };
        match keyword {
            "v" => {
                let [x, y, z] = numbers::<3>(&mut words, "v", "vertex position").map_err(fail)?;
                let mut p = Vec3::new(x, y, z);
                // `v x y z w`: divide by w; `v x y z r g b`: colours, ignored.
                if let (Some(w), None) = (words.next(), words.next()) {
                    let w: f32 = w.parse().map_err(|_| {
                        fail(ChunkError::Syntax(format!("`v`: expected w, found {w:?}")))
                    })?;
                    if w == 0.0 || !w.is_finite() {
                        return Err(fail(ChunkError::Syntax(format!(
                            "`v`: w = {w} cannot scale a position"
                        ))));
                    }
                    p /= w;
                }
                chunk.positions.push(p);
            }
            "vt" => {
                let [u, v] = numbers::<2>(&mut words, "vt", "texture coordinate").map_err(fail)?;
                chunk.uvs.push(Vec2::new(u, v));
            }
            "vn" => {
                let [x, y, z] = numbers::<3>(&mut words, "vn", "vertex normal").map_err(fail)?;
                chunk.normals.push(Vec3::new(x, y, z));
            }
            "f" => {
                face.clear();
                for word in words {
                    face.push(corner(word, &chunk).map_err(fail)?);
                }
                if face.len() >= 3 {
                    for k in 1..face.len() - 1 {
                        chunk.corners.extend_from_slice(&[face[0], face[k], face[k + 1]]);
                    }
                }
            }
            "o" | "g" => {
                chunk.events.push((chunk.corners.len() / 3, Event::Object(rest_of(line, keyword))));
            }
            "usemtl" => {
                let name = rest_of(line, keyword);
                if name.is_empty() {
                    return Err(fail(ChunkError::Syntax(
                        "`usemtl` needs a material name".to_owned(),
                    )));
                }
                chunk.events.push((chunk.corners.len() / 3, Event::Material(name)));
            }
            "mtllib" => chunk
                .events
                .push((chunk.corners.len() / 3, Event::Library(rest_of(line, keyword), i + 1))),
            _ => {}
        }
    }
    Ok(chunk)
}

/// Parses a face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`.
fn corner(word: &str, chunk: &Chunk) -> Result<Corner, ChunkError> {
    let mut c = Corner { index: [i64::from(MISSING); 3], relative: 0 };
    // A fourth slot only to report a corner of four indices.
    let counts = [chunk.positions.len(), chunk.uvs.len(), chunk.normals.len(), 0];
    let mut rest = word;
    for (slot, &count) in counts.iter().enumerate() {
        if rest.is_empty() && slot > 0 {
            break;
        }
        let (field, tail) = match rest.as_bytes().iter().position(|&b| b == b'/') {
            Some(at) => (&rest[..at], &rest[at + 1..]),
            None => (rest, ""),
        };
        // `v/vt/` or `v//`: a trailing separator with nothing after it.
        let ends = tail.is_empty() && field.len() < rest.len();
        rest = tail;
        if slot > 2 {
            return Err(ChunkError::Syntax(format!(
                "face corner {word:?} has more than three indices"
            )));
        }
        if field.is_empty() && slot > 0 {
            if ends {
                break;
            }
            continue;
        }
        let index: i64 = field.parse().map_err(|_| {
            ChunkError::Syntax(format!("face corner {word:?}: expected an index, found {field:?}"))
        })?;
        c.index[slot] = match index {
            // Out of range: resolution fails and the diagnostic pass names the line.
            0 => -1,
            i if i > 0 => i - 1,
            i => {
                c.relative |= 1 << slot;
                count as i64 + i
            }
        };
        // An index equal to the sentinel, or absurdly large, is out of range too.
        if c.index[slot] >= i64::from(MISSING) {
            c.index[slot] = -1;
            c.relative &= !(1 << slot);
        }
    }
    Ok(c)
}
