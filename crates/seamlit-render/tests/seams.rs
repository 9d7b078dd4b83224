//! Seams: the Newell teapot (32 patch objects) fixed in `object` mode keeps a lighting
//! discontinuity along the patch boundaries; fixed in `model` mode it does not. The boundaries
//! are found in the object-id view; the luminance jump across them is measured in the lit
//! renders of both modes, from the same camera, and the model-mode jump must be much smaller.

mod common;

use common::{ctx, luminance, save};
use glam::Vec3;
use image::RgbaImage;
use seamlit_io::{Asset, Material};
use seamlit_mesh::{FixOptions, Mode, fix};
use seamlit_render::{
    CameraDescriptor, CameraView, DebugView, FrameDescriptor, FrameSettings, GpuScene,
    IMAGE_FORMAT, Light, Projection, Renderer,
};

const TEAPOT: &str =
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/models/newell_teaset/teapot");
const SIZE: u32 = 320;

fn teapot(mode: Mode) -> Asset {
    let text = std::fs::read_to_string(TEAPOT).expect("read the Newell teapot");
    let mut asset = seamlit_io::newell::parse(&text, "teapot", 6).expect("parse the teapot");
    asset.model = fix(&asset.model, &FixOptions::DEFAULT.with_mode(mode)).expect("fix");
    asset.materials = vec![Material {
        base_color: [0.7, 0.7, 0.7, 1.0],
        specular: [0.6; 3],
        shininess: 40.0,
        ..Material::default()
    }];
    for o in &mut asset.model.objects {
        o.material = Some(0);
    }
    asset
}

/// Two adjacent pixels on either side of a patch boundary.
type Pair = ((u32, u32), (u32, u32));

/// The discontinuity across each boundary pair (p, q), q = p + d: how much the luminance step
/// from p to q exceeds the steps just before and after it (p - d to p, q to q + d). Smooth
/// shading changes at about the same rate on both sides; a seam adds a step. Returns the
/// median and the mean over the pairs.
fn seam_steps(image: &RgbaImage, pairs: &[Pair]) -> (f64, f64) {
    let lum = |x: u32, y: u32| luminance(image.get_pixel(x, y));
    let mut steps: Vec<f64> = pairs
        .iter()
        .map(|&((px, py), (qx, qy))| {
            let (dx, dy) = (qx - px, qy - py);
            let across = (lum(qx, qy) - lum(px, py)).abs();
            let before = (lum(px, py) - lum(px - dx, py - dy)).abs();
            let after = (lum(qx + dx, qy + dy) - lum(qx, qy)).abs();
            (across - 0.5 * (before + after)).max(0.0)
        })
        .collect();
    steps.sort_by(f64::total_cmp);
    let mean = steps.iter().sum::<f64>() / steps.len() as f64;
    (steps[steps.len() / 2], mean)
}

#[test]
fn model_mode_removes_the_lighting_jump_at_patch_boundaries() {
    let ctx = ctx();
    let object_mode = teapot(Mode::Object);
    let model_mode = teapot(Mode::Model);
    let (lo, hi) = model_mode.model.bounds().expect("bounds");
    let centre = (lo + hi) * 0.5;
    let radius = (hi - lo).length() * 0.5;
    // The Newell teapot has Z up.
    let eye = centre + Vec3::new(1.2, -2.0, 1.1).normalize() * radius * 2.6;
    let camera = CameraView::look_at(&CameraDescriptor {
        eye,
        target: centre,
        up: Vec3::Z,
        projection: Projection::Perspective { fov_y_deg: 40.0 },
        aspect: 1.0,
        near: radius * 0.1,
        far: radius * 10.0,
    });
    let settings = FrameSettings {
        lights: vec![
            Light::Directional {
                direction: Vec3::new(-0.6, 0.8, -0.9),
                color: Vec3::ONE,
                intensity: 0.9,
            },
            Light::Directional {
                direction: Vec3::new(0.9, 0.3, -0.2),
                color: Vec3::new(0.4, 0.45, 0.5),
                intensity: 0.6,
            },
        ],
        ambient: Vec3::splat(0.05),
        clear_color: [0.0, 0.0, 0.0, 1.0],
        ..FrameSettings::default()
    };
    // One sample per pixel: crisp ids, and identical pixel positions in every render.
    let mut renderer = Renderer::new(&ctx, IMAGE_FORMAT, 1).expect("renderer");
    let mut render = |asset: &Asset, view: DebugView, name: &str| {
        let scene = GpuScene::upload(&ctx, asset).expect("upload");
        let s = FrameSettings { debug_view: view, ..settings.clone() };
        let image = renderer
            .render_to_image(
                &ctx,
                &FrameDescriptor {
                    scene: &scene,
                    camera: &camera,
                    settings: &s,
                    size: (SIZE, SIZE),
                },
            )
            .expect("render");
        save(name, &image);
        image
    };
    let ids = render(&model_mode, DebugView::ObjectIds, "seams_ids");
    let lit_object = render(&object_mode, DebugView::Lit, "seams_object_mode");
    let lit_model = render(&model_mode, DebugView::Lit, "seams_model_mode");

    // Boundary pairs: horizontally or vertically adjacent pixels of different objects, away
    // from the background (so silhouettes do not count).
    let id = |x: u32, y: u32| ids.get_pixel(x, y).0;
    let background = |x: u32, y: u32| id(x, y)[..3] == [0, 0, 0];
    let near_background = |x: u32, y: u32| {
        (x.saturating_sub(2)..=(x + 2).min(SIZE - 1))
            .any(|i| (y.saturating_sub(2)..=(y + 2).min(SIZE - 1)).any(|j| background(i, j)))
    };
    let mut pairs = Vec::new();
    for y in 1..SIZE - 2 {
        for x in 1..SIZE - 2 {
            if near_background(x, y) {
                continue;
            }
            for (qx, qy) in [(x + 1, y), (x, y + 1)] {
                if id(x, y) != id(qx, qy) && !near_background(qx, qy) {
                    pairs.push(((x, y), (qx, qy)));
                }
            }
        }
    }
    assert!(pairs.len() > 200, "too few boundary pixels ({}) in the object-id view", pairs.len());
    let (object_median, object_mean) = seam_steps(&lit_object, &pairs);
    let (model_median, model_mean) = seam_steps(&lit_model, &pairs);
    println!(
        "{} boundary pairs; seam step (luminance): object mode median {object_median:.4} mean {object_mean:.4}, model mode median {model_median:.4} mean {model_mean:.4}",
        pairs.len()
    );
    assert!(object_mean > 0.01, "object mode should show seams (mean step {object_mean:.4})");
    // Measured on lavapipe: medians 0.0385 and 0.0010, means 0.0668 and 0.0241 (the mean
    // keeps real creases and occlusion edges, which both modes share).
    assert!(
        model_median / object_median < 0.2,
        "model mode median step {model_median:.4} is not much smaller than object mode {object_median:.4}"
    );
    assert!(
        model_mean / object_mean < 0.5,
        "model mode mean step {model_mean:.4} is not much smaller than object mode {object_mean:.4}"
    );
}
