//! Analytic checks: a lit plane's pixels equal the lighting equation computed here, in f64,
//! within 2/255 (lavapipe in CI: real rendering).

mod common;

use common::{
    Ortho, assert_pixel, asset, ctx, decode, dot, normalize, ortho_camera, pixel_world, plane,
    render_image, render_ortho, save, srgb, tex_ref, texture,
};
use glam::Vec3;
use image::RgbaImage;
use seamlit_io::Material;
use seamlit_render::{FrameDescriptor, FrameSettings, GpuScene, Light, LightingModel};

const SIZE: u32 = 64;
const HALF: f32 = 1.0;
/// The plane seen head-on, filling the picture.
const VIEW: Ortho = Ortho { half: HALF, size: SIZE };
const EYE: [f64; 3] = [0.0, 0.0, 5.0];

/// A plane with one uniform normal-map texel everywhere.
fn normal_mapped_plane(texel: [u8; 3], material: Material) -> seamlit_io::Asset {
    let img = RgbaImage::from_pixel(4, 4, image::Rgba([texel[0], texel[1], texel[2], 255]));
    asset(
        plane(1.5),
        Material { normal_texture: tex_ref(0), ..material },
        vec![texture("normal", img)],
    )
}

/// The tangent-space normal of a texel in world space for the plane (T = +X, B = +Y, N = +Z).
fn texel_normal(texel: [u8; 3]) -> [f64; 3] {
    normalize([decode(texel[0]), decode(texel[1]), decode(texel[2])])
}

#[test]
fn directional_light_on_a_flat_normal_map_matches_blinn_phong() {
    let ctx = ctx();
    let material = Material {
        base_color: [0.8, 0.6, 0.4, 1.0],
        specular: [0.5, 0.5, 0.5],
        shininess: 16.0,
        ..Material::default()
    };
    let texel = [128, 128, 255];
    let scene =
        GpuScene::upload(&ctx, &normal_mapped_plane(texel, material.clone())).expect("upload");
    let dir = [-0.3, -0.2, -1.0];
    let light_color = [1.0, 0.9, 0.8];
    let intensity = 0.9;
    let ambient = 0.05;
    let settings = FrameSettings {
        lights: vec![Light::Directional {
            direction: Vec3::new(-0.3, -0.2, -1.0),
            color: Vec3::new(1.0, 0.9, 0.8),
            intensity: 0.9,
        }],
        ambient: Vec3::splat(0.05),
        ..FrameSettings::default()
    };
    let image = render_ortho(&ctx, &scene, &settings, VIEW);
    save("analytic_flat", &image);

    let n = texel_normal(texel);
    let l = normalize(dir.map(|d: f64| -d));
    for (x, y) in [(32, 32), (5, 7), (60, 50), (20, 58)] {
        let p = pixel_world(x, y, SIZE, HALF);
        let v = normalize([EYE[0] - p[0], EYE[1] - p[1], EYE[2] - p[2]]);
        let h = normalize([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
        let n_dot_l = dot(n, l).max(0.0);
        let spec = dot(n, h).max(0.0).powf(f64::from(material.shininess));
        let expected: [f64; 3] = std::array::from_fn(|c| {
            let albedo = f64::from(material.base_color[c]);
            let radiance = light_color[c] * intensity;
            srgb(
                albedo * (ambient + radiance * n_dot_l)
                    + f64::from(material.specular[c]) * radiance * spec,
            )
        });
        assert_pixel(&image, x, y, expected, 2.0, "flat normal map, Blinn-Phong");
    }
}

#[test]
fn a_normal_map_texel_tilted_45_degrees_is_darker_by_the_cosine() {
    let ctx = ctx();
    let material =
        Material { base_color: [0.9, 0.9, 0.9, 1.0], specular: [0.0; 3], ..Material::default() };
    // n = (sin 45, 0, cos 45): tilted toward +T = +X.
    let t = (std::f64::consts::FRAC_1_SQRT_2 * 0.5 + 0.5) * 255.0;
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "218.2 fits a byte"
    )]
    let tilted = [t.round() as u8, 128, t.round() as u8];
    let flat = [128, 128, 255];
    let lambert = |direction: Vec3| FrameSettings {
        lights: vec![Light::Directional { direction, color: Vec3::ONE, intensity: 1.0 }],
        ambient: Vec3::splat(0.02),
        lighting_model: LightingModel::Lambert,
        ..FrameSettings::default()
    };
    let camera = ortho_camera(HALF);
    let render = |texel: [u8; 3], direction: Vec3, name: &str| {
        let scene =
            GpuScene::upload(&ctx, &normal_mapped_plane(texel, material.clone())).expect("upload");
        let image = render_image(
            &ctx,
            &FrameDescriptor {
                scene: &scene,
                camera: &camera,
                settings: &lambert(direction),
                size: (SIZE, SIZE),
            },
        )
        .expect("render");
        save(name, &image);
        image
    };
    let expect = |texel: [u8; 3], l: [f64; 3]| -> [f64; 3] {
        let n_dot_l = dot(texel_normal(texel), normalize(l)).max(0.0);
        [srgb(0.9 * (0.02 + n_dot_l)); 3]
    };

    // Light straight down: the flat texel gets cos 0, the tilted one cos 45.
    let down = Vec3::NEG_Z;
    let flat_img = render(flat, down, "analytic_flat_down");
    let tilted_img = render(tilted, down, "analytic_tilted_down");
    assert_pixel(
        &flat_img,
        32,
        32,
        expect(flat, [0.0, 0.0, 1.0]),
        2.0,
        "flat texel, light from above",
    );
    assert_pixel(
        &tilted_img,
        32,
        32,
        expect(tilted, [0.0, 0.0, 1.0]),
        2.0,
        "tilted texel, light from above",
    );
    let expected_tilted = expect(tilted, [0.0, 0.0, 1.0])[0];
    assert!(
        expected_tilted < expect(flat, [0.0, 0.0, 1.0])[0] - 20.0,
        "the tilted texel must be clearly darker"
    );

    // Light from 45 degrees on the +X side: the tilted texel faces it (full light); from the
    // -X side it faces away (ambient only). This fixes the direction of the tangent.
    let from_plus_x = render(tilted, Vec3::new(-1.0, 0.0, -1.0), "analytic_tilted_plus_x");
    let from_minus_x = render(tilted, Vec3::new(1.0, 0.0, -1.0), "analytic_tilted_minus_x");
    assert_pixel(
        &from_plus_x,
        32,
        32,
        expect(tilted, [1.0, 0.0, 1.0]),
        2.0,
        "tilted texel, light from +X",
    );
    assert_pixel(
        &from_minus_x,
        32,
        32,
        expect(tilted, [-1.0, 0.0, 1.0]),
        2.0,
        "tilted texel, light from -X",
    );
}

