//! Meshes to objects: one object per mesh instance (node) per material part, triangulated by
//! ufbx, with a vertex per distinct combination of a corner's position and attribute
//! indices (FBX stores each attribute with its own index per face corner).

use glam::{Mat4, Vec2, Vec3};
use rayon::prelude::*;
use seamlit_mesh::{MorphTarget, Object};

use super::nodes::Tree;
use super::scene::{f32_of, mat4};
use seamlit_asset::LoadOptions;
use seamlit_asset::Skin;
use seamlit_asset::error::IoError;
use seamlit_asset::error::fbx::FbxKind;

/// No index: the attribute is absent.
const NONE: u32 = u32::MAX;

/// The objects of every mesh instance, in node order, and the skins of the skinned ones;
/// each node's `objects`, `skin` and morph `weights` filled in. A skinned instance's objects
/// are in bind-pose model space (`skin.rs`).
///
/// # Errors
///
/// [`IoError::TooManyElements`] past `options.max_model_triangles` (counted over instances
/// before any is built) or `options.max_elements`; [`IoError::Fbx`] with
/// [`FbxKind::NotFinite`] for a position, normal or UV that is not finite.
pub(super) fn objects(
    root: &ufbx::SceneRoot,
    tree: &mut Tree,
    path: &std::path::Path,
    options: &LoadOptions,
) -> Result<(Vec<Object>, Vec<Skin>), IoError> {
    let scene: &ufbx::Scene = root;
    let instances: Vec<(usize, &ufbx::Node, &ufbx::Mesh)> = (0..tree.nodes.len())
        .filter_map(|i| {
            let node = scene.nodes.get(tree.typed[i])?;
            node.mesh.as_ref().map(|mesh| (i, node.as_ref(), mesh.as_ref()))
        })
        .collect();
    let total: usize = instances.iter().map(|(_, _, mesh)| mesh.num_triangles).sum();
    if total > options.max_model_triangles {
        return Err(IoError::TooManyElements {
            path: path.to_path_buf(),
            what: "the model (every mesh instance)".to_owned(),
            limit: options.max_model_triangles,
            actual: total,
        });
    }
    let mut parts = converted_parts(root, tree, &instances, path, options).into_iter();
    let mut objects = Vec::new();
    let mut skins = Vec::new();
    for (i, node, mesh) in instances {
        let transform = mat4(&node.geometry_to_world);
        let joint_of =
            |n: &ufbx::Node| tree.index.get(n.element.typed_id as usize).copied().flatten();
        let bound = super::skin::bound(node, mesh, i, joint_of);
        if let Some(bound) = &bound {
            tree.nodes[i].skin = Some(skins.len());
            skins.push(bound.skin.clone());
        }
        tree.nodes[i].weights =
            blend_shapes(mesh).map(|(channel, _)| f32_of(channel.weight)).collect();
        for part in mesh.material_parts.iter().filter(|p| p.num_triangles > 0) {
            let (mut object, corners) = parts.next().expect("a part converted per part")?;
            object.transform = (transform != Mat4::IDENTITY).then_some(transform);
            object.material = material_of(scene, node, mesh, part.index as usize);
            if let Some(bound) = &bound {
                bound.apply(&mut object, mesh, &corners);
            }
            tree.nodes[i].objects.push(objects.len());
            objects.push(object);
        }
    }
    Ok((objects, skins))
}

/// Every instance's material parts with triangles as objects with their morph targets, and
/// each object's vertices' corners, in instance and part order; converted on rayon's threads
/// (ufbx's scene is only read; each job finds its mesh from the root, which alone may be
/// shared between threads).
fn converted_parts(
    root: &ufbx::SceneRoot,
    tree: &Tree,
    instances: &[(usize, &ufbx::Node, &ufbx::Mesh)],
    path: &std::path::Path,
    options: &LoadOptions,
) -> Vec<Result<(Object, Vec<u32>), IoError>> {
    // (the node's index in ufbx's nodes, the part's index in its mesh's parts, its name)
    let mut jobs: Vec<(usize, usize, String)> = Vec::new();
    for &(i, _, mesh) in instances {
        let parts = mesh.material_parts.iter().filter(|p| p.num_triangles > 0).count();
        for (k, part) in mesh.material_parts.iter().enumerate().filter(|(_, p)| p.num_triangles > 0)
        {
            let base = &tree.nodes[i].name;
            let name = if parts > 1 { format!("{base}.{}", part.index) } else { base.clone() };
            jobs.push((tree.typed[i], k, name));
        }
    }
    jobs.into_par_iter()
        .map(|(node, part, name)| {
            let mesh = root.nodes[node].mesh.as_ref().expect("a node with a mesh");
            let (mut object, corners) =
                part_object(mesh, &mesh.material_parts[part], name, path, options)?;
            object.morph_targets = morph_targets(mesh, &corners);
            // Kept for the skin's weights only (`skin::bound` needs a skin deformer): the
            // others' lists are freed here, not held until every part is done.
            let corners = if mesh.skin_deformers.is_empty() { Vec::new() } else { corners };
            Ok((object, corners))
        })
        .collect()
}

