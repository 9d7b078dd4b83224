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
        let index_accessor = primitive.indices();
        if primitive.mode() == gltf::mesh::Mode::Triangles
            && let Some(accessor) = &index_accessor
            && let Some(triangles) = packed_triangles(accessor, buffers)
        {
            return self.in_range(mesh, primitive, accessor, triangles, vertex_count);
        }
        let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
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
        self.in_range(mesh, primitive, &accessor, triangles, vertex_count)
    }

    /// `triangles`, read from index accessor `accessor`, if each index is below the vertex
    /// count.
    fn in_range(
        &self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        accessor: &gltf::Accessor<'_>,
        triangles: Vec<[u32; 3]>,
        vertex_count: usize,
    ) -> Result<Vec<[u32; 3]>, IoError> {
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

/// The triangles of a list's index `accessor` read straight from its bytes, where they lie
/// packed in its buffer view (no sparse values, no stride but the index's size, a whole
/// number of triangles, within the view and the buffer); `None` otherwise, for the gltf
/// crate's reader. The same values, read several times faster than through its iterator and
/// a second array (the 1M teapot's indices: a tenth of the load).
fn packed_triangles(accessor: &gltf::Accessor<'_>, buffers: &[Bytes]) -> Option<Vec<[u32; 3]>> {
    let view = accessor.view()?;
    let size = accessor.data_type().size();
    let (count, length) = (accessor.count(), accessor.count().checked_mul(size)?);
    if accessor.sparse().is_some()
        || view.stride().is_some_and(|stride| stride != size)
        || !count.is_multiple_of(3)
        || accessor.offset().checked_add(length)? > view.length()
    {
        return None;
    }
    let start = view.offset().checked_add(accessor.offset())?;
    let bytes = buffers.get(view.buffer().index())?.get(start..start.checked_add(length)?)?;
    let triangles = bytes.chunks_exact(3 * size);
    Some(match size {
        1 => triangles.map(|t| [t[0], t[1], t[2]].map(u32::from)).collect(),
        2 => triangles
            .map(|t| {
                let at = |k: usize| u32::from(u16::from_le_bytes([t[2 * k], t[2 * k + 1]]));
                [at(0), at(1), at(2)]
            })
            .collect(),
        _ => triangles
            .map(|t| {
                let at = |k: usize| {
                    u32::from_le_bytes([t[4 * k], t[4 * k + 1], t[4 * k + 2], t[4 * k + 3]])
                };
                [at(0), at(1), at(2)]
            })
            .collect(),
    })
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Index lists of every size, at offsets in their views and buffer, read packed give
    /// what the gltf crate's reader gives; a sparse accessor, a count that is no whole
    /// number of triangles and lists past their view are left to the reader.
    #[test]
    fn packed_indices_read_as_the_reader_does() {
        let mut data = vec![0xEEu8; 8];
        let u8s: Vec<u8> = (0..12).map(|i| (i * 37 % 251) as u8).collect();
        data.extend(&u8s);
        let u16s: Vec<u8> = (0..12u16).flat_map(|i| (i * 5003 + 7).to_le_bytes()).collect();
        data.extend(&u16s);
        let u32s: Vec<u8> = (0..12u32).flat_map(|i| (i * 0x0101_0101 + 3).to_le_bytes()).collect();
        data.extend(&u32s);
        let json = serde_json::json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": data.len()}],
            "bufferViews": [
                {"buffer": 0, "byteOffset": 4, "byteLength": 16},
                {"buffer": 0, "byteOffset": 20, "byteLength": 24},
                {"buffer": 0, "byteOffset": 44, "byteLength": 48},
            ],
            "accessors": [
                {"bufferView": 0, "byteOffset": 4, "componentType": 5121, "count": 12, "type": "SCALAR"},
                {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"},
                {"bufferView": 1, "byteOffset": 6, "componentType": 5123, "count": 9, "type": "SCALAR"},
                {"bufferView": 2, "componentType": 5125, "count": 12, "type": "SCALAR"},
                {"bufferView": 2, "componentType": 5125, "count": 10, "type": "SCALAR"},
                {"bufferView": 2, "byteOffset": 12, "componentType": 5125, "count": 12, "type": "SCALAR"},
                {"bufferView": 1, "byteOffset": 6, "componentType": 5123, "count": 12, "type": "SCALAR"},
                {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR",
                 "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5121},
                            "values": {"bufferView": 1}}},
            ],
        });
        let document = gltf::Document::from_json_without_validation(
            serde_json::from_value(json).expect("a glTF root"),
        );
        let buffers = [Bytes::from(data)];
        let packed: Vec<Option<Vec<[u32; 3]>>> =
            document.accessors().map(|a| packed_triangles(&a, &buffers)).collect();
        for (a, packed) in document.accessors().zip(&packed).take(4) {
            let expected = match a.data_type() {
                DataType::U8 => reader_values::<u8>(&a, &buffers),
                DataType::U16 => reader_values::<u16>(&a, &buffers),
                _ => reader_values::<u32>(&a, &buffers),
            };
            assert_eq!(expected.len(), a.count(), "accessor {}", a.index());
            let packed = packed.as_ref().unwrap_or_else(|| panic!("accessor {}", a.index()));
            assert_eq!(packed.as_flattened(), expected, "accessor {}", a.index());
        }
        // 10 indices; 12 from byte 12 of a 48-byte view (past the buffer too); 12 from byte 6
        // of a 24-byte view (within the buffer); a sparse accessor.
        assert_eq!(packed[4..], [None, None, None, None]);
    }

    /// The values of `accessor` as the gltf crate's reader gives them.
    fn reader_values<T: gltf::accessor::Item + Into<u32>>(
        accessor: &gltf::Accessor<'_>,
        buffers: &[Bytes],
    ) -> Vec<u32> {
        let get = |b: gltf::Buffer<'_>| buffers.get(b.index()).map(|d| &d[..]);
        gltf::accessor::Iter::<T>::new(accessor.clone(), get)
            .map(|values| values.map(Into::into).collect())
            .unwrap_or_default()
    }
}
