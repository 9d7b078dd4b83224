//! KTX2 textures (Khronos KTX 2.0, as glTF names them with `image/ktx2`): the container read
//! by the `ktx2` crate, Zstandard supercompression undone by `ruzstd` (pure Rust), level 0 of
//! a 2D image in an 8-bit format (R, RG, RGB, BGR, RGBA, BGRA; UNORM, SRGB or UINT) as RGBA8.
//!
//! Missing channels are read as a GPU samples them (`(r, 0, 0, 1)` for R8). The format's
//! SRGB or UNORM is not applied here: as for PNG and JPEG, the texture slot decides how the
//! bytes are read (base colour and emissive as sRGB, the rest linear). Rows are tightly
//! packed in KTX2 (KTX 2.0 section 4.2: no row padding), and the image's first row is its
//! top, as glTF's KTX2 images are (KHR_texture_basisu, "KTX2 orientation").
//!
//! Not decoded, each with one warning that names it: Basis Universal (BasisLZ/ETC1S and
//! UASTC: no maintained pure-Rust transcoder), block-compressed formats (BC, ETC, ASTC), 16-
//! and 32-bit formats, zlib supercompression, cube maps, arrays and 3D images.

use std::fmt;
use std::io::Read;

use ktx2::{Format, SupercompressionScheme};

/// The first 12 bytes of every KTX2 file (KTX 2.0 section 3.1).
pub(crate) const SIGNATURE: &[u8; 12] = b"\xABKTX 20\xBB\r\n\x1A\n";

/// The DFD colour model of UASTC (KHR Data Format 1.3, `KHR_DF_MODEL_UASTC`).
const COLOR_MODEL_UASTC: u8 = 166;

/// Why a KTX2 file was not decoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Ktx2Error {
    /// The container is malformed (the `ktx2` crate's reason).
    Container(String),
    /// Basis Universal data (BasisLZ/ETC1S or UASTC), which seamlit does not transcode.
    BasisUniversal,
    /// A format other than the 8-bit ones read here (its Vulkan name, or its number).
    Format(String),
    /// A supercompression scheme other than Zstandard.
    Supercompression(String),
    /// A cube map, array or 3D texture where glTF wants one 2D image.
    NotTwoDimensional,
    /// Level 0 is not the size its header says (after decompression).
    Length {
        /// Bytes the header's dimensions and format need.
        expected: u64,
        /// Bytes there are.
        actual: u64,
    },
    /// The Zstandard stream is corrupt.
    Zstandard(String),
    /// Wider or higher than the limit.
    TooLarge {
        /// Width and height.
        size: (u32, u32),
        /// The limit on each.
        limit: u32,
    },
}

impl fmt::Display for Ktx2Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Container(why) => write!(f, "KTX2: {why}"),
            Self::BasisUniversal => f.write_str(
                "KTX2 with Basis Universal data (ETC1S/UASTC) is not supported: there is no maintained pure-Rust transcoder",
            ),
            Self::Format(format) => write!(
                f,
                "KTX2 format {format} is not supported (8-bit R, RG, RGB and RGBA formats are)"
            ),
            Self::Supercompression(scheme) => write!(
                f,
                "KTX2 supercompression {scheme} is not supported (none and Zstandard are)"
            ),
            Self::NotTwoDimensional => {
                f.write_str("KTX2 cube maps, arrays and 3D images are not glTF textures")
            }
            Self::Length { expected, actual } => {
                write!(f, "KTX2 level 0 has {actual} bytes where its header needs {expected}")
            }
            Self::Zstandard(why) => write!(f, "KTX2 Zstandard data: {why}"),
            Self::TooLarge { size: (w, h), limit } => {
                write!(f, "KTX2 image is {w} x {h}, past the limit of {limit} texels a side")
            }
        }
    }
}

/// Whether `bytes` start like a KTX2 file.
#[must_use]
pub(crate) fn is_ktx2(bytes: &[u8]) -> bool {
    bytes.starts_with(SIGNATURE)
}

/// How the texels of a format read as RGBA: bytes per texel and, per output channel, the
/// input byte it comes from (`None`: 0 for colour, 255 for alpha).
struct Layout {
    bytes: usize,
    channels: [Option<usize>; 4],
}

/// The layout of the 8-bit formats read here; `None` for any other.
fn layout(format: Format) -> Option<Layout> {
    let (bytes, channels) = match format {
        Format::R8_UNORM | Format::R8_SRGB | Format::R8_UINT => (1, [Some(0), None, None, None]),
        Format::R8G8_UNORM | Format::R8G8_SRGB | Format::R8G8_UINT => {
            (2, [Some(0), Some(1), None, None])
        }
        Format::R8G8B8_UNORM | Format::R8G8B8_SRGB | Format::R8G8B8_UINT => {
            (3, [Some(0), Some(1), Some(2), None])
        }
        Format::B8G8R8_UNORM | Format::B8G8R8_SRGB | Format::B8G8R8_UINT => {
            (3, [Some(2), Some(1), Some(0), None])
        }
        Format::R8G8B8A8_UNORM | Format::R8G8B8A8_SRGB | Format::R8G8B8A8_UINT => {
            (4, [Some(0), Some(1), Some(2), Some(3)])
        }
        Format::B8G8R8A8_UNORM | Format::B8G8R8A8_SRGB | Format::B8G8R8A8_UINT => {
            (4, [Some(2), Some(1), Some(0), Some(3)])
        }
        _ => return None,
    };
    Some(Layout { bytes, channels })
}

