//! Reading a rendered texture back into an image: a copy into a buffer with rows padded to
//! wgpu's 256-byte alignment, then the padding stripped.

use image::RgbaImage;

use crate::{GpuContext, RenderError};

/// A copy of a 4-byte-per-pixel texture into a buffer, recorded but not yet read: the
/// headless path and the viewer's screenshots share it.
pub struct PendingReadback {
    buffer: wgpu::Buffer,
    width: u32,
    height: u32,
    padded_row: u32,
}

impl PendingReadback {
    /// Records into `encoder` a copy of `texture` (`width` x `height`, 4 bytes a pixel) into a
    /// new buffer whose rows are padded to wgpu's 256-byte alignment.
    #[must_use]
    pub fn record(
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
        width: u32,
        height: u32,
    ) -> Self {
        let padded_row = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("seamlit readback"),
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
        Self { buffer, width, height, padded_row }
    }

    /// Waits for the copy (the encoder must have been submitted) and returns the pixels with
    /// the row padding stripped, as the texture stores them (RGBA or BGRA).
    ///
    /// # Errors
    /// [`RenderError::Gpu`] when the buffer cannot be mapped.
    pub fn finish(self, ctx: &GpuContext) -> Result<RgbaImage, RenderError> {
        let (sender, receiver) = std::sync::mpsc::channel();
        self.buffer.slice(..).map_async(wgpu::MapMode::Read, move |result| {
            // The receiver lives until after the poll below; a send error cannot happen.
            let _ = sender.send(result);
        });
        ctx.device().poll(wgpu::PollType::wait_indefinitely())?;
        receiver.recv().map_err(|_| RenderError::Gpu {
            during: "reading back",
            message: "the map callback never ran".into(),
        })??;
        let row = (self.width * 4) as usize;
        let mut pixels = Vec::with_capacity(row * self.height as usize);
        {
            let mapped = self
                .buffer
                .slice(..)
                .get_mapped_range()
                .map_err(|e| RenderError::Gpu { during: "reading back", message: e.to_string() })?;
            for line in mapped.chunks_exact(self.padded_row as usize) {
                pixels.extend_from_slice(&line[..row]);
            }
        }
        self.buffer.unmap();
        RgbaImage::from_raw(self.width, self.height, pixels).ok_or_else(|| RenderError::Gpu {
            during: "reading back",
            message: "wrong number of bytes".into(),
        })
    }
}

/// Copies the RGBA8 `texture` (`width` x `height`) into a buffer after the commands in
/// `encoder`, submits, waits and returns the image.
pub(crate) fn read_texture(
    ctx: &GpuContext,
    mut encoder: wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    width: u32,
    height: u32,
) -> Result<RgbaImage, RenderError> {
    let pending = PendingReadback::record(ctx.device(), &mut encoder, texture, width, height);
    ctx.queue().submit([encoder.finish()]);
    pending.finish(ctx)
}
