//! Textures in and out. Decoding: every image of an asset decoded in parallel (rayon)
//! through the image crate (PNG, JPEG), or [`ktx2`] for KTX2 files (uncompressed or
//! Zstandard-supercompressed 8-bit formats; Basis Universal named in its warning). A texture that is missing, cannot be decoded, is larger than
//! [`LoadOptions::max_texture_size`] or does not fit the model's
//! [`LoadOptions::max_texture_bytes`] keeps `image: None` and adds a warning; renderers then
//! use a neutral default (white, or the flat normal (0.5, 0.5, 1)).
//!
//! Decoding goes in three steps, so that the budget is kept before memory is spent and the
//! same textures are refused on every run: the headers are read in parallel (dimensions only),
//! the budget is handed out in file order, then the admitted images are decoded in parallel.
//!
//! Encoding, for the generic writers: a texture's bytes as PNG or JPEG ([`encoded`]).

mod ktx2;

use std::borrow::Cow;
use std::fmt::Display;
use std::io::{BufRead, BufReader, Cursor, Read, Seek};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use bytes::Bytes;
use rayon::prelude::*;

use crate::files::Files;
use crate::paths::NotInside;
use crate::{IoError, LoadOptions, Texture, TextureSource};

/// Bytes of one decoded texel (RGBA8).
const TEXEL_BYTES: u64 = 4;

/// Where a texture's encoded bytes are read from.
enum Encoded {
    /// A file, by its real path (symbolic links followed and checked).
    File(PathBuf),
    /// Bytes in memory (GLB buffer view, data: URI).
    Bytes(Bytes),
}

impl Encoded {
    /// Runs `f` on an image reader over the bytes, the format guessed from their content.
    fn read<T>(
        &self,
        f: impl FnOnce(image::ImageReader<&mut dyn BufReadSeek>) -> image::ImageResult<T>,
    ) -> image::ImageResult<T> {
        match self {
            Self::File(path) => {
                let mut file = BufReader::new(std::fs::File::open(path)?);
                f(image::ImageReader::new(&mut file as &mut dyn BufReadSeek)
                    .with_guessed_format()?)
            }
            Self::Bytes(bytes) => {
                let mut cursor = Cursor::new(&bytes[..]);
                f(image::ImageReader::new(&mut cursor as &mut dyn BufReadSeek)
                    .with_guessed_format()?)
            }
        }
    }
}

/// Why a texture was not decoded: the image crate's error or the KTX2 reader's.
enum DecodeError {
    Image(image::ImageError),
    Ktx2(ktx2::Ktx2Error),
}

impl Display for DecodeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Image(err) => err.fmt(f),
            Self::Ktx2(err) => err.fmt(f),
        }
    }
}

impl Encoded {
    /// The whole encoded bytes where they are a KTX2 file (a file's first 12 bytes read to
    /// tell), `None` for any other format.
    fn ktx2_bytes(&self) -> std::io::Result<Option<Cow<'_, [u8]>>> {
        match self {
            Self::Bytes(bytes) => Ok(ktx2::is_ktx2(bytes).then_some(Cow::Borrowed(&bytes[..]))),
            Self::File(path) => {
                let mut file = std::fs::File::open(path)?;
                let mut signature = [0; ktx2::SIGNATURE.len()];
                let is_ktx2 = match file.read_exact(&mut signature) {
                    Ok(()) => ktx2::is_ktx2(&signature),
                    Err(err) if err.kind() == std::io::ErrorKind::UnexpectedEof => false,
                    Err(err) => return Err(err),
                };
                if !is_ktx2 {
                    return Ok(None);
                }
                Ok(Some(Cow::Owned(std::fs::read(path)?)))
            }
        }
    }

    /// The image's width and height, from its header.
    fn dimensions(&self) -> Result<(u32, u32), DecodeError> {
        match self.ktx2_bytes().map_err(|e| DecodeError::Image(e.into()))? {
            Some(bytes) => ktx2::dimensions(&bytes).map_err(DecodeError::Ktx2),
            None => self.read(|reader| reader.into_dimensions()).map_err(DecodeError::Image),
        }
    }

    /// The image as RGBA8, at most `max_size` wide and high.
    fn decode(&self, max_size: u32) -> Result<image::RgbaImage, DecodeError> {
        match self.ktx2_bytes().map_err(|e| DecodeError::Image(e.into()))? {
            Some(bytes) => ktx2::decode(&bytes, max_size).map_err(DecodeError::Ktx2),
            None => self
                .read(|reader| decode(reader, max_size))
                .map(image::DynamicImage::into_rgba8)
                .map_err(DecodeError::Image),
        }
    }
}

/// A texture whose header was read.
struct Probed {
    source: Encoded,
    width: u32,
    height: u32,
}

/// A buffered, seekable reader (what [`image::ImageReader`] reads from), as one trait object.
trait BufReadSeek: BufRead + Seek {}
impl<T: BufRead + Seek> BufReadSeek for T {}

