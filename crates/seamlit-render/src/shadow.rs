//! Shadow maps for directional and spot lights: one depth layer per shadow-casting light,
//! rendered before the scene (`shadow.wgsl`) and compared with percentage-closer filtering
//! in the lighting loop (`mesh.wgsl`).

use glam::{Mat4, Vec3};

use crate::pipeline::DEPTH_FORMAT;
use crate::scene::VertexRaw;
use crate::{GpuContext, GpuScene, Light};

/// The most lights that cast shadows in one frame (the first directional and spot lights):
/// the layers of the shadow maps' depth texture.
pub(crate) const MAX_SHADOW_MAPS: u32 = 4;
/// Texels per side of each shadow map.
pub(crate) const SHADOW_SIZE: u32 = 1024;

/// The shadow maps and the depth-only pipeline that fills them.
#[derive(Debug)]
pub(crate) struct Shadows {
    /// All layers, for the lighting shader.
    pub view: wgpu::TextureView,
    /// One view per layer, to render into.
    layers: Vec<wgpu::TextureView>,
    /// Each layer's light view-projection, for the shadow pass.
    pass_buffers: Vec<wgpu::Buffer>,
    pass_bind_groups: Vec<wgpu::BindGroup>,
    /// Every layer's light view-projection, for the lighting shader.
    pub matrices: wgpu::Buffer,
    pub sampler: wgpu::Sampler,
    /// For objects without a pose (`DEFORM` false), and for posed ones.
    pipeline: wgpu::RenderPipeline,
    posed_pipeline: wgpu::RenderPipeline,
}

impl Shadows {
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        let device = ctx.device();
        let (view, layers) = shadow_maps(device);
        let pass_buffers: Vec<wgpu::Buffer> =
            (0..MAX_SHADOW_MAPS).map(|_| uniform(device, "seamlit shadow pass", 64)).collect();
        let pass_layout = pass_layout(device);
        let pass_bind_groups = pass_buffers
            .iter()
            .map(|b| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("seamlit shadow pass"),
                    layout: &pass_layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: b.as_entire_binding(),
                    }],
                })
            })
            .collect();
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("seamlit shadow"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        Self {
            view,
            layers,
            pass_buffers,
            pass_bind_groups,
            matrices: uniform(device, "seamlit shadow matrices", 64 * u64::from(MAX_SHADOW_MAPS)),
            sampler,
            pipeline: pipeline(ctx, &pass_layout, false),
            posed_pipeline: pipeline(ctx, &pass_layout, true),
        }
    }

    /// Assigns shadow maps to the first `count` (at most [`MAX_SHADOW_MAPS`]) directional and
    /// spot lights of `lights`, writes their matrices, and returns each light's layer (-1: no
    /// shadow) and how many layers are in use.
    pub(crate) fn prepare(
        &self,
        ctx: &GpuContext,
        lights: &[Light],
        count: usize,
        bounds: Option<(Vec3, Vec3)>,
    ) -> (Vec<f32>, usize) {
        let (lo, hi) = bounds.unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
        let mut layers = Vec::with_capacity(lights.len());
        let mut matrices = Vec::new();
        for light in lights {
            let matrix = (matrices.len() < count.min(MAX_SHADOW_MAPS as usize))
                .then(|| light_matrix(light, lo, hi))
                .flatten();
            match matrix {
                Some(m) => {
                    layers.push(matrices.len() as f32);
                    matrices.push(m);
                }
                None => layers.push(-1.0),
            }
        }
        for (buffer, m) in self.pass_buffers.iter().zip(&matrices) {
            ctx.queue().write_buffer(buffer, 0, bytemuck::cast_slice(&m.to_cols_array()));
        }
        if !matrices.is_empty() {
            let all: Vec<f32> = matrices.iter().flat_map(Mat4::to_cols_array).collect();
            ctx.queue().write_buffer(&self.matrices, 0, bytemuck::cast_slice(&all));
        }
        (layers, matrices.len())
    }

    /// Records the depth passes of the first `used` shadow maps.
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder, scene: &GpuScene, used: usize) {
        for (layer, bind_group) in self.layers.iter().zip(&self.pass_bind_groups).take(used) {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("seamlit shadow map"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: layer,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, bind_group, &[]);
            for mesh in &scene.meshes {
                pass.set_pipeline(if mesh.posed { &self.posed_pipeline } else { &self.pipeline });
                pass.set_bind_group(1, &mesh.bind_group, &[]);
                pass.set_vertex_buffer(0, mesh.vertices.slice(..));
                pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..mesh.index_count, 0, 0..1);
            }
        }
    }
}

/// The light's view-projection (wgpu depth 0..1) over the scene's bounds `lo..hi`; `None`
/// for point lights, which cast no shadows.
fn light_matrix(light: &Light, lo: Vec3, hi: Vec3) -> Option<Mat4> {
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo).length() * 0.5).max(1e-3);
    let up_for = |d: Vec3| if d.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    match *light {
        Light::Directional { direction, .. } => {
            let d = direction.try_normalize().unwrap_or(Vec3::NEG_Y);
            let eye = centre - d * radius * 2.0;
            let view = glam::camera::rh::view::look_at_mat4(eye, centre, up_for(d));
            let r = radius;
            Some(
                glam::camera::rh::proj::directx::orthographic(
                    -r,
                    r,
                    -r,
                    r,
                    radius * 0.5,
                    radius * 3.5,
                ) * view,
            )
        }
        Light::Spot { position, direction, outer_cone_deg, .. } => {
            let d = direction.try_normalize().unwrap_or(Vec3::NEG_Y);
            let view = glam::camera::rh::view::look_at_mat4(position, position + d, up_for(d));
            let far = position.distance(centre) + radius;
            let fov = (2.0 * outer_cone_deg.clamp(1.0, 85.0)).to_radians();
            Some(glam::camera::rh::proj::directx::perspective(
                fov,
                1.0,
                (far * 1e-3).max(1e-3),
                far,
            ))
            .map(|p| p * view)
        }
        Light::Point { .. } => None,
    }
}

/// The shadow maps' depth texture: a view of all its layers, and one view per layer.
fn shadow_maps(device: &wgpu::Device) -> (wgpu::TextureView, Vec<wgpu::TextureView>) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("seamlit shadow maps"),
        size: wgpu::Extent3d {
            width: SHADOW_SIZE,
            height: SHADOW_SIZE,
            depth_or_array_layers: MAX_SHADOW_MAPS,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let all = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let layers = (0..MAX_SHADOW_MAPS)
        .map(|layer| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    (all, layers)
}

/// A uniform buffer of `size` bytes, written through the queue.
fn uniform(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn pass_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("seamlit shadow pass"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    })
}

/// The depth-only pipeline, skinning and morphing in its vertex stage where `deform` is true.
fn pipeline(
    ctx: &GpuContext,
    pass_layout: &wgpu::BindGroupLayout,
    deform: bool,
) -> wgpu::RenderPipeline {
    let device = ctx.device();
    let module = crate::shaders::SHADOW.module(device);
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("seamlit shadow"),
        bind_group_layouts: &[Some(pass_layout), Some(&ctx.layouts.object)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("seamlit shadow"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_shadow"),
            compilation_options: crate::pipeline::deform_option(deform),
            buffers: &[Some(VertexRaw::layout())],
        },
        primitive: wgpu::PrimitiveState::default(),
        // Slope-scaled bias against shadow acne on surfaces lit at a grazing angle.
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState { constant: 2, slope_scale: 2.0, clamp: 0.0 },
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}
