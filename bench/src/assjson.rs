//! Reads the meshes Assimp dumps as JSON (`assimp export IN OUT.assjson -fassjson ...`):
//! Assimp computes tangents (`-cts`), but its glTF 2 exporter (5.2) does not write them, so
//! the benchmark reads them from the dump to measure them.
//!
//! Only what the seam report needs: per mesh the positions, normals, tangents with the
//! handedness taken from Assimp's bitangents, the first UV set and the triangles; each node
//! that references a mesh becomes one object with the node's world transform. Assimp's UVs
//! have V up (its glTF importer flips V), so the model has [`VAxis::Up`].

use std::path::Path;

use anyhow::{Context as _, bail};
use glam::{Mat4, Vec2, Vec3, Vec4};
use seamlit_io::Asset;
use seamlit_mesh::{Model, Object, VAxis};
use serde_json::Value;

/// Loads an `assjson` file into an asset without materials.
///
/// # Errors
/// A file that cannot be read or parsed, or a mesh whose arrays do not fit together.
pub fn load(path: &Path) -> anyhow::Result<Asset> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    parse(&text, path)
}

/// Parses the text of an `assjson` file; `path` names it in errors.
fn parse(text: &str, path: &Path) -> anyhow::Result<Asset> {
    let root: Value =
        serde_json::from_str(text).with_context(|| format!("{}: not JSON", path.display()))?;
    let meshes = root["meshes"].as_array().map(Vec::as_slice).unwrap_or_default();
    let mut objects = Vec::new();
    let mut stack = vec![(&root["rootnode"], Mat4::IDENTITY)];
    while let Some((node, parent)) = stack.pop() {
        let world = parent * matrix(&node["transformation"]);
        for index in node["meshes"].as_array().into_iter().flatten() {
            let mesh = index
                .as_u64()
                .and_then(|i| meshes.get(usize::try_from(i).ok()?))
                .with_context(|| format!("{}: bad mesh index {index}", path.display()))?;
            let object = mesh_object(mesh, world)
                .with_context(|| format!("{}: mesh {index}", path.display()))?;
            objects.push(object);
        }
        for child in node["children"].as_array().into_iter().flatten().rev() {
            stack.push((child, world));
        }
    }
    Ok(Asset { model: Model { objects, v_axis: VAxis::Up }, ..Asset::default() })
}

fn mesh_object(mesh: &Value, world: Mat4) -> anyhow::Result<Object> {
    let positions: Vec<Vec3> =
        floats(&mesh["vertices"]).as_chunks::<3>().0.iter().map(|&c| Vec3::from_array(c)).collect();
    let n = positions.len();
    let vec3s = |key: &str| -> Option<Vec<Vec3>> {
        let v: Vec<Vec3> =
            floats(&mesh[key]).as_chunks::<3>().0.iter().map(|&c| Vec3::from_array(c)).collect();
        (v.len() == n).then_some(v)
    };
    let normals = vec3s("normals");
    let uvs = mesh["texturecoords"].get(0).and_then(|uv| {
        let width = mesh["numuvcomponents"].get(0).and_then(Value::as_u64).unwrap_or(2);
        let width = usize::try_from(width).ok().filter(|w| *w >= 2)?;
        let v: Vec<Vec2> = floats(uv).chunks_exact(width).map(|c| Vec2::new(c[0], c[1])).collect();
        (v.len() == n).then_some(v)
    });
    let tangents = match (vec3s("tangents"), vec3s("bitangents"), &normals) {
        (Some(t), Some(b), Some(normals)) => Some(
            t.iter()
                .zip(&b)
                .zip(normals)
                .map(|((t, b), n)| {
                    let w = if n.cross(*t).dot(*b) < 0.0 { -1.0 } else { 1.0 };
                    t.extend(w)
                })
                .collect::<Vec<Vec4>>(),
        ),
        _ => None,
    };
    let mut triangles = Vec::new();
    for face in mesh["faces"].as_array().into_iter().flatten() {
        let corners: Vec<u32> = face
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(|i| u32::try_from(i.as_u64()?).ok())
            .collect();
        match corners[..] {
            [a, b, c] => triangles.push([a, b, c]),
            _ => bail!("a face that is not a triangle: {face}"),
        }
    }
    let name = mesh["name"].as_str().unwrap_or("mesh").to_owned();
    let mut object = Object::new(name, positions, triangles);
    object.normals = normals;
    object.uvs = uvs;
    object.tangents = tangents;
    object.transform = (world != Mat4::IDENTITY).then_some(world);
    Ok(object)
}

