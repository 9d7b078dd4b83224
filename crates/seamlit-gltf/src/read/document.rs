//! The validated document of glTF or GLB bytes: the GLB container split (`glb.rs`), the
//! JSON parsed twice (as plain JSON for the pass-through writer, as typed glTF for the
//! reader), read again leniently where gltf-json is stricter than the specification
//! (`lenient.rs`), and checked where gltf-json would panic or refuse less than it should.

use std::ops::Range;
use std::path::Path;

use gltf::json::validation::Error as Problem;

use super::lenient::lenient;
#[cfg(feature = "draco")]
use seamlit_asset::LoadOptions;
use seamlit_asset::error::IoError;
use seamlit_asset::error::gltf::GltfKind;

/// The validated document of glTF or GLB bytes, the same JSON as written (for the
/// pass-through writer) and, for a GLB with a BIN chunk, where that chunk's data lies in
/// `bytes`.
pub(super) fn document(
    bytes: &[u8],
    path: &Path,
) -> Result<(gltf::Document, serde_json::Value, Option<Range<usize>>), IoError> {
    let (json, bin) = if bytes.starts_with(b"glTF") {
        let (json, bin) = crate::glb::chunks(bytes, path)?;
        (&bytes[json], bin)
    } else {
        (bytes, None)
    };
    // Parsed as plain JSON (what the pass-through writer writes back), then as typed glTF.
    let value: serde_json::Value = serde_json::from_slice(json).map_err(|e| json_error(e, path))?;
    // glTF 1.0 fails typed parsing at its first object-keyed member: say what it is instead.
    let version = match &value["asset"]["version"] {
        serde_json::Value::String(v) => Some(v.clone()),
        serde_json::Value::Number(n) => Some(n.to_string()),
        _ => None,
    };
    if let Some(version) = version.filter(|v| v == "1" || v.starts_with("1.")) {
        return Err(IoError::Gltf {
            path: path.to_path_buf(),
            place: "asset.version".to_owned(),
            kind: GltfKind::OldVersion { version: version.to_owned() },
        });
    }
    // A document gltf-json refuses is read again as the specification allows (see
    // `lenient`); if that fails too, the first error (with its line) is reported.
    let root = gltf::json::Root::from_slice(json).or_else(|error| {
        lenient(&value).and_then(|patched| serde_json::from_value(patched).ok()).ok_or(error)
    });
    let root = root.map_err(|e| json_error(e, path))?;
    #[cfg(not(feature = "draco"))]
    crate::decode::draco::refuse(&value, path)?;
    let document = validated(root, path)?;
    Ok((document, value, bin))
}

/// The typed document of a parsed root, after the checks that must run before gltf-json's
/// validation and that validation less what the specification allows (`lenient.rs`).
fn validated(mut root: gltf::json::Root, path: &Path) -> Result<gltf::Document, IoError> {
    check_position_indices(&root, path)?;
    check_image_sources(&root, path)?;
    check_required_extensions(&root, path)?;
    // The gltf crate refuses every required extension it does not implement; seamlit passes
    // through the ones that do not change how geometry is read (checked above).
    root.extensions_required.clear();
    super::lenient::validate(&root).map_err(|problems| validation_error(&problems, path))?;
    Ok(gltf::Document::from_json_without_validation(root))
}

/// Decodes the document's Draco-compressed primitives into plain data (`decode/draco.rs`),
/// changing `json` and buffer 0; returns the typed document of the changed JSON, or `None`
/// when there was nothing to decode.
#[cfg(feature = "draco")]
pub(super) fn decode_draco(
    json: &mut serde_json::Value,
    buffers: &mut [Vec<u8>],
    options: &LoadOptions,
    path: &Path,
) -> Result<Option<gltf::Document>, IoError> {
    if crate::decode::draco::decode(json, buffers, options.max_elements, path)? == 0 {
        return Ok(None);
    }
    let root = serde_json::from_value(json.clone())
        .or_else(|error| lenient(json).and_then(|p| serde_json::from_value(p).ok()).ok_or(error));
    let root = root.map_err(|e| json_error(e, path))?;
    validated(root, path).map(Some)
}

