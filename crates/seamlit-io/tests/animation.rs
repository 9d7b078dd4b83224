//! Skins, morph targets and animations: read from glTF, posed on the CPU against closed
//! forms, and the seams of a two-object character measured and closed in every pose.

mod common;

use std::f32::consts::FRAC_PI_2;

use glam::{Mat4, Quat, Vec3};
use seamlit_io::motion::seam_motion;
use seamlit_io::pose::{Pose, posed_object};
use seamlit_io::{
    Animation, Asset, Channel, Interpolation, LoadOptions, Node, Property, Sampler, SaveOptions,
    Skin,
};
use seamlit_mesh::{FixOptions, Influences, Model, MorphTarget, Object, WeldTolerance};

/// A unit quad in the XY plane (normal +Z), skinned wholly to node 1, a joint at the origin
/// turning about Y from 0 to 90 degrees over one second (LINEAR).
fn one_bone_quad() -> Asset {
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    let mut quad = Object::new("quad", positions, vec![[0, 1, 2], [0, 2, 3]]);
    quad.normals = Some(vec![Vec3::Z; 4]);
    quad.skin =
        vec![Influences { joints: vec![[1, 0, 0, 0]; 4], weights: vec![[1.0, 0.0, 0.0, 0.0]; 4] }];
    let mut mesh = Node::new("mesh", Mat4::IDENTITY, None);
    mesh.objects = vec![0];
    mesh.skin = Some(0);
    let joint = Node::new("bone", Mat4::IDENTITY, None);
    let rotations: Vec<f32> = [Quat::IDENTITY, Quat::from_rotation_y(FRAC_PI_2)]
        .iter()
        .flat_map(|q| q.to_array())
        .collect();
    Asset {
        model: Model::new(vec![quad]),
        nodes: vec![mesh, joint],
        skins: vec![Skin {
            name: String::new(),
            joints: vec![1],
            inverse_bind_matrices: vec![Mat4::IDENTITY],
        }],
        animations: vec![Animation {
            name: "turn".into(),
            channels: vec![Channel {
                node: 1,
                property: Property::Rotation,
                sampler: Sampler {
                    interpolation: Interpolation::Linear,
                    times: vec![0.0, 1.0],
                    values: rotations,
                },
            }],
        }],
        ..Asset::default()
    }
}

#[test]
fn one_bone_turns_a_quad_as_the_closed_form() {
    let asset = one_bone_quad();
    for (time, degrees) in [(0.0f32, 0.0f32), (0.5, 45.0), (1.0, 90.0), (3.0, 90.0)] {
        let posed = posed_object(&asset, &Pose::at(&asset, 0, time), 0);
        // Rotation by a about Y: (x, y, z) -> (x cos a + z sin a, y, -x sin a + z cos a).
        let (sin, cos) = degrees.to_radians().sin_cos();
        for (p, q) in asset.model.objects[0].positions.iter().zip(&posed.positions) {
            let expected = Vec3::new(p.x * cos + p.z * sin, p.y, -p.x * sin + p.z * cos);
            assert!(q.abs_diff_eq(expected, 1e-6), "t = {time}: {q} != {expected}");
        }
        let normal = Vec3::new(sin, 0.0, cos);
        for n in posed.normals.as_ref().unwrap() {
            assert!(n.abs_diff_eq(normal, 1e-6), "t = {time}: normal {n} != {normal}");
        }
    }
    // At 90 degrees the corner (1, 0, 0) is at (0, 0, -1).
    let posed = posed_object(&asset, &Pose::at(&asset, 0, 1.0), 0);
    assert!(posed.positions[1].abs_diff_eq(Vec3::new(0.0, 0.0, -1.0), 1e-6));
}

