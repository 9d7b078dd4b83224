//! What [`crate::fix_in_place`] did to each object: whose authored normals and tangents it
//! kept, how many normals it changed, how many vertices it split.

use serde::{Deserialize, Serialize};

/// What a fix changed, object by object (in the model's order).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Changes {
    /// One entry per object.
    pub objects: Vec<ObjectChanges>,
    /// What the seam-only repair decided at the positions that objects with kept normals
    /// share (all zero where it did not run).
    #[serde(default)]
    pub shared: SharedNormals,
}

/// What the seam-only repair of [`crate::NormalPolicy::Auto`] decided at the positions that
/// two or more objects share (after the weld), counted once per position. Each position is in
/// exactly one class, the first that applies, in this order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SharedNormals {
    /// Positions where at least one group of copies from two or more objects, each carrying
    /// its own object's smooth normal (per-object smoothing), was given one normal: the
    /// seams the paper is about.
    pub repaired: usize,
    /// Positions kept as authored hard edges: a copy carries its own face's normal (flat
    /// shading), or smooth copies meet at more than the crease angle.
    pub hard_edges: usize,
    /// Positions kept because a copy carries a normal that is neither flat nor its object's
    /// smooth normal (custom, weighted or edited normals: the artist's).
    pub custom: usize,
    /// Positions whose copies already carry the same normal (within rounding: 0.05 degrees):
    /// nothing to do.
    pub agreeing: usize,
}

impl SharedNormals {
    /// All positions visited.
    #[must_use]
    pub fn positions(&self) -> usize {
        self.repaired + self.hard_edges + self.custom + self.agreeing
    }
}

/// What a fix changed in one object.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ObjectChanges {
    /// The object's name.
    pub name: String,
    /// Whether the object's authored normals were kept (then only the seam repair of
    /// [`crate::NormalPolicy::Auto`] changes some of them); `false`: computed.
    pub kept_normals: bool,
    /// Whether the object's authored tangents were kept (re-orthogonalised where the normal
    /// changed); `false`: computed, or none (no UVs, or [`crate::TangentMethod::None`]).
    pub kept_tangents: bool,
    /// Vertices the object had before the fix.
    pub vertices: usize,
    /// Of those, vertices whose normal is no longer the input one bit for bit (every vertex
    /// of an object that had no normals).
    pub normals_changed: usize,
    /// Vertices appended as copies of others (see [`crate::Object::split_from`]).
    pub vertices_split: usize,
}

impl Changes {
    /// Objects whose authored normals were kept.
    #[must_use]
    pub fn kept_objects(&self) -> usize {
        self.objects.iter().filter(|o| o.kept_normals).count()
    }

    /// Input vertices over all objects.
    #[must_use]
    pub fn vertices(&self) -> usize {
        self.objects.iter().map(|o| o.vertices).sum()
    }

    /// Vertices whose normal changed, over all objects.
    #[must_use]
    pub fn normals_changed(&self) -> usize {
        self.objects.iter().map(|o| o.normals_changed).sum()
    }

    /// Vertices split, over all objects.
    #[must_use]
    pub fn vertices_split(&self) -> usize {
        self.objects.iter().map(|o| o.vertices_split).sum()
    }
}
