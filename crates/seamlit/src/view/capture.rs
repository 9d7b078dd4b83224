//! Screenshots of the window: the presented texture copied into a buffer and read back.

use image::RgbaImage;
use seamlit_render::GpuContext;

use crate::failure::Failure;

/// A pending copy of a frame.
pub struct Pending {
    buffer: wgpu::Buffer,
    width: u32,
    height: u32,
    padded_row: u32,
}

/// Records a copy of `texture` (4 bytes per pixel) into a new buffer, rows padded to wgpu's
/// alignment.
pub fn copy_to_buffer(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    width: u32,
    height: u32,
) -> Pending {
    let padded_row = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
        * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("seamlit screenshot"),
        size: u64::from(padded_row) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
    Pending { buffer, width, height, padded_row }
}

/// Waits for the copy (after the encoder was submitted) and returns the image, swapping
/// red and blue for BGRA surface formats.
///
/// # Errors
/// [`Failure::Processing`] when the buffer cannot be mapped.
pub fn read(
    ctx: &GpuContext,
    pending: &Pending,
    format: wgpu::TextureFormat,
) -> Result<RgbaImage, Failure> {
    let (sender, receiver) = std::sync::mpsc::channel();
    pending.buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    ctx.device()
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Failure::processing(format!("screenshot: {e}")))?;
    match receiver.recv() {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(Failure::processing(format!("screenshot: {e}"))),
        Err(_) => return Err(Failure::processing("screenshot: the copy never finished")),
    }
    let bgra =
        matches!(format, wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb);
    let row = (pending.width * 4) as usize;
    let mut pixels = Vec::with_capacity(row * pending.height as usize);
    {
        let mapped = pending
            .buffer
            .slice(..)
            .get_mapped_range()
            .map_err(|e| Failure::processing(format!("screenshot: {e}")))?;
        for line in mapped.chunks_exact(pending.padded_row as usize) {
            pixels.extend_from_slice(&line[..row]);
        }
    }
    pending.buffer.unmap();
    if bgra {
        for p in pixels.chunks_exact_mut(4) {
            p.swap(0, 2);
        }
    }
    // The window is opaque; some surfaces leave alpha undefined.
    for p in pixels.chunks_exact_mut(4) {
        p[3] = 255;
    }
    RgbaImage::from_raw(pending.width, pending.height, pixels)
        .ok_or_else(|| Failure::processing("screenshot: wrong number of bytes"))
}
