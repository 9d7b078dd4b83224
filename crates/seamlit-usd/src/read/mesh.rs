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

use std::path::Path;

use anyhow::{Context, bail};
use glam::{DMat4, Mat4, Vec2, Vec3};
use openusd::{sdf, usd};
use rustc_hash::FxHashMap;
use seamlit_mesh::{Influences, Object};

use super::skel::Binding;
use super::{f32_of, value};
use crate::source::{MeshSource, SkinSource};
use seamlit_asset::LoadOptions;
use seamlit_asset::error::IoError;
use seamlit_asset::error::usd::UsdKind;

/// No vertex: a corner of a face of fewer than three corners.
const NONE: u32 = u32::MAX;

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
    /// Per triangle of the object: the face (an index of `faceVertexCounts`) it is part of.
    pub triangle_faces: Vec<u32>,
    /// The mesh's number of faces.
    pub faces: usize,
}

/// Where a mesh is placed: its world matrix, the up-axis rotation, and its skin binding
/// (which, where it fits the mesh, places it instead: `geomBindTransform`, then the
/// skeleton's world matrix).
pub(super) struct Placement {
    pub world: DMat4,
    pub up: DMat4,
    pub skin: Option<Binding>,
}

/// A `Mesh` prim's values as read from the stage and checked: all that making its object
/// takes ([`Authored::build`]), which needs the stage no more, so that a stage's meshes are
/// read one after another and built side by side.
pub(super) struct Authored {
    prim: String,
    /// The most points, face corners, triangles or vertices the mesh may have.
    limit: usize,
    topology: Topology,
    /// The skin binding, where it fits the mesh.
    skin: Option<Binding>,
    /// Its world matrix (the skin's placement where it has one), before the up axis.
    world: DMat4,
    up: DMat4,
    subdivision: Option<String>,
    left_handed: bool,
    normals: Option<Primvar<Vec3>>,
    plain_normals: bool,
    uvs: Option<Primvar<Vec2>>,
    /// Read with the rest, reported after the checks of building (in the order of old).
    instance_proxy: Result<bool, IoError>,
    time_sampled: Result<Vec<String>, IoError>,
}

/// Reads the `Mesh` prim at `path`, placed by `placement`, for [`Authored::build`].
///
/// # Errors
///
/// [`IoError::Usd`] with [`UsdKind::Prim`] for values that cannot be read or do not fit
/// the mesh; [`IoError::TooManyElements`] past `options.max_elements`.
pub(super) fn read(
    prim: &usd::Prim,
    placement: Placement,
    file: &Path,
    options: &LoadOptions,
    warnings: &mut Vec<String>,
) -> Result<Authored, IoError> {
    let path = prim.path().clone();
    let at =
        At { file, prim: path.as_str(), limit: options.max_elements.min(u32::MAX as usize - 1) };
    let topology = Topology::read(prim, &at, warnings)?;
    let Placement { world, up, skin } = placement;
    let skin = fitting_skin(skin, topology.points.len(), &at, warnings);
    let world = skin.as_ref().map_or(world, |b| b.skeleton_world * b.geom_bind);
    let subdivision =
        at.token(prim, "subdivisionScheme")?.unwrap_or_else(|| "catmullClark".to_owned());
    let subdivision = (subdivision != "none").then_some(subdivision);
    let left_handed = at.token(prim, "orientation")?.as_deref() == Some("leftHanded");
    let (normals, plain_normals) =
        read_normals(prim, &at, &topology, subdivision.as_deref(), warnings)?;
    let uvs = read_uvs(prim, &at, &topology, warnings)?;
    Ok(Authored {
        prim: at.prim.to_owned(),
        limit: at.limit,
        topology,
        skin,
        world,
        up,
        subdivision,
        left_handed,
        normals,
        plain_normals,
        uvs,
        instance_proxy: prim.is_instance_proxy().map_err(|e| at.openusd(e)),
        time_sampled: time_sampled(prim).map_err(|e| at.openusd(e)),
    })
}

impl Authored {
    /// The mesh's face corners: the measure of the work of building it.
    pub(super) fn corners(&self) -> usize {
        self.topology.indices.len()
    }

