//! The scene walk: every triangle primitive of every mesh instance becomes an object, placed
//! by the composition of the node transforms above it, and every node a [`Node`].

use std::collections::HashMap;

use bytes::Bytes;
use glam::Mat4;
use gltf::mesh::Mode;
use rayon::prelude::*;
use seamlit_mesh::Object;

use super::{Reader, deform};
use crate::source::Instance;
use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::GltfKind;
use seamlit_asset::{Asset, Node};

/// The walk over a scene's node tree that makes an object of every triangle primitive of
/// every mesh instance (a mesh used by two nodes is two objects) and a [`Node`] of every
/// node.
pub(super) struct SceneWalk<'r> {
    reader: &'r Reader<'r>,
    buffers: &'r [Bytes],
    without_data: &'r [usize],
    /// Decoded primitives by (mesh, primitive): the object of their first instance, cloned
    /// for the other nodes that instance the mesh.
    decoded: HashMap<(usize, usize), usize>,
    /// Primitives decoded ahead of the walk ([`Self::decode_ahead`]), with the warnings
    /// their decoding gave, each taken by the walk where it first reaches it.
    ahead: HashMap<(usize, usize), Decoded>,
    /// Their skin influences as read (joints index the skin's `joints`), mapped per instance.
    influences: HashMap<(usize, usize), Vec<seamlit_mesh::Influences>>,
    /// Per object: where it came from in the document, for the pass-through writer.
    pub(super) instances: Vec<Instance>,
    /// Triangles placed so far, instances counted.
    triangles: usize,
    /// Per document node: its index in [`Asset::nodes`], where the walk reached it.
    pub(super) node_indices: HashMap<usize, usize>,
}

impl<'r> SceneWalk<'r> {
    pub(super) fn new(
        reader: &'r Reader<'r>,
        buffers: &'r [Bytes],
        without_data: &'r [usize],
    ) -> Self {
        Self {
            reader,
            buffers,
            without_data,
            decoded: HashMap::new(),
            ahead: HashMap::new(),
            influences: HashMap::new(),
            instances: Vec::new(),
            triangles: 0,
            node_indices: HashMap::new(),
        }
    }

