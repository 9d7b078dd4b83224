//! Texture decoding: every image of an asset decoded in parallel (rayon) through the image
//! crate. A texture that is missing or cannot be decoded keeps `image: None` and adds a
//! warning; renderers then use a neutral default (white, or the flat normal (0.5, 0.5, 1)).

use std::path::Path;
use std::sync::Arc;

use rayon::prelude::*;

use crate::{IoError, LoadOptions, Texture, TextureSource};

/// Decodes every texture whose `image` is `None`, in parallel.
///
/// Returns one warning per texture that could not be read or decoded. With
/// `options.strict`, a missing texture file is an error instead.
///
/// # Errors
///
/// [`IoError::MissingFile`] for a missing file when `options.strict` is set.
pub(crate) fn decode_all(
    textures: &mut [Texture],
    model: &Path,
    options: &LoadOptions,
) -> Result<Vec<String>, IoError> {
    if !options.load_textures {
        return Ok(Vec::new());
    }
    let results: Vec<Result<Option<String>, IoError>> = textures
        .par_iter_mut()
        .filter(|t| t.image.is_none())
        .map(|texture| {
            let bytes: Arc<[u8]> = match &texture.source {
                TextureSource::File(file) => match std::fs::read(file) {
                    Ok(bytes) => bytes.into(),
                    Err(err) if options.strict && err.kind() == std::io::ErrorKind::NotFound => {
                        return Err(IoError::MissingFile {
                            path: model.to_path_buf(),
                            what: "texture".to_owned(),
                            missing: file.clone(),
                            line: None,
                        });
                    }
                    Err(err) => {
                        return Ok(Some(format!(
                            "{}: texture {}: {err}; using a neutral default",
                            model.display(),
                            file.display()
                        )));
                    }
                },
                TextureSource::Embedded { bytes, .. } => Arc::clone(bytes),
                TextureSource::Generated => return Ok(None),
            };
            match decode(&bytes, options.max_texture_size) {
                Ok(image) => {
                    texture.image = Some(Arc::new(image.into_rgba8()));
                    Ok(None)
                }
                Err(err) => Ok(Some(format!(
                    "{}: texture {:?} cannot be decoded: {err}; using a neutral default",
                    model.display(),
                    texture.name
                ))),
            }
        })
        .collect();
    let mut warnings = Vec::new();
    for result in results {
        if let Some(warning) = result? {
            warnings.push(warning);
        }
    }
    Ok(warnings)
}

/// Decodes an image whose width and height are at most `max_size`: the header is read
/// first, so an oversized image allocates nothing.
fn decode(bytes: &[u8], max_size: u32) -> image::ImageResult<image::DynamicImage> {
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes)).with_guessed_format()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(max_size);
    limits.max_image_height = Some(max_size);
    reader.limits(limits);
    reader.decode()
}