    /// The mesh's object and source; `file` names the stage in errors.
    ///
    /// # Errors
    ///
    /// [`IoError::TooManyElements`] for more triangles or vertices than the limit;
    /// [`IoError::Usd`] for a singular world transform, and the errors [`read`] kept.
    pub(super) fn build(self, file: &Path) -> Result<Read, IoError> {
        let at = At { file, prim: &self.prim, limit: self.limit };
        let (topology, normals, uvs) = (&self.topology, self.normals, self.uvs);
        let mut corners = Corners::build(topology, normals.as_ref(), uvs.as_ref(), &at)?;
        let positions: Vec<Vec3> =
            corners.keys.iter().map(|k| topology.points[k[0] as usize]).collect();
        corners.ear_clip(&positions);
        let model = self.up * self.world;
        if model.determinant() == 0.0 || !model.is_finite() {
            return Err(at.bad("its world transform is singular or not finite"));
        }
        if self.left_handed != (model.determinant() < 0.0) {
            corners.flip_winding();
        }

        let corner_normals = normals.as_ref().map(|n| topology.corner_values(n));
        let object_normals =
            normals.map(|n| corners.keys.iter().map(|k| n.values[k[1] as usize]).collect());
        let object_uvs =
            uvs.map(|u| corners.keys.iter().map(|k| u.values[k[2] as usize]).collect());
        let transform = model.as_mat4();
        let vertex_point: Vec<u32> = corners.keys.iter().map(|k| k[0]).collect();
        let skin = self.skin;
        let object = Object {
            normals: object_normals,
            uvs: object_uvs,
            transform: (transform != Mat4::IDENTITY).then_some(transform),
            skin: skin.as_ref().map(|b| influences(b, &vertex_point)).unwrap_or_default(),
            ..Object::new(at.prim, positions, corners.triangles)
        };
        let skin = skin.map(|b| SkinSource {
            influences: b.influences,
            vertex_point,
            points: topology.points.len(),
        });
        let (instance_proxy, time_sampled) = (self.instance_proxy?, self.time_sampled?);
        let triangle_faces = triangle_faces(topology, &corners.triangle_corners);
        let faces = topology.faces().count();
        let source = MeshSource {
            prim: self.prim,
            triangle_corners: corners.triangle_corners,
            corner_vertex: corners.corner_vertex,
            corner_normals,
            subdivision: self.subdivision,
            plain_normals: self.plain_normals,
            instance_proxy,
            instance: None,
            root_sites: Vec::new(),
            time_sampled,
            skin,
        };
        Ok(Read { object, source, triangle_faces, faces })
    }
}

/// The skin binding where it fits a mesh of `points` points; one warning where it does not
/// (the mesh is then read unskinned, at its own transform).
fn fitting_skin(
    skin: Option<Binding>,
    points: usize,
    at: &At<'_>,
    warnings: &mut Vec<String>,
) -> Option<Binding> {
    skin.filter(|binding| match binding.misfit(points) {
        None => true,
        Some(reason) => {
            at.warn(
                warnings,
                &format!("its skin is ignored ({reason}): read unskinned, at its own transform"),
            );
            false
        }
    })
}

/// Per triangle (the corners it was cut from: `triangle_corners`), the face it belongs to.
fn triangle_faces(topology: &Topology, triangle_corners: &[[u32; 3]]) -> Vec<u32> {
    let mut corner_face = vec![0u32; topology.indices.len()];
    for (face, range) in topology.faces() {
        #[expect(clippy::cast_possible_truncation, reason = "faces are below the limit")]
        corner_face[range].fill(face as u32);
    }
    triangle_corners.iter().map(|t| corner_face[t[0] as usize]).collect()
}

/// Per vertex (whose points `vertex_point` gives), the binding's influences of its point, in
/// sets of four (`elementSize` 5 gives two sets, the second padded with zero weights).
fn influences(binding: &Binding, vertex_point: &[u32]) -> Vec<Influences> {
    let sets = binding.influences.element_size.div_ceil(4);
    let mut out = vec![
        Influences {
            joints: vec![[0; 4]; vertex_point.len()],
            weights: vec![[0.0; 4]; vertex_point.len()],
        };
        sets
    ];
    for (v, &p) in vertex_point.iter().enumerate() {
        for (lane, (joint, weight)) in binding.of_point(p as usize).enumerate() {
            out[lane / 4].joints[v][lane % 4] = joint;
            out[lane / 4].weights[v][lane % 4] = weight;
        }
    }
    out
}

