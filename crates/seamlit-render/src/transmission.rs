//! KHR_materials_transmission's view of what lies behind a transmissive surface, as the
//! Khronos glTF Sample Viewer makes it: before the scene pass, the scene without its
//! transmissive objects is drawn into a square target of [`SIZE`] texels (linear light, no
//! tone mapping, 8 bits a channel as the Sample Viewer's; the sky where the frame shows one),
//! and its mips are filtered down to one
//! texel; the transmissive surfaces then read it where the view leaves their volume, at the
//! mip of their roughness (`transmission_ambient` in layers.wgsl). Made on the first frame
//! that draws a transmissive material; frames without one never touch it.

use crate::GpuContext;
use crate::pipeline::{DEPTH_FORMAT, Pipelines};

/// Texels a side of the transmission target (the Sample Viewer's 1024).
pub(crate) const SIZE: u32 = 1024;

/// The transmission target's format: linear light in 8 bits a channel, clamped to 1, as the
/// Sample Viewer's RGBA8 target holds it (what is seen through glass is no brighter than
/// white before the tone mapping; with an HDR environment lighting the scene behind, a
/// floating-point target made the glass look more saturated than the Sample Viewer's: mean
/// FLIP 0.0483 against its 0.0254 on the transmission model under sky.hdr).
pub(crate) const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The transmission target, its depth, the mesh pipelines that draw into it and the pass
/// that makes its mips.
#[derive(Debug)]
pub(crate) struct Transmission {
    /// All mips, as the scene pass samples them (group 0, binding 5).
    pub view: wgpu::TextureView,
    /// Each mip as a render target (mip 0 is where the scene is drawn).
    mips: Vec<wgpu::TextureView>,
    pub depth: wgpu::TextureView,
    /// The mesh pipelines for this target: one sample, [`FORMAT`].
    pub pipelines: Pipelines,
    /// The frame uniforms of the pass: the scene's, linear (no exposure, no tone mapping).
    pub frame_buffer: wgpu::Buffer,
    mip_pipeline: wgpu::RenderPipeline,
    /// Mip i + 1 from mip i.
    mip_groups: Vec<wgpu::BindGroup>,
}

impl Transmission {
    /// The target and its mips' views, its depth, its frame uniforms (`frame_size` bytes), its
    /// mesh pipelines and the mip pass.
    pub(crate) fn new(ctx: &GpuContext, frame_size: u64) -> Self {
        let device = ctx.device();
        let texture = target_texture(device);
        let mips: Vec<wgpu::TextureView> = (0..texture.mip_level_count())
            .map(|level| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    base_mip_level: level,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("seamlit transmission frame"),
            size: frame_size,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let layout = mip_layout(device);
        Self {
            view: texture.create_view(&wgpu::TextureViewDescriptor::default()),
            mip_groups: mip_groups(device, &layout, &mips),
            mips,
            depth: depth_view(device),
            pipelines: Pipelines::new(ctx, FORMAT, 1),
            frame_buffer,
            mip_pipeline: mip_pipeline(device, &layout),
        }
    }

    /// Mip 0, where the scene is drawn.
    pub(crate) fn target(&self) -> &wgpu::TextureView {
        &self.mips[0]
    }

    /// Filters every mip from the one above it.
    pub(crate) fn encode_mips(&self, encoder: &mut wgpu::CommandEncoder) {
        for (group, target) in self.mip_groups.iter().zip(&self.mips[1..]) {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("seamlit transmission mip"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.mip_pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.draw(0..3, 0..1);
        }
    }
}

/// The target: [`SIZE`] texels square, [`FORMAT`], mips down to one texel.
fn target_texture(device: &wgpu::Device) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("seamlit transmission"),
        size: wgpu::Extent3d { width: SIZE, height: SIZE, depth_or_array_layers: 1 },
        mip_level_count: SIZE.ilog2() + 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}

/// The depth buffer of the pass that draws the target.
fn depth_view(device: &wgpu::Device) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("seamlit transmission depth"),
            size: wgpu::Extent3d { width: SIZE, height: SIZE, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

/// The mip pass's bindings: the mip above and a linear sampler (`transmission.wgsl`).
fn mip_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("seamlit transmission mips"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    })
}

/// One bind group a mip below the first: the mip above it, filtered linearly.
fn mip_groups(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    mips: &[wgpu::TextureView],
) -> Vec<wgpu::BindGroup> {
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("seamlit transmission mips"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    mips[..mips.len() - 1]
        .iter()
        .map(|above| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("seamlit transmission mip"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(above),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::Sampler(&sampler),
                    },
                ],
            })
        })
        .collect()
}

/// The pipeline that draws a mip from the one above (`transmission.wgsl`'s full-screen
/// triangle).
fn mip_pipeline(device: &wgpu::Device, layout: &wgpu::BindGroupLayout) -> wgpu::RenderPipeline {
    let module = crate::shaders::TRANSMISSION.module(device);
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("seamlit transmission mips"),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("seamlit transmission mips"),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_mip"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_mip"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: FORMAT,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}
