//! Animation in the vertex stage against closed forms (lavapipe in CI: real rendering): one
//! bone turning a quad by 90 degrees, a morph target at weight 0.5, the shadow of a skinned
//! occluder, and the posed vertices read back. Each image is written to
//! target/tmp/seamlit-render for inspection.

mod common;

use common::{
    Ortho, assert_pixel, asset, ctx, dot, normalize, ortho_camera, pixel_world, plane,
    render_ortho, save, srgb,
};
use glam::{Mat4, Vec3, Vec4};
use image::RgbaImage;
use seamlit_io::{Asset, Material};
use seamlit_mesh::{Influences, Model, MorphTarget, Object};
use seamlit_render::{
    DebugView, FrameDescriptor, FrameSettings, GpuScene, Light, LightingModel, ObjectPose,
    RenderError, Renderer,
};

const SIZE: u32 = 64;
const HALF: f32 = 1.0;
const VIEW: Ortho = Ortho { half: HALF, size: SIZE };
const BASE: f32 = 0.8;
const AMBIENT: f32 = 0.05;

/// A 1.2 x 0.6 rectangle in the plane x = `x0`, edge-on to the camera on +Z: y in -0.3..0.3,
/// z in -0.6..0.6, normal +X, tangent -Z. Every vertex is bound wholly to joint node 3 (the
/// other lanes name node 0 with weight 0).
fn edge_on_quad(x0: f32) -> Object {
    let mut o = Object::new(
        "bone quad",
        vec![
            Vec3::new(x0, -0.3, 0.6),
            Vec3::new(x0, -0.3, -0.6),
            Vec3::new(x0, 0.3, -0.6),
            Vec3::new(x0, 0.3, 0.6),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    o.normals = Some(vec![Vec3::X; 4]);
    o.tangents = Some(vec![Vec4::new(0.0, 0.0, -1.0, 1.0); 4]);
    o.skin =
        vec![Influences { joints: vec![[3, 0, 0, 0]; 4], weights: vec![[1.0, 0.0, 0.0, 0.0]; 4] }];
    o
}

/// The bone: a quarter turn about +Y (x' = -z, z' = x: the normal +X turns to +Z, the
/// tangent -Z to +X), then a move by `offset`.
fn bone(offset: Vec3) -> Mat4 {
    Mat4::from_translation(offset) * Mat4::from_rotation_y(-std::f32::consts::FRAC_PI_2)
}

/// A palette of four: joints 0..2 throw what they touch far out of view, joint 3 is `joint`.
fn palette(joint: Mat4) -> Vec<Mat4> {
    let away = Mat4::from_translation(Vec3::new(100.0, 0.0, 0.0));
    vec![away, away, away, joint]
}

fn lambert(direction: Vec3) -> FrameSettings {
    FrameSettings {
        lights: vec![Light::Directional { direction, color: Vec3::ONE, intensity: 1.0 }],
        ambient: Vec3::splat(AMBIENT),
        lighting_model: LightingModel::Lambert,
        clear_color: [0.0, 0.0, 0.0, 1.0],
        ..FrameSettings::default()
    }
}

fn grey() -> Material {
    Material { base_color: [BASE, BASE, BASE, 1.0], ..Material::default() }
}

/// Checks every pixel more than a pixel away from the rectangle's edges: inside it has the
/// colour `inside`, outside the black background.
fn check_rectangle(image: &RgbaImage, lo: [f64; 2], hi: [f64; 2], inside: [f64; 3], what: &str) {
    let margin = 1.5 * 2.0 * f64::from(HALF) / f64::from(SIZE);
    let mut counted = [0, 0];
    for y in 0..SIZE {
        for x in 0..SIZE {
            let p = pixel_world(x, y, SIZE, HALF);
            let d = (p[0] - lo[0]).min(hi[0] - p[0]).min(p[1] - lo[1]).min(hi[1] - p[1]);
            if d > margin {
                assert_pixel(image, x, y, inside, 2.0, what);
                counted[0] += 1;
            } else if d < -margin {
                assert_pixel(image, x, y, [0.0; 3], 0.0, what);
                counted[1] += 1;
            }
        }
    }
    assert!(counted[0] > 50 && counted[1] > 50, "{what}: {counted:?} pixels in and out");
}

fn lambert_value(n: [f64; 3], direction: Vec3) -> f64 {
    let l = normalize([-direction.x, -direction.y, -direction.z].map(f64::from));
    f64::from(BASE) * (f64::from(AMBIENT) + dot(n, l).max(0.0))
}

#[test]
fn one_bone_turns_a_quad_a_quarter_turn_as_the_closed_form_says() {
    let ctx = ctx();
    let mut scene =
        GpuScene::upload(&ctx, &asset(edge_on_quad(0.0), grey(), vec![])).expect("upload");
    let offset = Vec3::new(0.2, 0.1, 0.0);
    let pose = ObjectPose {
        transform: Mat4::IDENTITY,
        joints: Some(palette(bone(offset))),
        morph_weights: vec![],
    };
    scene.set_pose(&ctx, &[pose]).expect("pose");
    // Posed: x in -0.6..0.6 and y in -0.3..0.3, moved by the offset; the normal +Z.
    let (lo, hi) = ([-0.4, -0.2], [0.8, 0.4]);
    let direction = Vec3::new(0.3, 0.2, -1.0);
    let lit = render_ortho(&ctx, &scene, &lambert(direction), VIEW);
    save("animation_bone_lambert", &lit);
    let value = srgb(lambert_value([0.0, 0.0, 1.0], direction));
    check_rectangle(&lit, lo, hi, [value; 3], "the skinned quad, lit");
    // The frame the fragment shader gets: the normal +Z, the tangent +X.
    for (view, colour, name) in [
        (DebugView::Normals, [127.5, 127.5, 255.0], "normals"),
        (DebugView::Tangents, [255.0, 127.5, 127.5], "tangents"),
    ] {
        let settings = FrameSettings { debug_view: view, ..lambert(direction) };
        let image = render_ortho(&ctx, &scene, &settings, VIEW);
        save(&format!("animation_bone_{name}"), &image);
        check_rectangle(&image, lo, hi, colour, name);
    }
}

/// A 1 x 1 square facing the camera with two morph targets: target 0 would throw it out of
/// view, target 1 moves its left edge by 0.6 and its right edge by 1.0 along +X and tilts
/// its normal by (1.2, 0, 0).
fn morphing_square() -> Object {
    let mut o = plane(0.5);
    o.morph_targets = vec![
        MorphTarget {
            position_deltas: vec![Vec3::new(0.0, 5.0, 0.0); 4],
            normal_deltas: None,
            tangent_deltas: None,
            ..MorphTarget::default()
        },
        MorphTarget {
            position_deltas: vec![
                Vec3::new(0.6, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.6, 0.0, 0.0),
            ],
            normal_deltas: Some(vec![Vec3::new(1.2, 0.0, 0.0); 4]),
            tangent_deltas: None,
            ..MorphTarget::default()
        },
    ];
    o
}

#[test]
fn a_morph_target_at_weight_one_half_adds_half_its_deltas() {
    let ctx = ctx();
    let mut scene =
        GpuScene::upload(&ctx, &asset(morphing_square(), grey(), vec![])).expect("upload");
    let pose =
        ObjectPose { transform: Mat4::IDENTITY, joints: None, morph_weights: vec![0.0, 0.5] };
    scene.set_pose(&ctx, &[pose]).expect("pose");
    // base + 0.5 x delta: x from -0.5 + 0.3 to 0.5 + 0.5; the normal (0.6, 0, 1), normalised.
    let (lo, hi) = ([-0.2, -0.5], [1.0, 0.5]);
    let direction = Vec3::new(-0.5, -0.2, -1.0);
    let image = render_ortho(&ctx, &scene, &lambert(direction), VIEW);
    save("animation_morph_half", &image);
    let n = normalize([0.6, 0.0, 1.0]);
    check_rectangle(&image, lo, hi, [srgb(lambert_value(n, direction)); 3], "the morphed square");
}

/// The luminance at world point (x, y) of the floor of [`shadow_scene`].
#[expect(
    clippy::cast_possible_truncation,
    reason = "the test asks for points of the floor in view, inside the image"
)]
fn at(image: &RgbaImage, x: f32, y: f32) -> f64 {
    let px = ((x / HALF * 0.5 + 0.5) * SIZE as f32) as u32;
    let py = ((0.5 - y / HALF * 0.5) * SIZE as f32) as u32;
    common::luminance(image.get_pixel(px, py))
}

