//! The model types: a [`Model`] of named [`Object`]s, each an indexed triangle list.
//!
//! These types are both the input and the output of [`crate::fix`]: a fixed model is a
//! model whose objects carry normals (and tangents, where they have UVs), with vertices split
//! where a crease, a change of handedness or a tangent discontinuity needs two values at one
//! position.

use glam::{Mat4, Vec2, Vec3, Vec4};
use serde::{Deserialize, Serialize};

/// Which way the V texture coordinate runs, which decides the sign of the bitangent.
///
/// The bitangent points toward the normal map's +Y (up the image). Where V runs up the image
/// (OBJ, OpenGL) that is toward increasing V; where V runs down (glTF, whose texcoord origin is
/// the top-left corner) it is toward decreasing V. See docs/design.md section 4.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum VAxis {
    /// V = 0 at the bottom of the image (OBJ, OpenGL, Newell patches).
    #[default]
    Up,
    /// V = 0 at the top of the image (glTF 2.0).
    Down,
}

impl VAxis {
    /// +1.0 for [`VAxis::Up`], -1.0 for [`VAxis::Down`]: the factor that turns dP/dV into the
    /// bitangent direction.
    #[must_use]
    pub const fn bitangent_sign(self) -> f32 {
        match self {
            Self::Up => 1.0,
            Self::Down => -1.0,
        }
    }
}

/// One object of a model: an indexed triangle list with its own vertices.
///
/// Vertices on a boundary with another object are duplicated in each object; that is the
/// situation this crate exists for. All per-vertex arrays that are present have
/// `positions.len()` entries.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Object {
    /// The object's name, as the file gave it (OBJ `o`/`g`, glTF node or mesh name).
    pub name: String,
    /// Vertex positions in the object's local space.
    pub positions: Vec<Vec3>,
    /// Texture coordinates (TEXCOORD_0), if the object has them.
    pub uvs: Option<Vec<Vec2>>,
    /// The second set of texture coordinates (glTF TEXCOORD_1), if the object has them: what
    /// a material's texture reads when its `tex_coord` is 1. Carried, never computed with
    /// (tangents follow [`Object::uvs`]); [`crate::fix`] copies a vertex's to its copies.
    pub uvs1: Option<Vec<Vec2>>,
    /// Vertex normals in local space: as loaded (input), or as computed by [`crate::fix`].
    pub normals: Option<Vec<Vec3>>,
    /// Vertex colours (COLOR_0), linear RGBA, if the object has them. No colour space is
    /// converted on the way in or out: glTF's COLOR_0 is linear by definition, and OBJ's
    /// `v x y z r g b [a]` values are taken as they are written (as Assimp and tobj do),
    /// alpha 1 where the file gives none. [`crate::fix`] copies a vertex's colour to the
    /// copies it makes of it.
    pub colors: Option<Vec<Vec4>>,
    /// Vertex tangents in local space, `w` = +1 or -1 so that
    /// `B = cross(N, T.xyz) * T.w` (glTF convention).
    pub tangents: Option<Vec<Vec4>>,
    /// Triangles as three indices into the vertex arrays, counter-clockwise front faces.
    pub triangles: Vec<[u32; 3]>,
    /// Local-to-model transform; `None` is the identity.
    pub transform: Option<Mat4>,
    /// Index of the object's material in the file's material list, if any.
    pub material: Option<usize>,
    /// The smoothing group of each triangle (OBJ `s N`), one entry per triangle; `None`:
    /// every triangle of the object is in one group, shared with every other object without
    /// groups (and with no numbered group).
    ///
    /// When [`crate::fix`] computes normals, faces share a normal only where they are in the
    /// same nonzero group (and within the crease angle): faces of different groups meet at a
    /// hard edge, and a face in group 0 (`s off`) is flat. A group number means the same in
    /// every object, so objects in one group smooth across their boundary.
    pub smoothing_groups: Option<Vec<u32>>,
    /// Where split vertices came from. [`crate::fix`] appends a copy of a vertex where one
    /// position needs two frames; the last `split_from.len()` vertices are such copies, and
    /// entry `k` is the index of the input vertex (one of the first
    /// `vertex_count() - split_from.len()`) that the `k`-th copy duplicates. Writers use it to
    /// duplicate every attribute they carry beyond this type's (the glTF pass-through: every
    /// input attribute and morph target accessor, bytes as written) for the copies.
    /// Empty for a loaded model; fixing a fixed model keeps pointing at the first input.
    pub split_from: Vec<u32>,
    /// Skin influences, one [`Influences`] per set (glTF `JOINTS_n`/`WEIGHTS_n`); empty for an
    /// object that is not skinned. [`crate::fix`] copies a vertex's influences to the copies
    /// it makes of it, and [`crate::report`] counts welded positions whose objects disagree
    /// on them.
    pub skin: Vec<Influences>,
    /// Morph targets (glTF `targets`), in order. [`crate::fix`] copies a vertex's deltas to
    /// the copies it makes of it, and where it computes the object's normals it computes
    /// each target's normal (and tangent) deltas too (see [`MorphTarget`]).
    pub morph_targets: Vec<MorphTarget>,
}

