//! Screenshots of the window: the presented texture copied into a buffer and read back.

use image::RgbaImage;
use seamlit_render::GpuContext;

use crate::failure::Failure;

pub use seamlit_render::PendingReadback as Pending;

/// Records a copy of `texture` (4 bytes per pixel) into a new buffer.
pub(crate) fn copy_to_buffer(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    width: u32,
    height: u32,
) -> Pending {
    Pending::record(device, encoder, texture, width, height)
}

/// Waits for the copy (after the encoder was submitted) and returns the image, swapping
/// red and blue for BGRA surface formats.
///
/// # Errors
/// [`Failure::Processing`] when the buffer cannot be mapped.
pub(crate) fn read(
    ctx: &GpuContext,
    pending: Pending,
    format: wgpu::TextureFormat,
) -> Result<RgbaImage, Failure> {
    let mut image =
        pending.finish(ctx).map_err(|e| Failure::processing(format!("screenshot: {e}")))?;
    let bgra =
        matches!(format, wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb);
    for p in image.pixels_mut() {
        if bgra {
            p.0.swap(0, 2);
        }
        // The window is opaque; some surfaces leave alpha undefined.
        p.0[3] = 255;
    }
    Ok(image)
}
