//! Image-based lighting: a white furnace (a uniform environment lights a rough white sphere
//! to the environment's radiance times its albedo, and a white rough metal to the
//! radiance), a mirror sphere that reflects the sky
//! above and the ground below, a rotation that moves a reflected bright spot, and a
//! malformed or missing .hdr file refused with its name.

mod common;

use common::shapes::sphere;
use common::{asset, ctx, ortho_camera, save};
use glam::Vec3;
use image::{Rgba, Rgba32FImage, RgbaImage};
use seamlit_io::Material;
use seamlit_render::{
    CameraDescriptor, CameraView, Environment, FrameDescriptor, FrameSettings, GpuEnvironment,
    GpuScene, LightingModel, Projection, RenderError, Renderer, ToneMapping,
};

const SIZE: u32 = 64;
const HALF: f32 = 1.2;

/// sRGB byte to linear.
fn linear(b: u8) -> f64 {
    let c = f64::from(b) / 255.0;
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// The pixel of the image that shows world point (x, y) on the plane z = 0.
#[expect(
    clippy::cast_possible_truncation,
    reason = "the tests ask for points of the plane in view, inside the image"
)]
fn pixel_of(x: f32, y: f32) -> (u32, u32) {
    let px = (x / HALF * 0.5 + 0.5) * SIZE as f32;
    let py = (0.5 - y / HALF * 0.5) * SIZE as f32;
    (px as u32, py as u32)
}

/// No lights, no ambient, no tone mapping, PBR, no environment behind, black background.
fn settings(rotation_deg: f32) -> FrameSettings {
    FrameSettings {
        lights: Vec::new(),
        ambient: Vec3::ZERO,
        lighting_model: LightingModel::Pbr,
        tone_mapping: ToneMapping::None,
        clear_color: [0.0, 0.0, 0.0, 1.0],
        environment_background: false,
        environment_rotation_deg: rotation_deg,
        ..FrameSettings::default()
    }
}

/// A unit sphere of one material, lit by `environment` (none: no image-based light).
fn render(
    material: Material,
    environment: Option<&Environment>,
    rotation_deg: f32,
    name: &str,
) -> RgbaImage {
    render_from(&ortho_camera(HALF), material, environment, rotation_deg, name)
}

/// [`render`] through `camera`.
fn render_from(
    camera: &CameraView,
    material: Material,
    environment: Option<&Environment>,
    rotation_deg: f32,
    name: &str,
) -> RgbaImage {
    let ctx = ctx();
    let scene =
        GpuScene::upload(&ctx, &asset(sphere("ball", 1.0, 48, 96, 0.0, 1.0), material, vec![]))
            .expect("upload");
    let mut renderer = Renderer::for_images(&ctx).expect("renderer");
    renderer.set_environment(
        environment.map(|e| GpuEnvironment::new(&ctx, e).expect("prefilter the environment")),
    );
    let settings = settings(rotation_deg);
    let frame = FrameDescriptor { scene: &scene, camera, settings: &settings, size: (SIZE, SIZE) };
    let image = renderer.render_to_image(&ctx, &frame).expect("render");
    save(name, &image);
    image
}

fn material(base: f32, metallic: f32, roughness: f32) -> Material {
    Material { base_color: [base, base, base, 1.0], metallic, roughness, ..Material::default() }
}

/// Points on the sphere's visible face, from its centre out to where n.v = 0.6.
const POINTS: [(f32, f32); 5] = [(0.0, 0.0), (0.5, 0.1), (-0.3, 0.6), (0.1, -0.7), (-0.75, -0.2)];

/// Asserts every colour channel at each of [`POINTS`] is `expected` in linear light, within
/// `relative` of it plus 0.004 (a step of the 8-bit sRGB output at these levels).
fn assert_lit_to(image: &RgbaImage, expected: f64, relative: f64, what: &str) {
    for (x, y) in POINTS {
        let (px, py) = pixel_of(x, y);
        let p = image.get_pixel(px, py).0;
        for c in 0..3 {
            let got = linear(p[c]);
            assert!(
                (got - expected).abs() <= relative * expected + 0.004,
                "{what}, point ({x}, {y}): {got:.4} for {expected:.4} (pixel {p:?})"
            );
        }
    }
}

