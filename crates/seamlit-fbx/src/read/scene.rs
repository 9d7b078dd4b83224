//! The FBX file opened by ufbx, with the load options that give glTF's conventions: +Y up,
//! metres, right-handed (ufbx mirrors a left-handed file and keeps faces counter-clockwise),
//! geometry transforms and pivots folded into the geometry where they can be (helper nodes
//! where a mesh is instanced), and ufbx's errors as [`FbxKind`]s.

use std::path::Path;
use std::sync::Arc;

use seamlit_asset::error::IoError;
use seamlit_asset::error::fbx::FbxKind;

use super::threads::Pool;

/// What ufbx reads: a file, streamed, or bytes in memory.
pub(super) enum Input<'a> {
    File(std::fs::File),
    Bytes(&'a [u8]),
}

/// Opens `input` (the file at `path`) as FBX (never as OBJ, which ufbx reads too). External
/// files are not opened by ufbx (textures are read by this crate, inside the model's folder).
/// The compressed arrays of a binary file are inflated on rayon's threads (`threads.rs`).
///
/// # Errors
///
/// [`IoError::Fbx`] with [`FbxKind::Truncated`] or [`FbxKind::Refused`] (an error reading a
/// streamed file among them, as ufbx's `IO`).
pub(super) fn open(input: Input<'_>, path: &Path) -> Result<ufbx::SceneRoot, IoError> {
    // Kept alive until ufbx returns: its tasks reach it through a raw pointer.
    let pool = Arc::new(Pool::default());
    let options = ufbx::LoadOpts { thread_opts: Pool::options(&pool), ..load_options() };
    let scene = match input {
        Input::File(file) => ufbx::load_stream(ufbx::Stream::File(file), options),
        Input::Bytes(bytes) => ufbx::load_memory(bytes, options),
    };
    drop(pool);
    scene.map_err(|error| {
        let description = error.description.to_string();
        let info = error.info();
        let description =
            if info.is_empty() { description } else { format!("{description} ({info})") };
        let kind = match error.type_ {
            ufbx::ErrorType::TruncatedFile => FbxKind::Truncated { description },
            other => FbxKind::Refused { error: error_name(other).to_owned(), description },
        };
        IoError::Fbx { path: path.to_path_buf(), kind }
    })
}

/// ufbx's options for glTF's conventions, without a thread pool.
pub(super) fn load_options() -> ufbx::LoadOpts<'static> {
    ufbx::LoadOpts {
        file_format: ufbx::FileFormat::Fbx,
        no_format_from_content: true,
        no_format_from_extension: true,
        load_external_files: false,
        ignore_missing_external_files: true,
        generate_missing_normals: false,
        clean_skin_weights: true,
        target_axes: ufbx::CoordinateAxes::right_handed_y_up(),
        target_unit_meters: 1.0,
        space_conversion: ufbx::SpaceConversion::ModifyGeometry,
        geometry_transform_handling: ufbx::GeometryTransformHandling::ModifyGeometry,
        inherit_mode_handling: ufbx::InheritModeHandling::Compensate,
        pivot_handling: ufbx::PivotHandling::AdjustToPivot,
        ..Default::default()
    }
}

/// ufbx's name of an error kind.
fn error_name(kind: ufbx::ErrorType) -> &'static str {
    use ufbx::ErrorType as E;
    match kind {
        E::None => "NONE",
        E::Unknown => "UNKNOWN",
        E::FileNotFound => "FILE_NOT_FOUND",
        E::EmptyFile => "EMPTY_FILE",
        E::ExternalFileNotFound => "EXTERNAL_FILE_NOT_FOUND",
        E::OutOfMemory => "OUT_OF_MEMORY",
        E::MemoryLimit => "MEMORY_LIMIT",
        E::AllocationLimit => "ALLOCATION_LIMIT",
        E::TruncatedFile => "TRUNCATED_FILE",
        E::Io => "IO",
        E::Cancelled => "CANCELLED",
        E::UnrecognizedFileFormat => "UNRECOGNIZED_FILE_FORMAT",
        E::UninitializedOptions => "UNINITIALIZED_OPTIONS",
        E::ZeroVertexSize => "ZERO_VERTEX_SIZE",
        E::TruncatedVertexStream => "TRUNCATED_VERTEX_STREAM",
        E::InvalidUtf8 => "INVALID_UTF8",
        E::FeatureDisabled => "FEATURE_DISABLED",
        E::BadNurbs => "BAD_NURBS",
        E::BadIndex => "BAD_INDEX",
        E::NodeDepthLimit => "NODE_DEPTH_LIMIT",
        E::ThreadedAsciiParse => "THREADED_ASCII_PARSE",
        E::UnsafeOptions => "UNSAFE_OPTIONS",
        E::DuplicateOverride => "DUPLICATE_OVERRIDE",
        E::UnsupportedVersion => "UNSUPPORTED_VERSION",
    }
}

/// A ufbx matrix (affine, column-major 3 x 4, f64) as a glam matrix.
pub(super) fn mat4(m: &ufbx::Matrix) -> glam::Mat4 {
    glam::DMat4::from_cols_array(&[
        m.m00, m.m10, m.m20, 0.0, m.m01, m.m11, m.m21, 0.0, m.m02, m.m12, m.m22, 0.0, m.m03, m.m13,
        m.m23, 1.0,
    ])
    .as_mat4()
}

/// A ufbx real (f64) rounded to the `f32` seamlit stores.
#[expect(clippy::cast_possible_truncation, reason = "rounding to f32 is the point")]
pub(super) fn f32_of(x: f64) -> f32 {
    x as f32
}