/// Checks that no texture file is reached through a symbolic link leading out of the model's
/// folder, then decodes every texture whose `image` is `None`, within the limits of
/// `options`.
///
/// The check runs even when `options.load_textures` is off, since writers copy texture files.
/// With `options.decode_textures` off, the headers are read and the budget handed out (with
/// their warnings), and nothing is decoded. Returns one warning per texture that could not be
/// read or decoded or was refused by a limit. With `options.strict`, a missing texture file is an error instead.
///
/// # Errors
///
/// [`IoError::LinkEscapes`] for a texture file whose links lead out of the model's folder;
/// [`IoError::MissingFile`] for a missing file when `options.strict` is set.
pub fn decode_all(
    textures: &mut [Texture],
    model: &Path,
    options: &LoadOptions,
) -> Result<Vec<String>, IoError> {
    let sources = locate(textures, model, options)?;
    if !options.load_textures {
        return Ok(Vec::new());
    }
    let probed = probe(sources, textures, model);
    let mut warnings = Vec::new();
    let admitted = hand_out_budget(probed, textures, model, options, &mut warnings);
    if options.decode_textures {
        warnings.extend(decode_admitted(textures, admitted, model, options.max_texture_size));
    }
    Ok(warnings)
}

/// Per texture: where to read it (`None` where it has an image or needs none, or where
/// textures are not loaded and its file is missing), or a warning.
type Located = Option<Result<Encoded, String>>;

/// Where each texture is to be read from, after the check that no link leads out of the
/// model's folder.
///
/// # Errors
///
/// As [`decode_all`].
fn locate(
    textures: &[Texture],
    model: &Path,
    options: &LoadOptions,
) -> Result<Vec<Located>, IoError> {
    let folder = model.parent().unwrap_or(Path::new(""));
    let mut sources = Vec::with_capacity(textures.len());
    for texture in textures {
        let source = match &texture.source {
            _ if texture.image.is_some() => None,
            TextureSource::Generated => None,
            TextureSource::Embedded { bytes, .. } => Some(Ok(Encoded::Bytes(bytes.clone()))),
            TextureSource::File(file) => match options.files.real_inside(folder, file) {
                Ok(real) => Some(encoded_file(real, options)),
                // A folder the caller allows (a USD stage's textures beside its other layers).
                Err(NotInside::Outside(target)) if in_asset_root(&target, options) => {
                    Some(Ok(Encoded::File(target)))
                }
                Err(NotInside::Outside(target)) => {
                    return Err(IoError::LinkEscapes {
                        path: model.to_path_buf(),
                        what: "texture".to_owned(),
                        reference: file.strip_prefix(folder).unwrap_or(file).display().to_string(),
                        target,
                    });
                }
                // Not decoding: a missing file is not reported (`LoadOptions::load_textures`).
                Err(NotInside::Io(_)) if !options.load_textures => None,
                Err(NotInside::Io(err))
                    if options.strict && err.kind() == std::io::ErrorKind::NotFound =>
                {
                    return Err(IoError::MissingFile {
                        path: model.to_path_buf(),
                        what: "texture".to_owned(),
                        missing: file.clone(),
                        line: None,
                    });
                }
                Err(NotInside::Io(err)) => Some(Err(format!(
                    "{}: texture {}: {err}; using a neutral default",
                    model.display(),
                    file.display()
                ))),
            },
        };
        sources.push(source);
    }
    Ok(sources)
}

/// Where to read the texture file at `real`: the file system, or its bytes in memory
/// ([`LoadOptions::files`]).
fn encoded_file(real: PathBuf, options: &LoadOptions) -> Result<Encoded, String> {
    match &options.files {
        Files::Disk => Ok(Encoded::File(real)),
        Files::Memory(files) => files
            .get(&real)
            .map(|bytes| Encoded::Bytes(Bytes::from_owner(Arc::clone(bytes))))
            .ok_or_else(|| format!("texture {}: not among the files given", real.display())),
    }
}

/// Whether `real` (a canonical path; in memory, a normalised one) lies in one of
/// [`LoadOptions::asset_roots`].
fn in_asset_root(real: &Path, options: &LoadOptions) -> bool {
    if let Files::Memory(_) = options.files {
        let roots = options.asset_roots.iter().map(|r| crate::files::normalize(r));
        return roots.into_iter().any(|r| real.starts_with(r));
    }
    options.asset_roots.iter().filter_map(|r| r.canonicalize().ok()).any(|r| real.starts_with(r))
}

/// The warning for a texture that cannot be decoded.
fn cannot_decode(model: &Path, texture: &Texture, err: &impl Display) -> String {
    format!(
        "{}: texture {:?} cannot be decoded: {err}; using a neutral default",
        model.display(),
        texture.name
    )
}