#[test]
fn a_morph_at_half_weight_is_base_plus_half_the_delta() {
    let mut asset = one_bone_quad();
    let object = &mut asset.model.objects[0];
    object.skin.clear();
    let deltas: Vec<Vec3> = (0..4).map(|v| Vec3::new(0.25, -0.5, v as f32)).collect();
    object.morph_targets = vec![MorphTarget {
        name: "lift".into(),
        position_deltas: deltas.clone(),
        ..MorphTarget::default()
    }];
    asset.nodes[0].weights = vec![0.5];
    let posed = posed_object(&asset, &Pose::rest(&asset), 0);
    for ((p, d), q) in asset.model.objects[0].positions.iter().zip(&deltas).zip(&posed.positions) {
        assert_eq!(*q, *p + 0.5 * *d);
    }
    // A weights channel moves it: at t = 0.5 of a 0 -> 1 ramp the weight is 0.5 as well.
    asset.nodes[0].weights = vec![0.0];
    asset.animations[0].channels = vec![Channel {
        node: 0,
        property: Property::Weights,
        sampler: Sampler {
            interpolation: Interpolation::Linear,
            times: vec![0.0, 1.0],
            values: vec![0.0, 1.0],
        },
    }];
    let posed = posed_object(&asset, &Pose::at(&asset, 0, 0.5), 0);
    for ((p, d), q) in asset.model.objects[0].positions.iter().zip(&deltas).zip(&posed.positions) {
        assert_eq!(*q, *p + 0.5 * *d);
    }
}

fn character() -> (tempfile::TempDir, Asset) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("character.gltf");
    seamlit_testkit::character::write(&path);
    let asset = seamlit_io::load(&path, &LoadOptions::DEFAULT).unwrap();
    (dir, asset)
}

#[test]
fn skins_and_animations_are_read_with_their_nodes() {
    let (_dir, asset) = character();
    assert_eq!(asset.model.objects.len(), 2);
    let names: Vec<&str> = asset.nodes.iter().map(|n| n.name.as_str()).collect();
    let at = |name: &str| names.iter().position(|&n| n == name).unwrap();
    assert_eq!(asset.skins.len(), 2);
    assert_eq!(asset.skins[0].joints, [at("root"), at("chest"), at("neck")]);
    assert_eq!(asset.skins[1].joints, [at("neck")]);
    assert_eq!(asset.nodes[at("body")].skin, Some(0));
    assert_eq!(asset.nodes[at("head")].skin, Some(1));
    // Influences name nodes of the asset: the head's ring follows the neck alone.
    let head = &asset.model.objects[asset.nodes[at("head")].objects[0]];
    assert_eq!(head.skin[0].joints[0][0] as usize, at("neck"));
    assert_eq!(asset.animations.len(), 1);
    let nod = &asset.animations[0];
    assert_eq!((nod.name.as_str(), nod.duration()), ("nod", 2.0));
    assert_eq!(nod.channels[0].node, at("neck"));
    // At 1 s the neck has turned 60 degrees about X, at its place 1.5 up.
    let pose = Pose::at(&asset, 0, 1.0);
    let expected =
        Mat4::from_translation(Vec3::Y * 1.5) * Mat4::from_rotation_x(60f32.to_radians());
    assert!(pose.globals[at("neck")].abs_diff_eq(expected, 1e-6));
}

/// The largest gap and normal angle across the neck over 21 times of the nod.
fn motion(asset: &Asset) -> (f32, Option<f32>) {
    let copies = seamlit_mesh::shared_copies(&asset.model, WeldTolerance::default()).unwrap();
    assert_eq!(copies.len(), seamlit_testkit::character::SEGMENTS, "the neck ring is shared");
    // Every copy counts as a seam side (the character's normals are computed, or smooth).
    let seams: Vec<Vec<bool>> = copies.iter().map(|g| vec![true; g.len()]).collect();
    let m = seam_motion(asset, 0, 21, &copies, &seams, 30.0);
    (m.max_gap_fraction, m.max_normal_angle_deg)
}

