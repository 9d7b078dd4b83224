//! A `Mesh` prim to an object: its points, its polygons triangulated (a fan where convex, ear
//! clipping on the best-fit plane where not: `obj/polygon.rs`), and its primvars expanded by
//! their interpolation (constant, uniform, vertex, varying, faceVarying; indexed or not), with
//! a vertex per distinct combination of a corner's point and its normal and UV values. What
//! the `.usda` writer needs to put normals back on the prim's face corners is kept beside it
//! ([`MeshSource`]).
//!
//! The rules of UsdGeomMesh that decide the normals: `primvars:normals` wins over `normals`
//! (whose interpolation defaults to vertex); a mesh whose `subdivisionScheme` is not `none`
//! (unauthored, it is `catmullClark`) is a subdivision surface, whose authored normals
//! renderers ignore, so it is read without them; `orientation = "leftHanded"` and a mirroring
//! world matrix each flip the winding (seamlit's triangles face counter-clockwise in model
//! space).

use std::collections::HashMap;
use std::path::Path;

use anyhow::{Context, bail};
use glam::{DMat4, Mat4, Vec2, Vec3};
use openusd::{sdf, usd};
use seamlit_mesh::Object;

use super::{f32_of, value};
use crate::error::IoError;
use crate::options::LoadOptions;
use crate::usd::error::UsdKind;

/// No vertex: a corner of a face of fewer than three corners.
const NONE: u32 = u32::MAX;

/// What the writer needs of a mesh besides its object: how the object's triangles map onto
/// the prim's face corners, and the normals as read.
#[derive(Clone, Debug)]
pub(crate) struct MeshSource {
    /// The prim's path in the composed stage.
    pub prim: String,
    /// Per triangle of the object (as loaded), per corner: the face corner (an index into
    /// `faceVertexIndices`) it is.
    pub triangle_corners: Vec<[u32; 3]>,
    /// Per face corner: the object's vertex, [`u32::MAX`] for a corner of a face of fewer than
    /// three corners (which gives no triangle).
    pub corner_vertex: Vec<u32>,
    /// Per face corner: the normal as read (local space), `None` where the mesh has none or
    /// they are ignored (a subdivision surface).
    pub corner_normals: Option<Vec<Vec3>>,
    /// The subdivision scheme, where it is not `none`.
    pub subdivision: Option<String>,
    /// Whether a plain `normals` attribute has a value (the writer blocks it).
    pub plain_normals: bool,
    /// Whether the prim is an instance proxy (its normals cannot be overridden).
    pub instance_proxy: bool,
}

/// How a primvar's values map onto a mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Interpolation {
    Constant,
    Uniform,
    Vertex,
    FaceVarying,
}

/// A primvar: its values and, per element of its interpolation, the value's index.
struct Primvar<T> {
    values: Vec<T>,
    indices: Option<Vec<i32>>,
    interpolation: Interpolation,
}

impl<T> Primvar<T> {
    /// The value index of face corner `corner` of face `face`, on point `point`.
    fn index(&self, face: usize, corner: usize, point: usize) -> u32 {
        let element = match self.interpolation {
            Interpolation::Constant => 0,
            Interpolation::Uniform => face,
            Interpolation::Vertex => point,
            Interpolation::FaceVarying => corner,
        };
        let i = match &self.indices {
            Some(indices) => indices[element] as usize,
            None => element,
        };
        #[expect(clippy::cast_possible_truncation, reason = "checked below u32::MAX")]
        let i = i as u32;
        i
    }

    /// Why the primvar does not fit a mesh of `faces` faces, `corners` face corners and
    /// `points` points, if it does not.
    fn misfit(&self, faces: usize, corners: usize, points: usize) -> Option<String> {
        let elements = match self.interpolation {
            Interpolation::Constant => 1,
            Interpolation::Uniform => faces,
            Interpolation::Vertex => points,
            Interpolation::FaceVarying => corners,
        };
        let (count, what) = match &self.indices {
            Some(indices) => (indices.len(), "indices"),
            None => (self.values.len(), "values"),
        };
        let too_few = if self.interpolation == Interpolation::Constant {
            count < 1
        } else {
            count != elements
        };
        if too_few {
            return Some(format!(
                "{count} {what} for {elements} elements of {:?} interpolation",
                self.interpolation
            ));
        }
        if self.values.len() >= u32::MAX as usize {
            return Some(format!("{} values", self.values.len()));
        }
        if let Some(indices) = &self.indices
            && let Some(bad) = indices.iter().find(|&&i| i < 0 || i as usize >= self.values.len())
        {
            return Some(format!("index {bad} for {} values", self.values.len()));
        }
        None
    }
}

/// A mesh read: its object (in local space, `transform` its model matrix) and its source.
pub(super) struct Read {
    pub object: Object,
    pub source: MeshSource,
}

