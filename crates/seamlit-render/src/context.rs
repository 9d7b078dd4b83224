//! The GPU context: instance, adapter, device and queue, headless or for a window surface,
//! plus the bind group layouts that [`crate::GpuScene`] and [`crate::Renderer`] share.

use wgpu::ShaderStages as S;

use crate::RenderError;

/// Where the renderer runs: a wgpu device and queue (and the adapter they came from).
///
/// Create one with [`GpuContext::headless`] for offscreen rendering, or
/// [`GpuContext::for_surface`] for a window; a viewer that also draws with egui-wgpu uses
/// [`GpuContext::device`] and [`GpuContext::queue`] for its own renderer, so both share one
/// device.
pub struct GpuContext {
    instance: wgpu::Instance,
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    pub(crate) layouts: Layouts,
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuContext")
            .field("adapter", &self.adapter.get_info())
            .finish_non_exhaustive()
    }
}

/// The backends tried first: the native APIs. GL is the fallback.
const PRIMARY: wgpu::Backends = wgpu::Backends::PRIMARY;

impl GpuContext {
    /// A context without a window: picks a Vulkan, Metal or DX12 adapter (a real GPU if there
    /// is one, else a software one such as Mesa's lavapipe) and falls back to GL.
    ///
    /// The environment variable `WGPU_BACKEND` (e.g. `gl`, `vulkan`) restricts the choice.
    ///
    /// # Errors
    ///
    /// [`RenderError::NoAdapter`] when no adapter exists (the message says what to install),
    /// [`RenderError::RequestDevice`] when the adapter will not open a device.
    pub fn headless() -> Result<Self, RenderError> {
        Self::headless_with(wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all()))
    }

    /// As [`GpuContext::headless`], choosing only among `backends` (native ones first, then
    /// GL), for a `--backend` option.
    ///
    /// # Errors
    ///
    /// As [`GpuContext::headless`].
    pub fn headless_with(backends: wgpu::Backends) -> Result<Self, RenderError> {
        let mut tried = Vec::new();
        for backends in [backends & PRIMARY, backends & wgpu::Backends::GL] {
            if backends.is_empty() {
                continue;
            }
            tried.push(format!("{backends:?}"));
            let instance = Self::instance_for(backends);
            let options = wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                ..Default::default()
            };
            if let Ok(adapter) = pollster::block_on(instance.request_adapter(&options)) {
                return Self::from_adapter(instance, adapter);
            }
        }
        Err(RenderError::NoAdapter { tried: tried.join(", then ") })
    }

    /// A wgpu instance with every backend enabled (honouring `WGPU_BACKEND`), for a viewer to
    /// create its window surface with before calling [`GpuContext::for_surface`].
    #[must_use]
    pub fn new_instance() -> wgpu::Instance {
        let backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all());
        Self::instance_for(backends)
    }

    fn instance_for(backends: wgpu::Backends) -> wgpu::Instance {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        desc.backends = backends;
        wgpu::Instance::new(desc)
    }

    /// A context whose adapter can present to `surface` (created from `instance`, usually
    /// one from [`GpuContext::new_instance`]).
    ///
    /// # Errors
    ///
    /// As [`GpuContext::headless`].
    pub fn for_surface(
        instance: wgpu::Instance,
        surface: &wgpu::Surface<'_>,
    ) -> Result<Self, RenderError> {
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: Some(surface),
            ..Default::default()
        };
        let adapter = pollster::block_on(instance.request_adapter(&options)).map_err(|_| {
            RenderError::NoAdapter { tried: "adapters compatible with the window".into() }
        })?;
        Self::from_adapter(instance, adapter)
    }

    /// Opens a device on `adapter` with the features and limits the renderer uses.
    ///
    /// # Errors
    ///
    /// [`RenderError::RequestDevice`] when the adapter refuses.
    pub fn from_adapter(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
    ) -> Result<Self, RenderError> {
        // The adapter's own limits: big textures and buffers for million-triangle models, and
        // as many sampled textures as it allows (the PBR extensions' textures need 21).
        let limits = adapter.limits();
        Self::from_adapter_with_limits(instance, adapter, limits)
    }

    /// As [`GpuContext::from_adapter`], asking for `limits` (at most the adapter's) instead of
    /// all the adapter allows: a device with fewer than 21 sampled textures a shader stage
    /// (WebGPU's default is 16) draws the PBR extensions' factors without the textures of
    /// transmission, volume, iridescence and anisotropy
    /// ([`GpuContext::draws_all_extension_textures`]).
    ///
    /// # Errors
    ///
    /// [`RenderError::RequestDevice`] when the adapter refuses.
    pub fn from_adapter_with_limits(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
        limits: wgpu::Limits,
    ) -> Result<Self, RenderError> {
        pollster::block_on(Self::open(instance, adapter, limits))
    }

    /// As [`GpuContext::from_adapter_with_limits`], awaiting the device instead of blocking:
    /// the only way to open one in a web page (WebGPU), where nothing may block.
    ///
    /// # Errors
    ///
    /// [`RenderError::RequestDevice`] when the adapter refuses.
    pub async fn open(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
        limits: wgpu::Limits,
    ) -> Result<Self, RenderError> {
        let info = adapter.get_info();
        let desc = wgpu::DeviceDescriptor {
            label: Some("seamlit"),
            required_features: wgpu::Features::empty(),
            required_limits: limits,
            ..Default::default()
        };
        let (device, queue) =
            adapter.request_device(&desc).await.map_err(|source| RenderError::RequestDevice {
                adapter: format!("{} ({:?})", info.name, info.backend),
                source,
            })?;
        let layouts = Layouts::new(&device);
        Ok(Self { instance, adapter, device, queue, layouts })
    }

    /// Whether materials' transmission, thickness, iridescence, iridescence thickness and
    /// anisotropy textures are drawn: the device allows the 21 sampled textures a fragment
    /// stage they take (without them, 16, WebGPU's least, are enough: those materials are drawn
    /// by their factors).
    #[must_use]
    pub fn draws_all_extension_textures(&self) -> bool {
        self.layouts.extension_textures
    }

    /// The wgpu instance.
    #[must_use]
    pub fn instance(&self) -> &wgpu::Instance {
        &self.instance
    }

    /// The adapter the device was opened on.
    #[must_use]
    pub fn adapter(&self) -> &wgpu::Adapter {
        &self.adapter
    }

    /// The device: create surfaces' configurations and egui-wgpu renderers with it.
    #[must_use]
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue.
    #[must_use]
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// A one-line description of the adapter, e.g. `llvmpipe (LLVM 19.1.7, 256 bits) (Vulkan, Cpu)`.
    #[must_use]
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
    }

    /// The MSAA sample counts `format` supports as a render target on this adapter.
    #[must_use]
    pub fn supported_sample_counts(&self, format: wgpu::TextureFormat) -> Vec<u32> {
        let flags = self.adapter.get_texture_format_features(format).flags;
        [1, 2, 4, 8, 16]
            .into_iter()
            .filter(|&n| n == 1 || flags.sample_count_supported(n))
            .collect()
    }

    /// Runs `f` inside a validation error scope and turns a captured error into
    /// [`RenderError::Gpu`].
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn scoped<T>(
        &self,
        during: &'static str,
        f: impl FnOnce() -> Result<T, RenderError>,
    ) -> Result<T, RenderError> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let result = f();
        let validation = pollster::block_on(validation.pop());
        let oom = pollster::block_on(oom.pop());
        if let Some(error) = validation.or(oom) {
            return Err(RenderError::Gpu { during, message: error.to_string() });
        }
        result
    }

    /// In a web page nothing may block on the GPU, so errors are not scoped: WebGPU reports
    /// them to the device's uncaptured-error handler (the browser's console).
    #[cfg(target_arch = "wasm32")]
    pub(crate) fn scoped<T>(
        &self,
        _during: &'static str,
        f: impl FnOnce() -> Result<T, RenderError>,
    ) -> Result<T, RenderError> {
        f()
    }
}

