//! Headless rendering for the commands: one GPU context, one renderer, images out.

use image::RgbaImage;
use seamlit_io::Asset;
use seamlit_render::{FrameSettings, GpuContext, GpuScene, IMAGE_FORMAT, Light, Renderer};
use seamlit_scene::{Bounds, Camera};

use crate::cli::ViewFlags;
use crate::failure::{Classify, Failure};

/// Frame settings from the command line's view flags and the scene's lights.
#[must_use]
pub fn frame_settings(flags: &ViewFlags, lights: Vec<Light>) -> FrameSettings {
    FrameSettings {
        lights,
        lighting_model: flags.lighting.into(),
        normal_mapping: !flags.no_normal_map,
        debug_view: flags.view.into(),
        show_tbn: flags.tbn,
        ..FrameSettings::default()
    }
}

/// A headless GPU context and an image renderer (4x MSAA where supported).
pub struct Gpu {
    /// The device.
    pub ctx: GpuContext,
    /// The renderer, drawing [`IMAGE_FORMAT`].
    pub renderer: Renderer,
}

impl Gpu {
    /// Opens the GPU (or the software rasteriser).
    ///
    /// # Errors
    /// [`Failure::Processing`] when no adapter or device is available.
    pub fn open() -> Result<Self, Failure> {
        let ctx = GpuContext::headless().processing()?;
        let samples = if ctx
            .supported_sample_counts(IMAGE_FORMAT)
            .contains(&seamlit_render::DEFAULT_SAMPLE_COUNT)
        {
            seamlit_render::DEFAULT_SAMPLE_COUNT
        } else {
            1
        };
        let renderer = Renderer::new(&ctx, IMAGE_FORMAT, samples).processing()?;
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
            .render_to_image(&self.ctx, &scene, &view, settings, size.0, size.1)
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
