//! seamlit's PBR against the Khronos glTF Sample Viewer: each model in assets/sample-viewer
//! rendered by `seamlit render` through the file's camera, with its one punctual light, no
//! ambient light, no shadows (the Sample Viewer draws none) and PBR Neutral tone mapping,
//! must stay within the aim of the Sample Viewer's picture of it (made once by
//! bench/sample-viewer/compare.sh; how, in assets/sample-viewer/README.md): a mean FLIP error
//! under 0.05 without an environment (`NAME.viewer.png`), under 0.1 with sky.hdr as the
//! environment in both (`NAME.environment.viewer.png`). On failure the picture and the side
//! by side (Sample Viewer | seamlit | FLIP error) are left in the test's temporary folder,
//! named in the message. Animated models are compared at three times of an animation
//! (`NAME@T.viewer.png`: the Sample Viewer at T seconds; seamlit `--animation N --time T`),
//! punctual light only, under 0.05 too. The glTF material extensions (issue 34: clearcoat,
//! sheen, ior and specular, anisotropy, texture transforms, emissive strength, transmission
//! and volume, iridescence, dispersion, one model each) are held to a mean FLIP under 0.035
//! under the punctual light, most also with the extension taken out of the file drawn at
//! least the aim away; KHR_materials_variants is compared with each variant selected. The
//! textures of transmission, volume, iridescence and anisotropy have a model each, and fail
//! with the texture taken out; Khronos' own ClearCoatTest, TextureTransformTest (with its
//! glTF sampler), TransmissionTest, EmissiveStrengthTest, AttenuationTest (volume),
//! SpecularTest and TransmissionRoughnessTest (ior) are compared under both lightings,
//! IridescenceSuzanne's films and ior over the left two thirds of the frame, and
//! glTF-Blender-IO's anisotropy and sheen test models too, and Khronos' SheenChair (velvet).

use std::path::{Path, PathBuf};
use std::process::Command;

/// How the model is lit besides its punctual light, with the aim for it.
#[derive(Clone, Copy)]
enum Lighting {
    /// No environment: mean FLIP under 0.05.
    PunctualOnly,
    /// sky.hdr at intensity 1, rotation 0 (the Sample Viewer's default 90): under 0.1.
    Environment,
    /// As `PunctualOnly`, with no aim: the unposed picture a posed reference is also measured
    /// against.
    Loose,
}

impl Lighting {
    fn aim(self) -> f32 {
        match self {
            Self::PunctualOnly => 0.05,
            Self::Environment => 0.1,
            Self::Loose => f32::INFINITY,
        }
    }

    /// The name of `name`'s pictures lit this way: `name`, or `name.environment`.
    fn picture(self, name: &str) -> String {
        match self {
            Self::PunctualOnly | Self::Loose => name.to_owned(),
            Self::Environment => format!("{name}.environment"),
        }
    }

    /// The reference picture's file name.
    fn reference(self, name: &str) -> String {
        format!("{}.viewer.png", self.picture(name))
    }

    /// `seamlit render`'s flags for it, as compare.sh passes them.
    fn flags(self) -> Vec<String> {
        let sky = data().join("sky.hdr").display().to_string();
        let flags: &[&str] = match self {
            Self::PunctualOnly | Self::Loose => &["--environment", "none"],
            // The Sample Viewer's clear colour, seamlit's default background (39, 39, 44).
            Self::Environment => &[
                "--environment",
                &sky,
                "--environment-intensity",
                "1",
                "--environment-rotation",
                "0",
                "--background",
                "0.1529,0.1529,0.1725",
            ],
        };
        flags.iter().map(|s| (*s).to_owned()).collect()
    }
}

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/sample-viewer")
}

/// `seamlit render NAME.toml` at the reference's size, as compare.sh runs it, with `pose`'s
/// flags (`--animation N --time T`, or none).
fn render(
    name: &str,
    lighting: Lighting,
    pose: &[String],
    size: (u32, u32),
    out: &Path,
) -> image::RgbImage {
    render_scene(&data().join(format!("{name}.toml")), lighting, pose, size, out)
}

/// As [`render`], of the scene file `scene`.
fn render_scene(
    scene: &Path,
    lighting: Lighting,
    pose: &[String],
    size: (u32, u32),
    out: &Path,
) -> image::RgbImage {
    let name = scene.display();
    let output = Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .arg("render")
        .arg(scene)
        .arg("-o")
        .arg(out)
        .args(["--size", &format!("{}x{}", size.0, size.1), "--camera", "compare"])
        .args(["--lighting", "pbr", "--tone-mapping", "neutral"])
        .args(["--exposure", "1", "--ambient", "0"])
        .args(["--shadows", "off"])
        .args(lighting.flags())
        .args(pose)
        .output()
        .expect("the binary runs");
    assert!(output.status.success(), "{name}: {}", String::from_utf8_lossy(&output.stderr));
    image::open(out).expect("a PNG").to_rgb8()
}

/// The mean FLIP error of `test` against `reference` and the error map (magma colours).
fn flip(reference: &image::RgbImage, test: &image::RgbImage) -> (f32, image::RgbImage) {
    let (w, h) = reference.dimensions();
    let error = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, reference.as_raw()),
        nv_flip::FlipImageRgb8::with_data(w, h, test.as_raw()),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mean = nv_flip::FlipPool::from_image(&error).mean();
    let map = error.apply_color_lut(&nv_flip::magma_lut()).to_vec();
    (mean, image::RgbImage::from_raw(w, h, map).expect("w x h RGB"))
}

fn within_aim_of_the_sample_viewer(model: &str, lighting: Lighting) {
    let name = lighting.picture(model);
    within_aim(model, &name, &lighting.reference(model), lighting, &[], lighting.aim());
}

