//! Image-based lighting: an environment, prefiltered on the GPU when it is loaded, for the
//! split-sum approximation (B. Karis, "Real Shading in Unreal Engine 4", 2013). The shaders
//! are in `src/ibl.wgsl`; the steps are [`GpuEnvironment::new`]'s.

use std::path::Path;

use glam::Vec3;
use image::Rgba32FImage;
use wgpu::util::DeviceExt;

use crate::{GpuContext, RenderError};

/// Face size of the base cube map the environment is resampled into (mip 0).
const BASE_SIZE: u32 = 256;
/// Face size of the specular cube's mip 0 (roughness 0).
const SPECULAR_SIZE: u32 = 128;
/// Mips of the specular cube; mip `m` holds roughness `m / (SPECULAR_MIPS - 1)`.
pub(crate) const SPECULAR_MIPS: u32 = 6;
/// Face size of the irradiance cube.
const IRRADIANCE_SIZE: u32 = 32;
/// Mips of the irradiance cube after its first that hold KHR_materials_sheen's environment
/// (Charlie-prefiltered, as the Khronos glTF Sample Viewer prefilters it): mip `1 + m` for
/// sheen roughness `m / (SHEEN_MIPS - 1)` (`SHEEN_MIPS` in `layers.wgsl`). They share the
/// irradiance's texture because a material's shader stage has no sampled texture left for
/// a cube of their own (see `Layouts::environment`).
pub(crate) const SHEEN_MIPS: u32 = 5;
/// The base cube's mip that the irradiance sums over, texel by texel (16 x 16 per face).
const IRRADIANCE_SOURCE_MIP: u32 = 4;
/// Size of the split-sum BRDF table (n.v across, roughness down).
const LUT_SIZE: u32 = 64;
/// The format of every prefiltered texture.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Where image-based light comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// seamlit's procedural studio: a light grey cyclorama, a darker floor, a large warm key
    /// softbox at the upper front left, a cool strip to the right and a rim light behind.
    /// Needs no file.
    Builtin,
    /// The same radiance (linear RGB) from every direction.
    Uniform(Vec3),
    /// An equirectangular image of linear radiance: longitude across (the centre column
    /// looks toward +Z, a quarter of the width to the right toward -X, the edges toward -Z),
    /// +Y at the top row: as the Khronos glTF Sample Viewer shows it at its default
    /// environment rotation (90 degrees there, 0 here).
    Equirect(Rgba32FImage),
}

impl Environment {
    /// Reads an equirectangular Radiance `.hdr` file.
    ///
    /// # Errors
    ///
    /// [`RenderError::Environment`] naming the file when it cannot be opened or decoded.
    pub fn from_hdr_file(path: &Path) -> Result<Self, RenderError> {
        let error = |reason: String| RenderError::Environment { path: path.to_owned(), reason };
        let file = std::fs::File::open(path).map_err(|e| error(e.to_string()))?;
        let decoder = image::codecs::hdr::HdrDecoder::new(std::io::BufReader::new(file))
            .map_err(|e| error(e.to_string()))?;
        let image = image::DynamicImage::from_decoder(decoder).map_err(|e| error(e.to_string()))?;
        Ok(Self::Equirect(image.into_rgba32f()))
    }
}

/// An environment on the GPU: the specular cube (GGX-prefiltered mips), the irradiance cube
/// (with the sheen's Charlie-prefiltered environment in its smaller mips) and the split-sum
/// BRDF table, bound together for the mesh shader. Give it to
/// [`crate::Renderer::set_environment`]. Cloning shares the textures.
#[derive(Clone, Debug)]
pub struct GpuEnvironment {
    pub(crate) bind_group: wgpu::BindGroup,
}

