//! Wavefront OBJ (+ MTL) in: the file opened (UTF-8, or UTF-16 decoded), its geometry parsed
//! (`parse.rs`), its material libraries read (`mtl.rs`), its objects built.
//!
//! Every `o` and `g` statement starts an object, keeping its name (as in tobj, `usemtl`
//! changing the material inside an object also starts one: both parts keep the name). Faces are
//! triangulated as fans where they are convex, ear-clipped where not; `vt`, `vn` and vertex
//! colours (`v x y z r g b [a]`) are kept where every face of the object has them. A
//! `usemtl` that names no material of the file's libraries gets a warning, and a material
//! that `newmtl` leaves unnamed (Blender 2.61 writes one) has the empty name. A file with a
//! UTF-16 byte-order mark is decoded; a name (`o`, `g`, `usemtl`, `mtllib`) that is not UTF-8
//! is read as Windows-1252 with one warning (`parse/names.rs`); a NUL byte or invalid UTF-8
//! in any other statement is an error.
//! Material libraries are read with tobj and converted here, including the `-bm` (bump
//! multiplier), `-o` and `-s` options that tobj leaves in the texture name, and the `norm`
//! statement it does not know; a material statement seamlit cannot use is a warning, never
//! an error (`mtl/usable.rs`). Texture paths resolve against the `.mtl` file's folder.
//!
//! The geometry is read by this crate's parallel parser (`parse.rs` explains why and how it
//! matches tobj); material libraries by tobj. `mtllib` and texture paths that leave the
//! model's folder are refused. A face index out of range is named with its line by the
//! parser.
//!
//! The loaded asset keeps the file's text and where each object's faces are in it
//! ([`crate::ObjSource`]), for the OBJ pass-through writer (`passthrough.rs`).

use std::collections::HashMap;
use std::path::Path;

use seamlit_mesh::{Model, Object, VAxis};

use super::mtl::{convert_materials, read_libraries, warn_unknown_materials};
use crate::source::{ObjSource, SourceObject};
use seamlit_asset::Asset;
use seamlit_asset::LoadOptions;
use seamlit_asset::error::IoError;

/// Reads an OBJ file and the material libraries and textures it refers to, from
/// [`LoadOptions::files`] (a file in memory is parsed as [`parse`] does). A file without a face
/// loads as an empty model here; `seamlit_io::load` refuses it.
///
/// # Errors
///
/// [`IoError::Io`] / [`IoError::TooLarge`] for the file itself; [`IoError::Syntax`],
/// [`IoError::ReferenceOutOfRange`] and [`IoError::NotFinite`] with the line for a malformed
/// OBJ or MTL; [`IoError::NotText`] with the line for a NUL byte or invalid UTF-8 (or
/// UTF-16) in a statement; [`IoError::MissingFile`] for a missing `.mtl` or texture when
/// `options.strict` is set (a warning otherwise); [`IoError::TooManyElements`] past
/// `options.max_elements`.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    if let seamlit_asset::files::Files::Memory(_) = options.files {
        // Held in memory: the whole file is there already.
        let bytes = seamlit_asset::files::read_bytes(path, options)?;
        return parse(&bytes, path, options);
    }
    let (file, decoded) = open(path, options)?;
    let parsed = match &decoded {
        Some(text) => crate::parse::read(text.as_bytes(), path),
        None => crate::parse::read(file, path),
    }?;
    // The text as parsed, for the pass-through writer (`passthrough.rs`).
    let text = match decoded {
        Some(text) => text.into_bytes(),
        None => seamlit_asset::files::read_bytes(path, options)?,
    };
    finish(path, parsed, text, options)
}

