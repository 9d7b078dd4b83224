//! Reading a rendered texture back into an image: a copy into a buffer with rows padded to
//! wgpu's 256-byte alignment, then the padding stripped.

use glam::Vec3;
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
        map_for_reading(ctx, &self.buffer, "reading back")?;
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

/// Maps `buffer` (whose copies have been submitted) for reading and waits until it is.
fn map_for_reading(
    ctx: &GpuContext,
    buffer: &wgpu::Buffer,
    during: &'static str,
) -> Result<(), RenderError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    buffer.slice(..).map_async(wgpu::MapMode::Read, move |result| {
        // The receiver lives until after the poll below; a send error cannot happen.
        let _ = sender.send(result);
    });
    ctx.device().poll(wgpu::PollType::wait_indefinitely())?;
    receiver
        .recv()
        .map_err(|_| RenderError::Gpu { during, message: "the map callback never ran".into() })??;
    Ok(())
}

/// The bytes of each posed vertex `posed.wgsl` writes: position, normal (each padded to 4
/// floats) and tangent.
const POSED_STRIDE: u64 = 48;

/// Runs `posed.wgsl` over the first `count` vertices of the object whose group-2 bind group
/// is `object` and reads back what it wrote.
pub(crate) fn read_posed(
    ctx: &GpuContext,
    object: &wgpu::BindGroup,
    count: u32,
) -> Result<PosedVertices, RenderError> {
    let size = u64::from(count.max(1)) * POSED_STRIDE;
    let output = buffer(
        ctx,
        "seamlit posed vertices",
        size,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    );
    let read = buffer(
        ctx,
        "seamlit posed readback",
        size,
        wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
    );
    let (pipeline, output_group) = posed_pipeline(ctx, &output);
    let mut encoder = ctx
        .device()
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("seamlit posed") });
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("seamlit posed"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, object, &[]);
        pass.set_bind_group(1, &output_group, &[]);
        let (x, y) = workgroups(count);
        pass.dispatch_workgroups(x, y, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &read, 0, size);
    ctx.queue().submit([encoder.finish()]);
    map_for_reading(ctx, &read, "reading back posed vertices")?;
    let floats: Vec<f32> = {
        let mapped = read.slice(..).get_mapped_range().map_err(|e| RenderError::Gpu {
            during: "reading back posed vertices",
            message: e.to_string(),
        })?;
        bytemuck::cast_slice(&mapped).to_vec()
    };
    read.unmap();
    Ok(posed_vertices(&floats, count as usize))
}

/// A buffer of `size` bytes, not mapped.
fn buffer(ctx: &GpuContext, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    ctx.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage,
        mapped_at_creation: false,
    })
}

/// The compute pipeline of `posed.wgsl` (group 0: the object, group 1: `output`) and the bind
/// group of `output`.
fn posed_pipeline(
    ctx: &GpuContext,
    output: &wgpu::Buffer,
) -> (wgpu::ComputePipeline, wgpu::BindGroup) {
    let device = ctx.device();
    let output_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("seamlit posed output"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: false },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let output_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("seamlit posed output"),
        layout: &output_layout,
        entries: &[wgpu::BindGroupEntry { binding: 0, resource: output.as_entire_binding() }],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("seamlit posed"),
        bind_group_layouts: &[Some(&ctx.layouts.object), Some(&output_layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("seamlit posed"),
        layout: Some(&layout),
        module: &crate::shaders::POSED.module(device),
        entry_point: Some("cs_posed"),
        compilation_options: wgpu::PipelineCompilationOptions::default(),
        cache: None,
    });
    (pipeline, output_group)
}

/// The workgroups for `count` vertices, 64 a group: at most 65535 groups a dimension, so rows
/// of 65535 groups.
fn workgroups(count: u32) -> (u32, u32) {
    let groups = count.div_ceil(64);
    if groups <= 65535 { (groups.max(1), 1) } else { (65535, groups.div_ceil(65535)) }
}

/// The first `count` posed vertices of what `posed.wgsl` wrote (12 floats a vertex).
fn posed_vertices(floats: &[f32], count: usize) -> PosedVertices {
    let mut out = PosedVertices::default();
    for v in floats.as_chunks::<12>().0.iter().take(count) {
        out.positions.push(Vec3::new(v[0], v[1], v[2]));
        out.normals.push(Vec3::new(v[4], v[5], v[6]));
        out.tangents.push(glam::Vec4::new(v[8], v[9], v[10], v[11]));
    }
    out
}

/// The posed vertices of one object, read back by [`crate::GpuScene::posed_vertices`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PosedVertices {
    /// World-space positions.
    pub positions: Vec<Vec3>,
    /// World-space unit normals.
    pub normals: Vec<Vec3>,
    /// World-space tangents: xyz under the model matrix (not normalised), w the handedness.
    pub tangents: Vec<glam::Vec4>,
}

#[cfg(test)]
mod tests {
    use super::workgroups;

    #[test]
    fn workgroups_cover_every_vertex_within_the_dimension_limit() {
        assert_eq!(workgroups(0), (1, 1));
        assert_eq!(workgroups(64), (1, 1));
        assert_eq!(workgroups(65), (2, 1));
        assert_eq!(workgroups(65535 * 64), (65535, 1));
        let (x, y) = workgroups(65535 * 64 + 1);
        assert_eq!((x, y), (65535, 2));
        assert!(u64::from(x) * u64::from(y) * 64 > 65535 * 64, "every vertex has a lane");
    }
}