/// The mesh being read: where its errors and warnings point, and the element limit.
struct At<'a> {
    file: &'a Path,
    prim: &'a str,
    /// The most points, face corners, triangles or vertices a mesh may have.
    limit: usize,
}

impl At<'_> {
    /// A value of the prim that cannot be read or does not fit the mesh.
    fn bad(&self, message: impl Into<String>) -> IoError {
        IoError::Usd {
            path: self.file.to_path_buf(),
            kind: UsdKind::Prim { prim: self.prim.to_owned(), message: message.into() },
        }
    }

    /// An error openusd (or a reader here) gave.
    fn openusd(&self, e: anyhow::Error) -> IoError {
        self.bad(format!("{e:#}"))
    }

    /// `actual` elements of `what`, past the limit.
    fn too_many(&self, what: &str, actual: usize) -> IoError {
        IoError::TooManyElements {
            path: self.file.to_path_buf(),
            what: format!("{what} of mesh <{}>", self.prim),
            limit: self.limit,
            actual,
        }
    }

    /// A warning about the mesh.
    fn warn(&self, warnings: &mut Vec<String>, message: &str) {
        warnings.push(format!("{}: mesh <{}>: {message}", self.file.display(), self.prim));
    }

    /// The token (or string) attribute `name`, if it has a value.
    fn token(&self, prim: &usd::Prim, name: &str) -> Result<Option<String>, IoError> {
        let v = value(&prim.attribute(name)).map_err(|e| self.openusd(e))?;
        Ok(v.and_then(|v| match v {
            sdf::Value::Token(t) => Some(t.as_str().to_owned()),
            sdf::Value::String(s) => Some(s),
            _ => None,
        }))
    }

    /// `primvar` if it fits the topology, else `None` and a warning naming it.
    fn fitting<T>(
        &self,
        primvar: Option<Primvar<T>>,
        name: &str,
        topology: &Topology,
        warnings: &mut Vec<String>,
    ) -> Option<Primvar<T>> {
        let primvar = primvar?;
        let misfit =
            primvar.misfit(topology.counts.len(), topology.indices.len(), topology.points.len());
        match misfit {
            None => Some(primvar),
            Some(reason) => {
                self.warn(warnings, &format!("{name} ignored: {reason}"));
                None
            }
        }
    }
}

/// The attributes that decide the mesh's normals and have time samples (their own, a value
/// clip's, or across an arc): `points`, `primvars:normals`, its indices, `normals`.
fn time_sampled(prim: &usd::Prim) -> anyhow::Result<Vec<String>> {
    let mut out = Vec::new();
    for name in ["points", "primvars:normals", "primvars:normals:indices", "normals"] {
        if !prim.attribute(name).time_sample_times()?.is_empty() {
            out.push(name.to_owned());
        }
    }
    Ok(out)
}

/// A mesh's points and polygons, checked: counts add up, indices name points, points are
/// finite, sizes within the limit.
struct Topology {
    points: Vec<Vec3>,
    /// `faceVertexCounts`, none negative.
    counts: Vec<i32>,
    /// `faceVertexIndices`, each a point.
    indices: Vec<i32>,
}

