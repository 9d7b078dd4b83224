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

    /// What makes corner `c` a vertex of its own, besides its position: its attributes'
    /// value indices.
    fn key(&self, c: usize) -> [u32; 6] {
        fn at(indices: Option<&ufbx::List<u32>>, c: usize) -> u32 {
            indices.and_then(|i| i.get(c).copied()).unwrap_or(NONE)
        }
        [
            at(self.normal.map(|a| &a.indices), c),
            at(self.uv0.map(|a| &a.indices), c),
            at(self.uv1.map(|a| &a.indices), c),
            at(self.color.map(|a| &a.indices), c),
            at(self.tangent.map(|(t, _)| &t.indices), c),
            at(self.tangent.map(|(_, b)| &b.indices), c),
        ]
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
    // The vertices so far: each's first corner and key, chained per position.
    let mut head = vec![NONE; mesh.num_vertices];
    let mut next: Vec<u32> = Vec::new();
    let mut keys: Vec<[u32; 6]> = Vec::new();
    let mut corners: Vec<u32> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(part.num_triangles);
    let mut scratch = vec![0u32; mesh.max_face_triangles * 3];
    let mut vertex_of = |c: u32| -> Result<u32, IoError> {
        let c = c as usize;
        let position = mesh.vertex_indices.get(c).copied().unwrap_or(0) as usize;
        let key = attributes.key(c);
        let Some(slot) = head.get_mut(position) else { return Ok(NONE) };
        let mut v = *slot;
        while v != NONE {
            if keys[v as usize] == key {
                return Ok(v);
            }
            v = next[v as usize];
        }
        let new = corners.len();
        if new >= options.max_elements.min(u32::MAX as usize - 1) {
            return Err(too_many("the vertices", new + 1));
        }
        #[expect(clippy::cast_possible_truncation, reason = "below u32::MAX, checked above")]
        let new = new as u32;
        next.push(*slot);
        *slot = new;
        keys.push(key);
        #[expect(clippy::cast_possible_truncation, reason = "ufbx's corner indices are u32")]
        corners.push(c as u32);
        Ok(new)
    };
    for &face in part.face_indices.iter() {
        let Some(&face) = mesh.faces.get(face as usize) else { continue };
        if face.num_indices < 3 {
            continue;
        }
        let n = ufbx::triangulate_face(&mut scratch, mesh, face) as usize;
        for t in scratch[..3 * n].as_chunks::<3>().0 {
            let triangle = [vertex_of(t[0])?, vertex_of(t[1])?, vertex_of(t[2])?];
            if triangle.contains(&NONE) {
                continue;
            }
            triangles.push(triangle);
        }
    }
    let object = build(mesh, &attributes, &corners, triangles, name);
    check_finite(&object, path)?;
    Ok((object, corners))
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