#[test]
fn the_shadow_pass_skins_as_the_scene_pass_does() {
    // The floor (z = 0) and a 0.6 x 0.6 occluder bound to one bone. Unposed, the occluder
    // stands edge-on at x = 5, out of view and casting no shadow in view; the bone turns it
    // to face +Z, 0.5 above the floor, centred at x = -0.5 (as tests/shadows.rs places its
    // square). The light travels along +X and -Z at 45 degrees: the shadow covers x in
    // -0.3..0.3.
    let ctx = ctx();
    let mut occluder = edge_on_quad(5.0);
    for p in &mut occluder.positions {
        p.z *= 0.5;
    }
    let mut floor = plane(1.0);
    floor.material = Some(0);
    occluder.material = Some(0);
    let asset = Asset {
        model: Model::new(vec![floor, occluder]),
        materials: vec![grey()],
        ..Asset::default()
    };
    let mut scene = GpuScene::upload(&ctx, &asset).expect("upload");
    let joint = bone(Vec3::new(-0.5, 0.0, 0.5)) * Mat4::from_translation(Vec3::new(-5.0, 0.0, 0.0));
    let poses = [
        ObjectPose::default(),
        ObjectPose {
            transform: Mat4::IDENTITY,
            joints: Some(palette(joint)),
            morph_weights: vec![],
        },
    ];
    scene.set_pose(&ctx, &poses).expect("pose");
    let settings =
        FrameSettings { ambient: Vec3::ZERO, shadow_maps: 1, ..lambert(Vec3::new(1.0, 0.0, -1.0)) };
    let camera = ortho_camera(HALF);
    let frame =
        FrameDescriptor { scene: &scene, camera: &camera, settings: &settings, size: (SIZE, SIZE) };
    let image = Renderer::for_images(&ctx)
        .expect("renderer")
        .render_to_image(&ctx, &frame)
        .expect("render");
    save("animation_skinned_shadow", &image);
    let (shadowed, lit) = (at(&image, 0.05, 0.0), at(&image, 0.7, 0.0));
    assert!(lit > 0.2, "the lit floor is {lit}");
    assert!(shadowed < 0.25 * lit, "in the skinned occluder's shadow {shadowed}, outside {lit}");
    // The occluder itself is where the bone put it: x in -0.8..-0.2.
    assert!(at(&image, -0.5, 0.0) > 0.2, "the occluder, lit from the front");
}

