//! Test meshes: a UV sphere, a torus, the Newell teapot's patches, and a splitter that cuts a
//! mesh into objects along its edges, duplicating boundary vertices as artists' files do.
#![allow(dead_code, reason = "each test binary uses a different subset of these helpers")]

use glam::{Vec2, Vec3};
use seamlit_mesh::{Model, Object};

/// A UV sphere of radius 1: `rings` x `segments` quads, a UV seam at u = 0/1 (duplicated
/// column), poles collapsed (their triangles are degenerate ones, kept on purpose).
pub fn uv_sphere(rings: u32, segments: u32) -> Object {
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    for r in 0..=rings {
        let v = r as f32 / rings as f32;
        let theta = v * std::f32::consts::PI;
        for s in 0..=segments {
            let u = s as f32 / segments as f32;
            let phi = u * std::f32::consts::TAU;
            // Exact duplicates at the seam: s == segments reuses s == 0's angle.
            let phi = if s == segments { 0.0 } else { phi };
            positions.push(Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            ));
            uvs.push(Vec2::new(u, 1.0 - v));
        }
    }
    Object::new("sphere", positions, grid_triangles(rings, segments)).with_uvs(uvs)
}

/// A torus (major radius 1, minor 0.35): UV seams in both directions.
pub fn torus(rings: u32, segments: u32) -> Object {
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    for r in 0..=rings {
        let v = r as f32 / rings as f32;
        let a = if r == rings { 0.0 } else { v * std::f32::consts::TAU };
        for s in 0..=segments {
            let u = s as f32 / segments as f32;
            let b = if s == segments { 0.0 } else { u * std::f32::consts::TAU };
            let ring = 1.0 + 0.35 * a.cos();
            positions.push(Vec3::new(ring * b.cos(), 0.35 * a.sin(), -ring * b.sin()));
            uvs.push(Vec2::new(u, v));
        }
    }
    Object::new("torus", positions, grid_triangles(rings, segments)).with_uvs(uvs)
}

/// Triangles of a (rows + 1) x (cols + 1) vertex grid, counter-clockwise seen from outside.
pub fn grid_triangles(rows: u32, cols: u32) -> Vec<[u32; 3]> {
    let w = cols + 1;
    let mut tris = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            let a = r * w + c;
            let (b, d, e) = (a + 1, a + w, a + w + 1);
            tris.push([a, d, e]);
            tris.push([a, e, b]);
        }
    }
    tris
}

/// Cuts `object` into `assignment.iter().max() + 1` objects: triangle `t` goes to object
/// `assignment[t % assignment.len()]`. Each object gets its own copy of every vertex it uses;
/// every copy after the first is moved by `noise()`, as an exporter's rounding moves the
/// duplicated boundary of one object against the other's. Returns the model and, per object,
/// the original index of each of its triangles.
pub fn split(
    object: &Object,
    assignment: &[usize],
    mut noise: impl FnMut() -> Vec3,
) -> (Model, Vec<Vec<usize>>) {
    let k = assignment.iter().max().map_or(1, |m| m + 1);
    let mut objects = Vec::new();
    let mut origin = Vec::new();
    let mut copied = vec![false; object.positions.len()];
    for o in 0..k {
        let mut map = vec![u32::MAX; object.positions.len()];
        let mut positions = Vec::new();
        let mut uvs = Vec::new();
        let mut tris = Vec::new();
        let mut from = Vec::new();
        for (t, tri) in object.triangles.iter().enumerate() {
            if assignment[t % assignment.len()] != o {
                continue;
            }
            let local = tri.map(|v| {
                if map[v as usize] == u32::MAX {
                    map[v as usize] = u32::try_from(positions.len()).unwrap();
                    let offset = if copied[v as usize] { noise() } else { Vec3::ZERO };
                    copied[v as usize] = true;
                    positions.push(object.positions[v as usize] + offset);
                    uvs.push(object.uvs.as_ref().map_or(Vec2::ZERO, |u| u[v as usize]));
                }
                map[v as usize]
            });
            tris.push(local);
            from.push(t);
        }
        if tris.is_empty() {
            continue;
        }
        let mut obj = Object::new(format!("part{o}"), positions, tris);
        if object.uvs.is_some() {
            obj = obj.with_uvs(uvs);
        }
        objects.push(obj);
        origin.push(from);
    }
    (Model::new(objects), origin)
}

