//! The statements of a block of whole lines, parsed into a [`Chunk`] by the rules the parent
//! module lists (after tobj's `load_obj_buf`): `v`, `vt`, `vn`, `f`, `o`, `g`, `s`, `usemtl`,
//! `mtllib`; other statements are ignored.

use glam::{Vec2, Vec3, Vec4};

use super::blocks::{Cursor, Number, first_line_not_text};
use super::corners::{Corner, INVALID, corner, simple_corner};
use super::numbers::float;
use super::words::text;
use super::{Chunk, ChunkError, ChunkResult, Event, FaceRun, NO_COLOR};
use seamlit_asset::Syntax;

/// Parses a block of whole lines: its statements, and the first error among them or among
/// its lines that are not text (whichever comes first).
pub(super) fn parse_chunk(block: &[u8]) -> ChunkResult {
    let parsed = parse_statements(block);
    match (first_line_not_text(block), parsed) {
        (Some(bad), Err(error)) if error.0 < bad.0 => Err(error),
        (Some(bad), _) => Err(bad),
        (None, parsed) => parsed,
    }
}

/// Parses the statements of a block of whole lines.
fn parse_statements(block: &[u8]) -> ChunkResult {
    let mut chunk = Chunk::default();
    let mut face = Face { corners: Vec::with_capacity(8), last_line: 0 };
    let mut words = Cursor { text: block, at: 0 };
    let mut line = 0;
    while words.at < block.len() {
        line += 1;
        if let Some(keyword) = words.word() {
            chunk.statement(keyword, &mut words, line, &mut face).map_err(|e| (line, e))?;
        }
        words.next_line();
    }
    chunk.lines = line;
    if !chunk.colors.is_empty() {
        chunk.colors.resize(chunk.positions.len(), NO_COLOR);
    }
    Ok(chunk)
}

/// The face being read (its corners, and per corner the indices [`corner`] kept as written),
/// and the line of the last face that gave triangles.
struct Face {
    corners: Vec<(Corner, [Option<i64>; 3])>,
    last_line: usize,
}

impl Chunk {
    /// Parses the statement of `line` that starts with `keyword`.
    fn statement(
        &mut self,
        keyword: &[u8],
        words: &mut Cursor<'_>,
        line: usize,
        face: &mut Face,
    ) -> Result<(), ChunkError> {
        let next = self.triangles.len();
        match keyword {
            b"v" => self.vertex(words)?,
            b"vt" => {
                let [u, v] = numbers::<2>(words, "vt", "texture coordinate")?;
                self.uvs.push(Vec2::new(u, v));
            }
            b"vn" => {
                let [x, y, z] = numbers::<3>(words, "vn", "vertex normal")?;
                self.normals.push(Vec3::new(x, y, z));
            }
            b"f" => self.face(words, line, face)?,
            b"o" | b"g" => {
                let name = self.name(words, line);
                self.events.push((next, Event::Object(name)));
            }
            // An empty name is the name of a material `newmtl` left unnamed.
            b"usemtl" => {
                let name = self.name(words, line);
                self.events.push((next, Event::Material(name, line)));
            }
            b"s" => {
                let group = smoothing_group(words.word())?;
                self.smoothing.push((next, group));
            }
            b"mtllib" => {
                let name = self.name(words, line);
                self.events.push((next, Event::Library(name, line)));
            }
            _ => {}
        }
        Ok(())
    }

    /// The name a statement on `line` gives: the rest of the line, trimmed (names may hold
    /// spaces), decoded as Windows-1252 where it is not UTF-8 (noting the first such line).
    fn name(&mut self, words: &Cursor<'_>, line: usize) -> String {
        let (name, legacy) = super::names::decode(words.rest());
        if legacy && self.legacy_names.is_none() {
            self.legacy_names = Some(line);
        }
        name.trim().to_owned()
    }

    /// A `v` statement: `x y z`, `x y z w` (divided by w) or `x y z r g b [a]` (a colour).
    fn vertex(&mut self, words: &mut Cursor<'_>) -> Result<(), ChunkError> {
        let [x, y, z] = numbers::<3>(words, "v", "vertex position")?;
        let mut p = Vec3::new(x, y, z);
        match more_numbers(words)? {
            (1, [w, ..]) => {
                if w == 0.0 {
                    return Err(ChunkError::Syntax(Syntax::ZeroW { w }));
                }
                p /= w;
            }
            (3, [r, g, b, _]) => self.add_color(Vec4::new(r, g, b, 1.0)),
            (4, [r, g, b, a]) => self.add_color(Vec4::new(r, g, b, a)),
            (0, _) => {}
            (count, _) => {
                return Err(ChunkError::Syntax(Syntax::VertexNumbers { found: 3 + count }));
            }
        }
        self.positions.push(p);
        Ok(())
    }

    /// An `f` statement on `line`: its corners, fan-triangulated; polygons that are not
    /// convex are triangulated again once their positions are known (`obj/polygon.rs`).
    fn face(
        &mut self,
        words: &mut Cursor<'_>,
        line: usize,
        face: &mut Face,
    ) -> Result<(), ChunkError> {
        let corners = &mut face.corners;
        corners.clear();
        let mut any_kept = false;
        while words.skip_blanks() {
            if let Some((corner, length)) = simple_corner(&words.text[words.at..]) {
                words.at += length;
                corners.push((corner, [None; 3]));
                continue;
            }
            let Some(word) = words.word() else { break };
            let (corner, kept) = corner(word)?;
            any_kept |= kept != [None; 3];
            corners.push((corner, kept));
        }
        if corners.len() >= 3 {
            self.note_face(line, &mut face.last_line);
        }
        if corners.len() > 3 {
            self.polygons.push((self.triangles.len(), corners.len()));
        }
        for k in 1..corners.len().saturating_sub(1) {
            let triangle = [corners[0], corners[k], corners[k + 1]];
            if any_kept {
                self.keep_indices(&triangle);
            }
            self.triangles.push(triangle.map(|(corner, _)| corner));
        }
        Ok(())
    }
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
            ChunkError::Syntax(Syntax::NotAVertexNumber { found: text(word).into() })
        })?;
        count += 1;
    }
    Ok((count, values))
}

fn numbers<const N: usize>(
    words: &mut Cursor<'_>,
    keyword: &'static str,
    what: &'static str,
) -> Result<[f32; N], ChunkError> {
    let mut out = [0.0; N];
    for (k, slot) in out.iter_mut().enumerate() {
        let value = match words.number() {
            None => {
                return Err(ChunkError::Syntax(Syntax::TooFewNumbers {
                    keyword,
                    needed: N,
                    found: k,
                }));
            }
            Some(Number::Plain(value)) => value,
            Some(Number::Word(word)) => {
                let value: f32 = text(word).parse().map_err(|_| {
                    ChunkError::Syntax(Syntax::NotANumber { keyword, found: text(word).into() })
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

/// The group of an `s` statement from its first word: a number, 0 and `off` for none.
fn smoothing_group(word: Option<&[u8]>) -> Result<u32, ChunkError> {
    let word = text(word.unwrap_or_default());
    match &*word {
        "off" => Ok(0),
        _ => word
            .parse()
            .map_err(|_| ChunkError::Syntax(Syntax::SmoothingGroup { found: word.to_string() })),
    }
}