/// Reads the `Mesh` prim at `path` with world matrix `world` under the up-axis rotation
/// `up`.
///
/// # Errors
///
/// [`IoError::Usd`] with [`UsdKind::Prim`] for values that cannot be read or do not fit
/// the mesh; [`IoError::TooManyElements`] past `options.max_elements`.
pub(super) fn read(
    prim: &usd::Prim,
    world: DMat4,
    up: DMat4,
    file: &Path,
    options: &LoadOptions,
    warnings: &mut Vec<String>,
) -> Result<Read, IoError> {
    let path = prim.path().clone();
    let bad = |message: String| IoError::Usd {
        path: file.to_path_buf(),
        kind: UsdKind::Prim { prim: path.as_str().to_owned(), message },
    };
    let openusd = |e: anyhow::Error| bad(format!("{e:#}"));
    let points = vec3s(&prim.attribute("points")).context("points").map_err(openusd)?;
    let points = points.unwrap_or_default();
    let samples = prim.attribute("points").time_samples().map_err(openusd)?;
    if samples.is_some_and(|s| !s.is_empty()) {
        warnings.push(format!(
            "{}: mesh <{}>: its points are time-sampled; read at their default, else their earliest sample, and the normals fixed (and written) for that shape only",
            file.display(),
            path.as_str()
        ));
    }
    let counts = ints(&prim.attribute("faceVertexCounts"))
        .context("faceVertexCounts")
        .map_err(openusd)?
        .unwrap_or_default();
    let indices = ints(&prim.attribute("faceVertexIndices"))
        .context("faceVertexIndices")
        .map_err(openusd)?
        .unwrap_or_default();
    let limit = options.max_elements.min(u32::MAX as usize - 1);
    let too_many = |what: &str, actual: usize| IoError::TooManyElements {
        path: file.to_path_buf(),
        what: format!("{what} of mesh <{}>", path.as_str()),
        limit,
        actual,
    };
    if points.len() > limit {
        return Err(too_many("the points", points.len()));
    }
    if indices.len() > limit {
        return Err(too_many("the face corners", indices.len()));
    }
    if counts.iter().any(|&c| c < 0) {
        return Err(bad("a faceVertexCounts entry is negative".to_owned()));
    }
    let total: usize = counts.iter().map(|&c| c as usize).sum();
    if total != indices.len() {
        return Err(bad(format!(
            "faceVertexCounts add up to {total} corners, faceVertexIndices has {}",
            indices.len()
        )));
    }
    if let Some(i) = indices.iter().find(|&&i| i < 0 || i as usize >= points.len()) {
        return Err(bad(format!("faceVertexIndices holds {i}, for {} points", points.len())));
    }
    if !points.iter().all(|p| p.is_finite()) {
        return Err(bad("a point is not finite".to_owned()));
    }
    let token = |name: &str| -> Result<Option<String>, IoError> {
        Ok(value(&prim.attribute(name)).map_err(openusd)?.and_then(|v| match v {
            sdf::Value::Token(t) => Some(t.as_str().to_owned()),
            sdf::Value::String(s) => Some(s),
            _ => None,
        }))
    };
    let scheme = token("subdivisionScheme")?.unwrap_or_else(|| "catmullClark".to_owned());
    let left_handed = token("orientation")?.as_deref() == Some("leftHanded");
    let (faces, corners) = (counts.len(), indices.len());
    let fits = |primvar: Option<Primvar<Vec3>>,
                name: &str,
                warnings: &mut Vec<String>|
     -> Option<Primvar<Vec3>> {
        let primvar = primvar?;
        match primvar.misfit(faces, corners, points.len()) {
            None => Some(primvar),
            Some(reason) => {
                warnings.push(format!(
                    "{}: mesh <{}>: {name} ignored: {reason}",
                    file.display(),
                    path.as_str()
                ));
                None
            }
        }
    };
    let primvar_normals = primvar(prim, "primvars:normals", vec3s, Interpolation::Constant)
        .context("primvars:normals")
        .map_err(openusd)?;
    let plain = primvar(prim, "normals", vec3s, Interpolation::Vertex)
        .context("normals")
        .map_err(openusd)?;
    let plain_normals = plain.is_some();
    let normals = match primvar_normals {
        Some(n) => Some(n),
        None => plain,
    };
    let subdivision = (scheme != "none").then_some(scheme);
    let normals = match (&subdivision, normals) {
        (Some(scheme), Some(_)) => {
            warnings.push(format!(
                "{}: mesh <{}> is a subdivision surface (subdivisionScheme {scheme}): renderers ignore its authored normals, so seamlit reads it without them and writes none on it",
                file.display(),
                path.as_str()
            ));
            None
        }
        (_, normals) => fits(normals, "its normals", warnings),
    };
    if let Some(n) = &normals
        && !n.values.iter().all(|v| v.is_finite())
    {
        return Err(bad("a normal is not finite".to_owned()));
    }
    let uvs = uv_primvar(prim).map_err(openusd)?.and_then(|(name, uvs)| {
        match uvs.misfit(faces, corners, points.len()) {
            None => Some(uvs),
            Some(reason) => {
                warnings.push(format!(
                    "{}: mesh <{}>: {name} ignored: {reason}",
                    file.display(),
                    path.as_str()
                ));
                None
            }
        }
    });
    if let Some(uv) = &uvs
        && !uv.values.iter().all(|v| v.is_finite())
    {
        return Err(bad("a texture coordinate is not finite".to_owned()));
    }

    // A vertex per distinct (point, normal value, UV value).
    let mut vertex_of: HashMap<[u32; 3], u32> = HashMap::new();
    let mut keys: Vec<[u32; 3]> = Vec::new();
    let mut corner_vertex = vec![NONE; corners];
    let mut corner_normals = normals.as_ref().map(|_| vec![Vec3::ZERO; corners]);
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut triangle_corners: Vec<[u32; 3]> = Vec::new();
    let mut polygons: Vec<(usize, usize)> = Vec::new();
    let mut first = 0usize;
    for (face, &count) in counts.iter().enumerate() {
        let count = count as usize;
        let range = first..first + count;
        first += count;
        for c in range.clone() {
            let point = indices[c] as usize;
            if let (Some(n), Some(out)) = (&normals, &mut corner_normals) {
                out[c] = n.values[n.index(face, c, point) as usize];
            }
        }
        if count < 3 {
            continue;
        }
        for c in range.clone() {
            let point = indices[c] as usize;
            #[expect(clippy::cast_possible_truncation, reason = "points are below the limit")]
            let key = [
                point as u32,
                normals.as_ref().map_or(NONE, |n| n.index(face, c, point)),
                uvs.as_ref().map_or(NONE, |u| u.index(face, c, point)),
            ];
            let next = keys.len();
            let v = *vertex_of.entry(key).or_insert_with(|| {
                keys.push(key);
                #[expect(clippy::cast_possible_truncation, reason = "below the limit")]
                let next = next as u32;
                next
            });
            corner_vertex[c] = v;
        }
        if triangles.len() + count - 2 > limit {
            return Err(too_many("the triangles", triangles.len() + count - 2));
        }
        polygons.push((triangles.len(), count));
        let base = range.start;
        for k in 1..count - 1 {
            let corners = [base, base + k, base + k + 1];
            triangles.push(corners.map(|c| corner_vertex[c]));
            #[expect(clippy::cast_possible_truncation, reason = "corners are below the limit")]
            triangle_corners.push(corners.map(|c| c as u32));
        }
    }
    if keys.len() > limit {
        return Err(too_many("the vertices", keys.len()));
    }
    let positions: Vec<Vec3> = keys.iter().map(|k| points[k[0] as usize]).collect();
    // Polygons that are not convex are ear-clipped; map their new triangles' corners back.
    let polygons = polygons.into_iter().filter(|&(_, n)| n > 3);
    for (first, vertices) in crate::obj::polygon::triangulate(&mut triangles, &positions, polygons)
    {
        let face_start = triangle_corners[first][0] as usize;
        for t in first..first + vertices.len() - 2 {
            let corners = triangles[t].map(|v| {
                let j = vertices.iter().position(|&w| w == v).unwrap_or(0);
                #[expect(clippy::cast_possible_truncation, reason = "corners are below the limit")]
                let c = (face_start + j) as u32;
                c
            });
            triangle_corners[t] = corners;
        }
    }
    let model = up * world;
    if model.determinant() == 0.0 || !model.is_finite() {
        return Err(bad("its world transform is singular or not finite".to_owned()));
    }
    if left_handed != (model.determinant() < 0.0) {
        for t in triangles.iter_mut().chain(&mut triangle_corners) {
            t.swap(1, 2);
        }
    }
    let object_normals = normals.map(|n| keys.iter().map(|k| n.values[k[1] as usize]).collect());
    let object_uvs = uvs.map(|u| keys.iter().map(|k| u.values[k[2] as usize]).collect());
    let transform = model.as_mat4();
    let object = Object {
        normals: object_normals,
        uvs: object_uvs,
        transform: (transform != Mat4::IDENTITY).then_some(transform),
        ..Object::new(path.as_str(), positions, triangles)
    };
    let instance_proxy = prim.is_instance_proxy().map_err(openusd)?;
    let source = MeshSource {
        prim: path.as_str().to_owned(),
        triangle_corners,
        corner_vertex,
        corner_normals,
        subdivision,
        plain_normals,
        instance_proxy,
    };
    Ok(Read { object, source })
}

