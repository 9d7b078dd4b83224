//! The render pipelines: meshes in 32 variants (front faces counter-clockwise or clockwise,
//! culled or double-sided, opaque or alpha-blended; without or with skinning and morphing in
//! the vertex stage; without or with the PBR extensions' layers in the fragment stage), the
//! environment behind them and the TBN lines. Each is made on first use: a driver compiles
//! the whole shader for every pipeline (lavapipe about 0.2 s each), and a scene uses few.

use crate::GpuContext;
use crate::scene::VertexRaw;

/// The depth buffer's format.
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The pipelines for one target format and sample count, made by the `prepare` methods
/// before a pass draws with them.
#[derive(Debug)]
pub(crate) struct Pipelines {
    /// Indexed by [`MeshKey::index`].
    mesh: [Option<wgpu::RenderPipeline>; MeshKey::COUNT],
    tbn: Option<wgpu::RenderPipeline>,
    /// The environment, blurred, behind everything.
    sky: Option<wgpu::RenderPipeline>,
    /// What making a pipeline needs.
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    multisample: wgpu::MultisampleState,
}

/// Which mesh pipeline an object draws with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct MeshKey {
    pub features: Features,
    /// A transform with a negative determinant: counter-clockwise triangles turn clockwise
    /// on screen.
    pub mirrored: bool,
    /// Not culled.
    pub double_sided: bool,
    /// alphaMode BLEND: blended by alpha, the depth buffer left alone.
    pub blend: bool,
}

impl MeshKey {
    const COUNT: usize = 32;

    /// A distinct index under [`MeshKey::COUNT`] for each key.
    fn index(self) -> usize {
        usize::from(self.mirrored)
            | usize::from(self.double_sided) << 1
            | usize::from(self.blend) << 2
            | self.features.index() << 3
    }
}

impl Pipelines {
    pub(crate) fn new(ctx: &GpuContext, format: wgpu::TextureFormat, sample_count: u32) -> Self {
        let device = ctx.device();
        Self {
            mesh: std::array::from_fn(|_| None),
            tbn: None,
            sky: None,
            module: crate::shaders::mesh(ctx.layouts.extension_textures).module(device),
            layout: mesh_layout(ctx),
            format,
            multisample: wgpu::MultisampleState {
                count: sample_count,
                mask: !0,
                alpha_to_coverage_enabled: false,
            },
        }
    }

    fn shared<'a>(&'a self, device: &'a wgpu::Device) -> Shared<'a> {
        Shared {
            device,
            module: &self.module,
            layout: &self.layout,
            format: self.format,
            multisample: self.multisample,
        }
    }

    /// Makes the mesh pipeline of `key` if it is not made yet.
    pub(crate) fn prepare_mesh(&mut self, device: &wgpu::Device, key: MeshKey) {
        if self.mesh[key.index()].is_none() {
            let vertices = [Some(VertexRaw::layout())];
            let pipeline = self.shared(device).create(&mesh_pipeline(key, &vertices));
            self.mesh[key.index()] = Some(pipeline);
        }
    }

    /// Makes the TBN lines' pipeline if it is not made yet.
    pub(crate) fn prepare_tbn(&mut self, device: &wgpu::Device) {
        if self.tbn.is_none() {
            self.tbn = Some(self.shared(device).create(&tbn_pipeline()));
        }
    }

    /// Makes the sky's pipeline if it is not made yet.
    pub(crate) fn prepare_sky(&mut self, device: &wgpu::Device) {
        if self.sky.is_none() {
            self.sky = Some(self.shared(device).create(&sky_pipeline()));
        }
    }

    /// The mesh pipeline of `key`.
    ///
    /// # Panics
    ///
    /// If [`Pipelines::prepare_mesh`] has not made it: the renderer prepares every key
    /// before the pass that draws with it.
    pub(crate) fn mesh(&self, key: MeshKey) -> &wgpu::RenderPipeline {
        self.mesh[key.index()].as_ref().expect("mesh pipeline prepared before the pass")
    }

    /// The TBN lines' pipeline.
    ///
    /// # Panics
    ///
    /// If [`Pipelines::prepare_tbn`] has not made it.
    pub(crate) fn tbn(&self) -> &wgpu::RenderPipeline {
        self.tbn.as_ref().expect("TBN pipeline prepared before the pass")
    }

    /// The sky's pipeline.
    ///
    /// # Panics
    ///
    /// If [`Pipelines::prepare_sky`] has not made it.
    pub(crate) fn sky(&self) -> &wgpu::RenderPipeline {
        self.sky.as_ref().expect("sky pipeline prepared before the pass")
    }

    /// How many mesh pipelines are made.
    #[cfg(test)]
    pub(crate) fn made(&self) -> usize {
        self.mesh.iter().flatten().count()
    }

    /// Whether the TBN lines' pipeline is made.
    #[cfg(test)]
    pub(crate) fn made_tbn(&self) -> bool {
        self.tbn.is_some()
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

/// The mesh pipeline of `key`, reading `vertices`.
fn mesh_pipeline<'a>(
    key: MeshKey,
    vertices: &'a [Option<wgpu::VertexBufferLayout<'a>>],
) -> PipelineDescriptor<'a> {
    let MeshKey { features, mirrored, double_sided, blend } = key;
    let front_face = if mirrored { wgpu::FrontFace::Cw } else { wgpu::FrontFace::Ccw };
    PipelineDescriptor {
        label: "seamlit mesh",
        vertex: "vs_main",
        fragment: "fs_main",
        buffers: vertices,
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face,
            cull_mode: (!double_sided).then_some(wgpu::Face::Back),
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
