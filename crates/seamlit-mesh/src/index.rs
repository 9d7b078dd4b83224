//! 32-bit indices, and the one invariant that makes them safe.
//!
//! The pipeline numbers vertices, triangles, corners and the frames of complex positions with
//! `u32` (half the memory of `usize`, and what `Object::triangles` and the files use).
//! [`crate::validate::flatten`], which every entry point runs first, refuses a model whose
//! vertices, corners, or vertices plus corners exceed [`MAX_ELEMENTS`] (below `u32::MAX`).
//! Every index and count derived from them fits in a `u32`: a vertex, triangle or corner of
//! the model, the corners and frames of one position (at most one frame per corner), and the
//! vertices that `fix` adds to an object (at most one per corner).

use crate::MAX_ELEMENTS;

/// `i`, an index or count of the pipeline (see the module), as a `u32`.
///
/// Debug builds check the invariant; release builds compile this to nothing.
#[inline]
#[must_use]
#[expect(
    clippy::cast_possible_truncation,
    reason = "at most MAX_ELEMENTS (< u32::MAX), which validate::flatten checks"
)]
pub(crate) fn index(i: usize) -> u32 {
    debug_assert!(i <= MAX_ELEMENTS, "{i} is past the 32-bit indices flatten checked");
    i as u32
}

/// The low half of a packed `key << 32 | index` entry (the pipeline sorts such entries to
/// group indices by key): the index.
#[inline]
#[must_use]
pub(crate) const fn low_half(entry: u64) -> u32 {
    (entry & 0xFFFF_FFFF) as u32
}

/// The part that element `i` of a concatenation belongs to, where `starts` holds each part's
/// first element (ascending; one extra entry at the end): the last part starting at or
/// before `i`, so that empty parts, which start there too, are passed over.
#[inline]
#[must_use]
pub(crate) fn part_of(starts: &[u32], i: usize) -> usize {
    starts.partition_point(|&s| s as usize <= i) - 1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_element_belongs_to_the_last_part_starting_at_or_before_it() {
        // Parts 0..2, an empty part at 2, 2..5, an empty last part.
        let starts = [0, 2, 2, 5, 5];
        let parts: Vec<usize> = (0..5).map(|i| part_of(&starts, i)).collect();
        assert_eq!(parts, [0, 0, 2, 2, 2]);
    }

    #[test]
    fn packed_entries_give_back_their_index() {
        for (key, i) in [(0u64, 0u32), (7, 1), (u64::from(u32::MAX), u32::MAX - 1)] {
            assert_eq!(low_half((key << 32) | u64::from(i)), i);
        }
    }

    #[test]
    fn the_largest_model_index_fits() {
        assert_eq!(index(MAX_ELEMENTS), u32::MAX - 1);
        assert_eq!(index(0), 0);
    }
}
