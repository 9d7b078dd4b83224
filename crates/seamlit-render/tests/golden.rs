//! Golden images: a few views of a small scene compared with PNGs under tests/golden/ with a
//! tolerance. On failure the actual image and a difference image are written to
//! target/tmp/seamlit-render/ (the message says where). To accept new images after a
//! deliberate change: `SEAMLIT_BLESS=1 cargo test -p seamlit-render --test golden`, then look at
//! them before committing.
//!
//! The scene: two spheres with a brick normal map and a checker base colour. The left one is
//! two objects (the hemispheres); the right one is mirrored by its transform (scale x by -1),
//! so it is drawn only if back-face culling follows the negative determinant.

mod common;

use std::path::{Path, PathBuf};

use common::shapes::{brick_normal_map, checker, sphere};
use common::{ctx, save, tex_ref, texture};
use glam::{Mat4, Vec3};
use image::RgbaImage;
use seamlit_io::{Asset, Material};
use seamlit_mesh::Model;
use seamlit_render::{
    CameraDescriptor, CameraView, DebugView, FrameDescriptor, FrameSettings, GpuContext, GpuScene,
    IMAGE_FORMAT, Light, LightingModel, Projection, Renderer,
};

const SIZE: (u32, u32) = (160, 96);

fn scene(ctx: &GpuContext) -> GpuScene {
    let left = Mat4::from_translation(Vec3::new(-1.1, 0.0, 0.0));
    let right = Mat4::from_translation(Vec3::new(1.1, 0.0, 0.0))
        * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    let mut objects = vec![
        sphere("south", 1.0, 12, 48, 0.0, 0.5).with_transform(left),
        sphere("north", 1.0, 12, 48, 0.5, 1.0).with_transform(left),
        sphere("mirrored", 1.0, 24, 48, 0.0, 1.0).with_transform(right),
    ];
    for o in &mut objects {
        o.material = Some(0);
    }
    let asset = Asset {
        model: Model::new(objects),
        materials: vec![Material {
            base_color: [1.0, 1.0, 1.0, 1.0],
            base_color_texture: tex_ref(0),
            normal_texture: tex_ref(1),
            specular: [0.4, 0.4, 0.4],
            shininess: 24.0,
            ..Material::default()
        }],
        textures: vec![texture("checker", checker(64)), texture("bricks", brick_normal_map(128))],
        ..Asset::default()
    };
    GpuScene::upload(ctx, &asset).expect("upload")
}

fn settings() -> FrameSettings {
    FrameSettings {
        lights: vec![
            Light::Directional {
                direction: Vec3::new(-0.5, -0.4, -1.0),
                color: Vec3::new(1.0, 0.95, 0.9),
                intensity: 0.8,
            },
            Light::Point {
                position: Vec3::new(-2.0, 1.5, 2.0),
                color: Vec3::new(0.3, 0.5, 1.0),
                intensity: 4.0,
                range: 6.0,
            },
            Light::Spot {
                position: Vec3::new(2.5, 2.0, 2.5),
                direction: Vec3::new(-1.4, -2.0, -2.5),
                color: Vec3::new(1.0, 0.6, 0.3),
                intensity: 8.0,
                range: 8.0,
                inner_cone_deg: 10.0,
                outer_cone_deg: 20.0,
            },
        ],
        ambient: Vec3::splat(0.04),
        ..FrameSettings::default()
    }
}

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// Compares `actual` with tests/golden/NAME.png: fails when more than 1% of the pixels differ
/// by more than 24 in a channel, or the mean difference exceeds 1.5.
fn check(name: &str, actual: &RgbaImage) {
    let path = golden_dir().join(format!("{name}.png"));
    if std::env::var_os("SEAMLIT_BLESS").is_some() {
        actual.save(&path).expect("write a golden image");
        return;
    }
    let Ok(expected) = image::open(&path).map(|i| i.to_rgba8()) else {
        let written = save(&format!("golden-{name}-actual"), actual);
        panic!(
            "no golden image {}; the actual one is {}; bless with SEAMLIT_BLESS=1",
            path.display(),
            written.display()
        );
    };
    assert_eq!(
        expected.dimensions(),
        actual.dimensions(),
        "{name}: size differs from {}",
        path.display()
    );
    let mut bad = 0usize;
    let mut total = 0u64;
    let diff = RgbaImage::from_fn(actual.width(), actual.height(), |x, y| {
        let (a, e) = (actual.get_pixel(x, y).0, expected.get_pixel(x, y).0);
        let d: [u8; 3] = std::array::from_fn(|c| a[c].abs_diff(e[c]));
        total += d.iter().map(|&v| u64::from(v)).sum::<u64>();
        if d.iter().any(|&v| v > 24) {
            bad += 1;
        }
        image::Rgba([d[0].saturating_mul(4), d[1].saturating_mul(4), d[2].saturating_mul(4), 255])
    });
    let pixels = (actual.width() * actual.height()) as usize;
    let mean = total as f64 / (pixels * 3) as f64;
    if bad * 100 > pixels || mean > 1.5 {
        let a = save(&format!("golden-{name}-actual"), actual);
        let d = save(&format!("golden-{name}-diff"), &diff);
        panic!(
            "{name}: {bad} of {pixels} pixels differ by more than 24, mean difference {mean:.2}; expected {}, actual {}, difference (x4) {}",
            path.display(),
            a.display(),
            d.display()
        );
    }
}

#[test]
fn golden_views_match() {
    let ctx = ctx();
    let scene = scene(&ctx);
    let camera = CameraView::look_at(&CameraDescriptor {
        eye: Vec3::new(0.0, 0.6, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: Projection::Perspective { fov_y_deg: 40.0 },
        aspect: SIZE.0 as f32 / SIZE.1 as f32,
        near: 0.1,
        far: 20.0,
    });
    let mut renderer = Renderer::new(&ctx, IMAGE_FORMAT, 4).expect("renderer");
    let views = [
        ("lit", FrameSettings { ..settings() }),
        ("normals", FrameSettings { debug_view: DebugView::Normals, ..settings() }),
        ("objects", FrameSettings { debug_view: DebugView::ObjectIds, ..settings() }),
        (
            "uvs_tbn",
            FrameSettings {
                debug_view: DebugView::Uvs,
                show_tbn: true,
                tbn_length: Some(0.12),
                ..settings()
            },
        ),
        ("gouraud", FrameSettings { lighting_model: LightingModel::Gouraud, ..settings() }),
        ("bitangent_sign", FrameSettings { debug_view: DebugView::BitangentSign, ..settings() }),
        ("tangents", FrameSettings { debug_view: DebugView::Tangents, ..settings() }),
        ("lighting_only", FrameSettings { debug_view: DebugView::LightingOnly, ..settings() }),
        ("no_normal_map", FrameSettings { normal_mapping: false, ..settings() }),
    ];
    for (name, settings) in views {
        let image = renderer
            .render_to_image(
                &ctx,
                &FrameDescriptor {
                    scene: &scene,
                    camera: &camera,
                    settings: &settings,
                    size: (SIZE.0, SIZE.1),
                },
            )
            .expect("render");
        save(&format!("golden-{name}-latest"), &image);
        check(name, &image);
    }
}