/// A parsed KTX2 file whose level 0 this module can decode.
struct Checked<'a> {
    reader: ktx2::Reader<&'a [u8]>,
    layout: Layout,
    width: u32,
    height: u32,
}

/// Parses the container and checks everything but the data: a 2D image, a format and a
/// supercompression this module reads.
fn check(bytes: &[u8]) -> Result<Checked<'_>, Ktx2Error> {
    let reader = ktx2::Reader::new(bytes).map_err(|e| Ktx2Error::Container(e.to_string()))?;
    let header = reader.header();
    match header.supercompression_scheme {
        None | Some(SupercompressionScheme::Zstandard) => {}
        Some(SupercompressionScheme::BasisLZ) => return Err(Ktx2Error::BasisUniversal),
        Some(other) => return Err(Ktx2Error::Supercompression(format!("{other:?}"))),
    }
    let Some(format) = header.format else {
        // VK_FORMAT_UNDEFINED: the DFD says what it is; UASTC is Basis Universal.
        // (The colour model is the basic block's first byte; read here, since the crate's
        // DfdBlockBasic::parse panics on some malformed blocks.)
        let uastc = reader.dfd_blocks().any(|block| block.data.first() == Some(&COLOR_MODEL_UASTC));
        return Err(if uastc {
            Ktx2Error::BasisUniversal
        } else {
            Ktx2Error::Format("UNDEFINED".to_owned())
        });
    };
    let layout = layout(format).ok_or_else(|| Ktx2Error::Format(format!("{format:?}")))?;
    if header.face_count != 1 || header.layer_count > 1 || header.pixel_depth > 1 {
        return Err(Ktx2Error::NotTwoDimensional);
    }
    Ok(Checked { reader, layout, width: header.pixel_width, height: header.pixel_height.max(1) })
}

/// The width and height of a KTX2 image this module can decode.
///
/// # Errors
///
/// [`Ktx2Error`] where the file is malformed or not one this module decodes.
pub(crate) fn dimensions(bytes: &[u8]) -> Result<(u32, u32), Ktx2Error> {
    check(bytes).map(|c| (c.width, c.height))
}

/// Level 0 of a KTX2 image as RGBA8, at most `max_size` wide and high (checked before any
/// texel is decoded).
///
/// # Errors
///
/// [`Ktx2Error`] where the file is malformed, not one this module decodes, over the size
/// limit, or its level 0 is not the length its header says.
pub(crate) fn decode(bytes: &[u8], max_size: u32) -> Result<image::RgbaImage, Ktx2Error> {
    let Checked { reader, layout, width, height } = check(bytes)?;
    if width > max_size || height > max_size {
        return Err(Ktx2Error::TooLarge { size: (width, height), limit: max_size });
    }
    let texels = u64::from(width) * u64::from(height);
    let expected = texels * layout.bytes as u64;
    let level = reader.levels().next().ok_or(Ktx2Error::Length { expected, actual: 0 })?;
    let data = match reader.header().supercompression_scheme {
        Some(SupercompressionScheme::Zstandard) => unzstd(level.data, expected)?,
        _ => level.data.to_vec(),
    };
    if data.len() as u64 != expected {
        return Err(Ktx2Error::Length { expected, actual: data.len() as u64 });
    }
    let mut rgba = Vec::with_capacity(data.len() / layout.bytes * 4);
    for texel in data.chunks_exact(layout.bytes) {
        for (c, from) in layout.channels.iter().enumerate() {
            rgba.push(from.map_or(if c == 3 { u8::MAX } else { 0 }, |i| texel[i]));
        }
    }
    image::RgbaImage::from_raw(width, height, rgba)
        .ok_or(Ktx2Error::Length { expected, actual: data.len() as u64 })
}

/// A Zstandard frame decompressed, reading at most one byte past `expected` (so a stream
/// that claims more allocates no more).
fn unzstd(data: &[u8], expected: u64) -> Result<Vec<u8>, Ktx2Error> {
    let decoder = ruzstd::decoding::StreamingDecoder::new(data)
        .map_err(|e| Ktx2Error::Zstandard(e.to_string()))?;
    let mut out = Vec::new();
    decoder
        .take(expected + 1)
        .read_to_end(&mut out)
        .map_err(|e| Ktx2Error::Zstandard(e.to_string()))?;
    Ok(out)
}
