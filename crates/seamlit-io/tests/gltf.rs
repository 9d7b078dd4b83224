//! glTF / GLB loading of the shared sample, and the Khronos validator on files written from
//! every shared model.

mod common;

use common::gltf::glb_json;
use common::{model, usize_of, validate};
use seamlit_io::{LoadOptions, SaveOptions, TextureSource};

#[test]
fn normal_tangent_test_glb() {
    let asset = seamlit_io::load(&model("NormalTangentTest.glb"), &LoadOptions::default()).unwrap();
    assert!(asset.warnings.is_empty(), "{:?}", asset.warnings);
    assert_eq!(asset.model.v_axis, seamlit_mesh::VAxis::Down);
    // SOURCES.md: NORMAL + TEXCOORD_0, no TANGENT. (It also says the root node is rotated,
    // but this copy's JSON, read by hand, has two nodes without any transform: node 0 with
    // child 1, which carries mesh 0, one primitive.)
    assert_eq!(asset.model.objects.len(), 1);
    let json = glb_json(&model("NormalTangentTest.glb"));
    let primitive = &json["meshes"][0]["primitives"][0];
    let index_count =
        json["accessors"][primitive["indices"].as_u64().map(usize_of).unwrap()]["count"]
            .as_u64()
            .unwrap();
    let vertex_count = json["accessors"]
        [primitive["attributes"]["POSITION"].as_u64().map(usize_of).unwrap()]["count"]
        .as_u64()
        .unwrap();
    assert_eq!(asset.model.triangle_count() as u64, index_count / 3);
    assert_eq!(asset.model.vertex_count() as u64, vertex_count);
    assert_eq!(asset.nodes.len(), 2);
    assert_eq!(asset.nodes[1].parent, Some(0));
    assert_eq!(asset.nodes[1].objects, [0]);
    for object in &asset.model.objects {
        assert!(object.normals.is_some() && object.uvs.is_some() && object.tangents.is_none());
        assert_eq!(object.transform, None);
    }
    // The material's normal map is embedded in the GLB and decodes.
    let material = &asset.materials[asset.model.objects[0].material.unwrap()];
    let normal = &asset.textures[material.normal_texture.as_ref().unwrap().texture];
    assert!(matches!(normal.source, TextureSource::Embedded { .. }));
    assert!(normal.image.is_some());
}

#[test]
fn the_shared_glb_itself_passes_the_validator() {
    // A control for the validator harness: a file made by others, known to be valid.
    let (errors, report) = validate(&model("NormalTangentTest.glb"));
    assert_eq!(errors, 0, "{report}");
}

#[test]
fn every_written_gltf_and_glb_passes_the_validator() {
    let dir = tempfile::tempdir().unwrap();
    let inputs = [
        "NormalTangentTest.glb",
        "cornell_box/cornell_box.obj",
        "groups.obj",
        "spot/spot_triangulated.obj",
        "spot/spot_quadrangulated.obj",
        "newell_teaset/teapot",
        "newell_teaset/teacup",
        "newell_teaset/teaspoon",
    ];
    for input in inputs {
        let asset = seamlit_io::load(&model(input), &LoadOptions::default()).unwrap();
        let stem = input.replace(['/', '.'], "_");
        for extension in ["glb", "gltf"] {
            let out = dir.path().join(format!("{stem}.{extension}"));
            seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap();
            let (errors, report) = validate(&out);
            assert_eq!(errors, 0, "{input} -> {}: {report}", out.display());
        }
    }
}

/// Vertex colours, fixed (split vertices copy theirs), written as COLOR_0: valid glTF.
#[test]
fn vertex_colours_pass_the_validator() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("tile.obj");
    let text = "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0.5 0 0 1 0.25\nv 0 1 0 0.5 0.5 0.5\n\
                f 1 2 3\nf 1 3 4\n";
    std::fs::write(&obj, text).unwrap();
    let mut asset = seamlit_io::load(&obj, &LoadOptions::default()).unwrap();
    seamlit_mesh::fix_in_place(&mut asset.model, &seamlit_mesh::FixOptions::default()).unwrap();
    for extension in ["glb", "gltf"] {
        let out = dir.path().join(format!("tile.{extension}"));
        seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap();
        let (errors, report) = validate(&out);
        assert_eq!(errors, 0, "{}: {report}", out.display());
    }
    let json = glb_json(&dir.path().join("tile.glb"));
    let attributes = &json["meshes"][0]["primitives"][0]["attributes"];
    let color = &json["accessors"][attributes["COLOR_0"].as_u64().map(usize_of).unwrap()];
    assert_eq!(
        (color["type"].as_str(), color["componentType"].as_u64()),
        (Some("VEC4"), Some(5126))
    );
}

#[test]
fn a_fixed_model_with_normals_and_tangents_passes_the_validator() {
    let asset = seamlit_io::load(&model("newell_teaset/teapot"), &LoadOptions::default()).unwrap();
    let Ok(fixed) = std::panic::catch_unwind(|| {
        seamlit_mesh::fix(&asset.model, &seamlit_mesh::FixOptions::default())
    }) else {
        panic!("seamlit_mesh::fix panicked");
    };
    let asset = seamlit_io::Asset { model: fixed.unwrap(), ..asset };
    assert!(asset.model.objects.iter().all(|o| o.tangents.is_some()));
    let dir = tempfile::tempdir().unwrap();
    for extension in ["glb", "gltf"] {
        let out = dir.path().join(format!("teapot.{extension}"));
        seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap();
        let (errors, report) = validate(&out);
        assert_eq!(errors, 0, "{report}");
        let back = seamlit_io::load(&out, &LoadOptions::default()).unwrap();
        assert!(back.model.objects.iter().all(|o| o.tangents.is_some() && o.normals.is_some()));
    }
}