/// Issue 34's aim for the material extensions' models.
const EXTENSION_AIM: f32 = 0.035;

/// `model` (a model of material extensions) under the punctual light alone, under `aim`:
/// [`EXTENSION_AIM`], or less where the picture drawn without the extension (its layers
/// switched off in the renderer) also stays under that, so that the test fails without it.
/// (Its `NAME.environment.viewer.png` is checked in too; the comparison
/// with the environment is asserted for clearcoat, sheen, specular, transmission and
/// ClearCoatTest (`seen_under`):
/// on the machine the others were made on, lavapipe returned black for every prefiltered
/// level but the first, before issue 34's changes as after
/// (`a_white_furnace_returns_the_environment_times_the_albedo` in
/// seamlit-render/tests/ibl.rs failed there), so the figure could not be measured; on the
/// machine of the 8-bit transmission target that test passes.)
fn extension_matches_the_sample_viewer(model: &str, aim: f32) {
    assert!(aim <= EXTENSION_AIM);
    let lighting = Lighting::PunctualOnly;
    within_aim(model, model, &lighting.reference(model), lighting, &[], aim);
}

/// `model` posed by its animation `animation` at each of `times` (seconds, as the reference
/// pictures' names write them) against `MODEL@T.viewer.png`, within the aim; and, so that the
/// comparison sees the pose, closer to it than half the FLIP error of seamlit's unposed
/// picture (the rest pose) against the same reference.
fn posed_within_aim_of_the_sample_viewer(model: &str, animation: usize, times: [&str; 3]) {
    for t in times {
        let name = format!("{model}@{t}");
        let reference = format!("{name}.viewer.png");
        let pose = ["--animation".to_owned(), animation.to_string(), "--time".to_owned(), t.into()];
        let (punctual, loose) = (Lighting::PunctualOnly, Lighting::Loose);
        let posed = within_aim(model, &name, &reference, punctual, &pose, punctual.aim());
        let rest = within_aim(model, &format!("{name}.rest"), &reference, loose, &[], loose.aim());
        assert!(
            posed < 0.5 * rest,
            "{name}: mean FLIP {posed:.4} posed, {rest:.4} unposed: the pose does not bring \
             seamlit's picture near the Sample Viewer's"
        );
    }
}

/// The mean FLIP error of seamlit's picture against `reference`, asserted under `aim`.
fn within_aim(
    model: &str,
    name: &str,
    reference: &str,
    lighting: Lighting,
    pose: &[String],
    aim: f32,
) -> f32 {
    let reference =
        image::open(data().join(reference)).expect("the Sample Viewer's picture").to_rgb8();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sample_viewer");
    std::fs::create_dir_all(&dir).unwrap();
    let ours =
        render(model, lighting, pose, reference.dimensions(), &dir.join(format!("{name}.png")));
    assert_eq!(ours.dimensions(), reference.dimensions(), "{name}: picture size");
    let (mean, map) = flip(&reference, &ours);
    // The figure, for BENCHMARKS.md (`cargo test ... -- --nocapture` shows it).
    eprintln!("{name}: mean FLIP {mean:.4} against the Sample Viewer");
    if mean >= aim {
        let (w, h) = reference.dimensions();
        let mut sheet = image::RgbImage::new(w * 3, h);
        for (i, picture) in [&reference, &ours, &map].into_iter().enumerate() {
            image::imageops::replace(&mut sheet, picture, i64::from(w) * i as i64, 0);
        }
        let path = dir.join(format!("{name}.side-by-side.png"));
        sheet.save(&path).unwrap();
        panic!(
            "{name}: mean FLIP {mean:.4} against the Sample Viewer, aim < {aim}; see {}",
            path.display()
        );
    }
    mean
}

#[test]
fn metallic_roughness_spheres_match_the_sample_viewer() {
    within_aim_of_the_sample_viewer("spheres", Lighting::PunctualOnly);
}

#[test]
fn emissive_textured_occluded_and_alpha_materials_match_the_sample_viewer() {
    within_aim_of_the_sample_viewer("materials", Lighting::PunctualOnly);
}

#[test]
fn the_khronos_fox_matches_the_sample_viewer() {
    within_aim_of_the_sample_viewer("Fox", Lighting::PunctualOnly);
}

#[test]
fn metallic_roughness_spheres_in_an_environment_match_the_sample_viewer() {
    within_aim_of_the_sample_viewer("spheres", Lighting::Environment);
}

#[test]
fn materials_in_an_environment_match_the_sample_viewer() {
    within_aim_of_the_sample_viewer("materials", Lighting::Environment);
}

#[test]
fn the_khronos_fox_in_an_environment_matches_the_sample_viewer() {
    within_aim_of_the_sample_viewer("Fox", Lighting::Environment);
}

#[test]
fn the_khronos_fox_walking_matches_the_sample_viewer_at_three_times() {
    posed_within_aim_of_the_sample_viewer("Fox", 1, ["0.15", "0.35", "0.55"]);
}

#[test]
fn the_simple_morph_triangle_matches_the_sample_viewer_at_three_times() {
    posed_within_aim_of_the_sample_viewer("SimpleMorph", 0, ["1.5", "2.5", "3.5"]);
}

#[test]
fn clearcoat_matches_the_sample_viewer() {
    // Mean FLIP 0.0088 with the clearcoat, 0.0140 without (lavapipe, 2026-11-27).
    extension_matches_the_sample_viewer("clearcoat", 0.0115);
}

#[test]
fn clearcoat_in_an_environment_matches_the_sample_viewer() {
    // Under sky.hdr: mean FLIP 0.0090 with the clearcoat, 0.0184 without.
    let (model, extension) = ("clearcoat", "KHR_materials_clearcoat");
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, 0.014);
}