    /// Decodes, on rayon's threads, every triangle primitive with data of the meshes the
    /// trees under `roots` reach: the walk then takes each where it first reaches it, with
    /// its warnings and its error in the walk's order, so that what the walk says is as if
    /// it had decoded them itself, one after another.
    pub(super) fn decode_ahead(&mut self, roots: &[gltf::Node<'_>]) {
        let mut jobs: Vec<(gltf::Mesh<'_>, gltf::Primitive<'_>)> = Vec::new();
        for mesh in reached_meshes(roots) {
            for primitive in mesh.primitives() {
                if is_triangles(&primitive)
                    && super::lenient::without_data(&primitive, self.without_data).is_none()
                {
                    jobs.push((mesh.clone(), primitive));
                }
            }
        }
        if jobs.len() < 2 {
            return; // nothing to share between threads: the walk decodes it
        }
        let (reader, buffers) = (self.reader, self.buffers);
        self.ahead = jobs
            .into_par_iter()
            .map(|(mesh, primitive)| {
                let mut warnings = Vec::new();
                let object = reader.primitive(&mesh, &primitive, buffers, &mut warnings);
                ((mesh.index(), primitive.index()), Decoded { object, warnings })
            })
            .collect();
    }

    /// Walks the trees under `roots` depth first, in document order, pushing the nodes and
    /// objects into `asset`.
    ///
    /// # Errors
    ///
    /// [`IoError::Gltf`] for a node reached twice (a cycle, or two parents); the errors of
    /// [`Self::mesh_instance`].
    pub(super) fn walk<'d>(
        &mut self,
        roots: Vec<gltf::Node<'d>>,
        asset: &mut Asset,
        warnings: &mut Vec<String>,
    ) -> Result<(), IoError> {
        let path = self.reader.path;
        let mut stack: Vec<(gltf::Node<'d>, Option<usize>, Mat4)> =
            roots.into_iter().rev().map(|n| (n, None, Mat4::IDENTITY)).collect();
        let mut visited = std::collections::HashSet::new();
        while let Some((node, parent, parent_global)) = stack.pop() {
            if !visited.insert(node.index()) {
                return Err(IoError::Gltf {
                    path: path.to_path_buf(),
                    place: format!("nodes[{}]", node.index()),
                    kind: GltfKind::NodeReachedTwice,
                });
            }
            let local = Mat4::from_cols_array_2d(&node.transform().matrix());
            let global = parent_global * local;
            let node_index = asset.nodes.len();
            let objects = match node.mesh() {
                Some(mesh) => self.mesh_instance(&node, &mesh, global, asset, warnings)?,
                None => Vec::new(),
            };
            let trs = match node.transform() {
                gltf::scene::Transform::Decomposed { translation, rotation, scale } => {
                    Some(seamlit_asset::Trs {
                        translation: translation.into(),
                        rotation: glam::Quat::from_array(rotation),
                        scale: scale.into(),
                    })
                }
                gltf::scene::Transform::Matrix { .. } => None,
            };
            let weights = node
                .weights()
                .or_else(|| node.mesh().and_then(|m| m.weights()))
                .map(<[f32]>::to_vec)
                .unwrap_or_default();
            self.node_indices.insert(node.index(), node_index);
            asset.nodes.push(Node {
                objects,
                trs,
                skin: node.skin().map(|s| s.index()),
                weights,
                ..Node::new(node.name().unwrap_or_default(), local, parent)
            });
            for child in node.children().collect::<Vec<_>>().into_iter().rev() {
                stack.push((child, Some(node_index), global));
            }
        }
        Ok(())
    }

    /// The objects of one node's mesh, one per triangle primitive, placed at `global` (a
    /// skinned mesh at its bind pose); returns their indices in `asset.model.objects`.
    fn mesh_instance(
        &mut self,
        node: &gltf::Node<'_>,
        mesh: &gltf::Mesh<'_>,
        global: Mat4,
        asset: &mut Asset,
        warnings: &mut Vec<String>,
    ) -> Result<Vec<usize>, IoError> {
        let path = self.reader.path;
        let mut objects = Vec::new();
        for primitive in mesh.primitives() {
            let Some(mut object) = self.first_object(mesh, &primitive, asset, warnings)? else {
                continue;
            };
            let key = (mesh.index(), primitive.index());
            let read = self.influences.entry(key).or_insert_with(|| object.skin.clone());
            object.skin = deform::joint_nodes(read, node, path)?;
            // Instancing multiplies triangles without costing file bytes: capped.
            self.triangles = self.triangles.saturating_add(object.triangles.len());
            let limit = self.reader.options.max_model_triangles;
            if self.triangles > limit {
                return Err(IoError::TooManyElements {
                    path: path.to_path_buf(),
                    what: format!("the model (mesh instances up to nodes[{}])", node.index()),
                    limit,
                    actual: self.triangles,
                });
            }
            // A skinned mesh is placed by its joints, never by its node (glTF 2.0,
            // "Skins"): it is welded in its bind-pose space.
            let placed = if node.skin().is_some() { Mat4::IDENTITY } else { global };
            objects.push(asset.model.objects.len());
            self.instances.push(Instance {
                node: node.index(),
                mesh: mesh.index(),
                primitive: primitive.index(),
            });
            asset.model.objects.push(Object {
                name: object_name(node, mesh, &primitive),
                transform: (placed != Mat4::IDENTITY).then_some(placed),
                ..object
            });
        }
        Ok(objects)
    }

    /// The object of a primitive as its first instance read it (a clone for the others), or
    /// `None`, with a warning, for a primitive that is not a triangle list or whose data is
    /// not in the file.
    fn first_object(
        &mut self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        asset: &Asset,
        warnings: &mut Vec<String>,
    ) -> Result<Option<Object>, IoError> {
        let (path, m, p) = (self.reader.path.display(), mesh.index(), primitive.index());
        if !is_triangles(primitive) {
            warnings.push(format!(
                "{path}: mesh {m} primitive {p}: mode {:?} skipped (only triangles are read)",
                primitive.mode()
            ));
            return Ok(None);
        }
        if let Some(&first) = self.decoded.get(&(m, p)) {
            return Ok(Some(asset.model.objects[first].clone()));
        }
        if let Some(reason) = super::lenient::without_data(primitive, self.without_data) {
            warnings.push(format!("{path}: mesh {m} primitive {p} skipped: {reason}"));
            return Ok(None);
        }
        let object = match self.ahead.remove(&(m, p)) {
            Some(Decoded { object, warnings: mut said }) => {
                warnings.append(&mut said);
                object?
            }
            None => self.reader.primitive(mesh, primitive, self.buffers, warnings)?,
        };
        if object.is_some() {
            self.decoded.insert((m, p), asset.model.objects.len());
        }
        Ok(object)
    }
}

/// Whether the primitive is one of triangles (a list, a strip or a fan): the ones read.
fn is_triangles(primitive: &gltf::Primitive<'_>) -> bool {
    matches!(primitive.mode(), Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)
}

/// A primitive decoded ahead of the walk: what [`Reader::primitive`] gave, and the warnings
/// it said.
///
/// [`Reader::primitive`]: super::Reader
struct Decoded {
    object: Result<Option<Object>, IoError>,
    warnings: Vec<String>,
}

/// The meshes of the nodes under `roots`, each once, in the order the walk first reaches
/// them (depth first, in document order; a node reached twice is the walk's error to give).
fn reached_meshes<'d>(roots: &[gltf::Node<'d>]) -> Vec<gltf::Mesh<'d>> {
    let mut stack: Vec<gltf::Node<'d>> = roots.iter().rev().cloned().collect();
    let (mut visited, mut seen) =
        (std::collections::HashSet::new(), std::collections::HashSet::new());
    let mut meshes = Vec::new();
    while let Some(node) = stack.pop() {
        if !visited.insert(node.index()) {
            continue;
        }
        if let Some(mesh) = node.mesh().filter(|m| seen.insert(m.index())) {
            meshes.push(mesh);
        }
        stack.extend(node.children().collect::<Vec<_>>().into_iter().rev());
    }
    meshes
}

/// An object's name: its node's (else its mesh's, else `mesh{index}`), with `.{primitive}`
/// appended when the mesh has several primitives.
fn object_name(
    node: &gltf::Node<'_>,
    mesh: &gltf::Mesh<'_>,
    primitive: &gltf::Primitive<'_>,
) -> String {
    let base = node
        .name()
        .filter(|n| !n.is_empty())
        .or_else(|| mesh.name().filter(|n| !n.is_empty()))
        .map_or_else(|| format!("mesh{}", mesh.index()), str::to_owned);
    if mesh.primitives().len() > 1 { format!("{base}.{}", primitive.index()) } else { base }
}