/// Parses OBJ `bytes` (a file held in memory: the web page's); `path` names the file in
/// errors and its folder resolves the material libraries it names, which are read from there
/// where there is one (in a browser there is none: each is a warning, as a missing library
/// is).
///
/// # Errors
///
/// As [`load`], but for reading the file itself.
pub fn parse(bytes: &[u8], path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    if bytes.len() as u64 > options.max_file_bytes {
        return Err(IoError::TooLarge {
            path: path.to_path_buf(),
            limit: options.max_file_bytes,
            actual: bytes.len() as u64,
        });
    }
    let text = match bytes.get(..2) {
        Some([0xFF, 0xFE]) => decode_utf16(bytes, u16::from_le_bytes, path)?.into_bytes(),
        Some([0xFE, 0xFF]) => decode_utf16(bytes, u16::from_be_bytes, path)?.into_bytes(),
        _ => bytes.to_vec(),
    };
    let parsed = crate::parse::read_slice(&text, path)?;
    finish(path, parsed, text, options)
}

/// The asset of a parsed file whose `text` (UTF-8) is kept for the pass-through writer: its
/// material libraries read, its objects built, its materials converted, its textures decoded.
fn finish(
    path: &Path,
    parsed: crate::parse::Parsed,
    text: Vec<u8>,
    options: &LoadOptions,
) -> Result<Asset, IoError> {
    let mut warnings = Vec::new();
    if let Some(line) = parsed.legacy_names {
        warnings.push(crate::parse::names::legacy_warning(path, line));
    }
    let libraries = read_libraries(path, &parsed.libraries, options, &mut warnings)?;
    if !libraries.missing {
        warn_unknown_materials(path, &parsed.materials_used, &libraries.by_name, &mut warnings);
    }
    let library_lines = parsed.libraries.clone();
    let (objects, sources) = build_objects(path, parsed, &libraries.by_name, options)?;
    let mut asset = Asset { model: Model { objects, v_axis: VAxis::Up }, ..Asset::default() };
    warnings.extend(objects_warnings(path, &sources));
    convert_materials(path, &libraries.materials, &mut asset)?;
    asset.source = Some(path.to_path_buf());
    let sources = sources.into_iter().map(|origin| origin.source).collect();
    let source = ObjSource::new(text, path, library_lines, sources, options.files.clone());
    asset.document = Some(seamlit_asset::SourceDocument::new(source));
    warnings.extend(seamlit_asset::texture::decode_all(&mut asset.textures, path, options)?);
    asset.warnings = warnings;
    Ok(asset)
}

/// Opens the file within `options.max_file_bytes`; a file with a UTF-16 byte-order mark is
/// decoded whole (it is at most that size), any other is left to be read as UTF-8, in blocks.
///
/// # Errors
///
/// [`IoError::Io`], [`IoError::TooLarge`], and [`IoError::NotText`] for invalid UTF-16.
fn open(path: &Path, options: &LoadOptions) -> Result<(std::fs::File, Option<String>), IoError> {
    let file = std::fs::File::open(path).map_err(|e| IoError::io(path, e))?;
    let size = file.metadata().map_err(|e| IoError::io(path, e))?.len();
    if size > options.max_file_bytes {
        return Err(IoError::TooLarge {
            path: path.to_path_buf(),
            limit: options.max_file_bytes,
            actual: size,
        });
    }
    let decoded = match utf16_order(&file).map_err(|e| IoError::io(path, e))? {
        Some(order) => {
            Some(decode_utf16(&seamlit_asset::files::read_bytes(path, options)?, order, path)?)
        }
        None => None,
    };
    Ok((file, decoded))
}

/// Where an object came from in the file (for the pass-through writer), its name, and which
/// attributes it dropped because only some of its faces had them: texture coordinates,
/// normals, vertex colours.
struct Origin {
    source: SourceObject,
    name: String,
    mixed: [bool; 3],
}