#[test]
fn ior_and_specular_in_an_environment_match_the_sample_viewer() {
    // Under sky.hdr: mean FLIP 0.0074 with ior and specular, 0.0193 with the specular
    // extension taken out (the ior kept).
    let (model, extension) = ("specular", "KHR_materials_specular");
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, 0.013);
}

#[test]
fn sheen_matches_the_sample_viewer() {
    // Mean FLIP 0.0102 with the sheen (0.0126 with the albedo table seamlit computed before
    // it took the Sample Viewer's: sheen.rs), 0.0557 without.
    extension_matches_the_sample_viewer("sheen", 0.0115);
}

/// The sheen model under sky.hdr: the sheen's light from the environment is the Sample
/// Viewer's (the environment Charlie-prefiltered for the sheen roughness, times its Charlie
/// table: crates/seamlit-render/src/sheen.rs). Mean FLIP 0.0111 (0.0270 with the albedo table
/// seamlit computed before it took the Sample Viewer's), 0.0822 without the sheen.
#[test]
fn sheen_in_an_environment_matches_the_sample_viewer() {
    let (model, extension) = ("sheen", "KHR_materials_sheen");
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, 0.018);
}

#[test]
fn ior_and_specular_match_the_sample_viewer() {
    // Mean FLIP 0.0073 with ior and specular, 0.0169 without.
    extension_matches_the_sample_viewer("specular", 0.012);
}

#[test]
fn anisotropy_matches_the_sample_viewer() {
    // Mean FLIP 0.0098 with anisotropy (streaks), 0.0321 without (round highlights).
    extension_matches_the_sample_viewer("anisotropy", 0.02);
}

#[test]
fn texture_transforms_on_every_slot_and_unlit_match_the_sample_viewer() {
    extension_matches_the_sample_viewer("transforms", EXTENSION_AIM);
}

/// A copy of assets/sample-viewer's `model` (GLB) with its JSON changed by `edit`, and its
/// scene (`model.toml`) beside it, in the test's temporary folder `folder`.
fn edited_copy(model: &str, folder: &str, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let bytes = std::fs::read(data().join(format!("{model}.glb"))).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let mut json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + length]).unwrap();
    edit(&mut json);
    let mut text = serde_json::to_vec(&json).unwrap();
    text.resize(text.len().next_multiple_of(4), b' ');
    let rest = &bytes[20 + length..];
    let mut glb = bytes[..12].to_vec();
    glb[8..12].copy_from_slice(&u32::try_from(20 + text.len() + rest.len()).unwrap().to_le_bytes());
    glb.extend_from_slice(&u32::try_from(text.len()).unwrap().to_le_bytes());
    glb.extend_from_slice(&bytes[16..20]);
    glb.extend_from_slice(&text);
    glb.extend_from_slice(rest);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sample_viewer").join(folder);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(format!("{model}.glb")), glb).unwrap();
    let scene = dir.join(format!("{model}.toml"));
    std::fs::copy(data().join(format!("{model}.toml")), &scene).unwrap();
    scene
}

/// `model` with the material extension `extension` taken out of every material: the model
/// as a renderer that ignores the extension draws it.
fn without_extension(model: &str, extension: &str) -> PathBuf {
    edited_copy(model, &format!("{model}-without"), |json| {
        for material in json["materials"].as_array_mut().unwrap() {
            if let Some(extensions) = material.get_mut("extensions").and_then(|e| e.as_object_mut())
            {
                extensions.remove(extension);
            }
        }
        json["extensionsUsed"].as_array_mut().unwrap().retain(|e| e != extension);
        if let Some(required) = json.get_mut("extensionsRequired").and_then(|r| r.as_array_mut()) {
            required.retain(|e| e != extension);
        }
    })
}

/// `model` with the texture `texture` (e.g. `transmissionTexture`) taken out of every
/// material's `extension`: the model as a renderer that draws the extension's factors but
/// not that texture draws it.
fn without_texture(model: &str, extension: &str, texture: &str) -> PathBuf {
    edited_copy(model, &format!("{model}-without-texture"), |json| {
        for material in json["materials"].as_array_mut().unwrap() {
            if let Some(e) = material.pointer_mut(&format!("/extensions/{extension}")) {
                e.as_object_mut().unwrap().remove(texture);
            }
        }
    })
}

/// `model` under the punctual light within `aim` of the Sample Viewer (as
/// [`extension_matches_the_sample_viewer`]), and drawn without `extension` (taken out of
/// the file) at least `aim` away from it: the comparison sees the extension.
fn extension_seen_by_the_comparison(model: &str, extension: &str, aim: f32) {
    seen_by_the_comparison(model, extension, &without_extension(model, extension), aim);
}

/// As [`extension_seen_by_the_comparison`], for one texture of an extension: `model` drawn
/// without `texture` is at least `aim` away from the Sample Viewer's picture.
fn texture_seen_by_the_comparison(model: &str, extension: &str, texture: &str, aim: f32) {
    seen_by_the_comparison(model, texture, &without_texture(model, extension, texture), aim);
}

/// `model` within `aim` of the Sample Viewer under the punctual light, and `scene` (the model
/// without `what`) at least `aim` away from it.
fn seen_by_the_comparison(model: &str, what: &str, scene: &Path, aim: f32) {
    assert!(aim <= EXTENSION_AIM);
    seen_under(Lighting::PunctualOnly, model, what, scene, aim);
}

/// As [`seen_by_the_comparison`], lit as `lighting` says, with any aim.
fn seen_under(lighting: Lighting, model: &str, what: &str, scene: &Path, aim: f32) {
    let name = lighting.picture(model);
    within_aim(model, &name, &lighting.reference(model), lighting, &[], aim);
    let reference = image::open(data().join(lighting.reference(model))).unwrap().to_rgb8();
    let out = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("sample_viewer")
        .join(format!("{name}.without.png"));
    let ours = render_scene(scene, lighting, &[], reference.dimensions(), &out);
    let (without, _) = flip(&reference, &ours);
    eprintln!("{name}: mean FLIP {without:.4} without {what}");
    assert!(without >= aim, "{name}: mean FLIP {without:.4} without {what}, aim {aim}");
}

