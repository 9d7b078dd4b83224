//! One triangle primitive (a list, a strip or a fan) read into an object: its accessors
//! checked first, then its attributes (floats or KHR_mesh_quantization's integers), its
//! triangles (a strip's or a fan's as a list) and its deformation.

use bytes::Bytes;
use glam::{Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use seamlit_mesh::Object;

use super::Reader;
use crate::decode::quantized::{read_directions, read_floats};
use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::{BadAccessor, GltfKind};

/// A primitive being read, and its vertex count (POSITION's).
pub(super) struct Vertices<'p, 'd> {
    pub(super) primitive: &'p gltf::Primitive<'d>,
    pub(super) count: usize,
}

impl Reader<'_> {
    /// Decodes one triangle primitive into an object (name and transform set by the caller).
    pub(super) fn primitive(
        &self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        buffers: &[Bytes],
        warnings: &mut Vec<String>,
    ) -> Result<Option<Object>, IoError> {
        let Some(position) = primitive.get(&gltf::Semantic::Positions) else {
            warnings.push(format!(
                "{}: mesh {} primitive {} has no POSITION; skipped",
                self.path.display(),
                mesh.index(),
                primitive.index()
            ));
            return Ok(None);
        };
        self.check_primitive(primitive, &position, buffers)?;
        let vertices = Vertices { primitive, count: position.count() };
        // Floats, or KHR_mesh_quantization's integers; an accessor without a view or sparse
        // data is zeros (the readers give nothing).
        let positions = self
            .vertex_attribute(&vertices, gltf::Semantic::Positions, "POSITION", |a| {
                read_floats::<3>(a, buffers).map(|v| v.into_iter().map(Vec3::from_array).collect())
            })?
            .unwrap_or_default();
        if positions.len() != vertices.count {
            return Err(self.short(&position, positions.len()));
        }
        let normals = self.vertex_attribute(&vertices, gltf::Semantic::Normals, "NORMAL", |a| {
            read_directions::<3>(a, buffers).map(|v| v.into_iter().map(Vec3::from_array).collect())
        })?;
        let tangents =
            self.vertex_attribute(&vertices, gltf::Semantic::Tangents, "TANGENT", |a| {
                read_directions::<4>(a, buffers)
                    .map(|v| v.into_iter().map(Vec4::from_array).collect())
            })?;
        let uvs =
            self.vertex_attribute(&vertices, gltf::Semantic::TexCoords(0), "TEXCOORD_0", |a| {
                read_floats::<2>(a, buffers).map(|v| v.into_iter().map(Vec2::from_array).collect())
            })?;
        let uvs1 =
            self.vertex_attribute(&vertices, gltf::Semantic::TexCoords(1), "TEXCOORD_1", |a| {
                read_floats::<2>(a, buffers).map(|v| v.into_iter().map(Vec2::from_array).collect())
            })?;
        let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
        let colors =
            self.vertex_attribute(&vertices, gltf::Semantic::Colors(0), "COLOR_0", |_| {
                reader.read_colors(0).map(|it| it.into_rgba_f32().map(Vec4::from_array).collect())
            })?;
        let triangles = self.triangles(mesh, primitive, buffers, vertices.count)?;
        let (skin, morph_targets) = self.deformation(mesh, primitive, buffers, vertices.count)?;
        Ok(Some(Object {
            name: String::new(),
            positions,
            uvs,
            uvs1,
            normals,
            tangents,
            colors,
            triangles,
            transform: None,
            material: primitive.material().index(),
            smoothing_groups: None,
            split_from: Vec::new(),
            skin,
            morph_targets,
        }))
    }

    /// Checks a primitive's accessors before anything is read: POSITION, NORMAL, TANGENT,
    /// TEXCOORD_0, TEXCOORD_1 and COLOR_0 (types, extent, as many elements as POSITION) and the indices
    /// (a triangle list's: a multiple of 3).
    fn check_primitive(
        &self,
        primitive: &gltf::Primitive<'_>,
        position: &gltf::Accessor<'_>,
        buffers: &[Bytes],
    ) -> Result<(), IoError> {
        let vertex_count = position.count();
        // KHR_mesh_quantization: integers, normalised or not, besides floats.
        let quantized = [DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16];
        let signed = [DataType::F32, DataType::I8, DataType::I16];
        self.check_accessor(position, Dimensions::Vec3, &quantized, "POSITION")?;
        self.check_sparse_indices(position, buffers)?;
        // COLOR_0 is RGB or RGBA, of floats or normalised integers.
        let color_dimensions =
            primitive.get(&gltf::Semantic::Colors(0)).map_or(Dimensions::Vec4, |a| {
                match a.dimensions() {
                    Dimensions::Vec3 => Dimensions::Vec3,
                    _ => Dimensions::Vec4,
                }
            });
        let colors = [DataType::F32, DataType::U8, DataType::U16];
        let attributes = [
            (gltf::Semantic::Normals, Dimensions::Vec3, &signed[..], "NORMAL"),
            (gltf::Semantic::Tangents, Dimensions::Vec4, &signed[..], "TANGENT"),
            (gltf::Semantic::TexCoords(0), Dimensions::Vec2, &quantized[..], "TEXCOORD_0"),
            (gltf::Semantic::TexCoords(1), Dimensions::Vec2, &quantized[..], "TEXCOORD_1"),
            (gltf::Semantic::Colors(0), color_dimensions, &colors[..], "COLOR_0"),
        ];
        for (semantic, dimensions, types, name) in attributes {
            if let Some(accessor) = primitive.get(&semantic) {
                self.check_attribute(&accessor, (dimensions, types), name, buffers, vertex_count)?;
            }
        }
        let error = |accessor: &gltf::Accessor<'_>, kind: BadAccessor| {
            IoError::gltf_data(
                self.path.to_path_buf(),
                GltfKind::Accessor { accessor: accessor.index(), kind: Box::new(kind) },
            )
        };
        let list = primitive.mode() == gltf::mesh::Mode::Triangles;
        let Some(accessor) = primitive.indices() else {
            if list && !vertex_count.is_multiple_of(3) {
                return Err(error(
                    position,
                    BadAccessor::NotTriangles { what: "vertices", count: vertex_count },
                ));
            }
            return Ok(());
        };
        let types = [DataType::U8, DataType::U16, DataType::U32];
        self.check_accessor(&accessor, Dimensions::Scalar, &types, "indices")?;
        self.check_sparse_indices(&accessor, buffers)?;
        if list && !accessor.count().is_multiple_of(3) {
            return Err(error(
                &accessor,
                BadAccessor::NotTriangles { what: "indices", count: accessor.count() },
            ));
        }
        Ok(())
    }
}