impl Topology {
    fn read(prim: &usd::Prim, at: &At<'_>, warnings: &mut Vec<String>) -> Result<Self, IoError> {
        let openusd = |e: anyhow::Error| at.openusd(e);
        let points = vec3s(&prim.attribute("points")).context("points").map_err(openusd)?;
        let points = points.unwrap_or_default();
        let samples = prim.attribute("points").time_samples().map_err(openusd)?;
        if samples.is_some_and(|s| !s.is_empty()) {
            at.warn(
                warnings,
                "its points are time-sampled; read at their default, else their earliest sample, and the normals fixed for that shape only",
            );
        }
        let ints_of =
            |name: &str| ints(&prim.attribute(name)).context(name.to_owned()).map_err(openusd);
        let counts = ints_of("faceVertexCounts")?.unwrap_or_default();
        let indices = ints_of("faceVertexIndices")?.unwrap_or_default();
        if points.len() > at.limit {
            return Err(at.too_many("the points", points.len()));
        }
        if indices.len() > at.limit {
            return Err(at.too_many("the face corners", indices.len()));
        }
        if counts.iter().any(|&c| c < 0) {
            return Err(at.bad("a faceVertexCounts entry is negative"));
        }
        let total: usize = counts.iter().map(|&c| c as usize).sum();
        if total != indices.len() {
            return Err(at.bad(format!(
                "faceVertexCounts add up to {total} corners, faceVertexIndices has {}",
                indices.len()
            )));
        }
        if let Some(i) = indices.iter().find(|&&i| i < 0 || i as usize >= points.len()) {
            return Err(at.bad(format!("faceVertexIndices holds {i}, for {} points", points.len())));
        }
        if !points.iter().all(|p| p.is_finite()) {
            return Err(at.bad("a point is not finite"));
        }
        Ok(Self { points, counts, indices })
    }

    /// Per face: its number of corners and the range of its corners.
    fn faces(&self) -> impl Iterator<Item = (usize, std::ops::Range<usize>)> + '_ {
        let mut first = 0usize;
        self.counts.iter().enumerate().map(move |(face, &count)| {
            let range = first..first + count as usize;
            first = range.end;
            (face, range)
        })
    }

    /// Per face corner: `primvar`'s value there.
    fn corner_values<T: Copy>(&self, primvar: &Primvar<T>) -> Vec<T> {
        let mut out = Vec::with_capacity(self.indices.len());
        for (face, range) in self.faces() {
            for c in range {
                let point = self.indices[c] as usize;
                out.push(primvar.values[primvar.index(face, c, point) as usize]);
            }
        }
        out
    }
}

/// The normals as the rules of UsdGeomMesh decide them (`primvars:normals` over `normals`,
/// none on a subdivision surface), and whether a plain `normals` has a value.
fn read_normals(
    prim: &usd::Prim,
    at: &At<'_>,
    topology: &Topology,
    subdivision: Option<&str>,
    warnings: &mut Vec<String>,
) -> Result<(Option<Primvar<Vec3>>, bool), IoError> {
    let openusd = |e: anyhow::Error| at.openusd(e);
    let primvar_normals = primvar(prim, "primvars:normals", vec3s, Interpolation::Constant)
        .context("primvars:normals")
        .map_err(openusd)?;
    let plain = primvar(prim, "normals", vec3s, Interpolation::Vertex)
        .context("normals")
        .map_err(openusd)?;
    let plain_normals = plain.is_some();
    let normals = primvar_normals.or(plain);
    let normals = match (subdivision, normals) {
        (Some(scheme), Some(_)) => {
            warnings.push(format!(
                "{}: mesh <{}> is a subdivision surface (subdivisionScheme {scheme}): renderers ignore its authored normals, so seamlit reads it without them and writes none on it",
                at.file.display(),
                at.prim
            ));
            None
        }
        (_, normals) => at.fitting(normals, "its normals", topology, warnings),
    };
    if let Some(n) = &normals
        && !n.values.iter().all(|v| v.is_finite())
    {
        return Err(at.bad("a normal is not finite"));
    }
    Ok((normals, plain_normals))
}

/// The first texture coordinates, if they fit the mesh.
fn read_uvs(
    prim: &usd::Prim,
    at: &At<'_>,
    topology: &Topology,
    warnings: &mut Vec<String>,
) -> Result<Option<Primvar<Vec2>>, IoError> {
    let Some((name, uvs)) = uv_primvar(prim).map_err(|e| at.openusd(e))? else {
        return Ok(None);
    };
    let uvs = at.fitting(Some(uvs), &name, topology, warnings);
    if let Some(uv) = &uvs
        && !uv.values.iter().all(|v| v.is_finite())
    {
        return Err(at.bad("a texture coordinate is not finite"));
    }
    Ok(uvs)
}