#[test]
fn emissive_strength_matches_the_sample_viewer() {
    extension_seen_by_the_comparison("emissive", "KHR_materials_emissive_strength", EXTENSION_AIM);
}

/// The mean colour, less the background, of the pixels of one third (0, 1, 2 from the left)
/// of a picture that are not the background: the sphere drawn there.
fn sphere_colour(picture: &image::RgbImage, third: u32) -> [f32; 3] {
    let (w, h) = picture.dimensions();
    let background = [39.0, 39.0, 44.0];
    let (mut sum, mut n) = ([0.0f32; 3], 0.0f32);
    for y in 0..h {
        for x in third * w / 3..(third + 1) * w / 3 {
            let p = picture.get_pixel(x, y).0.map(f32::from);
            if (0..3).map(|c| (p[c] - background[c]).abs()).sum::<f32>() > 30.0 {
                (0..3).for_each(|c| sum[c] += p[c]);
                n += 1.0;
            }
        }
    }
    assert!(n > 100.0, "a sphere in third {third}");
    sum.map(|s| s / n)
}

/// KHR_materials_variants: `seamlit render --variant NAME` draws each variant's materials
/// (the body red in "ruby", blue in "sapphire", the trim silver in "sapphire" only, the third
/// sphere unmapped), within the aim of the Sample Viewer with that variant selected,
/// and closer to it than half the error of the default materials' picture.
#[test]
fn each_material_variant_matches_the_sample_viewer() {
    let lighting = Lighting::PunctualOnly;
    let default = within_aim("variants", "variants", "variants.viewer.png", lighting, &[], 0.02);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sample_viewer");
    let picture = |name: &str| image::open(dir.join(format!("{name}.png"))).unwrap().to_rgb8();
    let plain = picture("variants");
    for variant in ["ruby", "sapphire"] {
        let name = format!("variants.{variant}");
        let reference = format!("{name}.viewer.png");
        let flags = ["--variant".to_owned(), variant.to_owned()];
        let chosen = within_aim("variants", &name, &reference, lighting, &flags, 0.02);
        let unchosen = within_aim(
            "variants",
            &format!("{name}.default"),
            &reference,
            Lighting::Loose,
            &[],
            1.0,
        );
        assert!(
            chosen < 0.5 * unchosen,
            "{name}: mean FLIP {chosen:.4} with the variant, {unchosen:.4} without"
        );
        let drawn = picture(&name);
        let [body, trim, third] = [0, 1, 2].map(|i| sphere_colour(&drawn, i));
        // The third sphere is mapped by no variant: as the default draws it.
        let unmapped = sphere_colour(&plain, 2);
        assert!((0..3).all(|c| (third[c] - unmapped[c]).abs() < 2.0), "{name}: {third:?}");
        match variant {
            "ruby" => {
                assert!(body[0] > 2.0 * body[2], "{name}: a red body, {body:?}");
                assert_eq!(trim, sphere_colour(&plain, 1), "{name}: the gold trim unmapped");
            }
            _ => {
                assert!(body[2] > 2.0 * body[0], "{name}: a blue body, {body:?}");
                let gold = sphere_colour(&plain, 1);
                assert!(
                    gold[0] > gold[2] * 1.3 && trim[0] < trim[2] * 1.15,
                    "{name}: silver trim, {trim:?}"
                );
            }
        }
    }
    eprintln!("variants (default): mean FLIP {default:.4}");
}

#[test]
fn transmission_and_volume_match_the_sample_viewer() {
    // Thin glass, a solid amber sphere (thickness, attenuation) and a rough tinted one before
    // a striped backdrop, seen through the transmission target.
    extension_seen_by_the_comparison("transmission", "KHR_materials_transmission", EXTENSION_AIM);
}

/// The transmission model under sky.hdr too: the Sample Viewer's transmission target holds 8
/// bits of linear light (an RGBA8 texture), so what is seen through glass is clamped to 1
/// before it is blurred and tone mapped; seamlit's target is the same (transmission.rs).
/// Mean FLIP 0.0254 (0.0483 while seamlit's target kept linear light beyond 1).
#[test]
fn transmission_in_an_environment_matches_the_sample_viewer() {
    let (model, extension) = ("transmission", "KHR_materials_transmission");
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, EXTENSION_AIM);
}

#[test]
fn iridescence_matches_the_sample_viewer() {
    // Films of 400 nm (ior 1.3) and 700 nm (ior 1.8) over a dark dielectric, 300 nm over a
    // rough metal, under the one sun: mean FLIP 0.0096 with the films, 0.0208 without (they
    // show in the highlights and rims only), so the aim is under the latter.
    extension_seen_by_the_comparison("iridescence", "KHR_materials_iridescence", 0.015);
}

#[test]
fn dispersion_matches_the_sample_viewer() {
    // Clear solid spheres at dispersion 0, 20 and 60 before a finely striped panel.
    extension_seen_by_the_comparison("dispersion", "KHR_materials_dispersion", EXTENSION_AIM);
}

// The textures of transmission, volume, iridescence and anisotropy: each on three spheres, as
// it is, through a KHR_texture_transform and from TEXCOORD_1; the test fails with the
// texture left out of the file (the extension's factors alone).

#[test]
fn the_transmission_texture_matches_the_sample_viewer() {
    // Mean FLIP 0.0220 with the texture, 0.0807 without (lavapipe, 2026-11-27).
    let (model, extension) = ("transmission_texture", "KHR_materials_transmission");
    texture_seen_by_the_comparison(model, extension, "transmissionTexture", EXTENSION_AIM);
}

