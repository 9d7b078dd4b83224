//! The render pipelines: meshes in four variants (front faces counter-clockwise or clockwise,
//! culled or double-sided) and the TBN lines.

use crate::GpuContext;
use crate::scene::VertexRaw;

/// The depth buffer's format.
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// All pipelines for one target format and sample count.
#[derive(Debug)]
pub(crate) struct Pipelines {
    /// Indexed by [`Pipelines::mesh_index`].
    mesh: [wgpu::RenderPipeline; 4],
    pub tbn: wgpu::RenderPipeline,
}

impl Pipelines {
    pub(crate) fn new(ctx: &GpuContext, format: wgpu::TextureFormat, sample_count: u32) -> Self {
        let device = ctx.device();
        let module = device.create_shader_module(wgpu::include_wgsl!("mesh.wgsl"));
        let layouts = &ctx.layouts;
        let mesh_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("seamlit mesh"),
            bind_group_layouts: &[
                Some(&layouts.frame),
                Some(&layouts.material),
                Some(&layouts.object),
            ],
            immediate_size: 0,
        });
        let depth = || wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        };
        let multisample = wgpu::MultisampleState {
            count: sample_count,
            mask: !0,
            alpha_to_coverage_enabled: false,
        };
        let targets = [Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let mesh_pipeline = |index: usize| {
            let (front_face, cull) = Self::variant(index);
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("seamlit mesh"),
                layout: Some(&mesh_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers: &[Some(VertexRaw::layout())],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face,
                    cull_mode: cull.then_some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: Some(depth()),
                multisample,
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let mesh = [mesh_pipeline(0), mesh_pipeline(1), mesh_pipeline(2), mesh_pipeline(3)];
        let tbn = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("seamlit tbn lines"),
            // The mesh layout, material group included though the lines do not read it: a gap
            // in the layout (None) misplaced the object group on lavapipe.
            layout: Some(&mesh_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_tbn"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::LineList,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                ..depth()
            }),
            multisample,
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_tbn"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        });
        Self { mesh, tbn }
    }

    /// Front face and whether back faces are culled, for a variant index.
    fn variant(index: usize) -> (wgpu::FrontFace, bool) {
        let front = if index & 1 == 0 { wgpu::FrontFace::Ccw } else { wgpu::FrontFace::Cw };
        (front, index & 2 == 0)
    }

    /// The mesh pipeline for an object: a transform with a negative determinant turns
    /// counter-clockwise triangles clockwise on screen; double-sided materials are not culled.
    pub(crate) fn mesh(&self, mirrored: bool, double_sided: bool) -> &wgpu::RenderPipeline {
        &self.mesh[usize::from(mirrored) | (usize::from(double_sided) << 1)]
    }
}