/// The dimensions of each texture to read, from its header, in parallel.
fn probe(
    sources: Vec<Located>,
    textures: &[Texture],
    model: &Path,
) -> Vec<Option<Result<Probed, String>>> {
    sources
        .into_par_iter()
        .zip(textures.par_iter())
        .map(|(source, texture)| {
            source.map(|source| {
                let source = source?;
                let (width, height) =
                    source.dimensions().map_err(|e| cannot_decode(model, texture, &e))?;
                Ok(Probed { source, width, height })
            })
        })
        .collect()
}

/// The textures admitted for decoding within the budget, in file order: a texture that would
/// take the total past it is refused (a warning), as is every texture that failed before.
fn hand_out_budget(
    probed: Vec<Option<Result<Probed, String>>>,
    textures: &[Texture],
    model: &Path,
    options: &LoadOptions,
    warnings: &mut Vec<String>,
) -> Vec<Option<Encoded>> {
    let mut spent: u64 = textures
        .iter()
        .filter_map(|t| t.image.as_ref())
        .map(|image| u64::from(image.width()) * u64::from(image.height()) * TEXEL_BYTES)
        .sum();
    let mut admitted = Vec::with_capacity(textures.len());
    for (probe, texture) in probed.into_iter().zip(textures) {
        admitted.push(match probe {
            None => None,
            Some(Err(warning)) => {
                warnings.push(warning);
                None
            }
            Some(Ok(Probed { source, width, height })) => {
                let bytes = u64::from(width) * u64::from(height) * TEXEL_BYTES;
                let oversized = width.max(height) > options.max_texture_size;
                // An image over the size cap is refused by the decoder (with its dimensions);
                // it costs nothing.
                if !oversized && spent.saturating_add(bytes) > options.max_texture_bytes {
                    warnings.push(format!(
                        "{}: texture {:?} needs {bytes} bytes decoded; with the {spent} bytes of the textures before it that is past the budget of {} bytes for one model's textures; using a neutral default",
                        model.display(),
                        texture.name,
                        options.max_texture_bytes
                    ));
                    None
                } else {
                    if !oversized {
                        spent += bytes;
                    }
                    Some(source)
                }
            }
        });
    }
    admitted
}

/// Decodes the admitted textures (at most `max_size` wide and high) in parallel, into their
/// `image`: a warning for each that fails.
fn decode_admitted(
    textures: &mut [Texture],
    admitted: Vec<Option<Encoded>>,
    model: &Path,
    max_size: u32,
) -> Vec<String> {
    let decoded: Vec<Option<String>> = textures
        .par_iter_mut()
        .zip(admitted.into_par_iter())
        .map(|(texture, source)| {
            let source = source?;
            match source.decode(max_size) {
                Ok(image) => {
                    texture.image = Some(Arc::new(image));
                    None
                }
                Err(err) => Some(cannot_decode(model, texture, &err)),
            }
        })
        .collect();
    decoded.into_iter().flatten().collect()
}

/// Decodes an image whose width and height are at most `max_size`: the header is read
/// first, so an oversized image allocates nothing.
fn decode<R: BufRead + Seek>(
    mut reader: image::ImageReader<R>,
    max_size: u32,
) -> image::ImageResult<image::DynamicImage> {
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(max_size);
    limits.max_image_height = Some(max_size);
    reader.limits(limits);
    reader.decode()
}

/// A texture's encoded bytes and MIME type (PNG or JPEG): the original bytes where they are
/// PNG or JPEG, else the image encoded as PNG: the decoded one, or, where the model was loaded
/// without decoding textures (`seamlit fix` decodes none: [`LoadOptions::load_textures`]), the
/// original decoded now (KTX2, WebP, ..., within [`LoadOptions::DEFAULT`]'s largest size);
/// `None` when neither is available.
pub fn encoded(texture: &Texture, path: &Path) -> Result<Option<(Vec<u8>, &'static str)>, IoError> {
    let sniff = |bytes: &[u8]| -> Option<&'static str> {
        if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            Some("image/png")
        } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
            Some("image/jpeg")
        } else {
            None
        }
    };
    let original = match &texture.source {
        TextureSource::File(file) => std::fs::read(file).ok(),
        TextureSource::Embedded { bytes, .. } => Some(bytes.to_vec()),
        TextureSource::Generated => None,
    };
    let original = match original.as_deref().and_then(sniff) {
        Some(mime) => return Ok(original.map(|bytes| (bytes, mime))),
        None => original,
    };
    let decoded;
    let image = match (&texture.image, original) {
        (Some(image), _) => &**image,
        (None, Some(bytes)) => {
            let max_size = LoadOptions::DEFAULT.max_texture_size;
            match Encoded::Bytes(Bytes::from(bytes)).decode(max_size) {
                Ok(image) => {
                    decoded = image;
                    &decoded
                }
                Err(_) => return Ok(None),
            }
        }
        (None, None) => return Ok(None),
    };
    let mut png = Vec::new();
    image.write_to(&mut Cursor::new(&mut png), image::ImageFormat::Png).map_err(|source| {
        IoError::Image { path: path.to_path_buf(), texture: texture.name.clone(), source }
    })?;
    Ok(Some((png, "image/png")))
}