/// One compute step: its pipeline, and the bind group layout of its entry point.
struct Step {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

/// The textures being built.
struct Targets {
    base: wgpu::Texture,
    specular: wgpu::Texture,
    irradiance: wgpu::Texture,
    lut: wgpu::Texture,
}

impl GpuEnvironment {
    /// Prefilters `environment` on the GPU: resamples it into a cube map with mips, then
    /// prefilters the specular mips (one per roughness), sums the irradiance, prefilters the
    /// sheen's mips and computes the BRDF table.
    ///
    /// # Errors
    ///
    /// [`RenderError::TextureTooLarge`] for an image larger than the device allows,
    /// [`RenderError::Gpu`].
    pub fn new(ctx: &GpuContext, environment: &Environment) -> Result<Self, RenderError> {
        if let Environment::Equirect(image) = environment {
            check_image(ctx, image)?;
        }
        ctx.scoped("prefiltering the environment", || {
            let targets = Targets::new(ctx);
            let module = crate::shaders::IBL.module(ctx.device());
            let mut encoder =
                ctx.device().create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("seamlit environment"),
                });
            let source = source_texture(ctx, environment);
            encode_sky(ctx, &module, &mut encoder, &targets, &source, environment);
            encode_base_mips(ctx, &module, &mut encoder, &targets);
            encode_specular(ctx, &module, &mut encoder, &targets);
            encode_irradiance(ctx, &module, &mut encoder, &targets);
            encode_sheen(ctx, &module, &mut encoder, &targets);
            encode_lut(ctx, &module, &mut encoder, &targets);
            let lut = lut_buffer(ctx);
            encoder.copy_texture_to_buffer(
                targets.lut.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &lut,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(LUT_SIZE * LUT_TEXEL_BYTES),
                        rows_per_image: None,
                    },
                },
                wgpu::Extent3d { width: LUT_SIZE, height: LUT_SIZE, depth_or_array_layers: 1 },
            );
            ctx.queue().submit([encoder.finish()]);
            let bind_group = bind(ctx, &targets.specular, &targets.irradiance, &lut);
            Ok(Self { bind_group })
        })
    }

    /// No environment: black textures, for frames without image-based light.
    pub(crate) fn none(ctx: &GpuContext) -> Self {
        let cube = cube_texture(ctx, "seamlit no environment", 1, 1);
        Self { bind_group: bind(ctx, &cube, &cube, &lut_buffer(ctx)) }
    }
}

fn check_image(ctx: &GpuContext, image: &Rgba32FImage) -> Result<(), RenderError> {
    let (width, height) = image.dimensions();
    let max = ctx.device().limits().max_texture_dimension_2d;
    if width == 0 || height == 0 || width > max || height > max {
        return Err(RenderError::TextureTooLarge {
            name: "the environment".into(),
            width,
            height,
            max,
        });
    }
    Ok(())
}

impl Targets {
    fn new(ctx: &GpuContext) -> Self {
        let base_mips = BASE_SIZE.ilog2() + 1;
        Self {
            base: cube_texture(ctx, "seamlit environment", BASE_SIZE, base_mips),
            specular: cube_texture(ctx, "seamlit specular", SPECULAR_SIZE, SPECULAR_MIPS),
            irradiance: cube_texture(ctx, "seamlit irradiance", IRRADIANCE_SIZE, 1 + SHEEN_MIPS),
            lut: texture_2d(ctx, "seamlit brdf lut", LUT_SIZE),
        }
    }
}

fn cube_texture(ctx: &GpuContext, label: &str, size: u32, mips: u32) -> wgpu::Texture {
    ctx.device().create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 6 },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING,
        view_formats: &[],
    })
}

/// Bytes of one BRDF table texel ([`FORMAT`]: four halves).
const LUT_TEXEL_BYTES: u32 = 8;

/// The BRDF table as the mesh shader reads it: the texture's texels copied into a storage
/// buffer (zeros until a copy fills it).
fn lut_buffer(ctx: &GpuContext) -> wgpu::Buffer {
    ctx.device().create_buffer(&wgpu::BufferDescriptor {
        label: Some("seamlit brdf lut"),
        size: u64::from(LUT_SIZE * LUT_SIZE * LUT_TEXEL_BYTES),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn texture_2d(ctx: &GpuContext, label: &str, size: u32) -> wgpu::Texture {
    ctx.device().create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// A view of a cube texture: all six faces as a cube, or one mip as an array of faces.
fn cube_view(texture: &wgpu::Texture, mip: Option<u32>) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(if mip.is_some() {
            wgpu::TextureViewDimension::D2Array
        } else {
            wgpu::TextureViewDimension::Cube
        }),
        base_mip_level: mip.unwrap_or(0),
        mip_level_count: mip.map(|_| 1),
        ..Default::default()
    })
}

/// The equirectangular image as a float texture (1 x 1 black for the other kinds).
fn source_texture(ctx: &GpuContext, environment: &Environment) -> wgpu::Texture {
    let black = Rgba32FImage::new(1, 1);
    let image = match environment {
        Environment::Equirect(image) => image,
        _ => &black,
    };
    ctx.device().create_texture_with_data(
        ctx.queue(),
        &wgpu::TextureDescriptor {
            label: Some("seamlit environment image"),
            size: wgpu::Extent3d {
                width: image.width(),
                height: image.height(),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(image.as_raw()),
    )
}

/// `Params` in `ibl.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct ParamsRaw {
    pub size: u32,
    pub kind: u32,
    pub roughness: f32,
    pub base_size: f32,
    pub color: [f32; 4],
}

fn step(ctx: &GpuContext, module: &wgpu::ShaderModule, entry: &str) -> Step {
    let pipeline = ctx.device().create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions::default(),
        cache: None,
    });
    let layout = pipeline.get_bind_group_layout(0);
    Step { pipeline, layout }
}