#[test]
fn posed_vertices_read_back_are_the_closed_form() {
    let ctx = ctx();
    let objects = vec![edge_on_quad(0.0), morphing_square()];
    let asset = Asset { model: Model::new(objects.clone()), ..Asset::default() };
    let mut scene = GpuScene::upload(&ctx, &asset).expect("upload");
    let joint = bone(Vec3::new(0.2, 0.1, 0.0));
    let moved = Mat4::from_translation(Vec3::new(0.0, 0.0, -1.0));
    let poses = [
        ObjectPose {
            transform: Mat4::IDENTITY,
            joints: Some(palette(joint)),
            morph_weights: vec![],
        },
        ObjectPose { transform: moved, joints: None, morph_weights: vec![0.0, 0.5] },
    ];
    scene.set_pose(&ctx, &poses).expect("pose");
    let close = |a: Vec3, b: Vec3, what: &str| {
        assert!((a - b).abs().max_element() < 1e-5, "{what}: {a} against {b}");
    };
    let bone_quad = scene.posed_vertices(&ctx, 0).expect("read back").expect("on the GPU");
    assert_eq!(bone_quad.positions.len(), 4);
    for (v, &p) in objects[0].positions.iter().enumerate() {
        // x' = -z, z' = x, then the offset.
        close(bone_quad.positions[v], Vec3::new(-p.z + 0.2, p.y + 0.1, p.x), "skinned position");
        close(bone_quad.normals[v], Vec3::Z, "skinned normal");
        close(bone_quad.tangents[v].truncate(), Vec3::X, "skinned tangent");
        assert!((bone_quad.tangents[v].w - 1.0).abs() < 1e-6, "the handedness is kept");
    }
    let square = scene.posed_vertices(&ctx, 1).expect("read back").expect("on the GPU");
    let target = &objects[1].morph_targets[1];
    for (v, &p) in objects[1].positions.iter().enumerate() {
        let expected = p + 0.5 * target.position_deltas[v] + Vec3::new(0.0, 0.0, -1.0);
        close(square.positions[v], expected, "morphed position");
        close(square.normals[v], Vec3::new(0.6, 0.0, 1.0).normalize(), "morphed normal");
    }
}

#[test]
fn poses_that_do_not_fit_are_refused_and_change_nothing() {
    let ctx = ctx();
    let asset =
        Asset { model: Model::new(vec![edge_on_quad(0.0), morphing_square()]), ..Asset::default() };
    let mut scene = GpuScene::upload(&ctx, &asset).expect("upload");
    let bounds = scene.bounds();
    let fits = || {
        vec![
            ObjectPose { joints: Some(palette(Mat4::IDENTITY)), ..ObjectPose::default() },
            ObjectPose { morph_weights: vec![0.0, 1.0], ..ObjectPose::default() },
        ]
    };
    let mut short = fits();
    short[0].joints = Some(vec![Mat4::IDENTITY; 3]);
    let mut extra = fits();
    extra[1].morph_weights = vec![0.0; 3];
    let mut infinite = fits();
    infinite[1].morph_weights[0] = f32::NAN;
    for (poses, says) in [
        (vec![ObjectPose::default()], "1 poses for 2 objects"),
        (short, "its palette has 3 joint matrices, its influences name joint 3"),
        (extra, "3 morph weights for 2 morph targets"),
        (infinite, "morph weight 0 is not finite"),
    ] {
        match scene.set_pose(&ctx, &poses) {
            Err(e @ RenderError::BadPose { .. }) => {
                assert!(e.to_string().contains(says), "{e} should say {says:?}");
            }
            other => panic!("{says}: {other:?}"),
        }
        assert_eq!(scene.bounds(), bounds, "a refused pose leaves the scene alone");
    }
    scene.set_pose(&ctx, &fits()).expect("a pose that fits");
    // Target 1 at weight 1 moves the square's right edge to x = 1.5.
    let (_, hi) = scene.bounds().expect("bounds");
    assert!((hi.x - 1.5).abs() < 1e-6, "posed bounds reach {hi}");
}