/// One set of up to four skin influences per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Influences {
    /// Per vertex, four joints as indices of the file's *nodes* (glTF: `JOINTS_n` mapped
    /// through the skin's `joints`), so that objects with different skins compare.
    pub joints: Vec<[u32; 4]>,
    /// Per vertex, the four joints' weights; a weight of 0 means no influence.
    pub weights: Vec<[f32; 4]>,
}

/// One morph target of an object: per-vertex displacements of its positions, and the normal
/// and tangent deltas that go with them.
///
/// The target shape is `positions + position_deltas`; its normals are `normals +
/// normal_deltas` (glTF 2.0, "Morph Targets"). The loader fills `position_deltas` only;
/// [`crate::fix`] sets `normal_deltas` (and `tangent_deltas` where it computes tangents) for
/// the objects whose normals it computes, from the displaced positions of every object, with
/// the base result's weld, creases and splits. `None`: not computed (a writer keeps what the
/// input had).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MorphTarget {
    /// The target's name (glTF: the mesh's `extras.targetNames`, FBX: the blend shape's),
    /// empty where the file gives none.
    pub name: String,
    /// Per vertex: the displacement of its position, in the object's local space.
    pub position_deltas: Vec<Vec3>,
    /// Per vertex: the target's unit normal minus the base normal, local space.
    pub normal_deltas: Option<Vec<Vec3>>,
    /// Per vertex: the target's unit tangent (xyz) minus the base tangent's xyz.
    pub tangent_deltas: Option<Vec<Vec3>>,
}

impl Influences {
    /// The influences of vertex `v` with a weight above zero, as `(joint node, weight)`.
    pub fn of(&self, v: usize) -> impl Iterator<Item = (u32, f32)> + '_ {
        self.joints[v].into_iter().zip(self.weights[v]).filter(|&(_, w)| w > 0.0)
    }
}

impl Object {
    /// An object with positions and triangles only.
    #[must_use]
    pub fn new(name: impl Into<String>, positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Self {
        Self { name: name.into(), positions, triangles, ..Self::default() }
    }

    /// Adds texture coordinates (builder style).
    #[must_use]
    pub fn with_uvs(mut self, uvs: Vec<Vec2>) -> Self {
        self.uvs = Some(uvs);
        self
    }

    /// Sets the smoothing group of every triangle (builder style; see
    /// [`Object::smoothing_groups`]).
    #[must_use]
    pub fn with_smoothing_groups(mut self, groups: Vec<u32>) -> Self {
        self.smoothing_groups = Some(groups);
        self
    }

    /// Sets the local-to-model transform (builder style).
    #[must_use]
    pub fn with_transform(mut self, transform: Mat4) -> Self {
        self.transform = Some(transform);
        self
    }

    /// Number of vertices.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// The number of vertices the object had before any vertex was split
    /// (see [`Object::split_from`]).
    #[must_use]
    pub fn input_vertex_count(&self) -> usize {
        self.positions.len() - self.split_from.len()
    }

    /// The input vertex that vertex `v` is, or copies (see [`Object::split_from`]).
    #[must_use]
    pub fn source_vertex(&self, v: u32) -> u32 {
        let base = self.input_vertex_count();
        match (v as usize).checked_sub(base) {
            Some(k) => self.split_from[k],
            None => v,
        }
    }

    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The local-to-model transform, the identity when there is none.
    #[must_use]
    pub fn model_transform(&self) -> Mat4 {
        self.transform.unwrap_or(Mat4::IDENTITY)
    }
}

/// A model: one visual surface delivered as several objects.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Model {
    /// The objects, in file order.
    pub objects: Vec<Object>,
    /// Which way V runs in every object's UVs.
    pub v_axis: VAxis,
}

impl Model {
    /// A model of the given objects, with V running up (OBJ convention).
    #[must_use]
    pub fn new(objects: Vec<Object>) -> Self {
        Self { objects, v_axis: VAxis::Up }
    }

    /// Total number of triangles over all objects.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(Object::triangle_count).sum()
    }

    /// Total number of vertices over all objects.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.objects.iter().map(Object::vertex_count).sum()
    }

    /// The axis-aligned bounds of all positions in model space, or `None` for a model without
    /// finite positions.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut min = Vec3::splat(f32::INFINITY);
        let mut max = Vec3::splat(f32::NEG_INFINITY);
        for object in &self.objects {
            let m = object.model_transform();
            for &p in &object.positions {
                let q = m.transform_point3(p);
                if q.is_finite() {
                    min = min.min(q);
                    max = max.max(q);
                }
            }
        }
        (min.x <= max.x).then_some((min, max))
    }
}
