//! The render pipelines: meshes in eight variants (front faces counter-clockwise or clockwise,
//! culled or double-sided, opaque or alpha-blended), each without and (made on first use)
//! with skinning and morphing in the vertex stage, and without and (made on first use) with
//! the PBR extensions' layers in the fragment stage; the environment behind them and the TBN
//! lines.

use crate::GpuContext;
use crate::scene::VertexRaw;

/// The depth buffer's format.
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// All pipelines for one target format and sample count.
#[derive(Debug)]
pub(crate) struct Pipelines {
    /// Indexed by [`Pipelines::mesh`]'s variant, `deform.wgsl`'s `DEFORM` false and
    /// `mesh.wgsl`'s `LAYERS` false: for objects without a pose whose materials use no PBR
    /// extension.
    mesh: [wgpu::RenderPipeline; 8],
    /// The same with `DEFORM` true (posed objects), `LAYERS` true (materials with layers), or
    /// both, indexed by [`Features::index`] less one; each made by [`Pipelines::prepare`].
    more: [Option<[wgpu::RenderPipeline; 8]>; 3],
    /// What making the posed variants needs.
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    multisample: wgpu::MultisampleState,
    pub tbn: wgpu::RenderPipeline,
    /// The environment, blurred, behind everything.
    pub sky: wgpu::RenderPipeline,
}

impl Pipelines {
    pub(crate) fn new(ctx: &GpuContext, format: wgpu::TextureFormat, sample_count: u32) -> Self {
        let device = ctx.device();
        let module = crate::shaders::mesh(ctx.layouts.extension_textures).module(device);
        let layout = mesh_layout(ctx);
        let multisample = wgpu::MultisampleState {
            count: sample_count,
            mask: !0,
            alpha_to_coverage_enabled: false,
        };
        let shared = Shared { device, module: &module, layout: &layout, format, multisample };
        let vertices = [Some(VertexRaw::layout())];
        let mesh = std::array::from_fn(|index| {
            shared.create(&mesh_pipeline(index, &vertices, Features::default()))
        });
        let (tbn, sky) = (shared.create(&tbn_pipeline()), shared.create(&sky_pipeline()));
        Self { mesh, more: [None, None, None], module, layout, format, multisample, tbn, sky }
    }

    /// Makes the mesh pipelines of `features` if they are not made yet.
    pub(crate) fn prepare(&mut self, device: &wgpu::Device, features: Features) {
        let Some(slot) = features.index().checked_sub(1) else { return };
        if self.more[slot].is_some() {
            return;
        }
        let shared = Shared {
            device,
            module: &self.module,
            layout: &self.layout,
            format: self.format,
            multisample: self.multisample,
        };
        let vertices = [Some(VertexRaw::layout())];
        self.more[slot] = Some(std::array::from_fn(|index| {
            shared.create(&mesh_pipeline(index, &vertices, features))
        }));
    }

    /// Front face, whether back faces are culled and whether colour is blended, for a
    /// variant index.
    fn variant(index: usize) -> (wgpu::FrontFace, bool, bool) {
        let front = if index & 1 == 0 { wgpu::FrontFace::Ccw } else { wgpu::FrontFace::Cw };
        (front, index & 2 == 0, index & 4 != 0)
    }

    /// The mesh pipeline for an object: a posed object's skins and morphs in the vertex stage,
    /// a material's PBR extensions in the fragment stage (once [`Pipelines::prepare`] has made
    /// those variants; before, the plain ones); a transform with a negative determinant turns
    /// counter-clockwise triangles clockwise on screen; double-sided materials are not culled;
    /// alphaMode BLEND materials blend by alpha and leave the depth buffer alone.
    pub(crate) fn mesh(
        &self,
        features: Features,
        mirrored: bool,
        double_sided: bool,
        blend: bool,
    ) -> &wgpu::RenderPipeline {
        let set = features
            .index()
            .checked_sub(1)
            .and_then(|slot| self.more[slot].as_ref())
            .unwrap_or(&self.mesh);
        &set[usize::from(mirrored) | (usize::from(double_sided) << 1) | (usize::from(blend) << 2)]
    }
}

/// What a mesh pipeline compiles in besides the metallic-roughness and lighting-model shading.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Features {
    /// Skinning and morphing in the vertex stage (`deform.wgsl`'s `DEFORM`).
    pub deform: bool,
    /// The PBR extensions' layers in the fragment stage (`mesh.wgsl`'s `LAYERS`).
    pub layers: bool,
}

impl Features {
    /// 0 for none, 1 deform, 2 layers, 3 both.
    fn index(self) -> usize {
        usize::from(self.deform) | (usize::from(self.layers) << 1)
    }
}

/// The layout of every pipeline: frame, material, object and environment groups.
fn mesh_layout(ctx: &GpuContext) -> wgpu::PipelineLayout {
    let layouts = &ctx.layouts;
    ctx.device().create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("seamlit mesh"),
        bind_group_layouts: &[
            Some(&layouts.frame),
            Some(&layouts.material),
            Some(&layouts.object),
            Some(&layouts.environment),
        ],
        immediate_size: 0,
    })
}