/// Assimp's row-major 4 x 4 matrix.
fn matrix(value: &Value) -> Mat4 {
    let f = floats(value);
    match <[f32; 16]>::try_from(f.as_slice()) {
        Ok(m) => Mat4::from_cols_array(&m).transpose(),
        Err(_) => Mat4::IDENTITY,
    }
}

/// The numbers of a JSON array (f64 in JSON), rounded to the model's f32.
#[expect(clippy::cast_possible_truncation, reason = "rounding to the model's f32 is the point")]
fn floats(value: &Value) -> Vec<f32> {
    value.as_array().into_iter().flatten().filter_map(Value::as_f64).map(|f| f as f32).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One triangle in the XY plane facing +Z, its tangent along +X; the second mesh has the
    /// bitangent flipped (mirrored UVs). The node moves the first mesh by +5 in X (row-major:
    /// the translation is the last column).
    const DUMP: &str = r#"{
      "rootnode": {"name": "ROOT", "transformation": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
        "children": [
          {"name": "a", "transformation": [1,0,0,5, 0,1,0,0, 0,0,1,0, 0,0,0,1], "meshes": [0]},
          {"name": "b", "transformation": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "meshes": [1]}
        ]},
      "meshes": [
        {"name": "m0", "vertices": [0,0,0, 1,0,0, 0,1,0], "normals": [0,0,1, 0,0,1, 0,0,1],
         "tangents": [1,0,0, 1,0,0, 1,0,0], "bitangents": [0,1,0, 0,1,0, 0,1,0],
         "numuvcomponents": [2], "texturecoords": [[0,0, 1,0, 0,1]], "faces": [[0,1,2]]},
        {"name": "m1", "vertices": [0,0,0, 1,0,0, 0,1,0], "normals": [0,0,1, 0,0,1, 0,0,1],
         "tangents": [1,0,0, 1,0,0, 1,0,0], "bitangents": [0,-1,0, 0,-1,0, 0,-1,0],
         "numuvcomponents": [2], "texturecoords": [[0,0, 1,0, 0,-1]], "faces": [[0,1,2]]}
      ]}"#;

    #[test]
    fn meshes_become_objects_with_handedness_from_the_bitangents_and_node_transforms() {
        let asset = parse(DUMP, Path::new("dump.assjson")).unwrap();
        let [a, b] = &asset.model.objects[..] else { panic!("expected two objects") };
        assert_eq!(asset.model.v_axis, VAxis::Up);
        assert_eq!((a.name.as_str(), b.name.as_str()), ("m0", "m1"));
        assert_eq!(a.triangles, vec![[0, 1, 2]]);
        assert_eq!(a.uvs.as_deref().unwrap()[2], Vec2::new(0.0, 1.0));
        assert_eq!(a.tangents.as_deref().unwrap()[0], Vec4::new(1.0, 0.0, 0.0, 1.0));
        assert_eq!(b.tangents.as_deref().unwrap()[0], Vec4::new(1.0, 0.0, 0.0, -1.0));
        assert_eq!(a.transform.unwrap().transform_point3(Vec3::ZERO), Vec3::new(5.0, 0.0, 0.0));
        assert_eq!(b.transform, None);
    }

    #[test]
    fn a_face_that_is_not_a_triangle_is_an_error_naming_the_mesh() {
        let text =
            DUMP.replacen("\"faces\": [[0,1,2]]}\n      ]", "\"faces\": [[0,1,2,0]]}\n      ]", 1);
        assert_ne!(text, DUMP);
        let e = parse(&text, Path::new("dump.assjson")).unwrap_err();
        assert_eq!(format!("{e}"), "dump.assjson: mesh 1");
        assert!(format!("{e:#}").contains("not a triangle"), "{e:#}");
    }
}