#[test]
fn the_thickness_texture_matches_the_sample_viewer() {
    // Mean FLIP 0.0268 with the texture, 0.0641 without.
    let (model, extension) = ("thickness_texture", "KHR_materials_volume");
    texture_seen_by_the_comparison(model, extension, "thicknessTexture", EXTENSION_AIM);
}

#[test]
fn the_iridescence_texture_matches_the_sample_viewer() {
    // Mean FLIP 0.0092 with the texture, 0.0270 without (the films colour the highlights):
    // the aim is under the latter.
    let (model, extension) = ("iridescence_texture", "KHR_materials_iridescence");
    texture_seen_by_the_comparison(model, extension, "iridescenceTexture", 0.018);
}

#[test]
fn the_iridescence_thickness_texture_matches_the_sample_viewer() {
    // Mean FLIP 0.0109 with the texture, 0.0294 without: the aim is under the latter.
    let (model, extension) = ("iridescence_thickness_texture", "KHR_materials_iridescence");
    texture_seen_by_the_comparison(model, extension, "iridescenceThicknessTexture", 0.02);
}

#[test]
fn the_anisotropy_texture_matches_the_sample_viewer() {
    // Mean FLIP 0.0118 with the texture, 0.0480 without.
    let (model, extension) = ("anisotropy_texture", "KHR_materials_anisotropy");
    texture_seen_by_the_comparison(model, extension, "anisotropyTexture", EXTENSION_AIM);
}

/// Khronos' ClearCoatTest (glTF-Sample-Assets, by Ed Mackey, CC-BY 4.0: assets/models/
/// clearcoat_test), framed by compare.sh: six rows of coatings (simple, partial by texture,
/// roughness by texture, base and coat normal maps), each beside its uncoated base and its
/// coat alone, with text labels. Under the one sun, mean FLIP 0.0337 (the aim), but
/// 0.0335 without the clearcoat: the sun's highlights on the coat are too few pixels to
/// count. Under sky.hdr the coat reflects the sky on every tile: 0.0404 with it, 0.0504
/// without, held under 0.045. Most of that is not the coat: the tiles are dark, and the
/// Sample Viewer encodes its output with pow(c, 1 / 2.2) where seamlit writes sRGB, which
/// in dark tones is several levels brighter (a black coated tile: the Sample Viewer's
/// (20, 15, 7), seamlit's (12, 6, 1), which is (20, 15, 6) so encoded; the uncoated tiles
/// differ as much). Re-encoded as the Sample Viewer encodes ([`as_the_sample_viewer_encodes`]),
/// 0.0288 with the coat and 0.0370 without: that comparison is held to 0.033.
#[test]
fn the_khronos_clearcoat_test_matches_the_sample_viewer() {
    let model = "ClearCoatTest";
    extension_matches_the_sample_viewer(model, EXTENSION_AIM);
    let extension = "KHR_materials_clearcoat";
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, 0.045);
    seen_as_the_sample_viewer_encodes(model, extension, 0.033);
}

/// The pictures of `model` under sky.hdr that [`seen_under`] wrote, with and without
/// `what`, encoded as the Sample Viewer encodes its output ([`as_the_sample_viewer_encodes`]):
/// within `aim` of its picture with, at least `aim` away without.
fn seen_as_the_sample_viewer_encodes(model: &str, what: &str, aim: f32) {
    let lighting = Lighting::Environment;
    let reference = image::open(data().join(lighting.reference(model))).unwrap().to_rgb8();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sample_viewer");
    let encoded = |file: String| {
        let picture = image::open(dir.join(file)).expect("seen_under's picture").to_rgb8();
        flip(&reference, &as_the_sample_viewer_encodes(&picture)).0
    };
    let name = lighting.picture(model);
    let (with, without) = (encoded(format!("{name}.png")), encoded(format!("{name}.without.png")));
    eprintln!("{name} as the Sample Viewer encodes: {with:.4}, {without:.4} without");
    assert!(with < aim, "{name}: mean FLIP {with:.4} as the Sample Viewer encodes, aim {aim}");
    assert!(without >= aim, "{name}: mean FLIP {without:.4} without {what}, aim {aim}");
}

/// seamlit's picture (sRGB bytes) as the Sample Viewer would have written the same light:
/// its shaders end with `linearTosRGB`, pow(c, 1 / 2.2) (GAMMA 2.2 in its
/// tonemapping.glsl), not the sRGB curve. The background, which both clear to the same bytes
/// (39, 39, 44) without a shader, is left as it is.
#[expect(clippy::cast_possible_truncation, reason = "a value rounded within 0..=255")]
fn as_the_sample_viewer_encodes(picture: &image::RgbImage) -> image::RgbImage {
    let encode = |byte: u8| {
        let c = f32::from(byte) / 255.0;
        let linear = if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
        (linear.powf(1.0 / 2.2) * 255.0).round() as u8
    };
    let mut out = picture.clone();
    for pixel in out.pixels_mut() {
        if pixel.0 != [39, 39, 44] {
            pixel.0 = pixel.0.map(encode);
        }
    }
    out
}

#[test]
fn the_clearcoat_roughness_texture_matches_the_sample_viewer() {
    // The textures already drawn before these models (clearcoat, sheen, specular) had no
    // Sample Viewer model for these two. Mean FLIP 0.0083 with the texture, 0.0124 without.
    let (model, extension) = ("clearcoat_roughness_texture", "KHR_materials_clearcoat");
    texture_seen_by_the_comparison(model, extension, "clearcoatRoughnessTexture", 0.01);
}