/// The object's vertices and triangles made from the face corners: a vertex per distinct
/// (point, normal value, UV value), each polygon a fan (ear-clipped later where it is not
/// convex).
struct Corners {
    /// Per vertex: its point, normal value index and UV value index ([`NONE`] without).
    keys: Vec<[u32; 3]>,
    /// Per face corner: its vertex, [`NONE`] on a face of fewer than three corners.
    corner_vertex: Vec<u32>,
    triangles: Vec<[u32; 3]>,
    /// Per triangle, per corner: the face corner it is.
    triangle_corners: Vec<[u32; 3]>,
    /// Per polygon of three corners or more: its first triangle and its number of corners.
    polygons: Vec<(usize, usize)>,
}

impl Corners {
    fn build(
        topology: &Topology,
        normals: Option<&Primvar<Vec3>>,
        uvs: Option<&Primvar<Vec2>>,
        at: &At<'_>,
    ) -> Result<Self, IoError> {
        let mut vertex_of: FxHashMap<[u32; 3], u32> = FxHashMap::default();
        // Where every key is its point's alone (no normals or UVs, or `vertex` or `constant`
        // ones: the usual layout), a table by point stands in for the hash map: the same
        // vertices in the same order, without hashing every corner.
        let by_point = [normals.map(|n| n.interpolation), uvs.map(|u| u.interpolation)]
            .into_iter()
            .flatten()
            .all(|i| matches!(i, Interpolation::Vertex | Interpolation::Constant));
        let mut vertex_of_point = if by_point { vec![NONE; topology.points.len()] } else { vec![] };
        let mut this = Self {
            keys: Vec::new(),
            corner_vertex: vec![NONE; topology.indices.len()],
            triangles: Vec::new(),
            triangle_corners: Vec::new(),
            polygons: Vec::new(),
        };
        for (face, range) in topology.faces() {
            let count = range.len();
            if count < 3 {
                continue;
            }
            for c in range.clone() {
                let point = topology.indices[c] as usize;
                #[expect(clippy::cast_possible_truncation, reason = "points are below the limit")]
                let key = [
                    point as u32,
                    normals.map_or(NONE, |n| n.index(face, c, point)),
                    uvs.map_or(NONE, |u| u.index(face, c, point)),
                ];
                #[expect(clippy::cast_possible_truncation, reason = "below the limit")]
                let next = this.keys.len() as u32;
                let v = if by_point {
                    let v = &mut vertex_of_point[point];
                    if *v == NONE {
                        this.keys.push(key);
                        *v = next;
                    }
                    *v
                } else {
                    *vertex_of.entry(key).or_insert_with(|| {
                        this.keys.push(key);
                        next
                    })
                };
                this.corner_vertex[c] = v;
            }
            if this.triangles.len() + count - 2 > at.limit {
                return Err(at.too_many("the triangles", this.triangles.len() + count - 2));
            }
            this.polygons.push((this.triangles.len(), count));
            let base = range.start;
            for k in 1..count - 1 {
                let corners = [base, base + k, base + k + 1];
                this.triangles.push(corners.map(|c| this.corner_vertex[c]));
                #[expect(clippy::cast_possible_truncation, reason = "corners are below the limit")]
                this.triangle_corners.push(corners.map(|c| c as u32));
            }
        }
        if this.keys.len() > at.limit {
            return Err(at.too_many("the vertices", this.keys.len()));
        }
        Ok(this)
    }

    /// Ear-clips the polygons that are not convex and maps their new triangles' corners back
    /// to the face corners.
    fn ear_clip(&mut self, positions: &[Vec3]) {
        let polygons = self.polygons.iter().copied().filter(|&(_, n)| n > 3);
        let clipped = seamlit_asset::polygon::triangulate(&mut self.triangles, positions, polygons);
        for (first, vertices) in clipped {
            let face_start = self.triangle_corners[first][0] as usize;
            for t in first..first + vertices.len() - 2 {
                let corners = self.triangles[t].map(|v| {
                    let j = vertices.iter().position(|&w| w == v).unwrap_or(0);
                    #[expect(
                        clippy::cast_possible_truncation,
                        reason = "corners are below the limit"
                    )]
                    let c = (face_start + j) as u32;
                    c
                });
                self.triangle_corners[t] = corners;
            }
        }
    }

    /// Reverses every triangle's winding.
    fn flip_winding(&mut self) {
        for t in self.triangles.iter_mut().chain(&mut self.triangle_corners) {
            t.swap(1, 2);
        }
    }
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
