//! The metallic-roughness model against the glTF 2.0 specification's Appendix B, computed here
//! in f64 independently of the shader: a lit plane under one directional light, no ambient
//! light, no tone mapping, within 2/255 per channel (lavapipe in CI: real rendering). Then the
//! material inputs that change the picture: the metallic-roughness texture, alpha MASK and
//! BLEND, the emissive colour.

mod common;

use common::{
    Ortho, assert_pixel, asset, ctx, dot, normalize, pixel_world, plane, render_ortho, save, srgb,
    tex_ref, texture,
};
use glam::Vec3;
use image::RgbaImage;
use seamlit_io::{AlphaMode, Asset, Material};
use seamlit_render::{FrameSettings, GpuScene, Light, LightingModel, ToneMapping};

const SIZE: u32 = 64;
const HALF: f32 = 1.0;
/// The plane seen head-on, filling the picture.
const VIEW: Ortho = Ortho { half: HALF, size: SIZE };
const EYE: [f64; 3] = [0.0, 0.0, 5.0];
/// The light's direction of travel, colour and intensity (lux).
const LIGHT_DIR: [f64; 3] = [-0.5, -0.3, -1.0];
const LIGHT_COLOR: [f64; 3] = [1.0, 0.95, 0.9];
const LIGHT_INTENSITY: f64 = 2.5;