/// What every pipeline of one [`Pipelines`] shares: the shader module (`mesh.wgsl`), the
/// layout, the target's format and the multisampling.
struct Shared<'a> {
    device: &'a wgpu::Device,
    module: &'a wgpu::ShaderModule,
    layout: &'a wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    multisample: wgpu::MultisampleState,
}

/// What differs between the pipelines.
struct PipelineDescriptor<'a> {
    label: &'a str,
    /// The vertex shader's entry point in `mesh.wgsl`.
    vertex: &'a str,
    /// The fragment shader's entry point in `mesh.wgsl`.
    fragment: &'a str,
    /// The vertex buffers read (none: the shader reads storage or makes its own vertices).
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    primitive: wgpu::PrimitiveState,
    depth_stencil: wgpu::DepthStencilState,
    /// How colour is blended into the target (`None`: replaced).
    blend: Option<wgpu::BlendState>,
    /// `deform.wgsl`'s `DEFORM` in the vertex stage and `mesh.wgsl`'s `LAYERS` in the
    /// fragment stage.
    features: Features,
}

impl Shared<'_> {
    fn create(&self, desc: &PipelineDescriptor<'_>) -> wgpu::RenderPipeline {
        self.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(desc.label),
            layout: Some(self.layout),
            vertex: wgpu::VertexState {
                module: self.module,
                entry_point: Some(desc.vertex),
                compilation_options: deform_option(desc.features.deform),
                buffers: desc.buffers,
            },
            primitive: desc.primitive,
            depth_stencil: Some(desc.depth_stencil.clone()),
            multisample: self.multisample,
            fragment: Some(wgpu::FragmentState {
                module: self.module,
                entry_point: Some(desc.fragment),
                compilation_options: layers_option(desc.features.layers),
                targets: &[Some(wgpu::ColorTargetState {
                    format: self.format,
                    blend: desc.blend,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// The vertex stage's options: `DEFORM` false where `deform` is (the shader's default is
/// true).
pub(crate) fn deform_option(deform: bool) -> wgpu::PipelineCompilationOptions<'static> {
    const OFF: &[(&str, f64)] = &[("DEFORM", 0.0)];
    wgpu::PipelineCompilationOptions {
        constants: if deform { &[] } else { OFF },
        ..wgpu::PipelineCompilationOptions::default()
    }
}

/// The fragment stage's options: `LAYERS` false where `layers` is (the shader's default is
/// true).
fn layers_option(layers: bool) -> wgpu::PipelineCompilationOptions<'static> {
    const OFF: &[(&str, f64)] = &[("LAYERS", 0.0)];
    wgpu::PipelineCompilationOptions {
        constants: if layers { &[] } else { OFF },
        ..wgpu::PipelineCompilationOptions::default()
    }
}

/// Depth tested (less) and written.
fn depth() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: wgpu::StencilState::default(),
        bias: wgpu::DepthBiasState::default(),
    }
}

/// The mesh pipeline of a variant index (see [`Pipelines::mesh`]), reading `vertices`, with
/// `features` compiled in.
fn mesh_pipeline<'a>(
    index: usize,
    vertices: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    features: Features,
) -> PipelineDescriptor<'a> {
    let (front_face, cull, blend) = Pipelines::variant(index);
    PipelineDescriptor {
        label: "seamlit mesh",
        vertex: "vs_main",
        fragment: "fs_main",
        buffers: vertices,
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face,
            cull_mode: cull.then_some(wgpu::Face::Back),
            ..Default::default()
        },
        // Blended surfaces are tested against the depth of opaque ones but do not hide what
        // lies behind them.
        depth_stencil: wgpu::DepthStencilState { depth_write_enabled: Some(!blend), ..depth() },
        blend: blend.then_some(wgpu::BlendState::ALPHA_BLENDING),
        features,
    }
}

/// The TBN lines. They use the mesh layout, material group included though the lines do not
/// read it: a gap in the layout (None) misplaced the object group on lavapipe.
fn tbn_pipeline() -> PipelineDescriptor<'static> {
    PipelineDescriptor {
        label: "seamlit tbn lines",
        vertex: "vs_tbn",
        fragment: "fs_tbn",
        buffers: &[],
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::LineList,
            ..Default::default()
        },
        depth_stencil: wgpu::DepthStencilState {
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            ..depth()
        },
        blend: None,
        features: Features { deform: true, layers: false },
    }
}

/// The environment behind everything: drawn first, everywhere, leaving the depth buffer
/// cleared for the meshes.
fn sky_pipeline() -> PipelineDescriptor<'static> {
    PipelineDescriptor {
        label: "seamlit sky",
        vertex: "vs_sky",
        fragment: "fs_sky",
        buffers: &[],
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: wgpu::DepthStencilState {
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Always),
            ..depth()
        },
        blend: None,
        features: Features::default(),
    }
}
