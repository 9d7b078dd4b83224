//! The API's edges: bad input gets a clear error, non-sRGB targets match sRGB ones, culling
//! follows the transform's determinant, TBN lines draw.

mod common;

use common::{
    Ortho, asset, ctx, ortho_camera, plane, render_image, render_ortho, save, tex_ref, texture,
};
use glam::{Mat4, Vec3};
use seamlit_io::Material;
use seamlit_render::{
    FrameDescriptor, FrameSettings, GpuScene, IMAGE_FORMAT, RenderError, Renderer, TextureOptions,
};

#[test]
fn objects_without_normals_or_with_bad_indices_are_refused_by_name() {
    let ctx = ctx();
    let mut no_normals = plane(1.0);
    no_normals.name = "lid".into();
    no_normals.normals = None;
    let err = GpuScene::upload(&ctx, &asset(no_normals, Material::default(), vec![]))
        .expect_err("no normals");
    assert!(matches!(&err, RenderError::MissingNormals { object } if object == "lid"), "{err}");
    assert!(err.to_string().contains("seamlit_mesh::fix"), "{err}");

    let mut bad_index = plane(1.0);
    bad_index.triangles[1] = [0, 2, 7];
    let err = GpuScene::upload(&ctx, &asset(bad_index, Material::default(), vec![]))
        .expect_err("bad index");
    assert_eq!(err.to_string(), "object \"plane\": triangle 1 uses vertex 7, but there are 4");

    let mut short_uvs = plane(1.0);
    short_uvs.uvs.as_mut().expect("uvs").pop();
    let err = GpuScene::upload(&ctx, &asset(short_uvs, Material::default(), vec![]))
        .expect_err("short uvs");
    assert_eq!(err.to_string(), "object \"plane\": 3 uvs for 4 positions");

    let mut a = asset(plane(1.0), Material::default(), vec![]);
    a.model.objects[0].material = Some(3);
    let err = GpuScene::upload(&ctx, &a).expect_err("bad material");
    assert_eq!(
        err.to_string(),
        "material (of object \"plane\") index 3 is out of range (there are 1)"
    );

    let a = asset(
        plane(1.0),
        Material { name: "wood".into(), normal_texture: tex_ref(2), ..Material::default() },
        vec![],
    );
    let err = GpuScene::upload(&ctx, &a).expect_err("bad texture");
    assert_eq!(
        err.to_string(),
        "texture (of material \"wood\") index 2 is out of range (there are 0)"
    );
}

#[test]
fn bad_sizes_and_sample_counts_are_errors() {
    let ctx = ctx();
    let scene =
        GpuScene::upload(&ctx, &asset(plane(1.0), Material::default(), vec![])).expect("upload");
    let mut renderer = Renderer::new(&ctx, IMAGE_FORMAT, 1).expect("renderer");
    let err = renderer
        .render_to_image(
            &ctx,
            &FrameDescriptor {
                scene: &scene,
                camera: &ortho_camera(1.0),
                settings: &FrameSettings::default(),
                size: (0, 10),
            },
        )
        .expect_err("zero width");
    assert!(matches!(err, RenderError::BadSize { width: 0, height: 10, .. }), "{err}");
    let err = Renderer::new(&ctx, IMAGE_FORMAT, 3).expect_err("3 samples");
    assert!(matches!(err, RenderError::UnsupportedSampleCount { count: 3, .. }), "{err}");
}

#[test]
fn a_non_srgb_target_gets_the_same_image() {
    let ctx = ctx();
    let scene = GpuScene::upload(
        &ctx,
        &asset(
            plane(1.0),
            Material { base_color_texture: tex_ref(0), ..Material::default() },
            vec![texture("checker", common::shapes::checker(32))],
        ),
    )
    .expect("upload");
    let camera = ortho_camera(1.2);
    let settings = FrameSettings::default();
    let frame =
        FrameDescriptor { scene: &scene, camera: &camera, settings: &settings, size: (48, 48) };
    let render = |format| {
        Renderer::new(&ctx, format, 4)
            .expect("renderer")
            .render_to_image(&ctx, &frame)
            .expect("render")
    };
    let srgb = render(IMAGE_FORMAT);
    let unorm = render(wgpu::TextureFormat::Rgba8Unorm);
    save("api_srgb_target", &srgb);
    save("api_unorm_target", &unorm);
    // Interior pixels (MSAA resolves edges differently in the two encodings).
    for y in 8..40 {
        for x in 8..40 {
            let (a, b) = (srgb.get_pixel(x, y).0, unorm.get_pixel(x, y).0);
            assert!(
                (0..3).all(|c| a[c].abs_diff(b[c]) <= 1),
                "pixel ({x}, {y}): sRGB target {a:?}, shader-encoded {b:?}"
            );
        }
    }
    // The background (a corner, outside the plane): the clear colour is encoded too.
    let (a, b) = (srgb.get_pixel(0, 0).0, unorm.get_pixel(0, 0).0);
    assert!(
        (0..3).all(|c| a[c].abs_diff(b[c]) <= 1) && a[0] > 30,
        "background: sRGB target {a:?}, shader-encoded {b:?}"
    );
}

