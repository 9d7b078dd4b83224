//! Headless rendering for the commands: one GPU context, one renderer, images out.

use std::path::Path;

use glam::Vec3;
use image::RgbaImage;
use seamlit_io::Asset;
use seamlit_render::{
    Environment, FrameDescriptor, FrameSettings, GpuContext, GpuEnvironment, GpuScene, Light,
    LightingModel, Renderer, ToneMapping,
};
use seamlit_scene::{Bounds, Camera, EnvironmentChoice};

use crate::cli::{Switch, ViewFlags};
use crate::failure::{Classify, Failure};
use crate::prepare::Loaded;

/// How frames look: each value from the command line's flag, else the scene's `[render]`
/// key, else the default.
#[derive(Clone, Debug, PartialEq)]
pub struct Look {
    /// `--lighting`, `[render] lighting`, else PBR when every model is glTF.
    pub lighting: LightingModel,
    /// `--tone-mapping`, `tone_mapping`; `None`: the lighting model's usual one.
    pub tone_mapping: Option<ToneMapping>,
    /// `--exposure`, `exposure`, else 1.
    pub exposure: f32,
    /// `--ambient`, `ambient`; `None`: [`default_ambient`].
    pub ambient: Option<f32>,
    /// `--environment`, `environment`, else [`default_environment`].
    pub environment: EnvironmentChoice,
    /// `--environment-intensity`, `environment_intensity`, else 1.
    pub environment_intensity: f32,
    /// `--environment-rotation`, `environment_rotation`, else 0.
    pub environment_rotation_deg: f32,
    /// `--background`, `background` (sRGB); `None`: the environment, blurred, when there is
    /// one, else the usual dark grey.
    pub background: Option<[f32; 3]>,
    /// `--shadows`, `shadows`, else on.
    pub shadows: bool,
}

impl Look {
    /// The look of `loaded` as `flags` change it.
    #[must_use]
    pub(crate) fn new(flags: &ViewFlags, loaded: &Loaded) -> Self {
        let scene = &loaded.scene.render;
        let lighting = flags.lighting.map_or_else(|| loaded.lighting(), Into::into);
        let environment = flags
            .environment
            .as_deref()
            .map(|e| EnvironmentChoice::parse(e, Path::new("")))
            .or_else(|| scene.environment.clone())
            .unwrap_or_else(|| default_environment(loaded, lighting));
        Self {
            lighting,
            tone_mapping: flags.tone_mapping.map(Into::into).or(scene.tone_mapping),
            exposure: flags.exposure.or(scene.exposure).unwrap_or(1.0),
            ambient: flags.ambient.or(scene.ambient),
            environment,
            environment_intensity: flags
                .environment_intensity
                .or(scene.environment_intensity)
                .unwrap_or(1.0),
            environment_rotation_deg: flags
                .environment_rotation
                .or(scene.environment_rotation_deg)
                .unwrap_or(0.0),
            background: flags.background.or(scene.background),
            shadows: flags.shadows.map(|s| s == Switch::On).or(scene.shadows).unwrap_or(true),
        }
    }

    /// Reads the environment the look names: `None` for `none`, the procedural studio for
    /// `builtin`, the image of a `.hdr` file.
    ///
    /// # Errors
    /// [`Failure::BadInput`] naming the file when it is missing or not a Radiance image.
    pub(crate) fn read_environment(&self) -> Result<Option<Environment>, Failure> {
        match &self.environment {
            EnvironmentChoice::None => Ok(None),
            EnvironmentChoice::Builtin => Ok(Some(Environment::Builtin)),
            EnvironmentChoice::File(path) => Environment::from_hdr_file(path)
                .map(Some)
                .map_err(|e| Failure::input(e.to_string())),
        }
    }

    /// The frame settings for `lighting` (the viewer switches it live) and `lights`: ambient
    /// light 0 where an environment lights the scene, the background as [`Look::background`]
    /// says.
    #[must_use]
    pub(crate) fn settings(&self, lighting: LightingModel, lights: Vec<Light>) -> FrameSettings {
        let environment = self.environment != EnvironmentChoice::None;
        let ambient = self.ambient.unwrap_or(if environment && lighting == LightingModel::Pbr {
            0.0
        } else {
            default_ambient(lighting)
        });
        let defaults = FrameSettings::default();
        let clear_color = self.background.map_or(defaults.clear_color, |[r, g, b]| {
            [srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b), 1.0]
        });
        FrameSettings {
            lights,
            lighting_model: lighting,
            tone_mapping: self.tone_mapping.unwrap_or(ToneMapping::default_for(lighting)),
            exposure: self.exposure,
            ambient: Vec3::splat(ambient),
            environment_intensity: self.environment_intensity,
            environment_rotation_deg: self.environment_rotation_deg,
            environment_background: self.background.is_none(),
            shadow_maps: if self.shadows { SHADOW_MAPS } else { 0 },
            clear_color,
            ..defaults
        }
    }
}

