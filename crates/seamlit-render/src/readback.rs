//! Reading a rendered texture back into an image: a copy into a buffer with rows padded to
//! wgpu's 256-byte alignment, then the padding stripped.

use image::RgbaImage;

use crate::{GpuContext, RenderError};

/// Copies the RGBA8 `texture` (`width` x `height`) into a buffer after the commands in
/// `encoder`, submits, waits and returns the image.
pub(crate) fn read_texture(
    ctx: &GpuContext,
    mut encoder: wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    width: u32,
    height: u32,
) -> Result<RgbaImage, RenderError> {
    let unpadded = width * 4;
    let padded =
        unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = ctx.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some("seamlit readback"),
        size: u64::from(padded) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
    ctx.queue().submit([encoder.finish()]);
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.slice(..).map_async(wgpu::MapMode::Read, move |result| {
        // The receiver lives until after the poll below; a send error cannot happen.
        let _ = sender.send(result);
    });
    ctx.device().poll(wgpu::PollType::wait_indefinitely())?;
    receiver.recv().map_err(|_| RenderError::Gpu {
        during: "reading back",
        message: "the map callback never ran".into(),
    })??;
    let mapped = buffer
        .slice(..)
        .get_mapped_range()
        .map_err(|e| RenderError::Gpu { during: "reading back", message: e.to_string() })?;
    let mut pixels = Vec::with_capacity((unpadded * height) as usize);
    for row in mapped.chunks_exact(padded as usize) {
        pixels.extend_from_slice(&row[..unpadded as usize]);
    }
    drop(mapped);
    buffer.unmap();
    RgbaImage::from_raw(width, height, pixels).ok_or_else(|| RenderError::Gpu {
        during: "reading back",
        message: "wrong number of bytes".into(),
    })
}