/// The index in the scene's materials of material slot `slot` of a mesh instance: the node's
/// own list where it has one (FBX materials belong to the instance), else the mesh's.
fn material_of(
    scene: &ufbx::Scene,
    node: &ufbx::Node,
    mesh: &ufbx::Mesh,
    slot: usize,
) -> Option<usize> {
    let material = if node.materials.is_empty() {
        mesh.materials.get(slot)
    } else {
        node.materials.get(slot)
    }?;
    let index = material.element.typed_id as usize;
    (index < scene.materials.len()).then_some(index)
}

/// The attributes of a mesh that an object carries, each with its per-corner index list.
struct Attributes<'m> {
    normal: Option<&'m ufbx::VertexVec3>,
    uv0: Option<&'m ufbx::VertexVec2>,
    uv1: Option<&'m ufbx::VertexVec2>,
    color: Option<&'m ufbx::VertexVec4>,
    /// Tangent and bitangent of the first UV set (both, and normals, or neither).
    tangent: Option<(&'m ufbx::VertexVec3, &'m ufbx::VertexVec3)>,
}

impl<'m> Attributes<'m> {
    fn of(mesh: &'m ufbx::Mesh) -> Self {
        let normal = Some(&mesh.vertex_normal).filter(|a| a.exists);
        let uv = |k: usize| mesh.uv_sets.get(k).map(|s| &s.vertex_uv).filter(|a| a.exists);
        let tangent = mesh.uv_sets.first().and_then(|s| {
            (normal.is_some() && s.vertex_tangent.exists && s.vertex_bitangent.exists)
                .then_some((&s.vertex_tangent, &s.vertex_bitangent))
        });
        Self {
            normal,
            uv0: uv(0),
            uv1: uv(1),
            color: Some(&mesh.vertex_color).filter(|a| a.exists),
            tangent,
        }
    }

    /// The attributes' per-corner value index lists, as [`Keys`].
    fn keys(&self) -> Keys<'m> {
        fn list(indices: Option<&ufbx::List<u32>>) -> &[u32] {
            indices.map_or(&[], |i| i.as_ref())
        }
        Keys([
            list(self.normal.map(|a| &a.indices)),
            list(self.uv0.map(|a| &a.indices)),
            list(self.uv1.map(|a| &a.indices)),
            list(self.color.map(|a| &a.indices)),
            list(self.tangent.map(|(t, _)| &t.indices)),
            list(self.tangent.map(|(_, b)| &b.indices)),
        ])
    }
}

/// The attributes' per-corner value index lists (normal, UV sets 0 and 1, colour, tangent,
/// bitangent), each empty where the attribute is absent.
struct Keys<'m>([&'m [u32]; 6]);

impl Keys<'_> {
    /// What makes corner `c` a vertex of its own, besides its position: its attributes'
    /// value indices ([`NONE`] where absent), two to a word (compared in registers).
    fn of(&self, c: usize) -> [u64; 3] {
        let at = |k: usize| u64::from(self.0[k].get(c).copied().unwrap_or(NONE));
        [at(0) | at(1) << 32, at(2) | at(3) << 32, at(4) | at(5) << 32]
    }

    /// Whether two keys are equal, word by word (`==` on the arrays compares them as one
    /// 16-byte load of the key just built, which waits for its two stores).
    fn same(a: &[u64; 3], b: &[u64; 3]) -> bool {
        (a[0] ^ b[0]) | (a[1] ^ b[1]) | (a[2] ^ b[2]) == 0
    }
}

