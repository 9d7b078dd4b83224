//! The OBJ pass-through writer: an asset loaded from OBJ and saved as OBJ is written as its
//! input file with only what seamlit owns changed.
//!
//! What changes (design: `docs/obj-pass-through.md`):
//!
//! - the input's `vn` lines are left out, and each object's fixed normals are written as
//!   `vn` lines just before its first face: each distinct value once in the file, in vertex
//!   order (an object's normals that an earlier object wrote are not repeated);
//! - each face corner's normal reference points at its corner's fixed normal (`v//vn`,
//!   `v/vt/vn`; a corner written `v` or `v/vt` gets one); its `v` and `vt` references stay as
//!   written, relative ones too, and a face keeps its corners, however seamlit triangulated
//!   it;
//! - faces of fewer than three corners (which give no triangle) lose their normal reference,
//!   since the input's normals are gone.
//!
//! Every other line is copied byte for byte: comments, `o`, `g`, `s`, `usemtl`, `mtllib`,
//! `v` (with its colour), `vt`, `vp`, `l`, `p`, statements seamlit does not know, blanks and
//! line ends. The material libraries that `mtllib` names, and the texture files they name,
//! are copied as written to the same relative places beside the output.

use std::collections::HashMap;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use seamlit_mesh::{Model, Object};

use crate::mtl::MapOptions;
use crate::parse::names;
use crate::source::{ObjSource, Source, SourceObject};
use seamlit_asset::Asset;
use seamlit_asset::error::{InvalidAsset, IoError};
use seamlit_asset::files::{Destination, Files};
use seamlit_asset::paths::NotInside;

/// The UTF-8 byte-order mark, copied through (the parser skips it).
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// The warning for an OBJ output of a model with tangents: OBJ has no statement for them.
pub(crate) fn tangents_not_written(model: &Model, path: &Path) -> Option<String> {
    let with = model.objects.iter().filter(|o| o.tangents.is_some()).count();
    (with > 0).then(|| {
        format!(
            "{}: OBJ has no tangents: the tangents of {with} object(s) are not written (a \
             renderer rebuilds them from the normals and texture coordinates, e.g. with \
             MikkTSpace); write glTF or GLB to keep them",
            path.display()
        )
    })
}

/// Writes `asset` (whose model passes [`ObjSource::check_model`] for `source`) as the input
/// OBJ with its normals replaced, and copies the material libraries and their textures beside it;
/// returns the warnings.
///
/// # Errors
///
/// [`IoError::InvalidAsset`] for an object whose arrays or indices are inconsistent, or where
/// the kept text does not give the loaded faces; [`IoError::LinkEscapes`] for a material
/// library or texture reached through a link that leaves the model's folder; [`IoError::Io`]
/// when reading a side file or writing fails.
pub(crate) fn save(
    asset: &Asset,
    source: &ObjSource,
    path: &Path,
    to: &mut Destination,
) -> Result<Vec<String>, IoError> {
    for object in &asset.model.objects {
        seamlit_asset::check::check_object(object, path)?;
    }
    let text = rewrite(&asset.model, &source.0).map_err(|kind| IoError::InvalidAsset {
        path: path.to_path_buf(),
        object: String::new(),
        kind,
    })?;
    let mut side = SideFiles::new(&source.0.path, path, &source.0.files);
    for (name, line) in &source.0.libraries {
        side.library(name, *line)?;
    }
    side.copy(to)?;
    to.write(path, &text)?;
    Ok(side.warnings)
}

/// Where a face's triangles are: the object and its first triangle there.
#[derive(Clone, Copy)]
struct Run {
    /// First triangle, counted over the file.
    first: usize,
    /// Number of triangles.
    len: usize,
    object: usize,
    /// First triangle in the object.
    local: usize,
}

/// The normals written so far: each distinct value (bits) once, with its OBJ index.
type Written = HashMap<[u32; 3], usize>;

/// The input text with the `vn` lines replaced by the model's and the faces' normal
/// references pointing at them; `Err` says where the text and the model disagree.
fn rewrite(model: &Model, source: &Source) -> Result<Vec<u8>, InvalidAsset> {
    let (bom, body) = match source.text.strip_prefix(UTF8_BOM) {
        Some(body) => (UTF8_BOM, body),
        None => (&[][..], &source.text[..]),
    };
    let mut rewriter = Rewriter::new(model, source);
    rewriter.out.extend_from_slice(bom);
    for (number, line) in body.split_inclusive(|&b| b == b'\n').enumerate() {
        rewriter.line(number + 1, line)?;
    }
    rewriter.finish()
}

