//! Newell's Bezier patch files (the Utah teapot, teacup and teaspoon).
//!
//! The text holds the patch count, one line of 16 one-based control-point indices per patch
//! (a 4 x 4 grid, row by row), the point count, and one `x,y,z` line per point. Commas and
//! blanks both separate numbers. Each bicubic patch is tessellated into its own object of
//! N x N quads (2 N^2 triangles, (N+1)^2 vertices) with UVs = the patch parameters (u along a
//! row of the grid, v across the rows), as in the paper's teapot (Mileff 2024, section 6).
//!
//! Points are evaluated with de Casteljau's algorithm, whose linear interpolations return
//! their end points exactly: patch corners are bit-identical to the control points, and the
//! collapsed edge of a pole patch is a single position, not a cloud of near misses.

use std::path::Path;

use glam::{Vec2, Vec3};
use seamlit_mesh::{Model, Object, VAxis};

use crate::{Asset, IoError, LoadOptions, Syntax};

/// The largest tessellation accepted; larger values are clamped.
pub const MAX_TESSELLATION: u32 = 1024;

/// A parsed patch file: control points and, per patch, 16 zero-based indices.
#[derive(Clone, Debug, PartialEq)]
pub struct Patches {
    /// Control points.
    pub points: Vec<Vec3>,
    /// Per patch, the 4 x 4 control-point grid (row-major) as indices into `points`.
    pub patches: Vec<[u32; 16]>,
}

/// Reads and tessellates a Newell patch file.
///
/// # Errors
///
/// [`IoError::Io`] if the file cannot be read, [`IoError::TooLarge`] past
/// `options.max_file_bytes`, and the errors of [`parse`].
pub fn load(path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    let text = seamlit_asset::files::read_text(path, options)?;
    let name =
        path.file_stem().map_or_else(|| "patches".to_owned(), |s| s.to_string_lossy().into_owned());
    let mut asset =
        parse_named(&text, &name, path, options.tessellation, options.max_model_triangles)?;
    asset.source = Some(path.to_path_buf());
    Ok(asset)
}

/// Parses and tessellates the text of a Newell patch file; `name` prefixes the object names
/// (`{name}_patch00`, ...) and stands for the file in error messages.
///
/// # Errors
///
/// [`IoError::Syntax`] for a malformed line, [`IoError::BadCount`] for a count the text cannot
/// hold, [`IoError::ReferenceOutOfRange`] for a control-point index outside `1..=count`,
/// [`IoError::NotFinite`] for a NaN or infinite coordinate.
pub fn parse(text: &str, name: &str, tessellation: u32) -> Result<Asset, IoError> {
    parse_named(text, name, Path::new(name), tessellation, usize::MAX)
}

fn parse_named(
    text: &str,
    name: &str,
    path: &Path,
    tessellation: u32,
    max_triangles: usize,
) -> Result<Asset, IoError> {
    let patches = parse_patches(text, path)?;
    let n = tessellation.clamp(1, MAX_TESSELLATION);
    // A 32-byte patch line becomes 2 n^2 triangles: checked before tessellating.
    let triangles = patches.patches.len().saturating_mul(2 * (n as usize).pow(2));
    if triangles > max_triangles {
        return Err(IoError::TooManyElements {
            path: path.to_path_buf(),
            what: format!("{} patches at tessellation {n}", patches.patches.len()),
            limit: max_triangles,
            actual: triangles,
        });
    }
    let objects = patches
        .patches
        .iter()
        .enumerate()
        .map(|(i, patch)| {
            let grid: [Vec3; 16] = std::array::from_fn(|k| patches.points[patch[k] as usize]);
            tessellate(&grid, n, format!("{name}_patch{i:02}"))
        })
        .collect();
    Ok(Asset { model: Model { objects, v_axis: VAxis::Up }, ..Asset::default() })
}