#[test]
fn point_light_falls_off_with_distance_as_specified() {
    let ctx = ctx();
    let material =
        Material { base_color: [1.0, 1.0, 1.0, 1.0], specular: [0.0; 3], ..Material::default() };
    let scene = GpuScene::upload(&ctx, &asset(plane(1.5), material, vec![])).expect("upload");
    let (height, range, intensity) = (1.0, 3.0, 0.8);
    let settings = FrameSettings {
        lights: vec![Light::Point {
            position: Vec3::new(0.0, 0.0, 1.0),
            color: Vec3::ONE,
            intensity: 0.8,
            range: 3.0,
        }],
        ambient: Vec3::ZERO,
        lighting_model: LightingModel::Lambert,
        ..FrameSettings::default()
    };
    let image = render_ortho(&ctx, &scene, &settings, VIEW);
    save("analytic_point", &image);
    // KHR_lights_punctual: clamp(1 - (d / range)^4, 0, 1)^2 / d^2, times N.L.
    let expected = |x: u32, y: u32| {
        let p = pixel_world(x, y, SIZE, HALF);
        let to_light = [-p[0], -p[1], height - p[2]];
        let d = dot(to_light, to_light).sqrt();
        let fade = (1.0 - (d / range).powi(4)).clamp(0.0, 1.0);
        let value = intensity * fade * fade / (d * d) * (to_light[2] / d);
        [srgb(value); 3]
    };
    // Near: right under the light (d ~ 1); far: 0.9 to the side (d ~ 1.35).
    let (near, far) = ((32, 32), (61, 32));
    assert_pixel(&image, near.0, near.1, expected(near.0, near.1), 2.0, "point light, near");
    assert_pixel(&image, far.0, far.1, expected(far.0, far.1), 2.0, "point light, far");
    assert!(
        expected(far.0, far.1)[0] < expected(near.0, near.1)[0] - 30.0,
        "the far pixel must be clearly darker"
    );
}

