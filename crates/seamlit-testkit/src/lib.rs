//! # seamlit-testkit
//!
//! What seamlit's tests and benchmark generators share, and nothing a user of seamlit needs:
//! the glTF [`Buffer`] that models built in code are written with, and the two-object
//! skinned, animated [`character`] the animation tests of several crates load. Not published.
//!
//! ```
//! use seamlit_testkit::Buffer;
//!
//! let mut buffer = Buffer::default();
//! let positions = buffer.vec3(&[glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y]);
//! let indices = buffer.indices(&[0, 1, 2]);
//! assert_eq!((positions, indices), (0, 1));
//! assert_eq!(buffer.accessors[0]["max"], serde_json::json!([1.0, 1.0, 0.0]));
//! assert_eq!(buffer.bin.len(), 3 * 12 + 3 * 2); // the next view would start at 44
//! ```

pub mod character;

use glam::Vec3;
use serde_json::{Value, json};

/// glTF's `bufferView.target` for vertex attributes (`ARRAY_BUFFER`).
pub const ARRAY_BUFFER: u32 = 34962;
/// glTF's `bufferView.target` for indices (`ELEMENT_ARRAY_BUFFER`).
pub const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// A glTF buffer under construction: its bytes, one view per accessor, and the accessors.
/// Every view starts at a multiple of 4 bytes, as glTF requires of vertex data.
#[derive(Debug, Default)]
pub struct Buffer {
    /// The buffer's bytes.
    pub bin: Vec<u8>,
    /// The document's `bufferViews`, all of buffer 0.
    pub views: Vec<Value>,
    /// The document's `accessors`.
    pub accessors: Vec<Value>,
}

impl Buffer {
    /// Appends `bytes` as a view of its own (with `target`, if any) and `accessor` over it
    /// (its `bufferView` set here); returns the accessor's index.
    pub fn push(&mut self, bytes: &[u8], mut accessor: Value, target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut view =
            json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()});
        if let Some(target) = target {
            view["target"] = json!(target);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(view);
        accessor["bufferView"] = json!(self.views.len() - 1);
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// A `FLOAT` accessor of type `kind` (`SCALAR`, `VEC2` ... `MAT4`) over `values`, with
    /// `min` and `max` where `bounds` (POSITION and animation inputs need them).
    ///
    /// # Panics
    ///
    /// On an unknown `kind`, or `values` not a whole number of elements.
    pub fn floats(
        &mut self,
        values: &[f32],
        kind: &str,
        bounds: bool,
        target: Option<u32>,
    ) -> usize {
        let width = components(kind);
        assert!(values.len().is_multiple_of(width), "{} floats are not {kind}s", values.len());
        let bytes: Vec<u8> = values.iter().flat_map(|f| f.to_le_bytes()).collect();
        let mut accessor =
            json!({"componentType": 5126, "count": values.len() / width, "type": kind});
        if bounds {
            let mut lo = vec![f32::INFINITY; width];
            let mut hi = vec![f32::NEG_INFINITY; width];
            for element in values.chunks(width) {
                for (i, &v) in element.iter().enumerate() {
                    lo[i] = lo[i].min(v);
                    hi[i] = hi[i].max(v);
                }
            }
            accessor["min"] = json!(lo);
            accessor["max"] = json!(hi);
        }
        self.push(&bytes, accessor, target)
    }

    /// A `FLOAT` `VEC3` accessor over `values`, with its bounds and no view target.
    pub fn vec3(&mut self, values: &[Vec3]) -> usize {
        let flat: Vec<f32> = values.iter().flat_map(|v| v.to_array()).collect();
        self.floats(&flat, "VEC3", true, None)
    }

    /// An `UNSIGNED_SHORT` `SCALAR` index accessor, no view target.
    pub fn indices(&mut self, indices: &[u16]) -> usize {
        let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        self.push(
            &bytes,
            json!({"componentType": 5123, "count": indices.len(), "type": "SCALAR"}),
            None,
        )
    }
}

/// A GLB file of `document` and `bin` (the BIN chunk, buffer 0), each chunk padded to 4 bytes
/// (the JSON with spaces, the BIN with zeros), as the GLB container requires.
///
/// # Panics
///
/// Never for a document `serde_json` can write and a file under 4 GiB.
#[must_use]
pub fn glb(document: &Value, bin: &[u8]) -> Vec<u8> {
    glb_of_text(&serde_json::to_vec(document).expect("a JSON value"), bin)
}

/// [`glb`] of JSON text as it is (valid or not: the mutation tests' inputs).
///
/// # Panics
///
/// For a file of 4 GiB or more.
#[must_use]
pub fn glb_of_text(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let mut json = json.to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let length = |n: usize| u32::try_from(n).expect("a GLB under 4 GiB").to_le_bytes();
    let mut out = Vec::with_capacity(28 + json.len() + bin.len());
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&length(12 + 8 + json.len() + 8 + bin.len()));
    out.extend_from_slice(&length(json.len()));
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&length(bin.len()));
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// The number of components of an accessor type (`SCALAR` 1 ... `MAT4` 16).
///
/// # Panics
///
/// On a string that is no accessor type.
#[must_use]
pub fn components(kind: &str) -> usize {
    match kind {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" | "MAT2" => 4,
        "MAT3" => 9,
        "MAT4" => 16,
        _ => panic!("{kind} is not a glTF accessor type"),
    }
}

/// A fixed pseudo-random sequence (Marsaglia's xorshift64), the same on every run: which
/// bytes the corruption tests overwrite, and with what. `seed` must not be 0.
///
/// ```
/// let mut next = seamlit_testkit::xorshift(0x2545_f491_4f6c_dd1d);
/// let (a, b) = (next(), next());
/// assert_ne!(a, b);
/// assert_eq!(a, seamlit_testkit::xorshift(0x2545_f491_4f6c_dd1d)());
/// ```
pub fn xorshift(seed: u64) -> impl FnMut() -> u64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_start_on_four_bytes_and_carry_their_target() {
        let mut buffer = Buffer::default();
        buffer.push(&[1, 2, 3], json!({}), Some(ELEMENT_ARRAY_BUFFER));
        let at = buffer.floats(&[1.0, -2.0, 0.5, 4.0], "VEC2", true, Some(ARRAY_BUFFER));
        assert_eq!(at, 1);
        assert_eq!(buffer.views[1]["byteOffset"], json!(4));
        assert_eq!(buffer.views[1]["target"], json!(ARRAY_BUFFER));
        assert_eq!(buffer.accessors[1]["count"], json!(2));
        assert_eq!(buffer.accessors[1]["min"], json!([0.5, -2.0]));
        assert_eq!(buffer.accessors[1]["max"], json!([1.0, 4.0]));
        assert_eq!(buffer.views[0].get("target"), Some(&json!(ELEMENT_ARRAY_BUFFER)));
    }
}
