//! KHR_materials_transmission, _volume and _dispersion as the reader keeps them: factors,
//! textures and the specifications' defaults (bench/sample-viewer/models.mjs's
//! `transmission`: thin glass, a solid amber sphere, a rough tinted one).

use std::path::Path;

use seamlit_io::{LoadOptions, Transmission, Volume};

#[test]
fn transmission_and_volume_are_read_with_their_defaults() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/sample-viewer/transmission.glb");
    let asset = seamlit_io::load(&path, &LoadOptions::DEFAULT).unwrap();
    let by_name = |name: &str| asset.materials.iter().find(|m| m.name == name).unwrap();
    let thin = &by_name("thin glass").extensions;
    assert_eq!(thin.transmission, Some(Transmission { factor: 1.0, texture: None }));
    assert_eq!(thin.volume, None, "thin-walled");
    let amber = &by_name("amber").extensions;
    assert_eq!(
        amber.volume,
        Some(Volume {
            thickness: 0.9,
            thickness_texture: None,
            attenuation_distance: Some(0.5),
            attenuation_color: [0.95, 0.55, 0.2],
        })
    );
    let frosted = &by_name("frosted").extensions;
    assert_eq!(frosted.transmission.as_ref().map(|t| t.factor), Some(0.9));
    let volume = frosted.volume.as_ref().unwrap();
    assert_eq!((volume.attenuation_distance, volume.attenuation_color), (None, [1.0; 3]));
    assert_eq!(
        by_name("frosted").extensions.names(),
        ["KHR_materials_transmission", "KHR_materials_volume"]
    );
    assert!(by_name("backdrop").extensions.transmission.is_none());
    let dispersion =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/sample-viewer/dispersion.glb");
    let asset = seamlit_io::load(&dispersion, &LoadOptions::DEFAULT).unwrap();
    let spread: Vec<Option<f32>> =
        asset.materials.iter().map(|m| m.extensions.dispersion).collect();
    assert_eq!(spread, [None, Some(0.0), Some(20.0), Some(60.0)], "KHR_materials_dispersion");
}

/// The textures a device with 16 sampled textures a stage leaves out, as
/// `PbrExtensions::has_transmission_volume_iridescence_or_anisotropy_texture` finds them: in
/// each of the texture models (bench/sample-viewer/models.mjs), with the texture's own
/// texCoord and transform read; in none of the models without such textures.
#[test]
fn the_extension_textures_are_read_with_their_slots() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/sample-viewer");
    let load = |name: &str| {
        seamlit_io::load(&dir.join(format!("{name}.glb")), &LoadOptions::DEFAULT).unwrap()
    };
    for name in [
        "transmission_texture",
        "thickness_texture",
        "iridescence_texture",
        "iridescence_thickness_texture",
        "anisotropy_texture",
    ] {
        let asset = load(name);
        let spheres: Vec<_> = asset.materials.iter().filter(|m| m.name != "backdrop").collect();
        assert_eq!(spheres.len(), 3, "{name}");
        for m in &spheres {
            let found = m.extensions.has_transmission_volume_iridescence_or_anisotropy_texture();
            assert!(found, "{name}: {}", m.name);
        }
    }
    let anisotropy = load("anisotropy_texture");
    let by_name = |name: &str| {
        let m = anisotropy.materials.iter().find(|m| m.name == name).unwrap();
        m.extensions.anisotropy.as_ref().unwrap().texture.clone().unwrap()
    };
    assert_eq!(by_name("texCoord 1").tex_coord, 1);
    assert!(by_name("transformed").transform.is_some());
    for name in ["transmission", "dispersion", "iridescence", "anisotropy", "clearcoat"] {
        let asset = load(name);
        let none = asset
            .materials
            .iter()
            .all(|m| !m.extensions.has_transmission_volume_iridescence_or_anisotropy_texture());
        assert!(none, "{name}");
    }
}
