//! The GPU's posed vertices (`GpuScene::posed_vertices`, the vertex stage's `deform.wgsl` run
//! in a compute pass) against the CPU's (`seamlit_io::pose::posed_object`), within float
//! tolerance: the Khronos Fox walking (one skin, 24 joints, four influences a vertex) and the
//! Khronos SimpleMorph triangle (two targets animated), each at three times.

mod common;

use std::path::{Path, PathBuf};

use glam::Mat4;
use seamlit_io::pose::{Pose, posed_object};
use seamlit_io::{Asset, LoadOptions};
use seamlit_mesh::{FixOptions, fix};
use seamlit_render::{GpuScene, ObjectPose};

fn model(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models").join(path)
}

/// The model loaded and fixed (normals and tangents for the vertex stage to move).
fn fixed(path: &str) -> Asset {
    let asset = seamlit_io::load(&model(path), &LoadOptions::DEFAULT).expect("load");
    let options = asset.fix_options(FixOptions::DEFAULT, false);
    Asset { model: fix(&asset.model, &options).expect("fix"), ..asset }
}

/// Each object's pose as the binary gives it (crates/seamlit/src/animate.rs): a skinned
/// object's palette places it (its node's transform is ignored), a rigid one its node.
fn object_poses(asset: &Asset, pose: &Pose) -> Vec<ObjectPose> {
    (0..asset.model.objects.len())
        .map(|o| {
            let joints = pose.joint_matrices(asset, o);
            let transform =
                if joints.is_some() { Mat4::IDENTITY } else { pose.object_transform(asset, o) };
            ObjectPose { transform, joints, morph_weights: pose.morph_weights(asset, o).to_vec() }
        })
        .collect()
}

/// Every object's posed vertices from the GPU against the CPU's (model space) under the same
/// pose: positions within 1e-5 of the model's size, unit normals within 1e-4, tangents'
/// directions within 1e-4 (the CPU normalises them, the vertex stage does when it builds the
/// frame) and their handedness equal.
fn gpu_matches_cpu(path: &str, animation: usize, times: [f32; 3]) {
    let ctx = common::ctx();
    let asset = fixed(path);
    let mut scene = GpuScene::upload(&ctx, &asset).expect("upload");
    let (lo, hi) = asset.model.bounds().expect("bounds");
    let size = (hi - lo).length();
    let mut checked = 0;
    for t in times {
        let pose = Pose::at(&asset, animation, t);
        scene.set_pose(&ctx, &object_poses(&asset, &pose)).expect("pose");
        for o in 0..asset.model.objects.len() {
            let Some(gpu) = scene.posed_vertices(&ctx, o).expect("read back") else { continue };
            let cpu = posed_object(&asset, &pose, o);
            assert_eq!(gpu.positions.len(), cpu.positions.len(), "{path} object {o}");
            for (v, (&g, &c)) in gpu.positions.iter().zip(&cpu.positions).enumerate() {
                assert!(
                    (g - c).length() <= 1e-5 * size,
                    "{path} at {t} s, object {o} vertex {v}: GPU {g}, CPU {c}"
                );
            }
            let normals = cpu.normals.as_ref().expect("fixed: normals");
            for (v, (&g, &c)) in gpu.normals.iter().zip(normals).enumerate() {
                assert!(
                    (g - c).length() <= 1e-4,
                    "{path} at {t} s, object {o} normal {v}: GPU {g}, CPU {c}"
                );
            }
            if let Some(tangents) = &cpu.tangents {
                for (v, (&g, &c)) in gpu.tangents.iter().zip(tangents).enumerate() {
                    let (g3, c3) = (g.truncate().normalize_or_zero(), c.truncate());
                    assert!(
                        (g3 - c3).length() <= 1e-4,
                        "{path} at {t} s, object {o} tangent {v}: GPU {g3}, CPU {c3}"
                    );
                    assert_eq!(g.w, c.w, "{path}: handedness of tangent {v}");
                }
            }
            checked += gpu.positions.len();
        }
    }
    assert!(checked > 0, "{path}: no vertex compared");
}

#[test]
fn the_fox_walking_is_posed_on_the_gpu_as_on_the_cpu() {
    gpu_matches_cpu("fox/Fox.glb", 1, [0.15, 0.35, 0.55]);
}

#[test]
fn the_simple_morph_is_morphed_on_the_gpu_as_on_the_cpu() {
    gpu_matches_cpu("simple_morph/SimpleMorph.gltf", 0, [1.5, 2.5, 3.5]);
}

/// The rest pose moves the Fox's vertices (the test above is not comparing unposed
/// vertices): under the walk at 0.35 s, some vertex is far from where it rests.
#[test]
fn the_walk_moves_the_fox() {
    let ctx = common::ctx();
    let asset = fixed("fox/Fox.glb");
    let mut scene = GpuScene::upload(&ctx, &asset).expect("upload");
    let mut at = |pose: &Pose| {
        scene.set_pose(&ctx, &object_poses(&asset, pose)).expect("pose");
        scene.posed_vertices(&ctx, 0).expect("read back").expect("on the GPU").positions
    };
    let rest = at(&Pose::rest(&asset));
    let walking = at(&Pose::at(&asset, 1, 0.35));
    let moved = rest.iter().zip(&walking).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
    let (lo, hi) = asset.model.bounds().expect("bounds");
    assert!(moved > 0.05 * (hi - lo).length(), "the walk moves vertices by {moved}");
}