#[test]
fn spot_light_is_full_inside_the_inner_cone_and_dark_outside_the_outer() {
    let ctx = ctx();
    let material =
        Material { base_color: [1.0, 1.0, 1.0, 1.0], specular: [0.0; 3], ..Material::default() };
    let scene = GpuScene::upload(&ctx, &asset(plane(1.5), material, vec![])).expect("upload");
    let (height, inner, outer) = (1.0f64, 20.0f64, 35.0f64);
    let settings = FrameSettings {
        lights: vec![Light::Spot {
            position: Vec3::new(0.0, 0.0, 1.0),
            direction: Vec3::NEG_Z,
            color: Vec3::ONE,
            intensity: 0.7,
            range: 0.0,
            inner_cone_deg: 20.0,
            outer_cone_deg: 35.0,
        }],
        ambient: Vec3::ZERO,
        lighting_model: LightingModel::Lambert,
        ..FrameSettings::default()
    };
    let image = render_ortho(&ctx, &scene, &settings, VIEW);
    save("analytic_spot", &image);
    // No range cut-off (range 0): 1 / d^2, times N.L, times the cone factor t^2 with
    // t = clamp((cos a - cos outer) / (cos inner - cos outer), 0, 1).
    let expected = |x: u32, y: u32| {
        let p = pixel_world(x, y, SIZE, HALF);
        let to_light = [-p[0], -p[1], height - p[2]];
        let d = dot(to_light, to_light).sqrt();
        let cos_a = to_light[2] / d;
        let (ci, co) = (inner.to_radians().cos(), outer.to_radians().cos());
        let t = ((cos_a - co) / (ci - co)).clamp(0.0, 1.0);
        [srgb(0.7 / (d * d) * cos_a * t * t); 3]
    };
    // Centre (inside the inner cone), x = 0.5 (26.6 degrees: in the fade), x = 0.9 (42
    // degrees: outside, black).
    for x in [32, 48, 60] {
        assert_pixel(&image, x, 32, expected(x, 32), 2.0, "spot light");
    }
    assert!(
        expected(60, 32)[0] < 0.5
            && expected(48, 32)[0] > 20.0
            && expected(48, 32)[0] < expected(32, 32)[0] - 20.0
    );
}

