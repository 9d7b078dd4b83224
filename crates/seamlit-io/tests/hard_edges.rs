//! Faceted low-poly models made by others (assets/models/lowpoly: Kenney's Platformer and
//! Space kits, Quaternius' furniture and vehicles; GLB and FBX), one object per colour with
//! hard edges between them: the default fix keeps every normal they carry, while the rule of
//! before (`smooth-shared`) softened their hard edges. A round tower of the Castle kit, whose
//! parts were smoothed one by one, is repaired. docs/normals.md, "What a shared position is".
#![cfg(feature = "fbx")]

use std::path::PathBuf;

use seamlit_io::LoadOptions;
use seamlit_mesh::{FixOptions, Model, NormalPolicy, ReportOptions, fix_in_place};

fn lowpoly(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/models/lowpoly")).join(name)
}

fn model(name: &str) -> Model {
    seamlit_io::load(&lowpoly(name), &LoadOptions::GEOMETRY).expect("loads").model
}

fn normal_bits(m: &Model) -> Vec<Vec<[u32; 3]>> {
    m.objects
        .iter()
        .map(|o| o.normals.iter().flatten().map(|n| n.to_array().map(f32::to_bits)).collect())
        .collect()
}

fn fixed(m: &Model, normals: NormalPolicy) -> (Model, seamlit_mesh::Changes) {
    let mut out = m.clone();
    let changes =
        fix_in_place(&mut out, &FixOptions::DEFAULT.with_normals(normals)).expect("valid");
    (out, changes)
}

const FACETED: [&str; 4] = [
    "kenney-platformer-cube.glb",
    "kenney-platformer-blockLevel.glb",
    "kenney-space-spaceCraft4.fbx",
    "quaternius-ambulance.fbx",
];

#[test]
fn faceted_models_by_others_keep_every_authored_normal() {
    for name in FACETED {
        let input = model(name);
        let (auto, changes) = fixed(&input, NormalPolicy::Auto);
        let (keep, _) = fixed(&input, NormalPolicy::Keep);
        let shared = changes.shared;
        assert!(shared.hard_edges > 0, "{name}: objects meet at hard edges: {shared:?}");
        assert!(normal_bits(&auto) == normal_bits(&keep), "{name}: a normal moved");
        assert_eq!(changes.normals_changed(), 0, "{name}");
        // The rule of before averaged the hard edges between objects.
        let (old, old_changes) = fixed(&input, NormalPolicy::SmoothShared);
        assert!(normal_bits(&old) != normal_bits(&keep), "{name}: the rule of before");
        assert!(old_changes.normals_changed() > 0, "{name}");
    }
}

#[test]
fn a_tower_smoothed_part_by_part_is_repaired() {
    let input = model("kenney-castle-towerBase.fbx");
    let seam = |m: &Model| {
        seamlit_mesh::report(m, &ReportOptions::default())
            .expect("valid")
            .cross_object
            .max_normal_angle_deg
            .expect("smooth cross-object edges")
    };
    let (keep, _) = fixed(&input, NormalPolicy::Keep);
    assert!(seam(&keep) > 5.0, "as authored the parts' normals part: {}", seam(&keep));
    let (auto, changes) = fixed(&input, NormalPolicy::Auto);
    assert_eq!(changes.shared.repaired, 24, "{:?}", changes.shared);
    assert_eq!(format!("{:.2}", seam(&auto)), "0.00");
}

/// A bus of flat panels with smooth-shaded wheels: the panels' hard edges between objects
/// stay, the 4 positions where smooth parts of two objects meet are repaired.
#[test]
fn a_faceted_bus_keeps_its_hard_edges_and_closes_its_smooth_seams() {
    let input = model("quaternius-bus.fbx");
    let (auto, changes) = fixed(&input, NormalPolicy::Auto);
    let (old, old_changes) = fixed(&input, NormalPolicy::SmoothShared);
    assert_eq!(changes.shared.repaired, 4, "{:?}", changes.shared);
    assert!(changes.shared.hard_edges > 150, "{:?}", changes.shared);
    assert!(old_changes.shared.repaired > 4, "{:?}", old_changes.shared);
    // Every vertex the new rule changed, the old one changed too; not the reverse.
    let (a, o, k) = (normal_bits(&auto), normal_bits(&old), normal_bits(&input));
    let moved = |m: &Vec<Vec<[u32; 3]>>| -> usize {
        m.iter().zip(&k).map(|(x, y)| x.iter().zip(y).filter(|(p, q)| p != q).count()).sum()
    };
    assert!(moved(&a) > 0 && moved(&a) < moved(&o), "{} of {}", moved(&a), moved(&o));
}