#[test]
fn culling_follows_the_determinant_and_double_sided_materials() {
    let ctx = ctx();
    let camera = ortho_camera(1.2);
    let settings = FrameSettings { clear_color: [0.0, 0.0, 0.0, 1.0], ..FrameSettings::default() };
    let centre = |transform: Mat4, double_sided: bool| {
        let object = plane(1.0).with_transform(transform);
        let scene = GpuScene::upload(
            &ctx,
            &asset(object, Material { double_sided, ..Material::default() }, vec![]),
        )
        .expect("upload");
        let image = render_image(
            &ctx,
            &FrameDescriptor {
                scene: &scene,
                camera: &camera,
                settings: &settings,
                size: (32, 32),
            },
        )
        .expect("render");
        image.get_pixel(16, 16).0
    };
    let background = [0, 0, 0, 255];
    // Mirrored in X: still faces the camera (+Z), winding reversed: must be drawn.
    assert_ne!(
        centre(Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)), false),
        background,
        "a mirrored plane facing the camera was culled"
    );
    // Turned away (rotated 180 degrees about Y): culled, unless double-sided.
    let away = Mat4::from_rotation_y(std::f32::consts::PI);
    assert_eq!(centre(away, false), background, "a plane facing away was drawn");
    assert_ne!(centre(away, true), background, "a double-sided plane facing away was not drawn");
    // Mirrored in Z: faces away (-Z) with reversed winding: culled.
    assert_eq!(
        centre(Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0)), false),
        background,
        "a mirrored plane facing away was drawn"
    );
}

#[test]
fn tbn_lines_are_drawn_in_their_colours() {
    let ctx = ctx();
    let scene =
        GpuScene::upload(&ctx, &asset(plane(0.5), Material::default(), vec![])).expect("upload");
    // Looking along -Z at the plane: T (+X, red) and B (+Y, green) lines of length 0.4 start
    // at the corners; N (blue) points at the camera and shows as a dot.
    let settings = FrameSettings {
        show_tbn: true,
        tbn_length: Some(0.4),
        lights: vec![],
        ambient: Vec3::ZERO,
        clear_color: [0.0, 0.0, 0.0, 1.0],
        ..FrameSettings::default()
    };
    let image = render_ortho(&ctx, &scene, &settings, Ortho { half: 1.0, size: 64 });
    save("api_tbn_lines", &image);
    // The top-right corner (0.5, 0.5) is pixel (48, 16); its T line runs right to x = 0.9
    // (pixel 60), its B line up to y = 0.9 (pixel 3).
    // The lines lie on pixel boundaries: look at both neighbouring rows (columns).
    let brightest = |pixels: [(u32, u32); 2], c: usize| {
        pixels
            .map(|(x, y)| image.get_pixel(x, y).0)
            .into_iter()
            .max_by_key(|p| p[c])
            .unwrap_or_default()
    };
    let red = brightest([(55, 15), (55, 16)], 0);
    let green = brightest([(47, 8), (48, 8)], 1);
    assert!(red[0] > 120 && red[1] < 80, "no red tangent line at (55, 15..=16): {red:?}");
    assert!(green[1] > 120 && green[0] < 80, "no green bitangent line at (47..=48, 8): {green:?}");
}

