//! What the `.usda` writer needs of a stage, kept by the reader in the asset's document
//! ([`UsdSource`]): the folders the stage's files were allowed to come from, how each object's
//! triangles map onto its mesh prim's face corners, and the root layer's stage metadata.
//! Types only (like seamlit-gltf's and seamlit-obj's sources).

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use seamlit_asset::files::Files;

/// How an OpenUSD stage was read, kept in [`seamlit_asset::Asset::document`]: the folders
/// besides the root layer's that its layers and textures were allowed to come from
/// ([`seamlit_asset::LoadOptions::asset_roots`]), and what the `.usda` writer needs of each
/// mesh (how the objects' triangles map onto the prims' face corners), so that it need not read
/// the stage again.
#[derive(Clone, Debug, Default)]
pub struct UsdSource {
    pub(crate) asset_roots: Vec<PathBuf>,
    pub(crate) stage: Option<Arc<StageSource>>,
    /// Where the stage's files were read from (a `.usdz` output packs the input's files from
    /// there).
    pub(crate) files: Files,
}

/// What the `.usda` writer needs of the stage: its meshes' sources, in the order of the
/// objects, and the root layer's stage metadata (which a layer over it must repeat: USD reads
/// stage metadata from the root layer only), as `(key, usda value)`.
#[derive(Clone, Debug, Default)]
pub(crate) struct StageSource {
    pub meshes: Vec<MeshSource>,
    pub metadata: Vec<(String, String)>,
    /// The joints that skinned objects' influences name: per id, (skeleton prim, joint path).
    pub joints: Vec<(String, String)>,
}

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
    /// Whether the prim is an instance proxy (its own properties cannot be overridden).
    pub instance_proxy: bool,
    /// For an instance proxy: its prototype, and where its normals can be written.
    pub instance: Option<InstanceSource>,
    /// For a mesh outside instances, in a stage that has instances: the sites in the root
    /// layer stack its opinions come from (its own path among them).
    pub root_sites: Vec<String>,
    /// Its attributes that decide its normals and are time-sampled (`points`,
    /// `primvars:normals`, ...): a value the layer writes would hold for every frame.
    pub time_sampled: Vec<String>,
    /// The skin binding the object's influences came from, for a skinned mesh.
    pub skin: Option<SkinSource>,
}

/// An instance proxy mesh: the prototype prim it stands for (`/__Prototype_1/Geom`), its
/// instance, and the path in the root layer stack where an `over` changes it in every
/// instance of that prototype (`/Prototypes/Crate/Geom`), or why there is none.
#[derive(Clone, Debug)]
pub(crate) struct InstanceSource {
    pub prototype: String,
    pub instance: String,
    pub site: Result<String, String>,
}

/// A skinned mesh's influences as authored (UsdSkelBindingAPI) and checked: what the reader
/// skins the mesh with and the writer puts matched influences back in terms of.
#[derive(Clone, Debug)]
pub(crate) struct SkinInfluences {
    /// The skeleton prim.
    pub skeleton: String,
    /// The joint ids (indices into [`StageSource::joints`]) the mesh's joint indices index,
    /// in its order.
    pub joints: Vec<u32>,
    /// Whether that order is a `skel:joints` of the mesh's own (or an ancestor's), which a
    /// writer may grow; else it is the skeleton's.
    pub own_order: bool,
    /// Influences per element (`elementSize`, 1 to 64).
    pub element_size: usize,
    /// Whether one element holds the whole mesh's influences (constant interpolation), not
    /// one per point (vertex).
    pub constant: bool,
    /// `primvars:skel:jointIndices` as authored (`element_size` per element), each checked to
    /// index `joints`.
    pub indices: Vec<i32>,
    /// `primvars:skel:jointWeights` as authored, as many as `indices`, finite.
    pub weights: Vec<f32>,
}

impl SkinInfluences {
    /// Point `p`'s influences as authored: (index into `joints`, weight), `element_size` of
    /// them.
    pub fn of_point(&self, p: usize) -> impl Iterator<Item = (u32, f32)> + '_ {
        let element = if self.constant { 0 } else { p };
        let range = element * self.element_size..(element + 1) * self.element_size;
        #[expect(clippy::cast_sign_loss, reason = "indices are checked non-negative")]
        self.indices[range.clone()].iter().zip(&self.weights[range]).map(|(&i, &w)| (i as u32, w))
    }
}

/// A skinned mesh's binding as read, so the writer can put matched influences back in the
/// mesh's own terms.
#[derive(Clone, Debug)]
pub(crate) struct SkinSource {
    pub influences: SkinInfluences,
    /// Per input vertex of the object: its point.
    pub vertex_point: Vec<u32>,
    /// The mesh's number of points.
    pub points: usize,
}