/// Shadow-casting lights when shadows are on: the renderer's most.
const SHADOW_MAPS: usize = 4;

fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// The environment when neither `--environment` nor the scene names one: the built-in studio
/// for PBR scenes whose models are all glTF (their materials expect image-based light, as in
/// every glTF viewer), none otherwise (OBJ models and the paper's demo keep their look).
#[must_use]
pub(crate) fn default_environment(loaded: &Loaded, lighting: LightingModel) -> EnvironmentChoice {
    let all_gltf =
        loaded.parts.iter().all(|(_, asset)| asset.document::<seamlit_io::GltfSource>().is_some());
    if all_gltf && lighting == LightingModel::Pbr {
        EnvironmentChoice::Builtin
    } else {
        EnvironmentChoice::None
    }
}

/// Frame settings from the command line's view flags and the scene ([`Look`]), with the
/// scene's lights.
#[must_use]
pub(crate) fn frame_settings(flags: &ViewFlags, loaded: &Loaded) -> FrameSettings {
    let look = Look::new(flags, loaded);
    let settings = look.settings(look.lighting, loaded.lights());
    FrameSettings {
        normal_mapping: !flags.no_normal_map,
        debug_view: flags.view.into(),
        show_tbn: flags.tbn,
        ..settings
    }
}

/// The ambient light when neither `--ambient` nor the scene gives one and no environment
/// lights the scene: the paper's pictures' 0.05; for PBR, where a uniform ambient light stands
/// in for the environment that metals reflect (without it they render black but for their
/// highlights), 0.3.
#[must_use]
pub(crate) fn default_ambient(model: LightingModel) -> f32 {
    if model == LightingModel::Pbr { 0.3 } else { 0.05 }
}

/// A headless GPU context and an image renderer (4x MSAA where supported).
pub struct Gpu {
    /// The device.
    pub ctx: GpuContext,
    /// The renderer, drawing [`seamlit_render::IMAGE_FORMAT`].
    pub renderer: Renderer,
}

impl Gpu {
    /// Opens the GPU (or the software rasteriser).
    ///
    /// # Errors
    /// [`Failure::Processing`] when no adapter or device is available.
    pub(crate) fn open() -> Result<Self, Failure> {
        let ctx = GpuContext::headless().processing()?;
        let renderer = Renderer::for_images(&ctx).processing()?;
        Ok(Self { ctx, renderer })
    }

    /// Prefilters `environment` on the GPU and lights every following frame with it.
    ///
    /// # Errors
    /// [`Failure::Processing`] when the GPU fails.
    pub(crate) fn set_environment(
        &mut self,
        environment: Option<&Environment>,
    ) -> Result<(), Failure> {
        let gpu =
            environment.map(|e| GpuEnvironment::new(&self.ctx, e)).transpose().processing()?;
        self.renderer.set_environment(gpu);
        Ok(())
    }

    /// Uploads `asset`, poses it (`poses`: one per object, see [`crate::animate::poses`])
    /// and renders it through `camera`.
    ///
    /// # Errors
    /// [`Failure::Processing`] when upload or rendering fails.
    pub(crate) fn render(
        &mut self,
        asset: &Asset,
        poses: Option<&[seamlit_render::ObjectPose]>,
        camera: &Camera,
        bounds: Bounds,
        settings: &FrameSettings,
        size: (u32, u32),
    ) -> Result<(GpuScene, RgbaImage), Failure> {
        warn_of_undrawn_textures(&self.ctx, asset);
        let mut scene = GpuScene::upload(&self.ctx, asset).processing()?;
        if let Some(poses) = poses {
            scene.set_pose(&self.ctx, poses).processing()?;
        }
        let aspect = size.0 as f32 / size.1 as f32;
        let view = camera.view(aspect, Some(bounds));
        let image = self
            .renderer
            .render_to_image(
                &self.ctx,
                &FrameDescriptor { scene: &scene, camera: &view, settings, size: (size.0, size.1) },
            )
            .processing()?;
        Ok((scene, image))
    }
}

/// Checks that `path` names a PNG.
///
/// # Errors
/// [`Failure::BadInput`] otherwise.
pub(crate) fn check_png(path: &Path) -> Result<(), Failure> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
        Ok(())
    } else {
        Err(Failure::input(format!("{}: the output must be a .png file", path.display())))
    }
}

/// One warning when `ctx`'s device leaves out the transmission, thickness, iridescence and
/// anisotropy textures (fewer than 21 sampled textures a shader stage) and `asset` has one.
pub(crate) fn warn_of_undrawn_textures(ctx: &GpuContext, asset: &Asset) {
    let has = |m: &seamlit_io::Material| {
        m.extensions.has_transmission_volume_iridescence_or_anisotropy_texture()
    };
    if !ctx.draws_all_extension_textures() && asset.materials.iter().any(has) {
        eprintln!(
            "warning: {} allows fewer than 21 sampled textures a shader stage: the \
             transmission, thickness, iridescence and anisotropy textures are not drawn \
             (their factors are)",
            ctx.describe()
        );
    }
}