/// Records one dispatch of `step` over `size` x `size` x `layers` texels with `params` and
/// the other `resources` (binding, resource) after the parameters at binding 0.
fn dispatch(
    ctx: &GpuContext,
    encoder: &mut wgpu::CommandEncoder,
    step: &Step,
    params: ParamsRaw,
    resources: &[(u32, wgpu::BindingResource<'_>)],
    layers: u32,
) {
    let uniform = ctx.device().create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("seamlit ibl params"),
        contents: bytemuck::bytes_of(&params),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let mut entries =
        vec![wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() }];
    entries.extend(resources.iter().map(|(binding, resource)| wgpu::BindGroupEntry {
        binding: *binding,
        resource: resource.clone(),
    }));
    let bind_group = ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("seamlit ibl step"),
        layout: &step.layout,
        entries: &entries,
    });
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
    pass.set_pipeline(&step.pipeline);
    pass.set_bind_group(0, &bind_group, &[]);
    let groups = params.size.div_ceil(8);
    pass.dispatch_workgroups(groups, groups, layers);
}

fn params(size: u32) -> ParamsRaw {
    ParamsRaw { size, kind: 0, roughness: 0.0, base_size: BASE_SIZE as f32, color: [0.0; 4] }
}

/// Step 1: the environment resampled into the base cube's mip 0.
fn encode_sky(
    ctx: &GpuContext,
    module: &wgpu::ShaderModule,
    encoder: &mut wgpu::CommandEncoder,
    targets: &Targets,
    source: &wgpu::Texture,
    environment: &Environment,
) {
    let (kind, color) = match environment {
        Environment::Equirect(_) => (0, [0.0; 4]),
        Environment::Builtin => (1, [0.0; 4]),
        Environment::Uniform(c) => (2, c.extend(1.0).to_array()),
    };
    let source_view = source.create_view(&wgpu::TextureViewDescriptor::default());
    let out = cube_view(&targets.base, Some(0));
    dispatch(
        ctx,
        encoder,
        &step(ctx, module, "cs_sky"),
        ParamsRaw { kind, color, ..params(BASE_SIZE) },
        &[
            (1, wgpu::BindingResource::TextureView(&source_view)),
            (2, wgpu::BindingResource::TextureView(&out)),
        ],
        6,
    );
}

/// Step 2: the base cube's mips, each the 2x2 average of the one above.
fn encode_base_mips(
    ctx: &GpuContext,
    module: &wgpu::ShaderModule,
    encoder: &mut wgpu::CommandEncoder,
    targets: &Targets,
) {
    let downsample = step(ctx, module, "cs_downsample");
    for mip in 1..targets.base.mip_level_count() {
        let src = cube_view(&targets.base, Some(mip - 1));
        let dst = cube_view(&targets.base, Some(mip));
        dispatch(
            ctx,
            encoder,
            &downsample,
            params((BASE_SIZE >> mip).max(1)),
            &[
                (3, wgpu::BindingResource::TextureView(&src)),
                (4, wgpu::BindingResource::TextureView(&dst)),
            ],
            6,
        );
    }
}