#[test]
fn a_white_furnace_returns_the_environment_times_the_albedo() {
    let radiance: f32 = 0.5;
    let environment = Environment::Uniform(Vec3::splat(radiance));
    for albedo in [1.0_f32, 0.5] {
        let name = format!("ibl_furnace_{albedo}");
        let image = render(material(albedo, 0.0, 1.0), Some(&environment), 0.0, &name);
        // The specular lobe reflects a few percent of L on top of the diffuse part (all of it
        // for albedo 1, where diffuse takes exactly what it leaves).
        assert_lit_to(&image, f64::from(radiance * albedo), 0.05, &format!("albedo {albedo}"));
    }
}

#[test]
fn a_white_rough_metal_in_a_white_furnace_loses_no_energy() {
    // A white metal reflects all the light: with the energy multiple scattering between
    // microfacets returns (Fdez-Aguera 2019, as the Khronos Sample Viewer has it) a uniform
    // environment lights it to the environment's radiance at any roughness; single
    // scattering alone loses a quarter of it at roughness 1.
    let radiance: f32 = 0.5;
    let environment = Environment::Uniform(Vec3::splat(radiance));
    for roughness in [0.5, 1.0] {
        let name = format!("ibl_furnace_metal_{roughness}");
        let image = render(material(1.0, 1.0, roughness), Some(&environment), 0.0, &name);
        assert_lit_to(&image, f64::from(radiance), 0.03, &format!("roughness {roughness}"));
    }
}

/// `image` written to a Radiance file (its first row first) and read back, as
/// `--environment PATH.hdr` reads it.
fn through_hdr_file(image: &Rgba32FImage) -> Environment {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("environment.hdr");
    let rgb: Vec<image::Rgb<f32>> =
        image.pixels().map(|p| image::Rgb([p[0], p[1], p[2]])).collect();
    let file = std::fs::File::create(&path).expect("create");
    image::codecs::hdr::HdrEncoder::new(std::io::BufWriter::new(file))
        .encode(&rgb, image.width() as usize, image.height() as usize)
        .expect("encode");
    Environment::from_hdr_file(&path).expect("read the .hdr")
}

/// An equirectangular image: `top` radiance above the horizon (the first rows), `bottom`
/// below.
fn sky_and_ground(top: [f32; 3], bottom: [f32; 3]) -> Rgba32FImage {
    Rgba32FImage::from_fn(64, 32, |_, y| {
        let c = if y < 16 { top } else { bottom };
        Rgba([c[0], c[1], c[2], 1.0])
    })
}

#[test]
fn a_mirror_sphere_reflects_the_sky_above_and_the_ground_below() {
    let environment = through_hdr_file(&sky_and_ground([1.0, 0.1, 0.1], [0.1, 0.1, 1.0]));
    let image = render(material(1.0, 1.0, 0.0), Some(&environment), 0.0, "ibl_mirror");
    // Near the top the view reflects upward, near the bottom downward.
    let (tx, ty) = pixel_of(0.0, 0.7);
    let (bx, by) = pixel_of(0.0, -0.7);
    let top = image.get_pixel(tx, ty).0;
    let bottom = image.get_pixel(bx, by).0;
    assert!(top[0] > 200 && top[2] < 120, "the top reflects the red sky: {top:?}");
    assert!(bottom[2] > 200 && bottom[0] < 120, "the bottom reflects the blue ground: {bottom:?}");
    // Without the environment a smooth metal under no light is black.
    let dark = render(material(1.0, 1.0, 0.0), None, 0.0, "ibl_mirror_off");
    assert!(dark.get_pixel(tx, ty).0[..3].iter().all(|&c| c < 8), "{:?}", dark.get_pixel(tx, ty));
}