#[test]
fn matched_skins_keep_the_neck_closed_in_every_pose() {
    let (dir, mut asset) = character();
    seamlit_mesh::fix_in_place(&mut asset.model, &FixOptions::default()).unwrap();
    let (gap, angle) = motion(&asset);
    assert!(gap > 0.01, "the ring opens as the neck turns: {gap}");
    assert!(angle.unwrap() > 5.0, "and its normals part: {angle:?}");

    let copies = seamlit_mesh::shared_copies(&asset.model, WeldTolerance::default()).unwrap();
    let matched = seamlit_io::match_skin_seams(&mut asset, &copies);
    assert_eq!(matched.positions, seamlit_testkit::character::SEGMENTS);
    let (gap, angle) = motion(&asset);
    assert!(gap < 1e-6, "the gap after matching: {gap}");
    assert!(angle.unwrap() < 0.01, "the normal angle after matching: {angle:?}");
    // The head's skin gained the chest, with the body's inverse bind matrix for it.
    let chest = asset.nodes.iter().position(|n| n.name == "chest").unwrap();
    assert_eq!(asset.skins[1].joints.last(), Some(&chest));
    assert_eq!(asset.skins[1].inverse_bind_matrices[1], asset.skins[0].inverse_bind_matrices[1]);

    // Written through the pass-through and read back by the loader: still closed.
    let out = dir.path().join("fixed.glb");
    seamlit_io::save(&asset, &out, &SaveOptions::default()).unwrap();
    let (errors, report) = common::validate(&out);
    assert_eq!(errors, 0, "{report}");
    let back = seamlit_io::load(&out, &LoadOptions::DEFAULT).unwrap();
    assert_eq!(back.skins[1].joints.len(), 2);
    let (gap, angle) = motion(&back);
    assert!(gap < 1e-6, "the gap read back: {gap}");
    assert!(angle.unwrap() < 0.01, "the normal angle read back: {angle:?}");
}

/// The seams in motion compare the normals of seam sides only (`seamlit_mesh::seam_copies`):
/// copies that carry their object's smooth normal, or whose normals `fix` computes. Copies
/// whose authored normals `fix` keeps (flat or custom) are no seam, whatever their angle.
#[test]
fn seams_in_motion_compare_seam_sides_only() {
    let (_dir, mut asset) = character();
    let options = FixOptions::default();
    let copies = seamlit_mesh::shared_copies(&asset.model, WeldTolerance::default()).unwrap();
    let angle = |asset: &Asset, seams: &[Vec<bool>]| {
        seam_motion(asset, 0, 21, &copies, seams, 30.0).max_normal_angle_deg
    };
    // Without normals, every copy is a seam side (fix computes them).
    let seams = seamlit_mesh::seam_copies(&asset.model, &copies, &options).unwrap();
    assert!(seams.iter().flatten().all(|&s| s));

    // Smoothed part by part (object mode): the neck ring is a seam, and its normals part.
    let recompute = options.with_normals(seamlit_mesh::NormalPolicy::Recompute);
    seamlit_mesh::fix_in_place(&mut asset.model, &recompute.with_mode(seamlit_mesh::Mode::Object))
        .unwrap();
    let seams = seamlit_mesh::seam_copies(&asset.model, &copies, &options).unwrap();
    assert!(seams.iter().flatten().all(|&s| s), "smooth per object: {seams:?}");
    assert!(angle(&asset, &seams).unwrap() > 1.0);

    // Custom normals (each object's leaning its own way, 20 degrees apart): kept, not measured.
    for (o, lean) in asset.model.objects.iter_mut().zip([0.2_f32, -0.15]) {
        let n = Vec3::new(1.0, lean, 0.3).normalize();
        o.normals = Some(vec![n; o.positions.len()]);
    }
    let seams = seamlit_mesh::seam_copies(&asset.model, &copies, &options).unwrap();
    assert!(seams.iter().flatten().all(|&s| !s), "custom: {seams:?}");
    assert_eq!(angle(&asset, &seams), None);
    // Measured as every copy (the rule of before), they were a 20-degree "seam".
    let all: Vec<Vec<bool>> = copies.iter().map(|g| vec![true; g.len()]).collect();
    assert!(angle(&asset, &all).unwrap() > 15.0);
    // `smooth-shared` averages them: then every copy is a seam side.
    let shared = options.with_normals(seamlit_mesh::NormalPolicy::SmoothShared);
    let seams = seamlit_mesh::seam_copies(&asset.model, &copies, &shared).unwrap();
    assert!(seams.iter().flatten().all(|&s| s));
}