#[test]
fn minified_textures_use_mipmaps_averaged_in_linear_light() {
    let ctx = ctx();
    // A one-texel black and white checker, 256 x 256, seen at about 7 texels per pixel.
    let checker = image::RgbaImage::from_fn(256, 256, |x, y| {
        if (x + y) % 2 == 0 { image::Rgba([0, 0, 0, 255]) } else { image::Rgba([255; 4]) }
    });
    let a = asset(
        plane(1.0),
        Material {
            base_color: [1.0; 4],
            base_color_texture: tex_ref(0),
            specular: [0.0; 3],
            ..Material::default()
        },
        vec![texture("checker", checker)],
    );
    // No lights, ambient 1: the pixel is the texture's colour. 7.2 texels per pixel: pixel
    // centres fall at varying places within the texels.
    let settings = FrameSettings { lights: vec![], ambient: Vec3::ONE, ..FrameSettings::default() };
    let render = |options: TextureOptions, name: &str| {
        let scene = GpuScene::upload_parts(&ctx, &a.model, &a.materials, &a.textures, &options)
            .expect("upload");
        let image = render_ortho(&ctx, &scene, &settings, Ortho { half: 0.9, size: 32 });
        save(name, &image);
        let reds: Vec<u8> = (2..30)
            .flat_map(|y| (2..30).map(move |x| (x, y)))
            .map(|(x, y)| image.get_pixel(x, y)[0])
            .collect();
        reds
    };
    // With mipmaps (anisotropy off, so only the mip chain averages): every pixel is 50% linear
    // grey, sRGB 188.
    let with = render(TextureOptions { mipmaps: true, anisotropy: 1 }, "api_mipmaps_on");
    assert!(
        with.iter().all(|r| r.abs_diff(188) <= 6),
        "with mipmaps: {:?}",
        with.iter().filter(|r| r.abs_diff(188) > 6).collect::<Vec<_>>()
    );
    // Without mipmaps the full-size level aliases: pixels spread far from grey. (This shows
    // the check above can fail.)
    let without = render(TextureOptions { mipmaps: false, anisotropy: 1 }, "api_mipmaps_off");
    assert!(
        without.iter().filter(|r| r.abs_diff(188) > 20).count() > 50,
        "without mipmaps the checker should alias"
    );
}

#[test]
fn replacing_the_geometry_keeps_materials_and_refuses_bad_models() {
    let ctx = ctx();
    let material =
        Material { base_color: [1.0, 0.0, 0.0, 1.0], specular: [0.0; 3], ..Material::default() };
    let mut scene = GpuScene::upload(&ctx, &asset(plane(0.25), material, vec![])).expect("upload");
    let settings = FrameSettings {
        lights: vec![],
        ambient: Vec3::ONE,
        clear_color: [0.0, 0.0, 0.0, 1.0],
        ..FrameSettings::default()
    };
    let camera = ortho_camera(1.0);
    let corner = |scene: &GpuScene| {
        render_image(
            &ctx,
            &FrameDescriptor { scene, camera: &camera, settings: &settings, size: (32, 32) },
        )
        .expect("render")
        .get_pixel(4, 4)
        .0
    };
    assert_eq!(corner(&scene), [0, 0, 0, 255], "the small plane does not reach the corner");
    // A bigger plane with the same material: the corner turns red.
    let mut bigger = asset(plane(1.0), Material::default(), vec![]).model;
    scene.replace_model(&ctx, &bigger).expect("replace");
    assert_eq!(corner(&scene), [255, 0, 0, 255], "the replaced geometry keeps the red material");
    assert_eq!(scene.triangle_count(), 2);
    // A material index the scene does not have: refused, the geometry stays.
    bigger.objects[0].material = Some(5);
    let err = scene.replace_model(&ctx, &bigger).expect_err("bad material");
    assert!(matches!(err, RenderError::IndexOutOfRange { index: 5, count: 1, .. }), "{err}");
    assert_eq!(corner(&scene), [255, 0, 0, 255]);
}

#[cfg(target_os = "linux")]
#[test]
fn no_adapter_says_what_to_install() {
    // Metal does not exist on Linux: no adapter, and the message names the package.
    let err = seamlit_render::GpuContext::headless_with(wgpu::Backends::METAL)
        .expect_err("no Metal on Linux");
    assert!(matches!(err, RenderError::NoAdapter { .. }), "{err}");
    assert!(err.to_string().contains("apt-get install mesa-vulkan-drivers"), "{err}");
}