/// The parsed objects as the model's, with where each came from in the file (for the
/// pass-through writer) and what it dropped.
///
/// # Errors
///
/// [`IoError::TooManyElements`] for an object past `options.max_elements`.
fn build_objects(
    path: &Path,
    parsed: crate::parse::Parsed,
    by_name: &HashMap<String, usize>,
    options: &LoadOptions,
) -> Result<(Vec<Object>, Vec<Origin>), IoError> {
    // Each corner may become a vertex, numbered with 32 bits below u32::MAX (`parse/dedup.rs`).
    let corners = parsed.corner_count();
    if corners >= u32::MAX as usize {
        return Err(IoError::TooManyElements {
            path: path.to_path_buf(),
            what: "the file's triangle corners".to_owned(),
            limit: u32::MAX as usize - 1,
            actual: corners,
        });
    }
    let mut objects = Vec::new();
    let mut sources = Vec::new();
    for parsed in parsed.into_objects(|name| by_name.get(name).copied()) {
        let too_many = parsed.positions.len().max(parsed.triangles.len());
        if too_many > options.max_elements {
            return Err(IoError::TooManyElements {
                path: path.to_path_buf(),
                what: format!("object {:?}", parsed.name),
                limit: options.max_elements,
                actual: too_many,
            });
        }
        let mixed = [parsed.mixed_uvs, parsed.mixed_normals, parsed.mixed_colors];
        sources.push(Origin {
            source: SourceObject {
                vertices: parsed.positions.len(),
                fingerprint: crate::source::fingerprint(parsed.triangles.iter().copied()),
                runs: parsed.runs,
                clipped: parsed.clipped,
            },
            name: parsed.name.clone(),
            mixed,
        });
        objects.push(Object {
            name: parsed.name,
            positions: parsed.positions,
            uvs: parsed.uvs,
            normals: parsed.normals,
            colors: parsed.colors,
            tangents: None,
            triangles: parsed.triangles,
            transform: None,
            material: parsed.material,
            smoothing_groups: parsed.smoothing_groups,
            ..Object::default()
        });
    }
    Ok((objects, sources))
}

/// A warning for each attribute an object dropped (see [`Origin`]).
fn objects_warnings(path: &Path, sources: &[Origin]) -> Vec<String> {
    let mut warnings = Vec::new();
    for Origin { name, mixed, .. } in sources {
        for (what, _) in ["texture coordinates", "normals", "vertex colours"]
            .iter()
            .zip(mixed)
            .filter(|(_, mixed)| **mixed)
        {
            warnings.push(format!(
                "{}: object {name:?}: some faces have {what} and some do not; {what} dropped",
                path.display()
            ));
        }
    }
    warnings
}

/// How two bytes of UTF-16 make a code unit: `u16::from_le_bytes` or `u16::from_be_bytes`.
type ByteOrder = fn([u8; 2]) -> u16;

/// The byte order of a file that starts with a UTF-16 byte-order mark (`FF FE`: little
/// endian, `FE FF`: big endian), read through the handle, which is then rewound.
fn utf16_order(file: &std::fs::File) -> std::io::Result<Option<ByteOrder>> {
    use std::io::Read as _;
    let mut head = [0u8; 2];
    let mut reader = file;
    let got = reader.read(&mut head)?;
    std::io::Seek::rewind(&mut reader)?;
    Ok(match (got, head) {
        (2, [0xFF, 0xFE]) => Some(u16::from_le_bytes),
        (2, [0xFE, 0xFF]) => Some(u16::from_be_bytes),
        _ => None,
    })
}

/// UTF-16 `bytes` (their byte-order mark first) as text.
///
/// # Errors
///
/// [`IoError::NotText`] on the line of an unpaired surrogate or of a lone final byte.
fn decode_utf16(bytes: &[u8], order: ByteOrder, path: &Path) -> Result<String, IoError> {
    let units =
        bytes.get(2..).unwrap_or_default().as_chunks::<2>().0.iter().map(|&pair| order(pair));
    let mut text = String::with_capacity(bytes.len() / 2);
    let mut line = 1;
    for unit in char::decode_utf16(units) {
        match unit {
            Ok(c) => {
                line += usize::from(c == '\n');
                text.push(c);
            }
            Err(_) => {
                return Err(IoError::NotText {
                    path: path.to_path_buf(),
                    line,
                    problem: seamlit_asset::NotText::InvalidUtf16,
                });
            }
        }
    }
    if bytes.len() % 2 == 1 {
        return Err(IoError::NotText {
            path: path.to_path_buf(),
            line,
            problem: seamlit_asset::NotText::InvalidUtf16,
        });
    }
    Ok(text)
}
