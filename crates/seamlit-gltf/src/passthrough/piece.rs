//! The data a save appends to buffer 0 (`passthrough.rs`): bytes made when appended, or the
//! fixed model's normals, tangents and indices, which are encoded from the model while the
//! file is written, a chunk at a time. They are most of what a fix adds (two thirds of the 1M
//! teapot's output), and a save that made them up front held a second copy of them at its
//! memory peak.

use std::borrow::Cow;
use std::io::{self, Write};

use glam::{Vec3, Vec4};
use seamlit_asset::check::{unit_normal, unit_tangent};

use crate::chunks::{chunked, le};

/// One piece of appended data.
pub(super) enum Piece<'a> {
    /// Bytes made when the piece was appended.
    Bytes(Vec<u8>),
    /// Normals, each made unit ([`unit_normal`]), as `FLOAT` `VEC3`.
    Normals(&'a [Vec3]),
    /// Tangents, each made unit with its handedness ([`unit_tangent`]), as `FLOAT` `VEC4`.
    Tangents(&'a [Vec4]),
    /// Triangle corners as little-endian indices of `size` bytes (1, 2 or 4); every corner
    /// fits (the caller chose the size).
    Indices { corners: &'a [u32], size: usize },
}

impl Piece<'_> {
    /// The piece's length in bytes.
    pub(super) fn len(&self) -> usize {
        self.elements() * self.element_size()
    }

    /// All the piece's bytes at once (for data gathered into a compressed view).
    pub(super) fn bytes(&self) -> Cow<'_, [u8]> {
        match self {
            Self::Bytes(bytes) => Cow::Borrowed(bytes),
            _ => {
                let mut bytes = Vec::with_capacity(self.len());
                self.write(&mut bytes).expect("writing into memory does not fail");
                Cow::Owned(bytes)
            }
        }
    }

    /// Writes the piece's bytes to `out`, the same bytes as [`Self::bytes`], encoding at
    /// most [`crate::chunks::CHUNK`] elements at a time.
    pub(super) fn write(&self, out: &mut dyn Write) -> io::Result<()> {
        match self {
            Self::Bytes(bytes) => out.write_all(bytes),
            Self::Normals(normals) => chunked(out, normals, |&n| le(unit_normal(n).to_array())),
            Self::Tangents(tangents) => chunked(out, tangents, |&t| le(unit_tangent(t).to_array())),
            // Every corner fits `size` bytes: the caller's choice.
            #[expect(clippy::cast_possible_truncation, reason = "each index fits `size`")]
            Self::Indices { corners, size } => match size {
                1 => chunked(out, corners, |&i| i as u8),
                2 => chunked(out, corners, |&i| (i as u16).to_le()),
                _ => chunked(out, corners, |&i| i.to_le()),
            },
        }
    }

    fn elements(&self) -> usize {
        match self {
            Self::Bytes(bytes) => bytes.len(),
            Self::Normals(normals) => normals.len(),
            Self::Tangents(tangents) => tangents.len(),
            Self::Indices { corners, .. } => corners.len(),
        }
    }

    fn element_size(&self) -> usize {
        match self {
            Self::Bytes(_) => 1,
            Self::Normals(_) => 12,
            Self::Tangents(_) => 16,
            Self::Indices { size, .. } => *size,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chunks::CHUNK;

    /// Written a chunk at a time or made at once, a piece is the same bytes: what the save
    /// made up front before pieces were written late.
    #[test]
    fn a_piece_written_in_chunks_is_its_bytes() {
        let n = CHUNK * 2 + 7;
        let normals: Vec<Vec3> =
            (0..n).map(|i| Vec3::new(i as f32, 1.0, -(i as f32) * 0.5)).collect();
        let tangents: Vec<Vec4> = (0..n)
            .map(|i| Vec4::new(1.0, i as f32, 0.25, if i % 3 == 0 { -1.0 } else { 1.0 }))
            .collect();
        let corners: Vec<u32> = (0..u32::try_from(n).unwrap()).map(|i| i * 7 % 251).collect();
        let expected_normals: Vec<u8> = normals
            .iter()
            .flat_map(|&v| unit_normal(v).to_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        let expected_tangents: Vec<u8> = tangents
            .iter()
            .flat_map(|&v| unit_tangent(v).to_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        let expected_short: Vec<u8> =
            corners.iter().flat_map(|&i| u16::try_from(i).unwrap().to_le_bytes()).collect();
        let expected_byte: Vec<u8> = corners.iter().map(|&i| u8::try_from(i).unwrap()).collect();
        let expected_int: Vec<u8> = corners.iter().flat_map(|&i| i.to_le_bytes()).collect();
        let cases = [
            (Piece::Normals(&normals), expected_normals),
            (Piece::Tangents(&tangents), expected_tangents),
            (Piece::Indices { corners: &corners, size: 1 }, expected_byte),
            (Piece::Indices { corners: &corners, size: 2 }, expected_short),
            (Piece::Indices { corners: &corners, size: 4 }, expected_int),
            (Piece::Bytes(vec![1, 2, 3]), vec![1, 2, 3]),
        ];
        for (piece, expected) in cases {
            let mut written = Vec::new();
            piece.write(&mut written).unwrap();
            assert_eq!(written, expected);
            assert_eq!(piece.bytes(), expected);
            assert_eq!(piece.len(), expected.len());
        }
    }
}
