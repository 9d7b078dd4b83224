//! Accessors whose bytes buffer 0 gave back because the model holds their elements bit for
//! bit (`passthrough/unread.rs`): written again from the model, as little-endian floats a
//! chunk at a time, and checked against a hash of the bytes they replace.

use std::hash::Hasher;
use std::io;
use std::ops::Range;

use rustc_hash::FxHasher;
use seamlit_mesh::Object;

use crate::chunks::{CHUNK, each_chunk, le};

/// Which of an object's arrays an accessor's elements are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Attribute {
    /// `POSITION`: [`Object::positions`].
    Positions,
    /// `TEXCOORD_0`: [`Object::uvs`].
    Uvs,
}

impl Attribute {
    /// The accessor `type` it is stored as (of floats).
    pub(crate) fn shape(self) -> &'static str {
        match self {
            Self::Positions => "VEC3",
            Self::Uvs => "VEC2",
        }
    }

    /// Bytes per element.
    pub(crate) fn element_size(self) -> usize {
        match self {
            Self::Positions => 12,
            Self::Uvs => 8,
        }
    }

    /// Gives `each` the file's bytes of `object`'s first `count` elements, [`CHUNK`]
    /// elements at a time; `false` where the object has fewer.
    fn chunks(
        self,
        object: &Object,
        count: usize,
        mut each: impl FnMut(&[u8]) -> io::Result<()>,
    ) -> io::Result<bool> {
        match self {
            Self::Positions => {
                encode(object.positions.get(..count), |p| le(p.to_array()), &mut each)
            }
            Self::Uvs => {
                let uvs = object.uvs.as_deref().and_then(|uvs| uvs.get(..count));
                encode(uvs, |uv| le(uv.to_array()), &mut each)
            }
        }
    }
}

/// [`Attribute::chunks`] of one array: `false` where it is missing.
fn encode<T, E: bytemuck::Pod>(
    items: Option<&[T]>,
    encode: impl Fn(&T) -> E,
    each: &mut impl FnMut(&[u8]) -> io::Result<()>,
) -> io::Result<bool> {
    let Some(items) = items else { return Ok(false) };
    each_chunk(items, encode, each).map(|()| true)
}

/// An accessor of buffer 0 given back at load, its elements the model's.
#[derive(Clone, Debug)]
pub(crate) struct FromModel {
    /// The accessor's index.
    pub(crate) accessor: usize,
    /// Its elements' bytes in buffer 0 (offsets as loaded), tightly packed.
    pub(crate) bytes: Range<usize>,
    pub(crate) attribute: Attribute,
    /// The objects whose elements these are (several where the primitive is instanced).
    pub(crate) objects: Vec<usize>,
}

impl FromModel {
    /// How many elements.
    fn count(&self) -> usize {
        self.bytes.len() / self.attribute.element_size()
    }

    /// The hash of its bytes as loaded, `host` being buffer 0.
    pub(crate) fn hash_of(&self, host: &[u8]) -> u64 {
        let mut hasher = FxHasher::default();
        for chunk in host[self.bytes.clone()].chunks(CHUNK * self.attribute.element_size()) {
            hasher.write(chunk);
        }
        hasher.finish()
    }

    /// The hash of `object`'s elements as the file's bytes ([`Self::hash_of`] of them);
    /// `None` where it has fewer.
    pub(crate) fn hash_in(&self, object: &Object) -> Option<u64> {
        let mut hasher = FxHasher::default();
        let whole = self.attribute.chunks(object, self.count(), |chunk| {
            hasher.write(chunk);
            Ok(())
        });
        whole.ok().filter(|&w| w).map(|_| hasher.finish())
    }

    /// Writes the bytes of `range` (offsets as loaded, inside [`Self::bytes`]) from
    /// `object`'s elements; zeros where it has fewer.
    pub(crate) fn write(
        &self,
        object: &Object,
        range: Range<usize>,
        out: &mut dyn io::Write,
    ) -> io::Result<()> {
        let mut at = self.bytes.start;
        let whole = self.attribute.chunks(object, self.count(), |chunk| {
            let (from, to) = (range.start.max(at), range.end.min(at + chunk.len()));
            if from < to {
                out.write_all(&chunk[from - at..to - at])?;
            }
            at += chunk.len();
            Ok(())
        })?;
        if !whole {
            super::zeros(out, range.len())?;
        }
        Ok(())
    }

    /// `object`'s elements as the file's bytes, all of them.
    pub(crate) fn bytes_in(&self, object: &Object) -> Option<Vec<u8>> {
        let mut bytes = Vec::with_capacity(self.bytes.len());
        let whole = self.attribute.chunks(object, self.count(), |chunk| {
            bytes.extend_from_slice(chunk);
            Ok(())
        });
        whole.ok().filter(|&w| w).map(|_| bytes)
    }
}