#[test]
fn the_specular_texture_matches_the_sample_viewer() {
    // Mean FLIP 0.0056 with the texture, 0.0142 without.
    let (model, extension) = ("specular_texture", "KHR_materials_specular");
    texture_seen_by_the_comparison(model, extension, "specularTexture", 0.008);
}

/// `model` with every KHR_texture_transform taken out of its materials' texture infos.
fn without_texture_transforms(model: &str) -> PathBuf {
    fn strip(value: &mut serde_json::Value) {
        match value {
            serde_json::Value::Object(object) => {
                if let Some(extensions) =
                    object.get_mut("extensions").and_then(|e| e.as_object_mut())
                {
                    extensions.remove("KHR_texture_transform");
                }
                object.values_mut().for_each(strip);
            }
            serde_json::Value::Array(items) => items.iter_mut().for_each(strip),
            _ => {}
        }
    }
    edited_copy(model, &format!("{model}-without-transforms"), |json| {
        strip(&mut json["materials"]);
        json["extensionsUsed"].as_array_mut().unwrap().retain(|e| e != "KHR_texture_transform");
    })
}

/// `model` with the glTF samplers taken out of its textures: every texture read as glTF's
/// default sampler reads (repeat, trilinear), as seamlit read all of them before it honoured
/// samplers.
fn without_samplers(model: &str) -> PathBuf {
    edited_copy(model, &format!("{model}-without-samplers"), |json| {
        for texture in json["textures"].as_array_mut().unwrap() {
            texture.as_object_mut().unwrap().remove("sampler");
        }
    })
}

/// Khronos' TextureTransformTest (glTF-Sample-Assets, Microsoft, CC0: assets/models/
/// texture_transform_test), framed by compare.sh: three quads offsetting a UV grid, and an
/// arrow rotated, scaled and both, each of which must point at its green marker. Its sampler
/// clamps to the textures' grey border and reads no mips, and the Sample Viewer honours it:
/// mean FLIP 0.0347 under the one sun and 0.0316 under sky.hdr; without the sampler (seamlit
/// read every texture with repeat before) 0.0779 and 0.0617; without the transforms 0.3064
/// and 0.3260.
#[test]
fn the_khronos_texture_transform_test_matches_the_sample_viewer() {
    let model = "TextureTransformTest";
    let what = "KHR_texture_transform";
    seen_by_the_comparison(model, what, &without_texture_transforms(model), EXTENSION_AIM);
    let environment = Lighting::Environment;
    seen_under(environment, model, "the glTF sampler", &without_samplers(model), EXTENSION_AIM);
    seen_by_the_comparison(model, "the glTF sampler", &without_samplers(model), EXTENSION_AIM);
}

/// Khronos' TransmissionTest (glTF-Sample-Assets, Adobe, CC0: assets/sample-viewer/
/// TransmissionTest.glb), framed by compare.sh: a grid of spheres, transmission by factor
/// and by texture, with alpha masks, roughness and metalness, before a draped cloth. Under
/// the one sun: mean FLIP 0.0173, 0.0388 with the extension taken out of the file; under
/// sky.hdr 0.0210 and 0.0416.
#[test]
fn the_khronos_transmission_test_matches_the_sample_viewer() {
    let (model, extension) = ("TransmissionTest", "KHR_materials_transmission");
    extension_seen_by_the_comparison(model, extension, 0.025);
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, 0.03);
}

/// Khronos' EmissiveStrengthTest (glTF-Sample-Assets, Ed Mackey, AGI, CC-BY 4.0: assets/
/// models/emissive_strength_test), framed by compare.sh: five cubes emitting one light blue
/// at strength 1, 2, 4, 8 and 16, between black dividers before a grey tiled wall. Under
/// the one sun: mean FLIP 0.0256 (lavapipe; 0.0303 on an NVIDIA H200), 0.0403 with the
/// extension taken out of the file (every cube the first one's blue); under sky.hdr 0.0269
/// and 0.0400. Both held to the aim, which the file without the extension misses.
#[test]
fn the_khronos_emissive_strength_test_matches_the_sample_viewer() {
    let (model, extension) = ("EmissiveStrengthTest", "KHR_materials_emissive_strength");
    extension_seen_by_the_comparison(model, extension, EXTENSION_AIM);
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, EXTENSION_AIM);
}

/// The mean FLIP error of `model`'s picture, lit as `lighting` says, drawn from `scene`,
/// against the Sample Viewer's over the left two thirds of the frame only; the whole
/// frame's is printed beside it.
fn left_two_thirds(model: &str, scene: &Path, lighting: Lighting, name: &str) -> f32 {
    let reference = image::open(data().join(lighting.reference(model))).unwrap().to_rgb8();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sample_viewer");
    std::fs::create_dir_all(&dir).unwrap();
    let ours = render_scene(
        scene,
        lighting,
        &[],
        reference.dimensions(),
        &dir.join(format!("{name}.png")),
    );
    let (w, h) = reference.dimensions();
    let crop = |picture: &image::RgbImage| {
        image::imageops::crop_imm(picture, 0, 0, w * 2 / 3, h).to_image()
    };
    let (whole, _) = flip(&reference, &ours);
    let (left, _) = flip(&crop(&reference), &crop(&ours));
    eprintln!("{name}: mean FLIP {left:.4} over the left two thirds, {whole:.4} over the frame");
    left
}