impl Reader<'_> {
    /// A primitive's triangles: its indices, checked against the vertex count, or `0, 1,
    /// 2, ...` for a non-indexed list; a strip's or a fan's as a list ([`unstrip`]).
    fn triangles(
        &self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        buffers: &[Bytes],
        vertex_count: usize,
    ) -> Result<Vec<[u32; 3]>, IoError> {
        let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
        let index_accessor = primitive.indices();
        let indices = super::lenient::zeros_without_view(
            index_accessor.as_ref(),
            reader.read_indices().map(|read| read.into_u32().collect::<Vec<u32>>()),
        );
        let (Some(accessor), Some(read)) = (index_accessor, indices) else {
            let Ok(count) = u32::try_from(vertex_count) else {
                return Err(IoError::TooManyElements {
                    path: self.path.to_path_buf(),
                    what: format!("mesh {} primitive {}", mesh.index(), primitive.index()),
                    limit: u32::MAX as usize,
                    actual: vertex_count,
                });
            };
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                return Ok(unstrip(primitive.mode(), &(0..count).collect::<Vec<u32>>()));
            }
            return Ok((0..count / 3).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect());
        };
        let read: Vec<u32> = match primitive.mode() {
            gltf::mesh::Mode::Triangles => read,
            mode => {
                let count = read.len();
                if count != accessor.count() {
                    return Err(self.short(&accessor, count));
                }
                unstrip(mode, &read).into_iter().flatten().collect()
            }
        };
        let accessor_count = if primitive.mode() == gltf::mesh::Mode::Triangles {
            accessor.count()
        } else {
            read.len()
        };
        let mut read = read.into_iter();
        let mut triangles = Vec::with_capacity(accessor_count / 3);
        while let (Some(a), Some(b), Some(c)) = (read.next(), read.next(), read.next()) {
            triangles.push([a, b, c]);
        }
        if triangles.len() * 3 != accessor_count {
            return Err(self.short(&accessor, triangles.len() * 3));
        }
        if let Some(&index) = triangles.as_flattened().iter().find(|&&i| i as usize >= vertex_count)
        {
            return Err(IoError::gltf_data(
                self.path.to_path_buf(),
                GltfKind::IndexOutOfRange {
                    mesh: mesh.index(),
                    primitive: primitive.index(),
                    accessor: accessor.index(),
                    index,
                    vertex_count,
                },
            ));
        }
        Ok(triangles)
    }
}

/// The triangles of a strip or a fan (`mode`) of vertices `v`, as the specification draws
/// them (3.7.2.1): strip triangle `i` is `v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]`, fan
/// triangle `i` is `v[i + 1], v[i + 2], v[0]`. Triangles with a repeated vertex (a strip's
/// joins) are left out: they have no area.
fn unstrip(mode: gltf::mesh::Mode, v: &[u32]) -> Vec<[u32; 3]> {
    let triangle = |i: usize| match mode {
        gltf::mesh::Mode::TriangleFan => [v[i + 1], v[i + 2], v[0]],
        _ => [v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]],
    };
    (0..v.len().saturating_sub(2))
        .map(triangle)
        .filter(|[a, b, c]| a != b && b != c && a != c)
        .collect()
}