/// Parses the text of a patch file without tessellating it.
///
/// # Errors
///
/// As [`parse`].
pub fn parse_patches(text: &str, path: &Path) -> Result<Patches, IoError> {
    let mut lines =
        text.lines().enumerate().map(|(i, l)| (i + 1, l)).filter(|(_, l)| !l.trim().is_empty());
    let total_lines = text.lines().filter(|l| !l.trim().is_empty()).count();
    let (count_line, patch_count) = read_count(&mut lines, path, "patch", 0)?;
    // Each patch needs a line, and the point count line must follow.
    let remaining = total_lines.saturating_sub(1);
    if patch_count >= remaining {
        return Err(bad_count(path, count_line, "patches", patch_count, remaining));
    }
    let mut raw = Vec::with_capacity(patch_count);
    let mut last_line = count_line;
    for _ in 0..patch_count {
        let (line, text) = lines
            .next()
            .ok_or_else(|| syntax(path, last_line + 1, Syntax::UnexpectedEnd { list: "patch" }))?;
        last_line = line;
        raw.push((line, read_patch(path, line, text)?));
    }
    let (point_line, point_count) = read_count(&mut lines, path, "point", last_line)?;
    let remaining = total_lines.saturating_sub(patch_count + 2);
    if point_count > remaining {
        return Err(bad_count(path, point_line, "points", point_count, remaining));
    }
    let mut points = Vec::with_capacity(point_count);
    for _ in 0..point_count {
        let (line, text) = lines
            .next()
            .ok_or_else(|| syntax(path, point_line, Syntax::UnexpectedEnd { list: "point" }))?;
        points.push(read_point(path, line, text)?);
    }
    if let Some((line, text)) = lines.next() {
        let kind = Syntax::TrailingText { points: point_count, text: text.to_owned() };
        return Err(syntax(path, line, kind));
    }
    let patches = raw
        .into_iter()
        .map(|(line, indices)| zero_based(path, line, indices, point_count))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Patches { points, patches })
}

/// An [`IoError::Syntax`] on `line` of `path`.
fn syntax(path: &Path, line: usize, kind: Syntax) -> IoError {
    IoError::Syntax { path: path.to_path_buf(), line, kind }
}

/// An [`IoError::BadCount`]: `declared` `what` on `line`, with only `remaining` lines after.
fn bad_count(
    path: &Path,
    line: usize,
    what: &'static str,
    declared: usize,
    remaining: usize,
) -> IoError {
    let declared = declared as u64;
    IoError::BadCount { path: path.to_path_buf(), line, what, declared, remaining }
}

/// A patch line: 16 one-based control-point indices, at least 1.
///
/// # Errors
///
/// [`IoError::Syntax`] for a count other than 16 or a word that is not an index,
/// [`IoError::ReferenceOutOfRange`] for an index below 1.
fn read_patch(path: &Path, line: usize, text: &str) -> Result<[u32; 16], IoError> {
    const WHAT: &str = "control-point indices";
    let mut indices = [0u32; 16];
    let mut k = 0;
    for token in tokens(text) {
        if k == 16 {
            let kind = Syntax::TooManyValues { expected: 16, what: WHAT, text: text.to_owned() };
            return Err(syntax(path, line, kind));
        }
        let value: i64 = token.parse().map_err(|_| {
            let found = token.to_owned();
            syntax(path, line, Syntax::NotAValue { expected: "a control-point index", found })
        })?;
        indices[k] =
            u32::try_from(value).ok().filter(|&v| v >= 1).ok_or(IoError::ReferenceOutOfRange {
                path: path.to_path_buf(),
                line,
                what: "control point",
                index: value,
                count: 0,
            })?;
        k += 1;
    }
    if k != 16 {
        let kind = Syntax::TooFewValues { expected: 16, what: WHAT, found: k };
        return Err(syntax(path, line, kind));
    }
    Ok(indices)
}

/// A point line: three finite coordinates.
///
/// # Errors
///
/// [`IoError::Syntax`] for a count other than 3 or a word that is not a number,
/// [`IoError::NotFinite`] for NaN or an infinity.
fn read_point(path: &Path, line: usize, text: &str) -> Result<Vec3, IoError> {
    let mut xyz = [0.0f32; 3];
    let mut k = 0;
    for token in tokens(text) {
        if k == 3 {
            let text = text.to_owned();
            let kind = Syntax::TooManyValues { expected: 3, what: "coordinates", text };
            return Err(syntax(path, line, kind));
        }
        let value: f32 = token.parse().map_err(|_| {
            let found = token.to_owned();
            syntax(path, line, Syntax::NotAValue { expected: "a number", found })
        })?;
        if !value.is_finite() {
            return Err(IoError::NotFinite {
                path: path.to_path_buf(),
                line,
                what: "control point coordinate",
                text: token.to_owned(),
            });
        }
        xyz[k] = value;
        k += 1;
    }
    if k != 3 {
        let kind = Syntax::TooFewValues { expected: 3, what: "coordinates", found: k };
        return Err(syntax(path, line, kind));
    }
    Ok(Vec3::from_array(xyz))
}