/// One material part of a mesh as an object in the mesh's geometry space.
fn part_object(
    mesh: &ufbx::Mesh,
    part: &ufbx::MeshPart,
    name: String,
    path: &std::path::Path,
    options: &LoadOptions,
) -> Result<(Object, Vec<u32>), IoError> {
    let attributes = Attributes::of(mesh);
    let too_many = |what: &str, actual: usize| IoError::TooManyElements {
        path: path.to_path_buf(),
        what: format!("{what} of mesh {name:?}"),
        limit: options.max_elements.min(u32::MAX as usize - 1),
        actual,
    };
    if part.num_triangles > options.max_elements {
        return Err(too_many("the triangles", part.num_triangles));
    }
    let limit = options.max_elements.min(u32::MAX as usize - 1);
    let mut vertices = Vertices::new(mesh, attributes.keys(), limit);
    let mut vertex_of = |c| vertices.of(c).map_err(|count| too_many("the vertices", count));
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(part.num_triangles);
    let mut scratch = vec![0u32; mesh.max_face_triangles * 3];
    for &face in part.face_indices.iter() {
        let Some(&face) = mesh.faces.get(face as usize) else { continue };
        if face.num_indices < 3 {
            continue;
        }
        let n = ufbx::triangulate_face(&mut scratch, mesh, face) as usize;
        // The vertices of the face's first four corners, each found once (a quad's two
        // triangles name its four corners six times); found in the triangles' order, so
        // numbered as they would be without.
        let mut found = [NONE; 4];
        let mut vertex_at = |c: u32| -> Result<u32, IoError> {
            match found.get_mut(c.wrapping_sub(face.index_begin) as usize) {
                Some(v) if *v != NONE => Ok(*v),
                Some(v) => {
                    *v = vertex_of(c)?;
                    Ok(*v)
                }
                None => vertex_of(c),
            }
        };
        for t in scratch[..3 * n].as_chunks::<3>().0 {
            let triangle = [vertex_at(t[0])?, vertex_at(t[1])?, vertex_at(t[2])?];
            if triangle.contains(&NONE) {
                continue;
            }
            triangles.push(triangle);
        }
    }
    let corners = vertices.corners;
    let object = build(mesh, &attributes, &corners, triangles, name);
    check_finite(&object, path)?;
    Ok((object, corners))
}

/// A part's vertices so far: each one's first corner and key, chained per position.
struct Vertices<'m> {
    mesh: &'m ufbx::Mesh,
    keys_of: Keys<'m>,
    /// Per position, its last vertex; per vertex, the one before it at its position.
    head: Vec<u32>,
    next: Vec<u32>,
    keys: Vec<[u64; 3]>,
    corners: Vec<u32>,
    /// The most vertices a part may have.
    limit: usize,
}

impl<'m> Vertices<'m> {
    fn new(mesh: &'m ufbx::Mesh, keys_of: Keys<'m>, limit: usize) -> Self {
        let head = vec![NONE; mesh.num_vertices];
        Self { mesh, keys_of, head, next: Vec::new(), keys: Vec::new(), corners: Vec::new(), limit }
    }

    /// The vertex of corner `c`: an earlier corner's with its position and key, else a new
    /// one; [`NONE`] for a corner whose position is out of range.
    ///
    /// # Errors
    ///
    /// The count of vertices there would be, past the limit.
    fn of(&mut self, c: u32) -> Result<u32, usize> {
        let position = self.mesh.vertex_indices.get(c as usize).copied().unwrap_or(0) as usize;
        let key = self.keys_of.of(c as usize);
        let Some(slot) = self.head.get_mut(position) else { return Ok(NONE) };
        let mut v = *slot;
        while v != NONE {
            if Keys::same(&self.keys[v as usize], &key) {
                return Ok(v);
            }
            v = self.next[v as usize];
        }
        let new = self.corners.len();
        if new >= self.limit {
            return Err(new + 1);
        }
        #[expect(clippy::cast_possible_truncation, reason = "below u32::MAX, checked above")]
        let new = new as u32;
        self.next.push(*slot);
        *slot = new;
        self.keys.push(key);
        self.corners.push(c);
        Ok(new)
    }
}

/// The blend shapes of a mesh as morph targets, one per blend channel with a target shape
/// (the shape at full weight; in-between shapes are not read), in the mesh's deformer and
/// channel order, named after the channel: per vertex, the offset of its position
/// (`corners`: each vertex's corner).
pub(super) fn morph_targets(mesh: &ufbx::Mesh, corners: &[u32]) -> Vec<MorphTarget> {
    blend_shapes(mesh)
        .map(|(channel, shape)| MorphTarget {
            name: channel.element.name.to_string(),
            position_deltas: corners
                .iter()
                .map(|&c| {
                    let vertex = mesh.vertex_indices.get(c as usize).copied().unwrap_or(0);
                    let d = ufbx::get_blend_shape_vertex_offset(shape, vertex as usize);
                    glam::DVec3::new(d.x, d.y, d.z).as_vec3()
                })
                .collect(),
            ..MorphTarget::default()
        })
        .collect()
}