#[test]
fn a_mirror_sphere_seen_from_above_reflects_the_sky_at_its_centre() {
    // An orthographic camera 30 degrees above the horizon: at the sphere's centre the
    // normal points back at the camera and the view reflects 30 degrees upward (the sky); the
    // reflected horizon lies 15 degrees below the centre, at screen y = -sin 15 = -0.26, and
    // at screen y = -0.5 the view reflects 30 degrees downward (the ground).
    let environment = through_hdr_file(&sky_and_ground([1.0, 0.1, 0.1], [0.1, 0.1, 1.0]));
    let (s, c) = 30f32.to_radians().sin_cos();
    let camera = CameraView::look_at(&CameraDescriptor {
        eye: Vec3::new(0.0, 5.0 * s, 5.0 * c),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: Projection::Orthographic { half_height: HALF },
        aspect: 1.0,
        near: 0.1,
        far: 10.0,
    });
    let image =
        render_from(&camera, material(1.0, 1.0, 0.0), Some(&environment), 0.0, "ibl_mirror_above");
    for (y, sky) in [(0.0, true), (0.2, true), (-0.45, false), (-0.6, false)] {
        let (px, py) = pixel_of(0.0, y);
        let p = image.get_pixel(px, py).0;
        let (bright, dim) = if sky { (p[0], p[2]) } else { (p[2], p[0]) };
        assert!(
            bright > 200 && dim < 120,
            "screen y {y}: {p:?}, expected the {}",
            if sky { "red sky" } else { "blue ground" }
        );
    }
}

/// Black but for a bright spot around +Z (the middle of the image).
fn spot_at_plus_z() -> Rgba32FImage {
    Rgba32FImage::from_fn(128, 64, |x, y| {
        let c = if (60..68).contains(&x) && (28..36).contains(&y) { 50.0 } else { 0.0 };
        Rgba([c, c, c, 1.0])
    })
}

/// The column of the brightest pixel in the middle row.
fn brightest_column(image: &RgbaImage) -> u32 {
    (0..SIZE)
        .max_by_key(|&x| {
            let p = image.get_pixel(x, SIZE / 2).0;
            u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2])
        })
        .unwrap_or(0)
}

#[test]
fn rotating_the_environment_moves_the_reflected_spot() {
    let environment = through_hdr_file(&spot_at_plus_z());
    let mirror = material(1.0, 1.0, 0.0);
    // The spot behind the camera (+Z) reflects in the middle of the sphere.
    let straight = render(mirror.clone(), Some(&environment), 0.0, "ibl_spot_0");
    let centre = brightest_column(&straight);
    assert!(centre.abs_diff(SIZE / 2) <= 3, "spot at column {centre}");
    // Turned 90 degrees about +Y, the spot lies at +X: it reflects where the normal is
    // halfway between +Z and +X, at x = sin 45 degrees.
    let turned = render(mirror, Some(&environment), 90.0, "ibl_spot_90");
    let (expected, _) = pixel_of(std::f32::consts::FRAC_1_SQRT_2, 0.0);
    let moved = brightest_column(&turned);
    assert!(moved.abs_diff(expected) <= 3, "spot at column {moved}, expected {expected}");
}

#[test]
fn a_missing_or_malformed_hdr_file_is_refused_by_name() {
    let dir = tempfile::tempdir().expect("temp dir");
    let missing = dir.path().join("missing.hdr");
    let bad = dir.path().join("bad.hdr");
    std::fs::write(&bad, b"#?RADIANCE\nnot really\n").expect("write");
    for path in [missing, bad] {
        let err = Environment::from_hdr_file(&path).expect_err("refused");
        assert!(matches!(err, RenderError::Environment { .. }), "{err:?}");
        let message = err.to_string();
        assert!(message.starts_with(&format!("{}: ", path.display())), "{message}");
        assert!(!message.contains('\n'), "{message}");
    }
}