/// The primvar `name` (its `interpolation` metadata, else `default`; its `:indices`), if it
/// has a value.
fn primvar<T>(
    prim: &usd::Prim,
    name: &str,
    read: impl Fn(&usd::Attribute) -> anyhow::Result<Option<Vec<T>>>,
    default: Interpolation,
) -> anyhow::Result<Option<Primvar<T>>> {
    let attribute = prim.attribute(name);
    let Some(values) = read(&attribute)? else { return Ok(None) };
    let interpolation = match attribute.get_metadata::<sdf::Value>("interpolation")? {
        Some(sdf::Value::Token(t)) => parse_interpolation(t.as_str())?,
        Some(sdf::Value::String(s)) => parse_interpolation(&s)?,
        _ => default,
    };
    let indices = if name.starts_with("primvars:") {
        ints(&prim.attribute(format!("{name}:indices"))).context("its indices")?
    } else {
        None
    };
    Ok(Some(Primvar { values, indices, interpolation }))
}

fn parse_interpolation(token: &str) -> anyhow::Result<Interpolation> {
    Ok(match token {
        "constant" => Interpolation::Constant,
        "uniform" => Interpolation::Uniform,
        "vertex" | "varying" => Interpolation::Vertex,
        "faceVarying" => Interpolation::FaceVarying,
        other => bail!("unknown interpolation {other:?}"),
    })
}

