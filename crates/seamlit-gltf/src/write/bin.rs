//! The binary buffer's parts: the asset's data, written little-endian when the file is
//! written, never assembled in memory.

use std::io::{self, Write};

use glam::{Vec2, Vec3, Vec4};

use seamlit_asset::check::{unit_normal, unit_tangent};

use crate::chunks::{chunked, le};

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

    /// Writes the piece, little-endian, [`CHUNK`] elements at a time.
    pub(super) fn write(&self, out: &mut dyn Write) -> io::Result<()> {
        match self {
            Self::Positions(v) => chunked(out, v, |p| le(p.to_array())),
            Self::Normals(v) => chunked(out, v, |&n| le(unit_normal(n).to_array())),
            Self::Tangents(v) => chunked(out, v, |&t| le(unit_tangent(t).to_array())),
            Self::Colors(v) => chunked(out, v, |x| le(x.to_array())),
            Self::Uvs { uvs, flip } => {
                chunked(out, uvs, |t| le([t.x, if *flip { 1.0 - t.y } else { t.y }]))
            }
            Self::Joints(joints) => chunked(out, joints, |j| j.map(u16::to_le)),
            Self::Weights(weights) => chunked(out, weights, |&w| le(w)),
            Self::Floats(values) => chunked(out, values, |&x| le([x])),
            // Every index is below 65535, checked by the caller.
            #[expect(clippy::cast_possible_truncation, reason = "below 65535, checked")]
            Self::Indices16(triangles) => {
                chunked(out, triangles, |t| t.map(|i| (i as u16).to_le()))
            }
            Self::Indices32(triangles) => chunked(out, triangles, |t| t.map(u32::to_le)),
            Self::Bytes(bytes) => out.write_all(bytes),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chunks::CHUNK;

    fn written(part: &BinPart<'_>) -> Vec<u8> {
        let mut out = Vec::new();
        part.write(&mut out).unwrap();
        assert_eq!(out.len(), part.len());
        out
    }

    fn le(values: &[f32]) -> Vec<u8> {
        values.iter().flat_map(|x| x.to_le_bytes()).collect()
    }

    /// Written a chunk at a time, every part is its elements' little-endian bytes in order,
    /// across the chunks' ends.
    #[test]
    #[expect(clippy::cast_possible_truncation, reason = "small test values")]
    #[expect(clippy::cast_precision_loss, reason = "small test values")]
    fn parts_written_in_chunks_are_their_elements_in_order() {
        let n = CHUNK * 2 + 7;
        let f = |i: usize| i as f32;
        let v3: Vec<Vec3> = (0..n).map(|i| Vec3::new(f(i), -f(i), 0.5)).collect();
        let units: Vec<Vec3> = (0..n).map(|i| Vec3::new(f(i % 7) + 1.0, 0.0, 0.0)).collect();
        let v4: Vec<Vec4> = (0..n).map(|i| Vec4::new(f(i), 2.0, 3.0, -f(i))).collect();
        let tangents: Vec<Vec4> = (0..n)
            .map(|i| Vec4::new(0.0, f(i % 5) + 1.0, 0.0, if i % 2 == 0 { 1.0 } else { -0.5 }))
            .collect();
        let uvs: Vec<Vec2> = (0..n).map(|i| Vec2::new(f(i), 0.25)).collect();
        let joints: Vec<[u16; 4]> = (0..n).map(|i| [i as u16, 1, 2, 3]).collect();
        let weights: Vec<[f32; 4]> = (0..n).map(|i| [f(i), 0.0, 0.0, 1.0]).collect();
        let floats: Vec<f32> = (0..n).map(f).collect();
        let triangles: Vec<[u32; 3]> = (0..n as u32).map(|i| [i, i + 1, i % 60_000]).collect();

        let xyz = |v: &[Vec3]| le(&v.iter().flat_map(|p| p.to_array()).collect::<Vec<_>>());
        assert_eq!(written(&BinPart::Positions(&v3)), xyz(&v3));
        let unit: Vec<Vec3> = (0..n).map(|_| Vec3::X).collect();
        assert_eq!(written(&BinPart::Normals(&units)), xyz(&unit));
        assert_eq!(
            written(&BinPart::Colors(&v4)),
            le(&v4.iter().flat_map(|c| c.to_array()).collect::<Vec<_>>())
        );
        let expected: Vec<f32> =
            (0..n).flat_map(|i| [0.0, 1.0, 0.0, if i % 2 == 0 { 1.0 } else { -1.0 }]).collect();
        assert_eq!(written(&BinPart::Tangents(&tangents)), le(&expected));
        let flipped: Vec<f32> = uvs.iter().flat_map(|t| [t.x, 0.75]).collect();
        assert_eq!(written(&BinPart::Uvs { uvs: &uvs, flip: true }), le(&flipped));
        let kept: Vec<f32> = uvs.iter().flat_map(|t| [t.x, t.y]).collect();
        assert_eq!(written(&BinPart::Uvs { uvs: &uvs, flip: false }), le(&kept));
        let joint_bytes: Vec<u8> =
            joints.iter().flat_map(|j| j.iter().flat_map(|x| x.to_le_bytes())).collect();
        assert_eq!(written(&BinPart::Joints(joints)), joint_bytes);
        assert_eq!(written(&BinPart::Weights(&weights)), le(weights.as_flattened()));
        assert_eq!(written(&BinPart::Floats(floats.clone())), le(&floats));
        let short: Vec<u8> =
            triangles.iter().flatten().flat_map(|&i| (i as u16).to_le_bytes()).collect();
        assert_eq!(written(&BinPart::Indices16(&triangles)), short);
        let int: Vec<u8> = triangles.iter().flatten().flat_map(|i| i.to_le_bytes()).collect();
        assert_eq!(written(&BinPart::Indices32(&triangles)), int);
        assert_eq!(written(&BinPart::Bytes(vec![1, 2, 3])), [1, 2, 3]);
    }
}
