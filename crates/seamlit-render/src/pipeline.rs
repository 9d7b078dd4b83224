//! The render pipelines: meshes in eight variants (front faces counter-clockwise or clockwise,
//! culled or double-sided, opaque or alpha-blended), the environment behind them and the TBN
//! lines.

use crate::GpuContext;
use crate::scene::VertexRaw;

/// The depth buffer's format.
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// All pipelines for one target format and sample count.
#[derive(Debug)]
pub(crate) struct Pipelines {
    /// Indexed by [`Pipelines::mesh_index`].
    mesh: [wgpu::RenderPipeline; 8],
    pub tbn: wgpu::RenderPipeline,
    /// The environment, blurred, behind everything.
    pub sky: wgpu::RenderPipeline,
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
                Some(&layouts.environment),
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
        let blended = [Some(wgpu::ColorTargetState {
            format,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let mesh_pipeline = |index: usize| {
            let (front_face, cull, blend) = Self::variant(index);
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
                // Blended surfaces are tested against the depth of opaque ones but do not hide
                // what lies behind them.
                depth_stencil: Some(wgpu::DepthStencilState {
                    depth_write_enabled: Some(!blend),
                    ..depth()
                }),
                multisample,
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: if blend { &blended } else { &targets },
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let mesh = std::array::from_fn(mesh_pipeline);
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
        let sky = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("seamlit sky"),
            layout: Some(&mesh_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_sky"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            // Drawn first, everywhere, leaving the depth buffer cleared for the meshes.
            depth_stencil: Some(wgpu::DepthStencilState {
                depth_write_enabled: Some(false),
                depth_compare: Some(wgpu::CompareFunction::Always),
                ..depth()
            }),
            multisample,
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_sky"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        });
        Self { mesh, tbn, sky }
    }

    /// Front face, whether back faces are culled and whether colour is blended, for a
    /// variant index.
    fn variant(index: usize) -> (wgpu::FrontFace, bool, bool) {
        let front = if index & 1 == 0 { wgpu::FrontFace::Ccw } else { wgpu::FrontFace::Cw };
        (front, index & 2 == 0, index & 4 != 0)
    }

    /// The mesh pipeline for an object: a transform with a negative determinant turns
    /// counter-clockwise triangles clockwise on screen; double-sided materials are not culled;
    /// alphaMode BLEND materials blend by alpha and leave the depth buffer alone.
    pub(crate) fn mesh(
        &self,
        mirrored: bool,
        double_sided: bool,
        blend: bool,
    ) -> &wgpu::RenderPipeline {
        &self.mesh
            [usize::from(mirrored) | (usize::from(double_sided) << 1) | (usize::from(blend) << 2)]
    }
}