/// The Newell teapot's 32 patches, each tessellated at `n` x `n` into its own object with the
/// patch's (u, v) as UVs. Reads assets/models/newell_teaset/teapot.
pub fn teapot(n: u32) -> Model {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/models/newell_teaset/teapot");
    let text = std::fs::read_to_string(path).expect("assets/models/newell_teaset/teapot");
    let mut tokens = text.split(|c: char| c.is_whitespace() || c == ',').filter(|t| !t.is_empty());
    let mut next = || tokens.next().expect("token");
    let count = |t: &str| t.parse::<usize>().expect("a count or an index");
    let patches = count(next());
    let indices: Vec<[usize; 16]> =
        (0..patches).map(|_| std::array::from_fn(|_| count(next()) - 1)).collect();
    let points = count(next());
    let mut number = || next().parse::<f32>().expect("number");
    let cps: Vec<Vec3> = (0..points).map(|_| Vec3::new(number(), number(), number())).collect();
    let bernstein = |t: f32| {
        let s = 1.0 - t;
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
    };
    let objects = indices
        .iter()
        .enumerate()
        .map(|(i, patch)| {
            let mut positions = Vec::new();
            let mut uvs = Vec::new();
            for r in 0..=n {
                let v = r as f32 / n as f32;
                for c in 0..=n {
                    let u = c as f32 / n as f32;
                    let (bu, bv) = (bernstein(u), bernstein(v));
                    let mut p = Vec3::ZERO;
                    for a in 0..4 {
                        for b in 0..4 {
                            p += cps[patch[a * 4 + b]] * bv[a] * bu[b];
                        }
                    }
                    // Newell's data is Z-up; seamlit is Y-up.
                    positions.push(Vec3::new(p.x, p.z, -p.y));
                    uvs.push(Vec2::new(u, v));
                }
            }
            Object::new(format!("patch{i}"), positions, grid_triangles(n, n)).with_uvs(uvs)
        })
        .collect();
    Model::new(objects)
}

/// The six sides of the cube [-1, 1]^3, in the order +X, -X, +Y, -Y, +Z, -Z: each its outward
/// normal and two in-plane directions (u, v) with u x v = normal.
pub const CUBE_SIDES: [(Vec3, Vec3, Vec3); 6] = [
    (Vec3::X, Vec3::NEG_Z, Vec3::Y),
    (Vec3::NEG_X, Vec3::Z, Vec3::Y),
    (Vec3::Y, Vec3::X, Vec3::NEG_Z),
    (Vec3::NEG_Y, Vec3::X, Vec3::Z),
    (Vec3::Z, Vec3::X, Vec3::Y),
    (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
];

/// The unit cube [0, 1]^3 as one object of 8 shared corners (vertex i at the bits of i) and 12
/// triangles: each corner meets three faces at 90 degrees.
pub fn shared_corner_cube() -> Object {
    let positions: Vec<Vec3> = (0..8)
        .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
        .collect();
    let quads =
        [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let triangles = quads.iter().flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]).collect();
    Object::new("cube", positions, triangles)
}

/// A fixed model's objects as one indexed mesh (positions, normals, UVs, indices), as the
/// peers' MikkTSpace generators take it (benches/tangents.rs, examples/time_fix.rs).
pub struct Merged {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub uvs: Vec<[f32; 2]>,
    pub indices: Vec<u32>,
}

impl Merged {
    pub fn of(model: &Model) -> Self {
        let mut m = Self { positions: vec![], normals: vec![], uvs: vec![], indices: vec![] };
        for object in &model.objects {
            let base = u32::try_from(m.positions.len()).expect("fits");
            m.positions.extend(object.positions.iter().map(|p| p.to_array()));
            m.normals.extend(object.normals.as_ref().expect("fixed").iter().map(|n| n.to_array()));
            let uvs = object.uvs.as_ref().expect("the teapot has UVs");
            m.uvs.extend(uvs.iter().map(|uv| uv.to_array()));
            m.indices.extend(object.triangles.as_flattened().iter().map(|i| i + base));
        }
        m
    }
}

impl bevy_mikktspace::Geometry for Merged {
    fn num_faces(&self) -> usize {
        self.indices.len() / 3
    }
    fn num_vertices_of_face(&self, _: usize) -> usize {
        3
    }
    fn position(&self, f: usize, v: usize) -> [f32; 3] {
        self.positions[self.indices[f * 3 + v] as usize]
    }
    fn normal(&self, f: usize, v: usize) -> [f32; 3] {
        self.normals[self.indices[f * 3 + v] as usize]
    }
    fn tex_coord(&self, f: usize, v: usize) -> [f32; 2] {
        self.uvs[self.indices[f * 3 + v] as usize]
    }
    fn set_tangent(&mut self, t: Option<bevy_mikktspace::TangentSpace>, _: usize, _: usize) {
        std::hint::black_box(t.map(|t| t.tangent()));
    }
}