/// The state of [`rewrite`] between lines.
struct Rewriter<'a> {
    model: &'a Model,
    source: &'a Source,
    /// The objects' runs of triangles in file order, and the one the next face is in.
    runs: Vec<Run>,
    run: usize,
    /// The next face's first triangle, counted over the file.
    triangle: usize,
    /// Per object, once its first face is reached: the OBJ index of each vertex's normal.
    normal_index: Vec<Option<Vec<usize>>>,
    written: Written,
    /// The current line's words (reused).
    words: Vec<(usize, usize)>,
    out: Vec<u8>,
}

impl<'a> Rewriter<'a> {
    fn new(model: &'a Model, source: &'a Source) -> Self {
        Self {
            model,
            source,
            runs: file_order_runs(&source.objects),
            run: 0,
            triangle: 0,
            normal_index: vec![None; model.objects.len()],
            written: Written::new(),
            words: Vec::new(),
            out: Vec::with_capacity(source.text.len() + source.text.len() / 4),
        }
    }

    /// Leaves out a `vn` line, rewrites an `f` line, copies any other.
    fn line(&mut self, number: usize, line: &[u8]) -> Result<(), InvalidAsset> {
        words(line, &mut self.words);
        match self.words.first().map(|&(start, end)| &line[start..end]) {
            Some(b"vn") => {}
            Some(b"f") if self.words.len() >= 4 => self.face(number, line)?,
            // No triangle: the normal references go, since the input's `vn` lines do.
            Some(b"f") => {
                let references = vec![None; self.words.len() - 1];
                write_face(&mut self.out, line, &self.words[1..], &references);
            }
            _ => self.out.extend_from_slice(line),
        }
        Ok(())
    }

    /// A face of three corners or more: where its triangles are, its object's normals (before
    /// the object's first face), and each corner's normal reference.
    fn face(&mut self, number: usize, line: &[u8]) -> Result<(), InvalidAsset> {
        let corners = self.words.len() - 1;
        let (o, first) = self
            .next_face_triangles(corners - 2)
            .ok_or(InvalidAsset::FaceNotLoaded { line: number })?;
        let object = &self.model.objects[o];
        let normals = match &mut self.normal_index[o] {
            Some(normals) => normals,
            slot => slot.insert(write_normals(&mut self.out, object, &mut self.written, line)),
        };
        let mut references = Vec::with_capacity(corners);
        for c in 0..corners {
            let (t, k) = corner_triangle(object, &self.source.objects[o], first, corners, c)
                .ok_or(InvalidAsset::CornerNotLoaded { line: number, corner: c + 1 })?;
            let vertex = object.triangles[t][k] as usize;
            references.push(object.normals.as_ref().map(|_| normals[vertex]));
        }
        write_face(&mut self.out, line, &self.words[1..], &references);
        Ok(())
    }

    /// The object and first triangle there of the next face, which gives `count` triangles.
    fn next_face_triangles(&mut self, count: usize) -> Option<(usize, usize)> {
        let triangle = self.triangle;
        while self.runs.get(self.run).is_some_and(|r| r.first + r.len <= triangle) {
            self.run += 1;
        }
        let run = self
            .runs
            .get(self.run)
            .filter(|r| r.first <= triangle && triangle + count <= r.first + r.len)?;
        self.triangle += count;
        Some((run.object, run.local + (triangle - run.first)))
    }

    /// The output, once every loaded triangle has had its face.
    fn finish(self) -> Result<Vec<u8>, InvalidAsset> {
        let loaded: usize = self.runs.iter().map(|r| r.len).sum();
        if self.triangle != loaded {
            return Err(InvalidAsset::TriangleCount { faces: self.triangle, loaded });
        }
        Ok(self.out)
    }
}

/// The objects' runs of triangles, in file order.
fn file_order_runs(objects: &[SourceObject]) -> Vec<Run> {
    let mut runs = Vec::new();
    for (object, loaded) in objects.iter().enumerate() {
        let mut local = 0;
        for &(first, len) in &loaded.runs {
            runs.push(Run { first, len, object, local });
            local += len;
        }
    }
    runs.sort_unstable_by_key(|r| r.first);
    runs
}

/// Writes the normals of `object` that no earlier object wrote as `vn` lines (ending as
/// `line` ends), each distinct value once; returns the OBJ index of each vertex's normal
/// (none for an object without normals).
fn write_normals(
    out: &mut Vec<u8>,
    object: &Object,
    written: &mut Written,
    line: &[u8],
) -> Vec<usize> {
    let end: &[u8] = if line.ends_with(b"\r\n") { b"\r\n" } else { b"\n" };
    let Some(normals) = &object.normals else { return Vec::new() };
    normals
        .iter()
        .map(|n| {
            let next = written.len() + 1;
            *written.entry(n.to_array().map(f32::to_bits)).or_insert_with(|| {
                // Writing to a Vec<u8> cannot fail.
                let _ = write!(out, "vn {} {} {}", n.x, n.y, n.z);
                out.extend_from_slice(end);
                next
            })
        })
        .collect()
}

