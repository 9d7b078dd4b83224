//! Options for loading and saving.

/// How to load a model file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoadOptions {
    /// Newell patches: each patch becomes an N x N grid of quads (2 N^2 triangles).
    /// Clamped to 1..=1024.
    pub tessellation: u32,
    /// Whether to read and decode textures (in parallel). When `false` textures are listed
    /// with `image: None` and no warning.
    pub load_textures: bool,
    /// With [`LoadOptions::load_textures`]: whether the textures' pixels are decoded. When
    /// `false` each texture is found and its header read, so that a missing file, an image
    /// that cannot be read and one past the size limits are warned of as when decoding, but
    /// `image` stays `None`: what `seamlit fix` needs ([`LoadOptions::FIX`]), whose writers
    /// copy the textures as they are (a generic writer decodes one that is neither PNG nor
    /// JPEG when it must re-encode it).
    pub decode_textures: bool,
    /// Files larger than this are refused with [`crate::IoError::TooLarge`] before being
    /// read (the model file itself and each external buffer).
    pub max_file_bytes: u64,
    /// The largest number of vertices or triangles one object may have.
    pub max_elements: usize,
    /// The largest number of triangles the whole model may have, counted before they are
    /// made: glTF mesh instances (one small mesh used by a million nodes) and Newell patches
    /// times the tessellation cannot multiply a small file into gigabytes.
    pub max_model_triangles: usize,
    /// The largest width or height of a texture; a larger image is not decoded (its header
    /// is read, its pixels are not) and gets a warning, like an undecodable one. The image
    /// crate's own 512 MiB allocation limit applies as well.
    pub max_texture_size: u32,
    /// The largest number of bytes all decoded textures of one model may take together
    /// (RGBA8: 4 bytes per texel; a 4096 x 4096 texture takes 64 MiB). Image headers are read
    /// first; in file order, a texture that would take the total past this budget is not
    /// decoded and gets a warning, like a missing one (renderers use a neutral default).
    pub max_texture_bytes: u64,
    /// When set, a missing material library or texture is an error
    /// ([`crate::IoError::MissingFile`]) instead of a warning.
    pub strict: bool,
    /// Empty (the default): the files a USD stage names (sublayers, references, payloads,
    /// textures) are read wherever they resolve, as USD reads them (only regular files).
    /// Otherwise the strict mode: those files may come only from the model file's own folder
    /// and these; a USD layer elsewhere is refused ([`crate::UsdKind::Outside`]), a texture
    /// elsewhere is not used (a warning). A `.usdz` output packs only files from the stage's
    /// folder and these, either way.
    pub asset_roots: Vec<std::path::PathBuf>,
    /// Whether to read the materials that OpenUSD `materialBind` GeomSubsets bind to parts
    /// of meshes, into [`crate::Asset::triangle_materials`] (and their materials and
    /// textures into the asset's lists), for drawing. Off by default and for `fix`: a mesh
    /// is then one object with its own material, and what is written from it does not change.
    pub subset_materials: bool,
    /// Where the model file's side files (buffers, images, material libraries, layers) are
    /// read from: the file system (the default), or files in memory
    /// ([`crate::files::Files::Memory`], the web page's dropped files). The model file itself
    /// comes from the caller of a reader's `parse`; its path names it in that set.
    pub files: crate::origin::Files,
}

impl LoadOptions {
    /// The defaults: tessellation 16, textures loaded and decoded, 4 GiB files, 2^28 elements per
    /// object, 2^26 triangles per model, textures up to 16384 x 16384 and 1 GiB decoded
    /// textures per model, missing side files are warnings.
    pub const DEFAULT: Self = Self {
        tessellation: 16,
        load_textures: true,
        decode_textures: true,
        max_file_bytes: 4 << 30,
        max_elements: 1 << 28,
        max_model_triangles: 1 << 26,
        max_texture_size: 16384,
        max_texture_bytes: 1 << 30,
        strict: false,
        asset_roots: Vec::new(),
        subset_materials: false,
        files: crate::origin::Files::Disk,
    };

    /// Geometry only: no textures read (faster; for `inspect`).
    pub const GEOMETRY: Self = Self::DEFAULT.without_textures();

    /// What `seamlit fix` reads: textures found and their headers read (missing, unreadable
    /// and oversized ones warned of), their pixels not decoded
    /// ([`LoadOptions::decode_textures`]).
    pub const FIX: Self = Self::DEFAULT.without_pixels();

    /// These options with textures found and measured, not decoded.
    const fn without_pixels(mut self) -> Self {
        self.decode_textures = false;
        self
    }

    /// These options with textures not loaded.
    const fn without_textures(mut self) -> Self {
        self.load_textures = false;
        self
    }

    /// These options with the materials of USD GeomSubsets read, for drawing (builder style;
    /// [`LoadOptions::subset_materials`]).
    #[must_use]
    pub fn with_subset_materials(mut self) -> Self {
        self.subset_materials = true;
        self
    }

    /// Sets the Newell tessellation (builder style).
    #[must_use]
    pub const fn with_tessellation(mut self, tessellation: u32) -> Self {
        self.tessellation = tessellation;
        self
    }

    /// Sets [`LoadOptions::strict`] (builder style).
    #[must_use]
    pub const fn with_strict(mut self, strict: bool) -> Self {
        self.strict = strict;
        self
    }
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// How to save a model file.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SaveOptions {
    /// Allow writing over the file the asset was loaded from ([`crate::Asset::source`]).
    pub overwrite_input: bool,
    /// For a glTF or GLB input that used EXT_meshopt_compression or
    /// KHR_meshopt_compression, saved as glTF or GLB: write the output with the same
    /// extension. The input's compressed buffer views keep their compressed bytes, mode and
    /// filter as written; the views the save writes anew (normals, tangents, split vertex
    /// streams, indices) are compressed with meshoptimizer's lossless codecs (filter NONE).
    /// When unset (the default) the output is uncompressed. An input without compression is
    /// written as without the option (the report says so); a Draco-compressed input, and an
    /// OBJ output, are refused with [`crate::IoError::CannotKeepCompression`].
    pub keep_compression: bool,
}