/// Khronos' IridescenceSuzanne (glTF-Sample-Assets, UX3D and Pascal Schoen, CC0:
/// assets/models/iridescence_suzanne), framed by compare.sh: three heads under a thin film,
/// a dielectric and a metal (left two thirds of the frame) and a transmissive one (right),
/// lit by the file's own lights and the comparison's sun. The transmissive head shows the
/// transmission target's clear colour, which the Sample Viewer fills with the background's
/// sRGB bytes taken as linear light (its (85, 85, 91) against seamlit's (13, 11, 19) there):
/// a known difference of the two renderers, not of iridescence, and nine tenths of the
/// frame's error (mean FLIP 0.0384 with the films, 0.0399 without). Over the left two thirds:
/// 0.0068 with the films, 0.0102 with the extension taken out of the file. Under sky.hdr the
/// films colour the metal head's reflections of the sky, and the whole frame is within the
/// issue's aim: 0.0323 with them, 0.0567 without.
#[test]
fn the_khronos_iridescence_suzanne_matches_the_sample_viewer() {
    let (model, extension) = ("IridescenceSuzanne", "KHR_materials_iridescence");
    let lighting = Lighting::PunctualOnly;
    let with = left_two_thirds(model, &data().join(format!("{model}.toml")), lighting, model);
    let scene = without_extension(model, extension);
    let without = left_two_thirds(model, &scene, lighting, &format!("{model}.without"));
    assert!(with < 0.0085, "{model}: mean FLIP {with:.4} over the left two thirds");
    assert!(without >= 0.0085, "{model}: mean FLIP {without:.4} without {extension}");
    seen_under(Lighting::Environment, model, extension, &scene, EXTENSION_AIM);
}

/// Khronos' AttenuationTest (glTF-Sample-Assets, Ed Mackey, AGI, CC-BY 4.0: assets/
/// sample-viewer/AttenuationTest.glb), framed by compare.sh: blue-tinted solid glass cubes
/// (KHR_materials_transmission and _volume) of five sizes in five rows, by thickness factor,
/// thickness texture, node scale and attenuation distance, under a row that fakes the
/// answer by base colour, before a grid. Under the one sun: mean FLIP 0.0267, 0.0721 with
/// KHR_materials_volume taken out of the file (thin, untinted glass); under sky.hdr 0.0264
/// and 0.0946.
#[test]
fn the_khronos_attenuation_test_matches_the_sample_viewer() {
    let (model, extension) = ("AttenuationTest", "KHR_materials_volume");
    extension_seen_by_the_comparison(model, extension, EXTENSION_AIM);
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, EXTENSION_AIM);
}

/// glTF-Blender-IO's anisotropy round-trip test (assets/sample-viewer/
/// BlenderAnisotropyTest.glb; the Khronos anisotropy test models by Eric Chadwick, CC0,
/// exported again by the Blender I/O, Apache 2.0), framed by compare.sh: two stacks of
/// black glossy rings streaked by KHR_materials_anisotropy (by tangents, texture and
/// rotation), and eleven discs whose anisotropyTexture turns the streaks at roughness 0 to
/// 1, with labels. Under the one sun: mean FLIP 0.0170, 0.0254 with the extension taken out
/// of the file (round highlights); under sky.hdr 0.0290 and 0.0454.
#[test]
fn the_blender_anisotropy_test_matches_the_sample_viewer() {
    let (model, extension) = ("BlenderAnisotropyTest", "KHR_materials_anisotropy");
    extension_seen_by_the_comparison(model, extension, 0.02);
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, EXTENSION_AIM);
}

/// glTF-Blender-IO's sheen round-trip test (assets/sample-viewer/BlenderSheenTest.glb,
/// Apache 2.0), framed by compare.sh: seven grey spheres, without sheen and with
/// KHR_materials_sheen by colour, roughness, colour texture and roughness texture, each with
/// and without its factor. Under the one sun mean FLIP 0.0094 (0.0307 with the albedo table
/// seamlit computed before it took the Sample Viewer's: sheen.rs); under sky.hdr, which rims
/// every sheened sphere, 0.0092 (0.0222 so), 0.0266 with the extension taken out of the file.
#[test]
fn the_blender_sheen_test_matches_the_sample_viewer() {
    let model = "BlenderSheenTest";
    let lighting = Lighting::PunctualOnly;
    within_aim(model, model, &lighting.reference(model), lighting, &[], 0.02);
    let extension = "KHR_materials_sheen";
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, 0.016);
}

/// The Khronos SheenChair (Wayfair, CC0: assets/models/licenses/SheenChair-CC0.txt; its
/// images scaled to 256 pixels), framed by compare.sh: velvet (KHR_materials_sheen) over a
/// base colour texture tiled by KHR_texture_transform and a normal map, with wood, metal and
/// a label. The default variant, Mango velvet (sheen colour (1, 0.33, 0.1), roughness 0.8),
/// shows the sheen's albedo scaling of the layers under it more than any other model here:
/// under the one sun mean FLIP 0.0252 with the Sample Viewer's albedo table (sheen.rs),
/// 0.0949 with the integral of the BRDF seamlit used before, 0.1103 with the extension taken
/// out; under sky.hdr 0.0246, and 0.0964 without the extension. The Peacock variant (a metal
/// base under a faint sheen): 0.0179.
#[test]
fn the_velvet_chair_matches_the_sample_viewer() {
    let (model, extension) = ("SheenChair", "KHR_materials_sheen");
    let scene = without_extension(model, extension);
    seen_under(Lighting::PunctualOnly, model, extension, &scene, 0.035);
    seen_under(Lighting::Environment, model, extension, &scene, 0.035);
    let lighting = Lighting::PunctualOnly;
    let (name, reference) = ("SheenChair.peacock", "SheenChair.peacock.viewer.png");
    let flags = ["--variant".to_owned(), "Peacock Velvet".to_owned()];
    within_aim(model, name, reference, lighting, &flags, EXTENSION_AIM);
}