/// Where corner `c` of the face of `n` corners whose triangles start at `first` lies: the
/// first of the face's triangles that holds it, and the corner there. (The triangles of one
/// polygon may give its corner different normals: with `s off` each triangle is flat on its
/// own, a bit apart; a polygon corner has one normal reference, the first triangle's.) A
/// fan holds corner `c >= 2` first in triangle `c - 2`; an ear-clipped polygon's corner is
/// found by its vertex.
fn corner_triangle(
    object: &Object,
    loaded: &SourceObject,
    first: usize,
    n: usize,
    c: usize,
) -> Option<(usize, usize)> {
    if let Ok(i) = loaded.clipped.binary_search_by_key(&first, |(f, _)| *f) {
        let vertex = *loaded.clipped[i].1.get(c)?;
        return (first..first + n - 2).find_map(|t| {
            let triangle = object.triangles.get(t)?;
            (0..3).find(|&k| object.source_vertex(triangle[k]) == vertex).map(|k| (t, k))
        });
    }
    // The fan's triangle `k` is corners `(0, k + 1, k + 2)`.
    let place = match c {
        0 | 1 => (first, c),
        c => (first + c - 2, 2),
    };
    (place.0 < object.triangles.len()).then_some(place)
}

/// Writes a face line as written, with each corner's normal reference replaced by
/// `references[c]` (an OBJ index; `None`: no normal reference).
fn write_face(
    out: &mut Vec<u8>,
    line: &[u8],
    corners: &[(usize, usize)],
    references: &[Option<usize>],
) {
    let mut at = 0;
    for (&(start, end), reference) in corners.iter().zip(references) {
        out.extend_from_slice(&line[at..start]);
        let mut fields = line[start..end].splitn(3, |&b| b == b'/');
        let v = fields.next().unwrap_or_default();
        let vt = fields.next().unwrap_or_default();
        out.extend_from_slice(v);
        if !vt.is_empty() {
            out.push(b'/');
            out.extend_from_slice(vt);
        }
        if let Some(reference) = reference {
            out.extend_from_slice(if vt.is_empty() { b"//" } else { b"/" });
            let _ = write!(out, "{reference}");
        }
        at = end;
    }
    out.extend_from_slice(&line[at..]);
}

/// The words of a line (start and end) into `words`, split at blanks as the parser splits
/// them.
fn words(line: &[u8], words: &mut Vec<(usize, usize)>) {
    let blank = |b: u8| matches!(b, b' ' | b'\t' | b'\r' | 0x0c | b'\n');
    words.clear();
    let mut at = 0;
    while at < line.len() {
        while at < line.len() && blank(line[at]) {
            at += 1;
        }
        let start = at;
        while at < line.len() && !blank(line[at]) {
            at += 1;
        }
        if at > start {
            words.push((start, at));
        }
    }
}

/// The material libraries and textures to copy beside the output, and what is missing.
struct SideFiles<'a> {
    /// The input OBJ: paths resolve against its folder.
    input: &'a Path,
    /// The output OBJ: copies go to the same relative paths beside it.
    output: &'a Path,
    /// Where the input's files are read from.
    files: &'a Files,
    /// (real source file, destination), each destination once.
    copies: Vec<(PathBuf, PathBuf)>,
    warnings: Vec<String>,
}

impl<'a> SideFiles<'a> {
    fn new(input: &'a Path, output: &'a Path, files: &'a Files) -> Self {
        Self { input, output, files, copies: Vec::new(), warnings: Vec::new() }
    }

    /// Plans the copy of the material library `name` (an `mtllib` on `line`) and of the
    /// texture files it names. A missing library is a warning.
    fn library(&mut self, name: &str, line: usize) -> Result<(), IoError> {
        let what = format!("material library {name:?} (line {line})");
        let Some(parts) = seamlit_asset::paths::inside(&[], name) else {
            self.warnings.push(format!(
                "{}: {what} leaves the model's folder; not copied",
                self.input.display()
            ));
            return Ok(());
        };
        let Some(real) = self.plan(&parts, &what)? else { return Ok(()) };
        let bytes = self.files.read(&real).map_err(|e| IoError::io(&real, e))?;
        let sub = &parts[..parts.len() - 1];
        // Names read as the reader read them (`parse/names.rs`); the file is copied as it is.
        let (text, _) = names::decode_lines(&bytes);
        for (number, statement) in text.lines().enumerate() {
            let Some(file) = texture_file(statement) else { continue };
            let what = format!("texture {file:?} ({name}:{})", number + 1);
            match seamlit_asset::paths::inside(sub, &file) {
                Some(parts) => {
                    self.plan(&parts, &what)?;
                }
                None => self.warnings.push(format!(
                    "{}: {what} leaves the model's folder; not copied",
                    self.input.display()
                )),
            }
        }
        Ok(())
    }

