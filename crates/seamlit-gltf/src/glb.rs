//! The GLB container (glTF 2.0, "GLB File Format Specification"): a 12-byte header, a JSON
//! chunk and an optional BIN chunk. Split when reading ([`chunks`]), assembled when writing
//! ([`write`]).

use std::io::Write;
use std::ops::Range;
use std::path::Path;

use seamlit_asset::error::gltf::{Glb, GltfKind};
use seamlit_asset::error::{InvalidAsset, IoError};
use seamlit_asset::files::Destination;

/// The JSON chunk's and, when the second chunk is one, the BIN chunk's data in GLB `bytes`,
/// after checking the 12-byte header and the chunk headers against the declared length, so
/// that a truncated file gets a message that says how much is missing. As the
/// specification allows, bytes after the declared length and chunks of other types after
/// the first two are ignored.
pub(crate) fn chunks(
    bytes: &[u8],
    path: &Path,
) -> Result<(Range<usize>, Option<Range<usize>>), IoError> {
    let err = |kind: Glb| IoError::Gltf {
        path: path.to_path_buf(),
        place: "GLB container".to_owned(),
        kind: GltfKind::Glb(kind),
    };
    let word = |at: usize| -> Option<u32> {
        bytes.get(at..at + 4).and_then(|b| b.try_into().ok()).map(u32::from_le_bytes)
    };
    let (Some(version), Some(declared)) = (word(4), word(8)) else {
        return Err(err(Glb::ShortHeader { bytes: bytes.len() }));
    };
    if version != 2 {
        return Err(err(Glb::Version { version }));
    }
    let declared = declared as usize;
    if declared > bytes.len() {
        return Err(err(Glb::Truncated { declared, bytes: bytes.len() }));
    }
    let mut at = 12;
    let mut chunk = 0;
    let mut chunks = Vec::new();
    while at < declared {
        let (Some(length), Some(kind)) = (word(at), word(at + 4)) else {
            return Err(err(Glb::ShortChunkHeader { chunk, at }));
        };
        let end = at as u64 + 8 + u64::from(length);
        if end > declared as u64 {
            return Err(err(Glb::ShortChunk {
                chunk,
                chunk_type: String::from_utf8_lossy(&kind.to_le_bytes()).into_owned(),
                length,
                start: at + 8,
                declared,
            }));
        }
        #[expect(clippy::cast_possible_truncation, reason = "at most `declared`, checked above")]
        let end = end as usize;
        chunks.push((kind, at + 8..end));
        at = end;
        chunk += 1;
    }
    match chunks.as_slice() {
        [(JSON_CHUNK, json), rest @ ..] => Ok((
            json.clone(),
            rest.first().filter(|(kind, _)| *kind == BIN_CHUNK).map(|(_, bin)| bin.clone()),
        )),
        [(kind, _), ..] => Err(err(Glb::FirstChunkNotJson {
            chunk_type: String::from_utf8_lossy(&kind.to_le_bytes())
                .trim_end_matches('\0')
                .to_owned(),
        })),
        [] => Err(err(Glb::NoJsonChunk)),
    }
}

/// GLB chunk types: `JSON` and `BIN\0`, little-endian.
const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;

/// Writes a GLB to `to` (atomically to a file): a 12-byte header, the JSON chunk (padded with spaces), and, when
/// `bin_len` is given, the BIN chunk of that many bytes that `write_bin` writes (padded with
/// zeros), each chunk behind an 8-byte header of its length and type.
///
/// # Errors
///
/// [`IoError::InvalidAsset`] for a file over the format's 4 GiB; [`IoError::Io`] when writing
/// fails.
pub(crate) fn write(
    to: &mut Destination,
    path: &Path,
    mut json: Vec<u8>,
    bin_len: Option<usize>,
    write_bin: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), IoError> {
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let bin_padded = bin_len.map(|n| n.next_multiple_of(4));
    let length = 12 + 8 + json.len() + bin_padded.map_or(0, |b| 8 + b);
    let word = |n: usize| {
        u32::try_from(n).map_err(|_| IoError::InvalidAsset {
            path: path.to_path_buf(),
            object: String::new(),
            kind: InvalidAsset::GlbTooLarge { bytes: length },
        })
    };
    let (length, json_length) = (word(length)?, word(json.len())?);
    let bin_chunk_length = bin_padded.map(word).transpose()?;
    to.write_with(path, |out| {
        out.write_all(b"glTF")?;
        out.write_all(&2u32.to_le_bytes())?;
        out.write_all(&length.to_le_bytes())?;
        out.write_all(&json_length.to_le_bytes())?;
        out.write_all(b"JSON")?;
        out.write_all(&json)?;
        if let (Some(chunk), Some(len), Some(padded)) = (bin_chunk_length, bin_len, bin_padded) {
            out.write_all(&chunk.to_le_bytes())?;
            out.write_all(b"BIN\0")?;
            write_bin(out)?;
            out.write_all(&[0; 3][..padded - len])?;
        }
        Ok(())
    })
}
