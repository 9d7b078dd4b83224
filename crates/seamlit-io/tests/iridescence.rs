//! KHR_materials_iridescence as the reader keeps it: factor, film ior and thickness range
//! with the specification's defaults (bench/sample-viewer/models.mjs's `iridescence`).

use std::path::Path;

use seamlit_io::{Iridescence, LoadOptions};

#[test]
fn iridescence_is_read_with_its_defaults() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/sample-viewer/iridescence.glb");
    let asset = seamlit_io::load(&path, &LoadOptions::DEFAULT).unwrap();
    let film = |name: &str| {
        asset.materials.iter().find(|m| m.name == name).unwrap().extensions.iridescence.clone()
    };
    let defaults = Iridescence {
        factor: 1.0,
        texture: None,
        ior: 1.3,
        thickness_minimum: 100.0,
        thickness_maximum: 400.0,
        thickness_texture: None,
    };
    assert_eq!(film("film 400"), Some(defaults.clone()));
    assert_eq!(
        film("film 700"),
        Some(Iridescence { ior: 1.8, thickness_maximum: 700.0, ..defaults.clone() })
    );
    assert_eq!(
        film("metal film"),
        Some(Iridescence { factor: 0.8, thickness_maximum: 300.0, ..defaults })
    );
}
