//! The binary buffer's parts: the asset's data, written little-endian when the file is
//! written, never assembled in memory.

use std::io::Write;

use glam::{Vec2, Vec3, Vec4};

use seamlit_asset::check::{unit_normal, unit_tangent};

/// A part of the binary buffer, written from the asset when the file is written.
pub(super) enum BinPart<'a> {
    /// Vertex positions (and morph targets' deltas), as they are.
    Positions(&'a [Vec3]),
    /// Normals, made unit length ([`unit_normal`]).
    Normals(&'a [Vec3]),
    /// Tangents, made unit length with w = +-1 ([`unit_tangent`]).
    Tangents(&'a [Vec4]),
    /// Vertex colours, linear RGBA, as they are.
    Colors(&'a [Vec4]),
    /// Texture coordinates, V flipped (`1 - v`) when `flip` is set.
    Uvs { uvs: &'a [Vec2], flip: bool },
    /// Skin joints as u16 (indices into the object's skin's joints).
    Joints(Vec<[u16; 4]>),
    /// Skin weights, as they are.
    Weights(&'a [[f32; 4]]),
    /// Floats, as they are: inverse bind matrices, animation times and values.
    Floats(Vec<f32>),
    /// Triangle indices as u16 (every index is below 65535).
    Indices16(&'a [[u32; 3]]),
    /// Triangle indices as u32.
    Indices32(&'a [[u32; 3]]),
    /// An encoded image.
    Bytes(Vec<u8>),
}

impl BinPart<'_> {
    /// Bytes this piece takes.
    pub(super) fn len(&self) -> usize {
        match self {
            Self::Positions(v) | Self::Normals(v) => v.len() * 12,
            Self::Tangents(v) | Self::Colors(v) => v.len() * 16,
            Self::Uvs { uvs, .. } => uvs.len() * 8,
            Self::Joints(j) => j.len() * 8,
            Self::Weights(w) => w.len() * 16,
            Self::Floats(f) => f.len() * 4,
            Self::Indices16(t) => t.len() * 6,
            Self::Indices32(t) => t.len() * 12,
            Self::Bytes(b) => b.len(),
        }
    }

    /// Writes the piece, little-endian.
    pub(super) fn write(&self, out: &mut dyn Write) -> std::io::Result<()> {
        fn floats<const N: usize>(out: &mut dyn Write, v: [f32; N]) -> std::io::Result<()> {
            let mut bytes = [[0u8; 4]; N];
            for (b, x) in bytes.iter_mut().zip(v) {
                *b = x.to_le_bytes();
            }
            out.write_all(bytes.as_flattened())
        }
        match self {
            Self::Positions(v) => v.iter().try_for_each(|p| floats(out, p.to_array())),
            Self::Normals(v) => v.iter().try_for_each(|&n| floats(out, unit_normal(n).to_array())),
            Self::Tangents(v) => {
                v.iter().try_for_each(|&t| floats(out, unit_tangent(t).to_array()))
            }
            Self::Colors(v) => v.iter().try_for_each(|c| floats(out, c.to_array())),
            Self::Uvs { uvs, flip } => {
                uvs.iter().try_for_each(|t| floats(out, [t.x, if *flip { 1.0 - t.y } else { t.y }]))
            }
            Self::Joints(joints) => joints
                .iter()
                .try_for_each(|j| out.write_all(j.map(u16::to_le_bytes).as_flattened())),
            Self::Weights(weights) => weights.iter().try_for_each(|w| floats(out, *w)),
            Self::Floats(values) => values.iter().try_for_each(|x| out.write_all(&x.to_le_bytes())),
            Self::Indices16(triangles) => triangles.iter().try_for_each(|t| {
                // Every index is below 65535, checked by the caller.
                #[expect(clippy::cast_possible_truncation, reason = "below 65535, checked")]
                let [[a0, a1], [b0, b1], [c0, c1]] = t.map(|i| (i as u16).to_le_bytes());
                out.write_all(&[a0, a1, b0, b1, c0, c1])
            }),
            Self::Indices32(triangles) => triangles
                .iter()
                .try_for_each(|t| out.write_all(t.map(u32::to_le_bytes).as_flattened())),
            Self::Bytes(bytes) => out.write_all(bytes),
        }
    }
}