/// KHR_materials_ior in Khronos' IridescenceSuzanne (see above): its dielectric head (the
/// left one) is ior 2 under its film (the transmissive head's 1.5 is the default). Over the
/// left two thirds of the frame, with the extension taken out of the file (ior 1.5 there):
/// mean FLIP 0.0116 under the one sun (0.0068 with it), 0.0157 under sky.hdr (0.0086).
#[test]
fn the_ior_of_the_khronos_iridescence_suzanne_is_seen_by_the_comparison() {
    let (model, extension) = ("IridescenceSuzanne", "KHR_materials_ior");
    let scene = without_extension(model, extension);
    let ours = data().join(format!("{model}.toml"));
    for (lighting, aim) in [(Lighting::PunctualOnly, 0.009), (Lighting::Environment, 0.012)] {
        let name = format!("{}.ior", lighting.picture(model));
        let with = left_two_thirds(model, &ours, lighting, &name);
        let without = left_two_thirds(model, &scene, lighting, &format!("{name}.without"));
        assert!(with < aim, "{name}: mean FLIP {with:.4} over the left two thirds, aim {aim}");
        assert!(without >= aim, "{name}: mean FLIP {without:.4} without {extension}, aim {aim}");
    }
}

/// Khronos' SpecularTest (glTF-Sample-Assets, Ed Mackey, AGI, CC-BY 4.0: assets/
/// sample-viewer/SpecularTest.glb), framed by compare.sh: seven rows of five smooth black
/// spheres under KHR_materials_specular (specularFactor and specularTexture from 0 to 1,
/// specularColorFactor and its texture in grey and yellow ramps, a colour factor above 1),
/// with labels. Its spheres are black and roughness 0, so under the one sun the Sample Viewer
/// draws no highlight on them (its GGX lobe vanishes at roughness 0) and the specular is not
/// seen: mean FLIP 0.0238, held to the aim only. Under sky.hdr they reflect the sky
/// as their specular says: 0.0415 with the extension, 0.0820 without, held under 0.045; the
/// frame is dark, so the Sample Viewer's pow(c, 1 / 2.2) encoding parts from seamlit's sRGB
/// by several levels (as in ClearCoatTest): so encoded ([`as_the_sample_viewer_encodes`]),
/// 0.0306 with the specular and 0.0858 without, held under the 0.035.
#[test]
fn the_khronos_specular_test_matches_the_sample_viewer() {
    let model = "SpecularTest";
    let lighting = Lighting::PunctualOnly;
    within_aim(model, model, &lighting.reference(model), lighting, &[], EXTENSION_AIM);
    let extension = "KHR_materials_specular";
    let scene = without_extension(model, extension);
    seen_under(Lighting::Environment, model, extension, &scene, 0.045);
    seen_as_the_sample_viewer_encodes(model, extension, EXTENSION_AIM);
}

/// `model` with its samplers' NEAREST_MIPMAP_LINEAR minifying filter read as
/// LINEAR_MIPMAP_LINEAR, and `extension` taken out of its materials when given.
fn with_linear_minification(model: &str, extension: Option<&str>) -> PathBuf {
    let folder = format!("{model}-linear{}", if extension.is_some() { "-without" } else { "" });
    edited_copy(model, &folder, |json| {
        for sampler in json["samplers"].as_array_mut().unwrap() {
            if sampler["minFilter"] == 9986 {
                sampler["minFilter"] = 9987.into();
            }
        }
        if let Some(extension) = extension {
            for material in json["materials"].as_array_mut().unwrap() {
                if let Some(e) = material.get_mut("extensions").and_then(|e| e.as_object_mut()) {
                    e.remove(extension);
                }
            }
        }
    })
}

/// Khronos' TransmissionRoughnessTest (glTF-Sample-Assets, Ed Mackey, AGI, CC-BY 4.0: assets/
/// sample-viewer/TransmissionRoughnessTest.glb), framed by compare.sh: solid glass cubes
/// (KHR_materials_transmission, _volume) in rows of KHR_materials_ior 1.0, 1.33, 1.5, 1.76
/// and 2.42, roughness rising along each row, before a patterned backdrop and floor. Under the
/// one sun: mean FLIP 0.0329, 0.0476 with the ior taken out of the file. Under sky.hdr 0.0373
/// and 0.0487, held under 0.04: most of the frame's error is the backdrop, whose sampler
/// minifies NEAREST_MIPMAP_LINEAR, which seamlit honours (nearest texels, no anisotropic
/// filtering: wgpu allows that only with linear filters) where the Sample Viewer turns on 16x
/// anisotropic filtering for that filter and WebGL filters it as linear. Read as
/// LINEAR_MIPMAP_LINEAR, 0.0313 under sky.hdr (0.0244 under the sun) with the ior, 0.0431
/// (0.0395) without, held to the 0.035.
#[test]
fn the_khronos_transmission_roughness_test_matches_the_sample_viewer() {
    let (model, extension) = ("TransmissionRoughnessTest", "KHR_materials_ior");
    extension_seen_by_the_comparison(model, extension, EXTENSION_AIM);
    let environment = Lighting::Environment;
    seen_under(environment, model, extension, &without_extension(model, extension), 0.04);
    let reference = image::open(data().join(environment.reference(model))).unwrap().to_rgb8();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sample_viewer");
    let size = reference.dimensions();
    let mean = |scene: &Path, file: &str| {
        let ours = render_scene(scene, environment, &[], size, &dir.join(file));
        flip(&reference, &ours).0
    };
    let with = mean(&with_linear_minification(model, None), "TRT.environment.linear.png");
    let without = mean(
        &with_linear_minification(model, Some(extension)),
        "TRT.environment.linear.without.png",
    );
    eprintln!("{model}.environment, minified linearly: {with:.4}, {without:.4} without the ior");
    assert!(with < EXTENSION_AIM, "{model}: mean FLIP {with:.4} minified linearly");
    assert!(without >= EXTENSION_AIM, "{model}: mean FLIP {without:.4} without {extension}");
}