/// Step 3: the specular cube, mip `m` prefiltered for roughness `m / (mips - 1)`.
fn encode_specular(
    ctx: &GpuContext,
    module: &wgpu::ShaderModule,
    encoder: &mut wgpu::CommandEncoder,
    targets: &Targets,
) {
    let specular = step(ctx, module, "cs_specular");
    let base = cube_view(&targets.base, None);
    let sampler = trilinear(ctx);
    for mip in 0..SPECULAR_MIPS {
        let out = cube_view(&targets.specular, Some(mip));
        let roughness = mip as f32 / (SPECULAR_MIPS - 1) as f32;
        dispatch(
            ctx,
            encoder,
            &specular,
            ParamsRaw { roughness, ..params(SPECULAR_SIZE >> mip) },
            &[
                (5, wgpu::BindingResource::TextureView(&base)),
                (6, wgpu::BindingResource::Sampler(&sampler)),
                (7, wgpu::BindingResource::TextureView(&out)),
            ],
            6,
        );
    }
}

/// A clamping trilinear sampler for the prefilters' reads of the base cube.
fn trilinear(ctx: &GpuContext) -> wgpu::Sampler {
    ctx.device().create_sampler(&wgpu::SamplerDescriptor {
        label: Some("seamlit ibl"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    })
}

/// Step 4: the irradiance cube, summed over every texel of a small mip of the base cube.
fn encode_irradiance(
    ctx: &GpuContext,
    module: &wgpu::ShaderModule,
    encoder: &mut wgpu::CommandEncoder,
    targets: &Targets,
) {
    let src = cube_view(&targets.base, Some(IRRADIANCE_SOURCE_MIP));
    let out = cube_view(&targets.irradiance, Some(0));
    dispatch(
        ctx,
        encoder,
        &step(ctx, module, "cs_irradiance"),
        params(IRRADIANCE_SIZE),
        &[
            (3, wgpu::BindingResource::TextureView(&src)),
            (4, wgpu::BindingResource::TextureView(&out)),
        ],
        6,
    );
}

/// Step 5: KHR_materials_sheen's environment in the irradiance cube's mips `1 + m`, each
/// Charlie-prefiltered for sheen roughness `m / (SHEEN_MIPS - 1)` from the whole base cube.
fn encode_sheen(
    ctx: &GpuContext,
    module: &wgpu::ShaderModule,
    encoder: &mut wgpu::CommandEncoder,
    targets: &Targets,
) {
    let sheen = step(ctx, module, "cs_sheen");
    let base = cube_view(&targets.base, None);
    let sampler = trilinear(ctx);
    for m in 0..SHEEN_MIPS {
        let out = cube_view(&targets.irradiance, Some(1 + m));
        let roughness = m as f32 / (SHEEN_MIPS - 1) as f32;
        dispatch(
            ctx,
            encoder,
            &sheen,
            ParamsRaw { roughness, ..params((IRRADIANCE_SIZE >> (1 + m)).max(1)) },
            &[
                (5, wgpu::BindingResource::TextureView(&base)),
                (6, wgpu::BindingResource::Sampler(&sampler)),
                (7, wgpu::BindingResource::TextureView(&out)),
            ],
            6,
        );
    }
}

/// Step 6: the split-sum BRDF table.
fn encode_lut(
    ctx: &GpuContext,
    module: &wgpu::ShaderModule,
    encoder: &mut wgpu::CommandEncoder,
    targets: &Targets,
) {
    let out = targets.lut.create_view(&wgpu::TextureViewDescriptor::default());
    dispatch(
        ctx,
        encoder,
        &step(ctx, module, "cs_brdf_lut"),
        params(LUT_SIZE),
        &[(8, wgpu::BindingResource::TextureView(&out))],
        1,
    );
}

/// The bind group the mesh shader reads (group 3): specular cube, irradiance cube, BRDF
/// table, and a clamping trilinear sampler.
fn bind(
    ctx: &GpuContext,
    specular: &wgpu::Texture,
    irradiance: &wgpu::Texture,
    lut: &wgpu::Buffer,
) -> wgpu::BindGroup {
    let specular = cube_view(specular, None);
    let irradiance = cube_view(irradiance, None);
    let sampler = ctx.device().create_sampler(&wgpu::SamplerDescriptor {
        label: Some("seamlit environment"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    });
    ctx.device().create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("seamlit environment"),
        layout: &ctx.layouts.environment,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&specular),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&irradiance),
            },
            wgpu::BindGroupEntry { binding: 2, resource: lut.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::Sampler(&sampler) },
        ],
    })
}
