//! Shadow maps: a plane under a small square, lit at 45 degrees by a directional light and by
//! a spot light, is darker in the square's shadow than outside it; with shadows off it is not.

mod common;

use common::{ctx, luminance, ortho_camera, plane, save};
use glam::{Mat4, Vec3};
use image::RgbaImage;
use seamlit_io::{Asset, Material};
use seamlit_mesh::Model;
use seamlit_render::{FrameDescriptor, FrameSettings, GpuScene, Light, LightingModel, Renderer};

const SIZE: u32 = 64;
const HALF: f32 = 1.0;

/// The floor (z = 0, 2 x 2) and, 0.5 above it, a 0.6 x 0.6 square centred at x = -0.5.
fn floor_and_occluder() -> Asset {
    let mut floor = plane(1.0);
    let mut square = plane(0.3).with_transform(Mat4::from_translation(Vec3::new(-0.5, 0.0, 0.5)));
    floor.material = Some(0);
    square.material = Some(0);
    Asset {
        model: Model::new(vec![floor, square]),
        materials: vec![Material { base_color: [0.8, 0.8, 0.8, 1.0], ..Material::default() }],
        ..Asset::default()
    }
}

fn render(light: Light, shadow_maps: usize, name: &str) -> RgbaImage {
    let ctx = ctx();
    let scene = GpuScene::upload(&ctx, &floor_and_occluder()).expect("upload");
    let settings = FrameSettings {
        lights: vec![light],
        ambient: Vec3::ZERO,
        lighting_model: LightingModel::Lambert,
        clear_color: [0.0, 0.0, 0.0, 1.0],
        shadow_maps,
        ..FrameSettings::default()
    };
    let camera = ortho_camera(HALF);
    let frame =
        FrameDescriptor { scene: &scene, camera: &camera, settings: &settings, size: (SIZE, SIZE) };
    let image = Renderer::for_images(&ctx)
        .expect("renderer")
        .render_to_image(&ctx, &frame)
        .expect("render");
    save(name, &image);
    image
}

/// The luminance at world point (x, y) of the floor.
#[expect(
    clippy::cast_possible_truncation,
    reason = "the tests ask for points of the floor in view, inside the image"
)]
fn at(image: &RgbaImage, x: f32, y: f32) -> f64 {
    let px = ((x / HALF * 0.5 + 0.5) * SIZE as f32) as u32;
    let py = ((0.5 - y / HALF * 0.5) * SIZE as f32) as u32;
    luminance(image.get_pixel(px, py))
}

/// The light travels along +X and -Z at 45 degrees: the square's shadow on the floor is the
/// square moved 0.5 along +X, x in -0.3..0.3 (x < -0.2 is hidden by the square itself).
fn check(light: Light, what: &str) {
    let on = render(light, 1, &format!("shadows_{what}_on"));
    let (shadowed, lit) = (at(&on, 0.05, 0.0), at(&on, 0.7, 0.0));
    assert!(lit > 0.2, "{what}: the lit floor is {lit}");
    assert!(shadowed < 0.25 * lit, "{what}: in the shadow {shadowed}, outside {lit}");
    let off = render(light, 0, &format!("shadows_{what}_off"));
    let (shadowed, lit) = (at(&off, 0.05, 0.0), at(&off, 0.7, 0.0));
    // Off, the same point is as bright as outside (the spot's nearer: brighter).
    assert!(shadowed >= 0.95 * lit, "{what}, off: {shadowed} against {lit}");
}

#[test]
fn a_plane_is_darker_in_the_shadow_of_a_square_above_it() {
    let direction = Vec3::new(1.0, 0.0, -1.0);
    check(Light::Directional { direction, color: Vec3::ONE, intensity: 1.0 }, "directional");
    // A spot 3 units up the same line: its light arrives at nearly the same angle.
    check(
        Light::Spot {
            position: Vec3::new(-0.5, 0.0, 0.5) - direction.normalize() * 3.0,
            direction,
            color: Vec3::ONE,
            intensity: 12.0,
            range: 0.0,
            inner_cone_deg: 40.0,
            outer_cone_deg: 50.0,
        },
        "spot",
    );
}