/// Required extensions that change how vertex data is stored and that seamlit does not
/// decode: a file that requires one of these cannot be read without it. Any other required
/// extension (lights, material and texture extensions, unknown ones) is passed through
/// untouched; KHR_mesh_quantization and EXT_/KHR_meshopt_compression are decoded
/// (`decode/`), and KHR_draco_mesh_compression with the `draco` feature
/// (`decode/draco.rs`).
#[cfg(not(feature = "draco"))]
const GEOMETRY_EXTENSIONS: [&str; 1] = ["KHR_draco_mesh_compression"];
#[cfg(feature = "draco")]
const GEOMETRY_EXTENSIONS: [&str; 0] = [];

/// Refuses a file that requires an extension in [`GEOMETRY_EXTENSIONS`].
fn check_required_extensions(root: &gltf::json::Root, path: &Path) -> Result<(), IoError> {
    match root
        .extensions_required
        .iter()
        .enumerate()
        .find(|(_, e)| GEOMETRY_EXTENSIONS.contains(&e.as_str()))
    {
        Some((i, extension)) => Err(IoError::Gltf {
            path: path.to_path_buf(),
            place: format!("extensionsRequired[{i}]"),
            kind: GltfKind::UnsupportedExtension { extension: extension.clone() },
        }),
        None => Ok(()),
    }
}

/// Every primitive's `POSITION` names an existing accessor. gltf-json 1.4.1's validation
/// indexes the accessors with it unchecked and panics otherwise (found by the `gltf` fuzz
/// target: regression input `tests/regressions/gltf_position_accessor_missing.gltf`), so this
/// runs before it.
fn check_position_indices(root: &gltf::json::Root, path: &Path) -> Result<(), IoError> {
    let semantic = gltf::json::validation::Checked::Valid(gltf::Semantic::Positions);
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(index) = primitive.attributes.get(&semantic)
                && index.value() >= root.accessors.len()
            {
                return Err(IoError::Gltf {
                    path: path.to_path_buf(),
                    place: format!("meshes[{m}].primitives[{p}].attributes.POSITION"),
                    kind: GltfKind::NoSuchAccessor {
                        accessor: index.value(),
                        count: root.accessors.len(),
                    },
                });
            }
        }
    }
    Ok(())
}

/// Every image has a `uri`, or a `bufferView` with a `mimeType`: gltf 1.4.1's
/// `Image::source` unwraps them and its validation lets them through (found by the `gltf`
/// fuzz target: regression input `tests/regressions/gltf_image_without_uri.gltf`).
fn check_image_sources(root: &gltf::json::Root, path: &Path) -> Result<(), IoError> {
    for (i, image) in root.images.iter().enumerate() {
        let kind = match (&image.uri, &image.buffer_view, &image.mime_type) {
            (_, Some(_), None) => GltfKind::ImageWithoutMimeType,
            (None, None, _) => GltfKind::ImageWithoutSource,
            _ => continue,
        };
        return Err(IoError::Gltf {
            path: path.to_path_buf(),
            place: format!("images[{i}]"),
            kind,
        });
    }
    Ok(())
}

/// An [`IoError::Gltf`] for JSON that does not parse as a glTF document.
fn json_error(error: serde_json::Error, path: &Path) -> IoError {
    IoError::Gltf {
        path: path.to_path_buf(),
        place: format!("JSON line {} column {}", error.line(), error.column()),
        kind: GltfKind::Json { source: error },
    }
}

/// An [`IoError::Gltf`] for gltf-json's validation problems: the first, at its JSON path.
fn validation_error(problems: &[(gltf::json::Path, Problem)], path: &Path) -> IoError {
    let (place, problem) = problems
        .first()
        .map_or(("document".to_owned(), Problem::Invalid), |(p, e)| (p.to_string(), *e));
    IoError::Gltf {
        path: path.to_path_buf(),
        place,
        kind: GltfKind::Validation {
            problem: problem.to_string(),
            more: problems.len().saturating_sub(1),
        },
    }
}