    /// Plans the copy of the file at `parts` below the input's folder to the same place below
    /// the output's; returns its real path, or `None` (and a warning) when it is missing.
    fn plan(&mut self, parts: &[String], what: &str) -> Result<Option<PathBuf>, IoError> {
        let folder = self.input.parent().unwrap_or(Path::new(""));
        // A name decoded from Windows-1252 may be on disk under its bytes as written.
        let file = names::on_disk(folder, parts);
        let real = match self.files.real_inside(folder, &file) {
            Ok(real) => real,
            Err(NotInside::Outside(target)) => {
                return Err(IoError::LinkEscapes {
                    path: self.input.to_path_buf(),
                    what: what.to_owned(),
                    reference: parts.join("/"),
                    target,
                });
            }
            Err(NotInside::Io(_)) => {
                self.warnings.push(format!(
                    "{}: {what} is missing; the output names it still",
                    self.input.display()
                ));
                return Ok(None);
            }
        };
        let out_folder = self.output.parent().unwrap_or(Path::new(""));
        let destination = match file.strip_prefix(folder) {
            Ok(below) => out_folder.join(below),
            Err(_) => parts.iter().fold(out_folder.to_path_buf(), |p, s| p.join(s)),
        };
        if !self.files.same_file(&real, &destination)
            && !self.copies.iter().any(|(_, to)| to == &destination)
        {
            self.copies.push((real.clone(), destination));
        }
        Ok(Some(real))
    }

    /// Copies the planned files to `to` (files: each to a temporary name renamed into place).
    fn copy(&self, to: &mut Destination) -> Result<(), IoError> {
        for (from, destination) in &self.copies {
            if let Some(parent) = destination.parent().filter(|p| !p.as_os_str().is_empty()) {
                to.create_folder(parent)?;
            }
            let files = self.files;
            to.write_with(destination, |out| match files {
                Files::Disk => std::io::copy(&mut std::fs::File::open(from)?, out).map(|_| ()),
                Files::Memory(_) => out.write_all(&files.read(from)?),
            })?;
        }
        Ok(())
    }
}

/// The file an MTL texture statement names (`map_Kd -o 0.5 0.5 file.png`: `file.png`):
/// statements `map_*`, `bump`, `disp`, `decal`, `refl` and `norm`.
fn texture_file(statement: &str) -> Option<String> {
    let statement = statement.trim();
    let (keyword, rest) = statement.split_once(char::is_whitespace)?;
    let keyword = keyword.to_ascii_lowercase();
    let is_texture = keyword.starts_with("map_")
        || ["bump", "disp", "decal", "refl", "norm"].contains(&keyword.as_str());
    let file = MapOptions::parse(rest).file;
    (is_texture && !file.is_empty()).then_some(file)
}

#[cfg(test)]
mod tests {
    use super::{texture_file, words, write_face};

    #[test]
    fn texture_statements_name_their_file_after_the_options() {
        assert_eq!(texture_file("map_Kd -o 0.5 0.5 tex/a b.png").as_deref(), Some("tex/a b.png"));
        assert_eq!(texture_file("  bump -bm 0.5 n.png\r").as_deref(), Some("n.png"));
        assert_eq!(texture_file("norm n.png").as_deref(), Some("n.png"));
        assert_eq!(texture_file("Kd 1 1 1"), None);
        assert_eq!(texture_file("map_Kd"), None);
    }

    #[test]
    fn a_face_keeps_its_blanks_and_indices_and_gets_normal_references() {
        let line = b"f  1/2/9\t-3//8 4/5 6\r\n";
        let mut w = Vec::new();
        words(line, &mut w);
        let mut out = Vec::new();
        write_face(&mut out, line, &w[1..], &[Some(10), Some(11), Some(12), Some(13)]);
        assert_eq!(out, b"f  1/2/10\t-3//11 4/5/12 6//13\r\n");
        out.clear();
        write_face(&mut out, line, &w[1..], &[None; 4]);
        assert_eq!(out, b"f  1/2\t-3 4/5 6\r\n");
    }
}
