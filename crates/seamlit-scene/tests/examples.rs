//! Every scene in examples/ parses, and names model files that exist.

use std::path::{Path, PathBuf};

use seamlit_mesh::Mode;
use seamlit_render::Light;
use seamlit_scene::{NormalTexture, Scene};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

#[test]
fn every_example_scene_parses_and_its_models_exist() {
    let mut count = 0;
    for entry in std::fs::read_dir(examples()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        for model in &scene.models {
            assert!(
                model.path.is_file(),
                "{}: {} is missing",
                path.display(),
                model.path.display()
            );
        }
        count += 1;
    }
    assert!(count >= 4, "only {count} example scenes");
}

#[test]
fn the_teapot_example_has_what_its_comments_say() {
    let scene = Scene::load(&examples().join("teapot.toml")).unwrap();
    assert_eq!(scene.models.len(), 1);
    assert_eq!(scene.models[0].fix.crease_angle_deg, 60.0);
    assert_eq!(scene.models[0].materials[0].normal_texture, Some(NormalTexture::Bricks));
    assert!(matches!(
        scene.lights[..],
        [
            Light::Directional { .. },
            Light::Point { .. },
            Light::Spot { inner_cone_deg: 20.0, outer_cone_deg: 35.0, .. }
        ]
    ));
    let names: Vec<&str> = scene.cameras.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["front", "side"]);
}

#[test]
fn the_spot_example_places_a_second_model_with_its_own_options() {
    let scene = Scene::load(&examples().join("spot.toml")).unwrap();
    assert_eq!(scene.models.len(), 2);
    assert!(scene.lights.is_empty(), "the default rig applies");
    let small = &scene.models[1];
    assert_eq!(small.fix.mode, Mode::Object);
    assert_eq!(small.materials[0].normal_mapping, Some(false));
    assert!(scene.models[0].materials.is_empty());
    // Scale 0.6, then the turn, then (1.5, -0.3, 0): the origin lands on the translation.
    let p = small.transform.transform_point3(glam::Vec3::ZERO);
    assert!((p - glam::Vec3::new(1.5, -0.3, 0.0)).length() < 1e-6);
    assert_eq!(scene.cameras[1].far, Some(20.0));
}