/// Bind group layouts shared by the scene (which creates bind groups) and the renderer (whose
/// pipelines use them).
#[derive(Debug)]
pub(crate) struct Layouts {
    /// Group 0: frame uniforms, the light storage buffer, the shadow maps, their comparison
    /// sampler and their matrices, and the transmission target.
    pub frame: wgpu::BindGroupLayout,
    /// Group 1: material uniforms, base colour and normal textures, sampler, then the
    /// metallic-roughness, occlusion and emissive textures, the PBR extensions' textures
    /// and the sheen albedo table; where `extension_textures`, then the textures of
    /// transmission, volume, iridescence and anisotropy.
    pub material: wgpu::BindGroupLayout,
    /// Whether group 1 has the textures of transmission, volume, iridescence and anisotropy
    /// (bindings 15 to 19): the device allows [`SAMPLED_TEXTURES_WITH_EXTENSIONS`] sampled
    /// textures a shader stage. The scene pass's shader is chosen to match
    /// (`shaders::mesh`).
    pub extension_textures: bool,
    /// Group 2: object uniforms, the object's vertices (read as storage for TBN lines and
    /// the posed-vertex readback), its skin influences and morph target deltas, and its
    /// pose's joint palette and morph weights (`deform.wgsl`).
    pub object: wgpu::BindGroupLayout,
    /// Group 3: the environment's specular and irradiance cubes, BRDF table (a storage
    /// buffer) and sampler.
    pub environment: wgpu::BindGroupLayout,
}

