//! Headless rendering for the commands: one GPU context, one renderer, images out.

use glam::Vec3;
use image::RgbaImage;
use seamlit_io::Asset;
use seamlit_render::{
    FrameDescriptor, FrameSettings, GpuContext, GpuScene, LightingModel, Renderer, ToneMapping,
};
use seamlit_scene::{Bounds, Camera};

use crate::cli::ViewFlags;
use crate::failure::{Classify, Failure};
use crate::prepare::Loaded;

/// Frame settings from the command line's view flags and the scene: its lights, and its
/// lighting model unless `--lighting` names one; tone mapping as `--tone-mapping` says, else
/// the lighting model's usual one.
#[must_use]
pub fn frame_settings(flags: &ViewFlags, loaded: &Loaded) -> FrameSettings {
    let lighting_model = flags.lighting.map_or_else(|| loaded.lighting(), Into::into);
    FrameSettings {
        lights: loaded.lights(),
        lighting_model,
        tone_mapping: flags
            .tone_mapping
            .map_or_else(|| ToneMapping::default_for(lighting_model), Into::into),
        exposure: flags.exposure,
        ambient: Vec3::splat(flags.ambient.unwrap_or(default_ambient(lighting_model))),
        normal_mapping: !flags.no_normal_map,
        debug_view: flags.view.into(),
        show_tbn: flags.tbn,
        ..FrameSettings::default()
    }
}

/// The ambient light when `--ambient` is not given: the paper's pictures' 0.05; for PBR,
/// where a uniform ambient light stands in for the environment that metals reflect (without
/// it they render black but for their highlights), 0.3.
#[must_use]
pub fn default_ambient(model: LightingModel) -> f32 {
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
    pub fn open() -> Result<Self, Failure> {
        let ctx = GpuContext::headless().processing()?;
        let renderer = Renderer::for_images(&ctx).processing()?;
        Ok(Self { ctx, renderer })
    }

    /// Uploads `asset` and renders it through `camera`.
    ///
    /// # Errors
    /// [`Failure::Processing`] when upload or rendering fails.
    pub fn render(
        &mut self,
        asset: &Asset,
        camera: &Camera,
        bounds: Bounds,
        settings: &FrameSettings,
        size: (u32, u32),
    ) -> Result<(GpuScene, RgbaImage), Failure> {
        let scene = GpuScene::upload(&self.ctx, asset).processing()?;
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
pub fn check_png(path: &std::path::Path) -> Result<(), Failure> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
        Ok(())
    } else {
        Err(Failure::input(format!("{}: the output must be a .png file", path.display())))
    }
}
