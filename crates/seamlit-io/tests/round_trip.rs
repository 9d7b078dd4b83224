//! Load -> write -> load keeps the geometry bit for bit and the object names, for OBJ, glTF
//! and GLB output, from every kind of input.

mod common;

use common::model;
use seamlit_io::{Asset, LoadOptions, SaveOptions};
use seamlit_mesh::{Object, VAxis};

/// Per triangle corner, the position's bits: in the object's local space when it has no
/// transform, else in model space (OBJ output moves positions into model space).
fn corners(object: &Object) -> Vec<[u32; 3]> {
    object
        .triangles
        .iter()
        .flatten()
        .map(|&i| {
            let p = object.positions[i as usize];
            let p = object.transform.map_or(p, |m| m.transform_point3(p));
            p.to_array().map(f32::to_bits)
        })
        .collect()
}

/// Per triangle corner, the UV with V running up.
fn corner_uvs(object: &Object, v_axis: VAxis) -> Option<Vec<[f32; 2]>> {
    let uvs = object.uvs.as_ref()?;
    Some(
        object
            .triangles
            .iter()
            .flatten()
            .map(|&i| {
                let t = uvs[i as usize];
                match v_axis {
                    VAxis::Up => [t.x, t.y],
                    VAxis::Down => [t.x, 1.0 - t.y],
                }
            })
            .collect(),
    )
}

fn compare(original: &Asset, back: &Asset, what: &str) {
    let names = |a: &Asset| a.model.objects.iter().map(|o| o.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(back), names(original), "{what}: names");
    let same_convention = original.model.v_axis == back.model.v_axis;
    for (a, b) in original.model.objects.iter().zip(&back.model.objects) {
        assert_eq!(corners(b), corners(a), "{what}: {} geometry", a.name);
        assert_eq!(a.normals.is_some(), b.normals.is_some(), "{what}: {} normals", a.name);
        match (corner_uvs(a, original.model.v_axis), corner_uvs(b, back.model.v_axis)) {
            (None, None) => {}
            (Some(x), Some(y)) if same_convention => {
                // Same convention: no flip, the bits survive.
                assert_eq!(x, y, "{what}: {} uvs", a.name);
            }
            (Some(x), Some(y)) => {
                // OBJ <-> glTF flips V (1 - v), which may round in the last bit.
                let worst = x
                    .iter()
                    .zip(&y)
                    .map(|(p, q)| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()))
                    .fold(0.0, f32::max);
                assert!(worst <= 1e-6, "{what}: {} uvs differ by {worst}", a.name);
            }
            (x, y) => panic!("{what}: {} uvs present {} -> {}", a.name, x.is_some(), y.is_some()),
        }
    }
}

#[test]
fn every_model_round_trips_through_obj_gltf_and_glb() {
    let dir = tempfile::tempdir().unwrap();
    let inputs = [
        "cornell_box/cornell_box.obj",
        "groups.obj",
        "spot/spot_triangulated.obj",
        "newell_teaset/teapot",
        "NormalTangentTest.glb",
    ];
    for input in inputs {
        let original = seamlit_io::load(&model(input), &LoadOptions::default()).unwrap();
        let stem = input.replace(['/', '.'], "_");
        for extension in ["obj", "gltf", "glb"] {
            let out = dir.path().join(format!("{stem}.{extension}"));
            seamlit_io::save(&original, &out, &SaveOptions::default()).unwrap();
            let back = seamlit_io::load(&out, &LoadOptions::default()).unwrap();
            compare(&original, &back, &format!("{input} -> {extension}"));
            // And once more, from the written file to the same format.
            let again = dir.path().join(format!("{stem}_again.{extension}"));
            seamlit_io::save(&back, &again, &SaveOptions::default()).unwrap();
            compare(
                &back,
                &seamlit_io::load(&again, &LoadOptions::default()).unwrap(),
                &format!("{input} -> {extension} x2"),
            );
        }
    }
}

#[test]
fn gltf_round_trip_keeps_arrays_tangents_and_materials() {
    let original =
        seamlit_io::load(&model("NormalTangentTest.glb"), &LoadOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for extension in ["gltf", "glb"] {
        let out = dir.path().join(format!("ntt.{extension}"));
        seamlit_io::save(&original, &out, &SaveOptions::default()).unwrap();
        let back = seamlit_io::load(&out, &LoadOptions::default()).unwrap();
        assert!(back.warnings.is_empty(), "{:?}", back.warnings);
        for (a, b) in original.model.objects.iter().zip(&back.model.objects) {
            assert_eq!(a.positions, b.positions);
            assert_eq!(a.triangles, b.triangles);
            assert_eq!(a.uvs, b.uvs);
            assert_eq!(a.transform, b.transform);
        }
        let (m, n) = (&original.materials[0], &back.materials[0]);
        assert_eq!(m.base_color, n.base_color);
        assert_eq!(m.normal_scale, n.normal_scale);
        assert_eq!(m.double_sided, n.double_sided);
        // The textures come back with the same pixels.
        for (r, s) in
            [(&m.base_color_texture, &n.base_color_texture), (&m.normal_texture, &n.normal_texture)]
        {
            let (r, s) = (r.as_ref().unwrap(), s.as_ref().unwrap());
            let a = original.textures[r.texture].image.as_ref().unwrap();
            let b = back.textures[s.texture].image.as_ref().unwrap();
            assert_eq!(a.as_raw(), b.as_raw());
        }
    }
}

#[test]
fn saving_refuses_to_overwrite_the_input_unless_asked() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("quad.obj");
    std::fs::write(&path, "o quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n").unwrap();
    let mut asset = seamlit_io::load(&path, &LoadOptions::default()).unwrap();
    seamlit_mesh::fix_in_place(&mut asset.model, &seamlit_mesh::FixOptions::default()).unwrap();
    let err = seamlit_io::save(&asset, &path, &SaveOptions::default()).unwrap_err();
    assert!(matches!(err, seamlit_io::IoError::WouldOverwriteInput { .. }), "{err}");
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "o quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n"
    );
    seamlit_io::save(
        &asset,
        &path,
        &SaveOptions { overwrite_input: true, ..SaveOptions::default() },
    )
    .unwrap();
    // The OBJ pass-through: the input with the fixed normals (distinct values; fix's
    // normalisation leaves one a bit below 1) added.
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "o quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvn 0 0 1\nvn 0 0 0.99999994\nf 1//1 2//1 3//2\n"
    );
    // No temporary files are left behind.
    let names: Vec<_> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 1, "{names:?}");
}

#[test]
fn a_failed_save_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut asset = seamlit_io::newell::parse("1\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n16\n0,0,0\n1,0,0\n2,0,0\n3,0,0\n0,1,0\n1,1,0\n2,1,0\n3,1,0\n0,2,0\n1,2,0\n2,2,0\n3,2,0\n0,3,0\n1,3,0\n2,3,0\n3,3,0\n", "flat", 2).unwrap();
    asset.model.objects[0].triangles.push([0, 1, 99]);
    for extension in ["obj", "gltf", "glb"] {
        let out = dir.path().join(format!("bad.{extension}"));
        let err = seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap_err();
        assert!(
            matches!(
                err,
                seamlit_io::IoError::InvalidAsset {
                    kind: seamlit_io::InvalidAsset::IndexOutOfRange { triangle: [0, 1, 99], .. },
                    ..
                }
            ),
            "{extension}: {err}"
        );
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