/// The sampled textures the scene pass's fragment stage reads with every extension texture
/// bound: 2 in group 0 (shadow maps, transmission target), 17 in group 1, 2 in group 3.
pub(crate) const SAMPLED_TEXTURES_WITH_EXTENSIONS: u32 = 21;

impl Layouts {
    fn new(device: &wgpu::Device) -> Self {
        let extension_textures = device.limits().max_sampled_textures_per_shader_stage
            >= SAMPLED_TEXTURES_WITH_EXTENSIONS;
        Self {
            frame: frame_layout(device),
            material: material_layout(device, extension_textures),
            extension_textures,
            object: object_layout(device),
            environment: environment_layout(device),
        }
    }
}

/// Group 0: see [`Layouts::frame`].
fn frame_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("seamlit frame"),
        entries: &[
            buffer(0, S::VERTEX_FRAGMENT, wgpu::BufferBindingType::Uniform),
            buffer(1, S::VERTEX_FRAGMENT, STORAGE),
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: S::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
                count: None,
            },
            sampler(3, wgpu::SamplerBindingType::Comparison),
            buffer(4, S::FRAGMENT, wgpu::BufferBindingType::Uniform),
            // KHR_materials_transmission's view of the scene behind (transmission.rs).
            texture(5, D2),
        ],
    })
}

/// Group 1: see [`Layouts::material`].
fn material_layout(device: &wgpu::Device, extension_textures: bool) -> wgpu::BindGroupLayout {
    let mut entries = vec![
        buffer(0, S::VERTEX_FRAGMENT, wgpu::BufferBindingType::Uniform),
        texture(1, D2),
        texture(2, D2),
        sampler(3, wgpu::SamplerBindingType::Filtering),
        texture(4, D2),
        texture(5, D2),
        texture(6, D2),
        // The PBR extensions' textures (specular, specular colour, clearcoat, clearcoat
        // roughness, clearcoat normal, sheen colour, sheen roughness), and the sheen's
        // albedo table (a storage buffer: with it, the scene pass needs no more than the
        // 16 sampled textures a stage that WebGPU guarantees, the extension textures
        // below aside).
        texture(7, D2),
        texture(8, D2),
        texture(9, D2),
        texture(10, D2),
        texture(11, D2),
        texture(12, D2),
        texture(13, D2),
        buffer(14, S::FRAGMENT, STORAGE),
    ];
    if extension_textures {
        // Transmission, thickness, iridescence, iridescence thickness, anisotropy
        // (extension_textures.wgsl).
        entries.extend((15..20).map(|binding| texture(binding, D2)));
    }
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("seamlit material"),
        entries: &entries,
    })
}

/// Group 2: see [`Layouts::object`].
fn object_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("seamlit object"),
        entries: &[
            buffer(0, S::VERTEX_FRAGMENT | S::COMPUTE, wgpu::BufferBindingType::Uniform),
            buffer(1, S::VERTEX | S::COMPUTE, STORAGE),
            buffer(2, S::VERTEX | S::COMPUTE, STORAGE),
            buffer(3, S::VERTEX | S::COMPUTE, STORAGE),
            buffer(4, S::VERTEX | S::COMPUTE, STORAGE),
            buffer(5, S::VERTEX | S::COMPUTE, STORAGE),
        ],
    })
}

/// Group 3: see [`Layouts::environment`].
fn environment_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("seamlit environment"),
        entries: &[
            texture(0, CUBE),
            texture(1, CUBE),
            // The BRDF table, a storage buffer: the 16 sampled textures a stage that WebGPU
            // guarantees are all taken, the transmission target's included.
            buffer(2, S::FRAGMENT, STORAGE),
            sampler(3, wgpu::SamplerBindingType::Filtering),
        ],
    })
}

const D2: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2;
const CUBE: wgpu::TextureViewDimension = wgpu::TextureViewDimension::Cube;
const STORAGE: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: true };

/// A buffer binding of `ty` (uniform or read-only storage), its size unchecked.
fn buffer(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BufferBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}

/// A filterable float texture the fragment shader samples, of one view dimension.
fn texture(binding: u32, view_dimension: wgpu::TextureViewDimension) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: S::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension,
            multisampled: false,
        },
        count: None,
    }
}

/// A sampler the fragment shader uses.
fn sampler(binding: u32, ty: wgpu::SamplerBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: S::FRAGMENT,
        ty: wgpu::BindingType::Sampler(ty),
        count: None,
    }
}
