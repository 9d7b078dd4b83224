//! A mesh's normals at its face corners as the layer authors them: indexed, the distinct
//! values (by their bits, in order of first use) and each corner's index into them
//! (`primvars:normals` and `primvars:normals:indices`).
//!
//! Most corners take the normal of a vertex, and a vertex is the normal of several corners
//! (six in a grid): each vertex's value is looked up by its bits once and remembered, not once
//! per corner. The values and indices are those of indexing every corner's normal in turn.

use glam::Vec3;
use rustc_hash::FxHashMap;
use seamlit_mesh::Object;

use crate::source::MeshSource;

/// Normals at a mesh's face corners, indexed.
#[derive(Debug, PartialEq)]
pub(super) struct CornerNormals {
    /// The distinct values, by their bits, in order of first use.
    pub values: Vec<Vec3>,
    /// Per face corner, its index into `values`.
    pub indices: Vec<u32>,
}

/// No vertex: a corner whose normal is not a vertex's, or a vertex not yet indexed.
const NONE: u32 = u32::MAX;

/// The distinct normals seen so far, by their bits.
#[derive(Default)]
struct Index {
    values: Vec<Vec3>,
    of_bits: FxHashMap<[u32; 3], u32>,
}

impl Index {
    fn with_capacity(n: usize) -> Self {
        let of_bits = FxHashMap::with_capacity_and_hasher(n, rustc_hash::FxBuildHasher);
        Self { values: Vec::with_capacity(n), of_bits }
    }

    /// The index of `normal`'s bits, a new one where they are new.
    fn of(&mut self, normal: Vec3) -> u32 {
        let values = &mut self.values;
        *self.of_bits.entry(normal.to_array().map(f32::to_bits)).or_insert_with(|| {
            values.push(normal);
            #[expect(clippy::cast_possible_truncation, reason = "a value per corner at most")]
            let index = (values.len() - 1) as u32;
            index
        })
    }
}

impl CornerNormals {
    /// The object's normal at each face corner of its mesh: the normal of the vertex the
    /// corner's first triangle gives it (after `fix`, a split vertex's copy), for a corner of
    /// no triangle its input vertex's, else the input's value, else zero. `None` for an object
    /// without normals.
    pub fn of(object: &Object, mesh: &MeshSource) -> Option<Self> {
        let normals = object.normals.as_deref()?;
        let corners = mesh.corner_vertex.len();
        let mut vertex = vec![NONE; corners];
        for (triangle, at) in object.triangles.iter().zip(&mesh.triangle_corners) {
            for (&v, &c) in triangle.iter().zip(at) {
                let slot = &mut vertex[c as usize];
                if *slot == NONE && (v as usize) < normals.len() {
                    *slot = v;
                }
            }
        }
        for (slot, &v) in vertex.iter_mut().zip(&mesh.corner_vertex) {
            if *slot == NONE && (v as usize) < normals.len() {
                *slot = v;
            }
        }
        let mut index = Index::with_capacity(normals.len());
        let mut of_vertex = vec![NONE; normals.len()];
        let indices = vertex
            .iter()
            .enumerate()
            .map(|(c, &v)| {
                if v == NONE {
                    let old = mesh.corner_normals.as_ref().map_or(Vec3::ZERO, |old| old[c]);
                    return index.of(old);
                }
                let known = &mut of_vertex[v as usize];
                if *known == NONE {
                    *known = index.of(normals[v as usize]);
                }
                *known
            })
            .collect();
        Some(Self { values: index.values, indices })
    }

    /// `normals`, one a corner, indexed.
    pub fn from_values(normals: &[Vec3]) -> Self {
        let mut index = Index::default();
        let indices = normals.iter().map(|&n| index.of(n)).collect();
        Self { values: index.values, indices }
    }

    /// Whether every normal is finite.
    pub fn is_finite(&self) -> bool {
        self.values.iter().all(|n| n.is_finite())
    }

    /// Each corner's normal.
    pub fn expanded(&self) -> Vec<Vec3> {
        self.indices.iter().map(|&i| self.values[i as usize]).collect()
    }

    /// Whether these are `normals`, bit for bit.
    pub fn same_bits(&self, normals: &[Vec3]) -> bool {
        let bits = |n: Vec3| n.to_array().map(f32::to_bits);
        self.indices.len() == normals.len()
            && self
                .indices
                .iter()
                .zip(normals)
                .all(|(&i, &n)| bits(self.values[i as usize]) == bits(n))
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use seamlit_mesh::Object;

    use super::CornerNormals;
    use crate::source::MeshSource;

    /// Two triangles of a quad (corners 0 1 2 3) and a fifth corner no triangle uses, its
    /// vertex 4 past the object's normals.
    fn quad(normals: Vec<Vec3>, corner_normals: Option<Vec<Vec3>>) -> (Object, MeshSource) {
        let object = Object {
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            normals: Some(normals),
            ..Object::default()
        };
        let mesh = MeshSource {
            prim: "/Quad".to_owned(),
            triangle_corners: vec![[0, 1, 2], [0, 2, 3]],
            corner_vertex: vec![0, 1, 2, 3, 4],
            corner_normals,
            subdivision: None,
            plain_normals: false,
            instance_proxy: false,
            instance: None,
            root_sites: Vec::new(),
            time_sampled: Vec::new(),
            skin: None,
        };
        (object, mesh)
    }

    /// The values are the distinct normals by their bits in order of first use, whatever
    /// vertex they come from; a corner of no triangle whose vertex has no normal takes the
    /// input's; +0 and -0 are two values.
    #[test]
    fn corners_are_indexed_by_bits_in_order_of_first_use() {
        let (up, z) = (Vec3::Y, Vec3::new(0.0, 0.0, 1.0));
        let negative_zero = Vec3::new(-0.0, 0.0, 1.0);
        let old = vec![Vec3::X; 5];
        let (object, mesh) = quad(vec![z, up, z, negative_zero], Some(old));
        let got = CornerNormals::of(&object, &mesh).unwrap();
        assert_eq!(got.values, vec![z, up, negative_zero, Vec3::X]);
        assert_eq!(got.indices, vec![0, 1, 0, 2, 3]);
        assert_eq!(got.values[2].x.to_bits(), (-0.0f32).to_bits());
        assert_eq!(got, CornerNormals::from_values(&got.expanded()));
        assert!(got.same_bits(&[z, up, z, negative_zero, Vec3::X]));
        assert!(!got.same_bits(&[z, up, z, z, Vec3::X]), "-0 and +0 are different bits");
    }

    /// A corner's first triangle gives it its vertex (after a split, the copy), not the
    /// mesh's input vertex; without input normals, a corner with nothing is zero.
    #[test]
    fn a_corner_takes_its_first_triangles_vertex() {
        let (mut object, mesh) = quad(vec![Vec3::X, Vec3::Y, Vec3::Z, Vec3::X, Vec3::NEG_X], None);
        // Vertex 4 is a split copy of vertex 0, used by the second triangle at corner 0: the
        // first triangle (vertex 0) still gives corner 0 its normal.
        object.triangles[1] = [4, 2, 3];
        let got = CornerNormals::of(&object, &mesh).unwrap();
        assert_eq!(got.expanded(), vec![Vec3::X, Vec3::Y, Vec3::Z, Vec3::X, Vec3::NEG_X]);
        object.normals.as_mut().unwrap().truncate(4);
        let got = CornerNormals::of(&object, &mesh).unwrap();
        assert_eq!(got.expanded()[4], Vec3::ZERO);
        assert!(got.is_finite());
    }
}