/// The blend channels of a mesh that have a target shape, with it, in order.
pub(super) fn blend_shapes(
    mesh: &ufbx::Mesh,
) -> impl Iterator<Item = (&ufbx::BlendChannel, &ufbx::BlendShape)> {
    mesh.blend_deformers.iter().flat_map(|deformer| {
        deformer.channels.iter().filter_map(|channel| {
            channel.target_shape.as_ref().map(|shape| (channel.as_ref(), shape.as_ref()))
        })
    })
}

/// Refuses positions, normals and UVs that are not finite (NaN or infinite), which no
/// step after loading can use.
///
/// # Errors
///
/// [`IoError::Fbx`] with [`FbxKind::NotFinite`].
fn check_finite(object: &Object, path: &std::path::Path) -> Result<(), IoError> {
    let bad = |what: &'static str| IoError::Fbx {
        path: path.to_path_buf(),
        kind: FbxKind::NotFinite { mesh: object.name.clone(), what },
    };
    if !object.positions.iter().all(|p| p.is_finite()) {
        return Err(bad("a vertex position"));
    }
    if !object.normals.iter().flatten().all(|n| n.is_finite()) {
        return Err(bad("a normal"));
    }
    let mut uvs = object.uvs.iter().chain(&object.uvs1).flatten();
    if !uvs.all(|uv| uv.is_finite()) {
        return Err(bad("a texture coordinate"));
    }
    Ok(())
}