#[test]
fn phong_and_gouraud_match_their_equations_on_a_plane() {
    let ctx = ctx();
    let material = Material {
        base_color: [0.6, 0.6, 0.6, 1.0],
        specular: [0.4; 3],
        shininess: 8.0,
        ..Material::default()
    };
    let scene = GpuScene::upload(&ctx, &asset(plane(1.5), material, vec![])).expect("upload");
    let dir = [0.4, 0.1, -1.0];
    let l = normalize(dir.map(|d: f64| -d));
    let n = [0.0, 0.0, 1.0];
    let base = FrameSettings {
        lights: vec![Light::Directional {
            direction: Vec3::new(0.4, 0.1, -1.0),
            color: Vec3::ONE,
            intensity: 0.8,
        }],
        ambient: Vec3::splat(0.03),
        ..FrameSettings::default()
    };
    // Phong: specular from the reflection vector R = 2 (N.L) N - L.
    let phong = render_ortho(
        &ctx,
        &scene,
        &FrameSettings { lighting_model: LightingModel::Phong, ..base.clone() },
        VIEW,
    );
    save("analytic_phong", &phong);
    for (x, y) in [(32, 32), (10, 50)] {
        let p = pixel_world(x, y, SIZE, HALF);
        let v = normalize([EYE[0] - p[0], EYE[1] - p[1], EYE[2] - p[2]]);
        let nl = dot(n, l);
        let r = [2.0 * nl * n[0] - l[0], 2.0 * nl * n[1] - l[1], 2.0 * nl * n[2] - l[2]];
        let value = 0.6 * (0.03 + 0.8 * nl) + 0.4 * 0.8 * dot(r, v).max(0.0).powf(8.0);
        assert_pixel(&phong, x, y, [srgb(value); 3], 2.0, "Phong");
    }
    // Gouraud: Blinn-Phong at the four corners, interpolated. With a directional light the
    // diffuse term is the same everywhere; the specular term varies slowly, so the centre is
    // close to the average of the corner values. The diffuse part is checked exactly by
    // turning specular off in a second render.
    let gouraud = render_ortho(
        &ctx,
        &scene,
        &FrameSettings { lighting_model: LightingModel::Gouraud, ..base.clone() },
        VIEW,
    );
    save("analytic_gouraud", &gouraud);
    let diffuse_only = GpuScene::upload(
        &ctx,
        &asset(
            plane(1.5),
            Material {
                base_color: [0.6, 0.6, 0.6, 1.0],
                specular: [0.0; 3],
                ..Material::default()
            },
            vec![],
        ),
    )
    .expect("upload");
    let g = render_ortho(
        &ctx,
        &diffuse_only,
        &FrameSettings { lighting_model: LightingModel::Gouraud, ..base },
        VIEW,
    );
    assert_pixel(&g, 20, 40, [srgb(0.6 * (0.03 + 0.8 * dot(n, l))); 3], 2.0, "Gouraud diffuse");
    // The per-vertex specular at the plane's corners (+-1.5) interpolated bilinearly-ish across
    // two triangles: at the centre it lies between the smallest and largest corner value.
    let corner_spec = |cx: f64, cy: f64| {
        let v = normalize([EYE[0] - cx, EYE[1] - cy, EYE[2]]);
        let h = normalize([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
        0.4 * 0.8 * dot(n, h).max(0.0).powf(8.0)
    };
    let corners = [
        corner_spec(-1.5, -1.5),
        corner_spec(1.5, -1.5),
        corner_spec(1.5, 1.5),
        corner_spec(-1.5, 1.5),
    ];
    let lo = corners.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = corners.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let diffuse = 0.6 * (0.03 + 0.8 * dot(n, l));
    let centre = f64::from(gouraud.get_pixel(32, 32)[0]);
    assert!(
        centre >= srgb(diffuse + lo) - 2.0 && centre <= srgb(diffuse + hi) + 2.0,
        "Gouraud centre {centre} outside [{}, {}]",
        srgb(diffuse + lo),
        srgb(diffuse + hi)
    );
}

#[test]
fn green_flip_and_normal_mapping_switches() {
    let ctx = ctx();
    let material =
        Material { base_color: [0.9, 0.9, 0.9, 1.0], specular: [0.0; 3], ..Material::default() };
    // n = (0, sin 45, cos 45): tilted toward +B = +Y (OpenGL convention, green up).
    let t = ((std::f64::consts::FRAC_1_SQRT_2 * 0.5 + 0.5) * 255.0).round();
    #[expect(clippy::cast_possible_truncation, clippy::cast_sign_loss, reason = "218 fits a byte")]
    let texel = [128, t as u8, t as u8];
    let scene =
        GpuScene::upload(&ctx, &normal_mapped_plane(texel, material.clone())).expect("upload");
    // Light from +Y at 45 degrees.
    let settings = FrameSettings {
        lights: vec![Light::Directional {
            direction: Vec3::new(0.0, -1.0, -1.0),
            color: Vec3::ONE,
            intensity: 1.0,
        }],
        ambient: Vec3::splat(0.02),
        lighting_model: LightingModel::Lambert,
        ..FrameSettings::default()
    };
    let camera = ortho_camera(HALF);
    let value = |n: [f64; 3]| {
        [srgb(0.9 * (0.02 + dot(normalize(n), normalize([0.0, 1.0, 1.0])).max(0.0))); 3]
    };
    let (x, y, z) = (decode(texel[0]), decode(texel[1]), decode(texel[2]));
    let up = render_image(
        &ctx,
        &FrameDescriptor {
            scene: &scene,
            camera: &camera,
            settings: &settings,
            size: (SIZE, SIZE),
        },
    )
    .expect("render");
    assert_pixel(&up, 32, 32, value([x, y, z]), 2.0, "green up faces the light");
    let flipped = render_image(
        &ctx,
        &FrameDescriptor {
            scene: &scene,
            camera: &camera,
            settings: &FrameSettings { flip_green: true, ..settings.clone() },
            size: (SIZE, SIZE),
        },
    )
    .expect("render");
    assert_pixel(&flipped, 32, 32, value([x, -y, z]), 2.0, "frame green flip faces away");
    // The material's own DirectX flag flips too, and the frame flip flips it back.
    let dx = GpuScene::upload(
        &ctx,
        &normal_mapped_plane(texel, Material { normal_green_down: true, ..material.clone() }),
    )
    .expect("upload");
    let dx_img = render_image(
        &ctx,
        &FrameDescriptor { scene: &dx, camera: &camera, settings: &settings, size: (SIZE, SIZE) },
    )
    .expect("render");
    assert_pixel(&dx_img, 32, 32, value([x, -y, z]), 2.0, "material green-down flips");
    // Strength 0.5 halves the tangent-space x and y.
    let half = render_image(
        &ctx,
        &FrameDescriptor {
            scene: &scene,
            camera: &camera,
            settings: &FrameSettings { normal_strength: 0.5, ..settings.clone() },
            size: (SIZE, SIZE),
        },
    )
    .expect("render");
    assert_pixel(&half, 32, 32, value([x * 0.5, y * 0.5, z]), 2.0, "strength 0.5");
    // Normal mapping off for the frame: the geometric normal.
    let off = render_image(
        &ctx,
        &FrameDescriptor {
            scene: &scene,
            camera: &camera,
            settings: &FrameSettings { normal_mapping: false, ..settings },
            size: (SIZE, SIZE),
        },
    )
    .expect("render");
    assert_pixel(&off, 32, 32, value([0.0, 0.0, 1.0]), 2.0, "normal mapping off");
}