/// The first texture coordinates: `primvars:st`, else the first `texCoord2f[]` primvar.
fn uv_primvar(prim: &usd::Prim) -> anyhow::Result<Option<(String, Primvar<Vec2>)>> {
    if let Some(st) = primvar(prim, "primvars:st", vec2s, Interpolation::Constant)? {
        return Ok(Some(("primvars:st".to_owned(), st)));
    }
    for name in prim.property_names()? {
        let name = name.as_str();
        if !name.starts_with("primvars:") || name.ends_with(":indices") {
            continue;
        }
        let attribute = prim.attribute(name);
        if attribute.type_name()?.is_some_and(|t| t.as_str() == "texCoord2f[]")
            && let Some(uvs) = primvar(prim, name, vec2s, Interpolation::Constant)?
        {
            return Ok(Some((name.to_owned(), uvs)));
        }
    }
    Ok(None)
}

/// A float3 array of any precision (`point3f[]`, `normal3f[]`, `double3[]`, `half3[]`).
fn vec3s(attribute: &usd::Attribute) -> anyhow::Result<Option<Vec<Vec3>>> {
    let Some(v) = value(attribute)? else { return Ok(None) };
    Ok(Some(match v {
        sdf::Value::Vec3fVec(v) => v.iter().map(|p| Vec3::new(p.x, p.y, p.z)).collect(),
        sdf::Value::Vec3dVec(v) => {
            v.iter().map(|p| Vec3::new(f32_of(p.x), f32_of(p.y), f32_of(p.z))).collect()
        }
        sdf::Value::Vec3hVec(v) => {
            v.iter().map(|p| Vec3::new(p.x.to_f32(), p.y.to_f32(), p.z.to_f32())).collect()
        }
        other => bail!("expected an array of three numbers each, found {}", kind(&other)),
    }))
}

/// A float2 array of any precision (`texCoord2f[]`, `float2[]`, `double2[]`).
fn vec2s(attribute: &usd::Attribute) -> anyhow::Result<Option<Vec<Vec2>>> {
    let Some(v) = value(attribute)? else { return Ok(None) };
    Ok(Some(match v {
        sdf::Value::Vec2fVec(v) => v.iter().map(|p| Vec2::new(p.x, p.y)).collect(),
        sdf::Value::Vec2dVec(v) => v.iter().map(|p| Vec2::new(f32_of(p.x), f32_of(p.y))).collect(),
        sdf::Value::Vec2hVec(v) => {
            v.iter().map(|p| Vec2::new(p.x.to_f32(), p.y.to_f32())).collect()
        }
        other => bail!("expected an array of two numbers each, found {}", kind(&other)),
    }))
}

/// An int array.
fn ints(attribute: &usd::Attribute) -> anyhow::Result<Option<Vec<i32>>> {
    let Some(v) = value(attribute)? else { return Ok(None) };
    Ok(Some(match v {
        sdf::Value::IntVec(v) => v,
        other => bail!("expected an int array, found {}", kind(&other)),
    }))
}

/// A value's kind for messages, without its (possibly long) contents.
fn kind(v: &sdf::Value) -> String {
    let text = format!("{v:?}");
    text.split(['(', ' ', '{']).next().unwrap_or("a value").to_owned()
}
