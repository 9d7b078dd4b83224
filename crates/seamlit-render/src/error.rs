//! The renderer's error type.

use thiserror::Error;

/// What can go wrong while setting up the GPU, uploading a model or rendering.
#[derive(Debug, Error)]
pub enum RenderError {
    /// No GPU adapter (nor a software one) could be found.
    #[error(
        "no graphics adapter found (tried {tried}); install a Vulkan driver: on Linux without a \
         GPU, `apt-get install mesa-vulkan-drivers` (Mesa's lavapipe), or GL drivers \
         (`libgl1-mesa-dri`)"
    )]
    NoAdapter {
        /// The backends that were tried, for the message.
        tried: String,
    },
    /// The adapter refused to create a device.
    #[error("could not open the graphics device {adapter}: {source}")]
    RequestDevice {
        /// The adapter's name and backend.
        adapter: String,
        /// wgpu's reason.
        #[source]
        source: wgpu::RequestDeviceError,
    },
    /// An environment image could not be read (missing, unreadable, not a Radiance `.hdr`).
    #[error("{}: cannot read the environment: {reason}", path.display())]
    Environment {
        /// The file.
        path: std::path::PathBuf,
        /// Why (the I/O or decoder error).
        reason: String,
    },
    /// An object has no normals; run `seamlit_mesh::fix` before uploading.
    #[error("object {object:?} has no normals; run seamlit_mesh::fix on the model first")]
    MissingNormals {
        /// The object's name.
        object: String,
    },
    /// An object's per-vertex arrays or indices do not fit together.
    #[error("object {object:?}: {what}")]
    BadObject {
        /// The object's name.
        object: String,
        /// What is wrong (expected and actual lengths, the bad index).
        what: String,
    },
    /// A pose given to `GpuScene::set_pose` does not fit the scene or one of its objects.
    #[error("pose of object {object:?}: {what}")]
    BadPose {
        /// The object's name (or "the scene" for the number of poses).
        object: String,
        /// What is wrong (a palette too short, more weights than targets, a non-finite number).
        what: String,
    },
    /// A material index or texture index points past the end of its list.
    #[error("{what} index {index} is out of range (there are {count})")]
    IndexOutOfRange {
        /// What the index refers to (`"material"` of an object, `"texture"` of a material).
        what: String,
        /// The bad index.
        index: usize,
        /// How many there are.
        count: usize,
    },
    /// A texture is larger than the device allows.
    #[error("texture {name:?} is {width}x{height}, larger than the device limit {max}")]
    TextureTooLarge {
        /// The texture's name.
        name: String,
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// The device's largest 2D texture side.
        max: u32,
    },
    /// A render target size is zero or larger than the device allows.
    #[error("render size {width}x{height} is not allowed (each side 1..={max})")]
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The device's largest 2D texture side.
        max: u32,
    },
    /// The target format does not support the requested MSAA sample count.
    #[error(
        "{format:?} does not support {count}x multisampling on this adapter (supported: {supported:?})"
    )]
    UnsupportedSampleCount {
        /// The target format.
        format: wgpu::TextureFormat,
        /// The requested sample count.
        count: u32,
        /// The counts the adapter supports for this format.
        supported: Vec<u32>,
    },
    /// Waiting for the GPU failed.
    #[error("waiting for the GPU failed: {0}")]
    Poll(#[from] wgpu::PollError),
    /// Mapping the readback buffer failed.
    #[error("reading the image back from the GPU failed: {0}")]
    Map(#[from] wgpu::BufferAsyncError),
    /// wgpu reported a validation or out-of-memory error.
    #[error("GPU error while {during}: {message}")]
    Gpu {
        /// What the renderer was doing.
        during: &'static str,
        /// wgpu's message.
        message: String,
    },
}