/// A patch's one-based indices (from `line`) as zero-based ones into `point_count` points.
///
/// # Errors
///
/// [`IoError::ReferenceOutOfRange`] for an index past the points.
fn zero_based(
    path: &Path,
    line: usize,
    indices: [u32; 16],
    point_count: usize,
) -> Result<[u32; 16], IoError> {
    let mut zero_based = [0u32; 16];
    for (dst, &one_based) in zero_based.iter_mut().zip(&indices) {
        if one_based as usize > point_count {
            return Err(IoError::ReferenceOutOfRange {
                path: path.to_path_buf(),
                line,
                what: "control point",
                index: i64::from(one_based),
                count: point_count,
            });
        }
        *dst = one_based - 1;
    }
    Ok(zero_based)
}

/// Reads a count line: `(line number, value)`.
fn read_count<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    path: &Path,
    what: &'static str,
    previous_line: usize,
) -> Result<(usize, usize), IoError> {
    let (line, text) = lines
        .next()
        .ok_or_else(|| syntax(path, previous_line + 1, Syntax::MissingCount { what }))?;
    let declared: u64 = text.trim().parse().map_err(|_| {
        syntax(path, line, Syntax::NotACount { what, found: text.trim().to_owned() })
    })?;
    Ok((line, usize::try_from(declared).unwrap_or(usize::MAX)))
}

fn tokens(line: &str) -> impl Iterator<Item = &str> {
    line.split(|c: char| c == ',' || c.is_whitespace()).filter(|t| !t.is_empty())
}

/// `a + (b - a) t`, returning `b` exactly at `t = 1` and `a` exactly when `a == b`.
fn lerp(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    if t == 1.0 { b } else { a + (b - a) * t }
}

/// A point of the cubic Bezier curve over four control points (de Casteljau).
fn de_casteljau(p: [Vec3; 4], t: f32) -> Vec3 {
    let a = [lerp(p[0], p[1], t), lerp(p[1], p[2], t), lerp(p[2], p[3], t)];
    let b = [lerp(a[0], a[1], t), lerp(a[1], a[2], t)];
    lerp(b[0], b[1], t)
}

/// A point of the bicubic patch: `u` along each row of the grid, `v` across the rows.
#[must_use]
pub fn evaluate(grid: &[Vec3; 16], u: f32, v: f32) -> Vec3 {
    let rows: [Vec3; 4] = std::array::from_fn(|r| {
        de_casteljau([grid[4 * r], grid[4 * r + 1], grid[4 * r + 2], grid[4 * r + 3]], u)
    });
    de_casteljau(rows, v)
}

/// Tessellates one patch into an object of `n` x `n` quads, two triangles each, with UVs
/// `(u, v)`; front faces are counter-clockwise seen from the side `dP/du x dP/dv` points to,
/// which is the outside of Newell's teapot.
#[must_use]
pub fn tessellate(grid: &[Vec3; 16], n: u32, name: String) -> Object {
    let n = n.clamp(1, MAX_TESSELLATION);
    let side = n + 1;
    let param = |k: u32| if k == n { 1.0 } else { k as f32 / n as f32 };
    let mut positions = Vec::with_capacity((side * side) as usize);
    let mut uvs = Vec::with_capacity((side * side) as usize);
    for j in 0..side {
        for i in 0..side {
            let (u, v) = (param(i), param(j));
            positions.push(evaluate(grid, u, v));
            uvs.push(Vec2::new(u, v));
        }
    }
    let mut triangles = Vec::with_capacity((2 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let a = j * side + i;
            let (b, c, d) = (a + 1, a + side + 1, a + side);
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    Object::new(name, positions, triangles).with_uvs(uvs)
}