/// The object whose vertex `v` takes every attribute of corner `corners[v]`.
fn build(
    mesh: &ufbx::Mesh,
    attributes: &Attributes<'_>,
    corners: &[u32],
    triangles: Vec<[u32; 3]>,
    name: String,
) -> Object {
    let v3 = |v: ufbx::Vec3| glam::DVec3::new(v.x, v.y, v.z).as_vec3();
    let v2 = |v: ufbx::Vec2| glam::DVec2::new(v.x, v.y).as_vec2();
    let at = |c: u32| c as usize;
    let positions: Vec<Vec3> = corners.iter().map(|&c| v3(mesh.vertex_position[at(c)])).collect();
    let normals: Option<Vec<Vec3>> =
        attributes.normal.map(|a| corners.iter().map(|&c| v3(a[at(c)])).collect());
    let uvs = |set: Option<&ufbx::VertexVec2>| -> Option<Vec<Vec2>> {
        set.map(|a| corners.iter().map(|&c| v2(a[at(c)])).collect())
    };
    let colors = attributes.color.map(|a| {
        corners
            .iter()
            .map(|&c| {
                let v = a[at(c)];
                glam::DVec4::new(v.x, v.y, v.z, v.w).as_vec4()
            })
            .collect()
    });
    let tangents = attributes.tangent.zip(normals.as_ref()).map(|((t, b), normals)| {
        corners
            .iter()
            .zip(normals)
            .map(|(&c, &n)| {
                let (t, b) = (v3(t[at(c)]), v3(b[at(c)]));
                let w = if n.cross(t).dot(b) < 0.0 { -1.0 } else { 1.0 };
                t.extend(w)
            })
            .collect()
    });
    Object {
        uvs: uvs(attributes.uv0),
        uvs1: uvs(attributes.uv1),
        normals,
        colors,
        tangents,
        ..Object::new(name, positions, triangles)
    }
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;
    use std::path::Path;

    use super::*;

    /// A part's triangles and each vertex's corner as the module's doc states them, written
    /// plainly: every corner of every triangle in turn, a new vertex at the first corner of
    /// each distinct position and set of attribute indices.
    fn plainly(mesh: &ufbx::Mesh, part: &ufbx::MeshPart) -> (Vec<[u32; 3]>, Vec<u32>) {
        let index = |list: &ufbx::List<u32>, c: usize| list.get(c).copied();
        let tangents = mesh.uv_sets.first().filter(|s| {
            mesh.vertex_normal.exists && s.vertex_tangent.exists && s.vertex_bitangent.exists
        });
        let key = |c: usize| {
            let uv = |k: usize| {
                mesh.uv_sets
                    .get(k)
                    .filter(|s| s.vertex_uv.exists)
                    .and_then(|s| index(&s.vertex_uv.indices, c))
            };
            let color = Some(&mesh.vertex_color).filter(|a| a.exists);
            (
                mesh.vertex_indices[c],
                Some(&mesh.vertex_normal).filter(|a| a.exists).and_then(|a| index(&a.indices, c)),
                (uv(0), uv(1), color.and_then(|a| index(&a.indices, c))),
                tangents.map(|s| {
                    (index(&s.vertex_tangent.indices, c), index(&s.vertex_bitangent.indices, c))
                }),
            )
        };
        let mut vertex = HashMap::new();
        let (mut triangles, mut corners) = (Vec::new(), Vec::new());
        let mut scratch = vec![0u32; mesh.max_face_triangles * 3];
        for &face in part.face_indices.iter() {
            let face = mesh.faces[face as usize];
            let n = ufbx::triangulate_face(&mut scratch, mesh, face) as usize;
            for t in scratch[..3 * n].as_chunks::<3>().0 {
                triangles.push(t.map(|c| {
                    *vertex.entry(key(c as usize)).or_insert_with(|| {
                        corners.push(c);
                        u32::try_from(corners.len() - 1).unwrap()
                    })
                }));
            }
        }
        (triangles, corners)
    }

    #[test]
    fn corners_differing_in_any_one_attribute_have_different_keys() {
        // Corner 0 has index 0 in every list; corner k + 1 has 1 in list k alone.
        let lists: Vec<Vec<u32>> =
            (0..6).map(|k| (0..7).map(|c| u32::from(c == k + 1)).collect()).collect();
        let keys = Keys(std::array::from_fn(|k| lists[k].as_slice()));
        for a in 0..7 {
            for b in 0..7 {
                assert_eq!(Keys::same(&keys.of(a), &keys.of(b)), a == b, "corners {a} and {b}");
            }
        }
        // An absent attribute (an empty list) is the same at every corner.
        let absent = Keys([&[0, 1], &[], &[], &[], &[], &[]]);
        assert!(Keys::same(&absent.of(1), &Keys([&[1], &[], &[], &[], &[], &[]]).of(0)));
    }

    #[test]
    fn parts_have_a_vertex_per_distinct_corner_numbered_as_first_met() {
        let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models");
        let mut faces_over_three = 0;
        for file in [
            "lowpoly/kenney-castle-towerBase.fbx",
            "lowpoly/quaternius-ambulance.fbx",
            "ufbx/blender_279_uv_set_tangents_7400_binary.fbx",
            "ufbx/maya_blend_shape_cube_6100_ascii.fbx",
        ] {
            let path = models.join(file);
            let bytes = std::fs::read(&path).unwrap();
            let scene = super::super::scene::open(super::super::scene::Input::Bytes(&bytes), &path)
                .unwrap();
            for mesh in &scene.meshes {
                faces_over_three += mesh.faces.iter().filter(|f| f.num_indices > 3).count();
                for part in mesh.material_parts.iter().filter(|p| p.num_triangles > 0) {
                    let (object, corners) =
                        part_object(mesh, part, "part".into(), &path, &LoadOptions::default())
                            .unwrap();
                    let (triangles, want) = plainly(mesh, part);
                    assert_eq!(object.triangles, triangles, "{file}");
                    assert_eq!(corners, want, "{file}");
                }
            }
        }
        assert!(faces_over_three > 100, "quads and polygons among the faces: {faces_over_three}");
    }

    #[test]
    fn a_part_past_the_vertex_limit_is_refused_with_its_count() {
        // A cube: 12 triangles, 24 vertices (each corner's normal is its face's).
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/models/ufbx/maya_cube_6100_ascii.fbx");
        let bytes = std::fs::read(&path).unwrap();
        let scene =
            super::super::scene::open(super::super::scene::Input::Bytes(&bytes), &path).unwrap();
        let mesh = &scene.meshes[0];
        let part = &mesh.material_parts[0];
        assert_eq!(part.num_triangles, 12);
        let options = |max_elements| LoadOptions { max_elements, ..LoadOptions::default() };
        let (object, _) = part_object(mesh, part, "cube".into(), &path, &options(24)).unwrap();
        assert_eq!(object.positions.len(), 24);
        let err = part_object(mesh, part, "cube".into(), &path, &options(12)).unwrap_err();
        let IoError::TooManyElements { what, limit, actual, .. } = err else { panic!("{err}") };
        assert_eq!((what.as_str(), limit, actual), ("the vertices of mesh \"cube\"", 12, 13));
    }
}