/// glTF 2.0 Appendix B (section B.3, "Metals" to "Mixed materials"): the BRDF times n.l for
/// unit vectors n, v, l, written as the specification composes it:
/// `metal_brdf = specular_brdf * conductor_fresnel(base)`,
/// `dielectric_brdf = fresnel_mix(ior 1.5, diffuse_brdf(base), specular_brdf)` and
/// `mix(dielectric_brdf, metal_brdf, metallic)`, with `specular_brdf = D Vis` (D the GGX
/// distribution, Vis the height-correlated Smith visibility, alpha = roughness^2), Schlick's
/// Fresnel on v.h, f0 = 0.04 for the dielectric. (The diffuse layer sits under the
/// dielectric's Fresnel, not the metallic-mixed one.)
fn appendix_b(
    n: [f64; 3],
    v: [f64; 3],
    l: [f64; 3],
    base: [f64; 3],
    metallic: f64,
    roughness: f64,
) -> [f64; 3] {
    use std::f64::consts::PI;
    let h = normalize([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
    let (n_l, n_v, n_h, v_h) = (dot(n, l), dot(n, v), dot(n, h), dot(v, h));
    if n_l <= 0.0 {
        return [0.0; 3];
    }
    let a2 = (roughness * roughness).powi(2);
    let d = a2 / (PI * (n_h * n_h * (a2 - 1.0) + 1.0).powi(2));
    let vis = 0.5
        / (n_l * (n_v * n_v * (1.0 - a2) + a2).sqrt() + n_v * (n_l * n_l * (1.0 - a2) + a2).sqrt());
    let schlick = (1.0 - v_h).powi(5);
    let specular_brdf = d * vis;
    std::array::from_fn(|c| {
        let metal_brdf = specular_brdf * (base[c] + (1.0 - base[c]) * schlick);
        let fresnel = 0.04 + (1.0 - 0.04) * schlick;
        let dielectric_brdf = base[c] / PI * (1.0 - fresnel) + specular_brdf * fresnel;
        (dielectric_brdf * (1.0 - metallic) + metal_brdf * metallic) * n_l
    })
}

/// The expected sRGB value of pixel (x, y) of the plane (n = +Z) for a uniform material.
fn expected(x: u32, y: u32, base: [f64; 3], metallic: f64, roughness: f64) -> [f64; 3] {
    let p = pixel_world(x, y, SIZE, HALF);
    let v = normalize([EYE[0] - p[0], EYE[1] - p[1], EYE[2] - p[2]]);
    let l = normalize(LIGHT_DIR.map(|d| -d));
    let f = appendix_b([0.0, 0.0, 1.0], v, l, base, metallic, roughness);
    std::array::from_fn(|c| srgb(f[c] * LIGHT_COLOR[c] * LIGHT_INTENSITY))
}

/// `x`, which the expected values use in f64, rounded to the f32 the renderer takes.
#[expect(clippy::cast_possible_truncation, reason = "rounding to f32 is the point")]
fn single(x: f64) -> f32 {
    x as f32
}

/// One directional light travelling along `direction`, no ambient, PBR, no tone mapping, a
/// black background.
fn settings_with(direction: [f64; 3], intensity: f64) -> FrameSettings {
    FrameSettings {
        lights: vec![Light::Directional {
            direction: Vec3::from_array(direction.map(single)),
            color: Vec3::from_array(LIGHT_COLOR.map(single)),
            intensity: single(intensity),
        }],
        ambient: Vec3::ZERO,
        lighting_model: LightingModel::Pbr,
        tone_mapping: ToneMapping::None,
        clear_color: [0.0, 0.0, 0.0, 1.0],
        ..FrameSettings::default()
    }
}

fn settings() -> FrameSettings {
    settings_with(LIGHT_DIR, LIGHT_INTENSITY)
}

fn render(asset: &Asset, name: &str) -> RgbaImage {
    render_with(asset, &settings(), name)
}

fn render_with(asset: &Asset, settings: &FrameSettings, name: &str) -> RgbaImage {
    let ctx = ctx();
    let scene = GpuScene::upload(&ctx, asset).expect("upload");
    let image = render_ortho(&ctx, &scene, settings, VIEW);
    save(name, &image);
    image
}

fn uniform(base: [f32; 3], metallic: f32, roughness: f32) -> Material {
    Material {
        base_color: [base[0], base[1], base[2], 1.0],
        metallic,
        roughness,
        ..Material::default()
    }
}

/// Sampled pixels: the centre, the corners' neighbourhoods, the highlight's side.
const PIXELS: [(u32, u32); 6] = [(32, 32), (5, 7), (60, 50), (20, 58), (10, 40), (48, 12)];

#[test]
fn a_plane_matches_appendix_b_for_dielectric_metal_and_in_between() {
    for (name, base, metallic, roughness) in [
        ("dielectric", [0.8, 0.5, 0.3], 0.0, 0.5),
        ("metal", [0.95, 0.64, 0.54], 1.0, 0.6),
        ("half", [0.3, 0.6, 0.9], 0.5, 0.8),
        ("glossy", [0.2, 0.2, 0.25], 0.0, 0.3),
    ] {
        let image = render(
            &asset(plane(1.5), uniform(base, metallic, roughness), vec![]),
            &format!("pbr_{name}"),
        );
        let base = base.map(f64::from);
        for (x, y) in PIXELS {
            let e = expected(x, y, base, f64::from(metallic), f64::from(roughness));
            assert_pixel(&image, x, y, e, 2.0, &format!("{name} plane, Appendix B"));
        }
    }
}

#[test]
fn a_tilted_plane_lit_from_the_mirror_direction_matches_appendix_b() {
    // The plane turned 60 degrees about X: n = (0, sin 60, cos 60), so the view (about +Z)
    // meets it at 60 degrees and the light comes from the mirror direction, 120 degrees from
    // the view. There v.h = 0.5, where Schlick's Fresnel and the visibility term are far from
    // their values at normal incidence, and the specular peak is in the picture.
    let tilt = 60f64.to_radians();
    let n = [0.0, tilt.sin(), tilt.cos()];
    let to_light = {
        let (v, k) = ([0.0, 0.0, 1.0], 2.0 * tilt.cos());
        normalize([k * n[0] - v[0], k * n[1] - v[1], k * n[2] - v[2]])
    };
    // Dimmer than elsewhere: the metal's peak stays below white.
    let intensity = 0.7;
    let settings = settings_with(to_light.map(|c| -c), intensity);
    for (name, base, metallic, roughness) in [
        ("dielectric", [0.8, 0.5, 0.3], 0.0, 0.5),
        ("metal", [0.95, 0.64, 0.54], 1.0, 0.6),
        ("rough", [0.3, 0.6, 0.9], 0.3, 0.9),
    ] {
        let plane = plane(3.0).with_transform(glam::Mat4::from_rotation_x(single(-tilt)));
        let asset = asset(plane, uniform(base, metallic, roughness), vec![]);
        let image = render_with(&asset, &settings, &format!("pbr_tilted_{name}"));
        for (x, y) in PIXELS {
            // The orthographic ray through the pixel meets the plane n.p = 0 at this p.
            let [px, py, _] = pixel_world(x, y, SIZE, HALF);
            let p = [px, py, -(n[1] * py) / n[2]];
            let v = normalize([EYE[0] - p[0], EYE[1] - p[1], EYE[2] - p[2]]);
            let f = appendix_b(
                n,
                v,
                to_light,
                base.map(f64::from),
                f64::from(metallic),
                f64::from(roughness),
            );
            let e = std::array::from_fn(|c| srgb(f[c] * LIGHT_COLOR[c] * intensity));
            assert_pixel(&image, x, y, e, 2.0, &format!("tilted {name} plane, Appendix B"));
        }
    }
}

/// A 16 x 16 texture whose left half is one texel and right half another.
fn halves(left: [u8; 4], right: [u8; 4]) -> RgbaImage {
    RgbaImage::from_fn(16, 16, |x, _| image::Rgba(if x < 8 { left } else { right }))
}

#[test]
fn the_metallic_roughness_texture_multiplies_the_factors() {
    // Factors 1: the texture alone decides. Left: metal (blue 255), roughness 0.25 (green 64);
    // right: dielectric, roughness 1.
    let material =
        Material { metallic_roughness_texture: tex_ref(0), ..uniform([0.9, 0.7, 0.3], 1.0, 1.0) };
    let texture = texture("metallic-roughness", halves([0, 64, 255, 255], [0, 255, 0, 255]));
    let image = render(&asset(plane(1.5), material, vec![texture]), "pbr_mr_texture");
    let base = [0.9, 0.7, 0.3];
    // The plane spans u from 1/6 to 5/6 across the image: u < 0.5 left of the centre column.
    for (x, y) in [(8, 20), (14, 50), (26, 8)] {
        let e = expected(x, y, base, 1.0, 64.0 / 255.0);
        assert_pixel(&image, x, y, e, 2.0, "metal, smooth half");
    }
    for (x, y) in [(40, 20), (50, 50), (58, 8)] {
        let e = expected(x, y, base, 0.0, 1.0);
        assert_pixel(&image, x, y, e, 2.0, "dielectric, rough half");
    }
}

#[test]
fn alpha_mask_cuts_out_pixels_under_the_cutoff() {
    let material = Material {
        base_color_texture: tex_ref(0),
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..uniform([1.0, 1.0, 1.0], 0.0, 0.5)
    };
    // Left alpha 0.4 (cut), right alpha 0.6 (kept, drawn opaque); white base colour.
    let texture = texture("alpha", halves([255, 255, 255, 102], [255, 255, 255, 153]));
    let image = render(&asset(plane(1.5), material, vec![texture]), "pbr_mask");
    for (x, y) in [(8, 20), (20, 50)] {
        assert_pixel(&image, x, y, [0.0; 3], 0.0, "cut-out half shows the black background");
    }
    for (x, y) in [(44, 20), (56, 50)] {
        let e = expected(x, y, [1.0; 3], 0.0, 0.5);
        assert_pixel(&image, x, y, e, 2.0, "kept half, lit as opaque");
    }
}

#[test]
fn alpha_blend_mixes_with_the_background_by_alpha() {
    let alpha = 0.25;
    let material = Material {
        base_color: [0.8, 0.5, 0.3, alpha],
        alpha_mode: AlphaMode::Blend,
        ..uniform([0.8, 0.5, 0.3], 0.0, 0.5)
    };
    let image = render(&asset(plane(1.5), material, vec![]), "pbr_blend");
    // Blending happens in linear light (the target is sRGB) over a black background.
    for (x, y) in PIXELS {
        let p = pixel_world(x, y, SIZE, HALF);
        let v = normalize([EYE[0] - p[0], EYE[1] - p[1], EYE[2] - p[2]]);
        let l = normalize(LIGHT_DIR.map(|d| -d));
        let f = appendix_b([0.0, 0.0, 1.0], v, l, [0.8, 0.5, 0.3], 0.0, 0.5);
        let e = std::array::from_fn(|c| {
            srgb(f[c] * LIGHT_COLOR[c] * LIGHT_INTENSITY * f64::from(alpha))
        });
        assert_pixel(&image, x, y, e, 2.0, "blended plane over black");
    }
}

#[test]
fn emissive_light_adds_to_the_lit_colour() {
    let emissive = [0.1, 0.2, 0.05];
    let material = Material { emissive, ..uniform([0.5, 0.5, 0.5], 0.0, 0.7) };
    let image = render(&asset(plane(1.5), material, vec![]), "pbr_emissive");
    for (x, y) in PIXELS {
        let p = pixel_world(x, y, SIZE, HALF);
        let v = normalize([EYE[0] - p[0], EYE[1] - p[1], EYE[2] - p[2]]);
        let l = normalize(LIGHT_DIR.map(|d| -d));
        let f = appendix_b([0.0, 0.0, 1.0], v, l, [0.5; 3], 0.0, 0.7);
        let e = std::array::from_fn(|c| {
            srgb(f[c] * LIGHT_COLOR[c] * LIGHT_INTENSITY + f64::from(emissive[c]))
        });
        assert_pixel(&image, x, y, e, 2.0, "emissive plane");
    }
}

#[test]
fn blended_objects_are_drawn_back_to_front_and_unlit_ones_show_their_base_colour() {
    // Two unlit half-transparent planes, the near (green) one first in the model: drawn in
    // model order, the far (red) one would land on top. Over black, back to front gives
    // green * a + red * a * (1 - a), in linear light.
    let a = 0.5;
    let unlit = |rgb: [f32; 3]| Material {
        base_color: [rgb[0], rgb[1], rgb[2], a],
        alpha_mode: AlphaMode::Blend,
        unlit: true,
        ..Material::default()
    };
    let mut near = plane(1.5);
    near.material = Some(0);
    let mut far =
        plane(1.5).with_transform(glam::Mat4::from_translation(Vec3::new(0.0, 0.0, -1.0)));
    far.material = Some(1);
    let asset = Asset {
        model: seamlit_mesh::Model::new(vec![near, far]),
        materials: vec![unlit([0.0, 1.0, 0.0]), unlit([1.0, 0.0, 0.0])],
        ..Asset::default()
    };
    let image = render(&asset, "pbr_blend_order");
    let a = f64::from(a);
    let expected = [srgb(a * (1.0 - a)), srgb(a), 0.0];
    for (x, y) in PIXELS {
        assert_pixel(&image, x, y, expected, 2.0, "near green over far red");
    }
}

/// The extensions that change the BRDF (issue 34), as their glTF specifications compose it
/// with Appendix B: KHR_materials_ior gives the dielectric f0 = ((ior - 1) / (ior + 1))^2,
/// KHR_materials_specular scales it by its colour and both f0 and f90 by its factor w
/// (`F = f0 w + (w - f0 w) (1 - v.h)^5`), and KHR_materials_clearcoat lays a GGX lobe of its
/// own roughness over the result, mixed by `clearcoat * Fresnel(n.v)` (f0 from the ior,
/// f90 = 1; the coat's normal is the plane's).
struct Layered {
    ior: f64,
    specular: f64,
    specular_color: [f64; 3],
    clearcoat: f64,
    clearcoat_roughness: f64,
}

fn layered(
    n: [f64; 3],
    v: [f64; 3],
    l: [f64; 3],
    base: [f64; 3],
    roughness: f64,
    x: &Layered,
) -> [f64; 3] {
    use std::f64::consts::PI;
    let h = normalize([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
    let (n_l, n_v, n_h, v_h) = (dot(n, l), dot(n, v), dot(n, h), dot(v, h));
    if n_l <= 0.0 {
        return [0.0; 3];
    }
    let ggx = |alpha: f64| {
        let a2 = alpha.max(1e-3).powi(2);
        let d = a2 / (PI * (n_h * n_h * (a2 - 1.0) + 1.0).powi(2));
        let vis = 0.5
            / (n_l * (n_v * n_v * (1.0 - a2) + a2).sqrt()
                + n_v * (n_l * n_l * (1.0 - a2) + a2).sqrt());
        d * vis
    };
    let f0_ior = ((x.ior - 1.0) / (x.ior + 1.0)).powi(2);
    let schlick = (1.0 - v_h).powi(5);
    let specular_brdf = ggx(roughness * roughness);
    let coat_fresnel = f0_ior + (1.0 - f0_ior) * (1.0 - n_v).powi(5);
    let k = x.clearcoat * coat_fresnel;
    let coat = ggx(x.clearcoat_roughness * x.clearcoat_roughness);
    std::array::from_fn(|c| {
        let f0 = (f0_ior * x.specular_color[c]).min(1.0) * x.specular;
        let fresnel = f0 + (x.specular - f0) * schlick;
        let dielectric = base[c] / PI * (1.0 - fresnel) + specular_brdf * fresnel;
        ((1.0 - k) * dielectric + k * coat) * n_l
    })
}

#[test]
fn ior_specular_and_clearcoat_match_their_specifications_on_a_plane() {
    use seamlit_io::{Clearcoat, PbrExtensions, Specular};
    let base = [0.6, 0.3, 0.2];
    let roughness = 0.5;
    let cases = [
        (
            "ior",
            Layered {
                ior: 2.4,
                specular: 1.0,
                specular_color: [1.0; 3],
                clearcoat: 0.0,
                clearcoat_roughness: 0.0,
            },
        ),
        (
            "specular",
            Layered {
                ior: 1.8,
                specular: 0.4,
                specular_color: [1.0, 0.3, 0.6],
                clearcoat: 0.0,
                clearcoat_roughness: 0.0,
            },
        ),
        (
            "clearcoat",
            Layered {
                ior: 1.5,
                specular: 1.0,
                specular_color: [1.0; 3],
                clearcoat: 0.8,
                clearcoat_roughness: 0.3,
            },
        ),
    ];
    for (name, x) in cases {
        let extensions = PbrExtensions {
            ior: Some(single(x.ior)),
            specular: Some(Specular {
                factor: single(x.specular),
                texture: None,
                color: x.specular_color.map(single),
                color_texture: None,
            }),
            clearcoat: (x.clearcoat > 0.0).then(|| Clearcoat {
                factor: single(x.clearcoat),
                texture: None,
                roughness: single(x.clearcoat_roughness),
                roughness_texture: None,
                normal_texture: None,
                normal_scale: 1.0,
            }),
            ..PbrExtensions::default()
        };
        let material = Material { extensions, ..uniform(base.map(single), 0.0, single(roughness)) };
        let image = render(&asset(plane(1.5), material, vec![]), &format!("pbr_layers_{name}"));
        for (px, py) in PIXELS {
            let p = pixel_world(px, py, SIZE, HALF);
            let v = normalize([EYE[0] - p[0], EYE[1] - p[1], EYE[2] - p[2]]);
            let l = normalize(LIGHT_DIR.map(|d| -d));
            let f = layered([0.0, 0.0, 1.0], v, l, base, roughness, &x);
            let e = std::array::from_fn(|c| srgb(f[c] * LIGHT_COLOR[c] * LIGHT_INTENSITY));
            assert_pixel(&image, px, py, e, 2.0, &format!("{name} plane, its specification"));
        }
    }
}

/// A device with WebGPU's 16 sampled textures a stage has no room for the textures of
/// transmission, volume, iridescence and anisotropy: it draws such a material by its factors
/// (the picture of the same material without the texture), where a device that allows more
/// draws the texture.
#[test]
fn a_device_with_16_sampled_textures_draws_the_extension_factors_alone() {
    use seamlit_io::{Iridescence, PbrExtensions};
    use seamlit_render::GpuContext;
    let film = |texture| Iridescence {
        factor: 1.0,
        texture,
        ior: 1.8,
        thickness_minimum: 100.0,
        thickness_maximum: 550.0,
        thickness_texture: None,
    };
    let material = |texture| {
        let extensions = PbrExtensions { iridescence: Some(film(texture)), ..Default::default() };
        Material { extensions, ..uniform([0.4, 0.4, 0.4], 1.0, 0.5) }
    };
    // The film on the left half only.
    let textured =
        asset(plane(1.5), material(tex_ref(0)), vec![texture("film", halves([255; 4], [0; 4]))]);
    let plain = asset(plane(1.5), material(None), vec![]);
    let full = ctx();
    let limits =
        wgpu::Limits { max_sampled_textures_per_shader_stage: 16, ..full.adapter().limits() };
    let small = GpuContext::from_adapter_with_limits(
        full.instance().clone(),
        full.adapter().clone(),
        limits,
    )
    .expect("a device with 16 sampled textures a stage");
    assert!(full.draws_all_extension_textures());
    assert!(!small.draws_all_extension_textures());
    let draw = |ctx: &GpuContext, asset: &Asset, name: &str| {
        let scene = GpuScene::upload(ctx, asset).expect("upload");
        let image = render_ortho(ctx, &scene, &settings(), VIEW);
        save(name, &image);
        image
    };
    let small_textured = draw(&small, &textured, "pbr_16_textures_textured");
    assert_eq!(small_textured, draw(&small, &plain, "pbr_16_textures_plain"));
    assert_eq!(small_textured, draw(&full, &plain, "pbr_film_plain"));
    // The right half, without the film, differs from the film's picture on the full device.
    let full_textured = draw(&full, &textured, "pbr_film_textured");
    let (left, right) = (full_textured.get_pixel(16, 32), full_textured.get_pixel(48, 32));
    assert_eq!(left, small_textured.get_pixel(16, 32), "the film where the texture is red");
    assert!(
        right.0.iter().zip(small_textured.get_pixel(48, 32).0).any(|(a, b)| a.abs_diff(b) > 8),
        "no film where the texture is black: {right:?}"
    );
}
