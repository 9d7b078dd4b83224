//! KHR_materials_variants: the reader keeps the variants' names and each primitive
//! instance's mappings, `Asset::select_variant` gives the objects a variant's materials (and
//! back), an unknown name is refused listing the variants, and a file written by the glTF
//! pass-through keeps the extension as the input had it.

use std::path::{Path, PathBuf};

use seamlit_io::{Asset, LoadOptions, SaveOptions, UnknownVariant};

/// bench/sample-viewer/models.mjs's `variants`: three spheres (body, trim, plain), the
/// variants "ruby" and "sapphire".
fn model() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/sample-viewer/variants.glb")
}

/// The name of each object's material, in object order.
fn materials(asset: &Asset) -> Vec<String> {
    asset
        .model
        .objects
        .iter()
        .map(|o| o.material.map_or("-".to_owned(), |m| asset.materials[m].name.clone()))
        .collect()
}

#[test]
fn the_reader_keeps_the_variants_and_a_variant_gives_its_materials() {
    let mut asset = seamlit_io::load(&model(), &LoadOptions::DEFAULT).unwrap();
    assert!(asset.warnings.is_empty(), "{:?}", asset.warnings);
    assert_eq!(asset.variants.names, ["ruby", "sapphire"]);
    // Body and trim are mapped, the plain sphere is not.
    assert_eq!(asset.variants.objects.iter().map(|o| o.object).collect::<Vec<_>>(), [0, 1]);
    assert_eq!(materials(&asset), ["white", "gold", "green"]);
    asset.select_variant(Some("ruby")).unwrap();
    assert_eq!(materials(&asset), ["ruby", "gold", "green"]);
    asset.select_variant(Some("sapphire")).unwrap();
    assert_eq!(materials(&asset), ["sapphire", "silver", "green"]);
    asset.select_variant(None).unwrap();
    assert_eq!(materials(&asset), ["white", "gold", "green"]);
}

#[test]
fn an_unknown_variant_is_refused_listing_the_variants() {
    let mut asset = seamlit_io::load(&model(), &LoadOptions::DEFAULT).unwrap();
    let error = asset.select_variant(Some("emerald")).unwrap_err();
    assert_eq!(
        error,
        UnknownVariant { name: "emerald".into(), known: vec!["ruby".into(), "sapphire".into()] }
    );
    assert_eq!(
        error.to_string(),
        r#"no material variant "emerald"; the variants are "ruby", "sapphire""#
    );
    assert_eq!(materials(&asset), ["white", "gold", "green"], "nothing changed");
    let mut plain = Asset::default();
    let error = plain.select_variant(Some("ruby")).unwrap_err();
    assert!(error.to_string().contains("has no variants"), "{error}");
}

/// The input's JSON of a GLB (its first chunk).
fn glb_json(path: &Path) -> serde_json::Value {
    let bytes = std::fs::read(path).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&bytes[20..20 + length]).unwrap()
}

#[test]
fn the_pass_through_keeps_the_variants() {
    let asset = seamlit_io::load(&model(), &LoadOptions::DEFAULT).unwrap();
    let fixed = Asset {
        model: seamlit_mesh::fix(&asset.model, &seamlit_mesh::FixOptions::DEFAULT).unwrap(),
        ..asset.clone()
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("variants.glb");
    seamlit_io::save(&fixed, &out, &SaveOptions::default()).unwrap();
    let (input, written) = (glb_json(&model()), glb_json(&out));
    assert_eq!(
        written["extensions"]["KHR_materials_variants"],
        input["extensions"]["KHR_materials_variants"]
    );
    assert!(
        written["extensionsUsed"].as_array().unwrap().iter().any(|e| e == "KHR_materials_variants")
    );
    for (a, b) in
        input["meshes"].as_array().unwrap().iter().zip(written["meshes"].as_array().unwrap())
    {
        assert_eq!(a["primitives"][0]["extensions"], b["primitives"][0]["extensions"]);
        assert_eq!(a["primitives"][0]["material"], b["primitives"][0]["material"]);
    }
    assert_eq!(written["materials"], input["materials"]);
    let again = seamlit_io::load(&out, &LoadOptions::DEFAULT).unwrap();
    assert_eq!(again.variants, asset.variants);
}
