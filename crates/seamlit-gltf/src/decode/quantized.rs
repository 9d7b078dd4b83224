//! KHR_mesh_quantization: POSITION, NORMAL, TANGENT and TEXCOORD_n stored as 8- or 16-bit
//! integers, normalised or not. [`read_floats`] reads any of them as floats, by the
//! specification's conversion (`max(c / 127, -1)` for a normalised byte, `c / 65535` for a
//! normalised unsigned short, the integer itself when not normalised); the node transform
//! that usually undoes a quantised position's scale is applied as any node transform is.
//! The pass-through writer keeps these accessors' bytes as they are.

use bytes::Bytes;
use gltf::accessor::{DataType, Item, Iter};

/// Reads an accessor of `N` components as floats, whatever its component type: `FLOAT` as
/// is; `BYTE`, `UNSIGNED_BYTE`, `SHORT`, `UNSIGNED_SHORT` normalised when the accessor says
/// `normalized` (glTF 2.0, "Accessor data types"), else converted as integers
/// (KHR_mesh_quantization). Sparse values are substituted. `None` for `UNSIGNED_INT` or when
/// the accessor's data cannot be reached (the caller checked it lies in its view).
pub(crate) fn read_floats<const N: usize>(
    accessor: &gltf::Accessor<'_>,
    buffers: &[Bytes],
) -> Option<Vec<[f32; N]>>
where
    [f32; N]: Item,
    [i8; N]: Item,
    [u8; N]: Item,
    [i16; N]: Item,
    [u16; N]: Item,
{
    let get = |b: gltf::Buffer<'_>| buffers.get(b.index()).map(|d| &d[..]);
    let normalized = accessor.normalized();
    fn convert<T: Copy, const N: usize>(
        iter: impl Iterator<Item = [T; N]>,
        f: impl Fn(T) -> f32,
    ) -> Vec<[f32; N]> {
        iter.map(|element| element.map(&f)).collect()
    }
    let a = accessor.clone();
    Some(match accessor.data_type() {
        DataType::F32 => Iter::<[f32; N]>::new(a, get)?.collect(),
        DataType::I8 => convert(Iter::<[i8; N]>::new(a, get)?, |c| match normalized {
            true => (f32::from(c) / 127.0).max(-1.0),
            false => f32::from(c),
        }),
        DataType::U8 => convert(Iter::<[u8; N]>::new(a, get)?, |c| match normalized {
            true => f32::from(c) / 255.0,
            false => f32::from(c),
        }),
        DataType::I16 => convert(Iter::<[i16; N]>::new(a, get)?, |c| match normalized {
            true => (f32::from(c) / 32767.0).max(-1.0),
            false => f32::from(c),
        }),
        DataType::U16 => convert(Iter::<[u16; N]>::new(a, get)?, |c| match normalized {
            true => f32::from(c) / 65535.0,
            false => f32::from(c),
        }),
        DataType::U32 => return None,
    })
}

/// Reads a NORMAL (`N = 3`) or TANGENT (`N = 4`) accessor as [`read_floats`] does; when it
/// is stored as integers (KHR_mesh_quantization), the `xyz` of each element is rescaled to
/// unit length: an 8-bit normal is a unit vector only up to its rounding (a length of 0.99
/// is common), and the frames seamlit keeps or orthogonalises against must be unit.
pub(crate) fn read_directions<const N: usize>(
    accessor: &gltf::Accessor<'_>,
    buffers: &[Bytes],
) -> Option<Vec<[f32; N]>>
where
    [f32; N]: Item,
    [i8; N]: Item,
    [u8; N]: Item,
    [i16; N]: Item,
    [u16; N]: Item,
{
    let mut values = read_floats::<N>(accessor, buffers)?;
    if accessor.data_type() != DataType::F32 {
        for v in &mut values {
            let length = v.iter().take(3).map(|c| c * c).sum::<f32>().sqrt();
            if length > 0.0 {
                v.iter_mut().take(3).for_each(|c| *c /= length);
            }
        }
    }
    Some(values)
}
