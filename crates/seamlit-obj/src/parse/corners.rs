//! Face corners, `v`, `v/vt`, `v//vn` and `v/vt/vn`, with tobj's rules for their indices
//! (tobj's `parse_face`): one-based, negative ones counting back from the last element
//! defined so far.

use super::ChunkError;
use super::numbers::integer;
use super::words::{end_of_word, text};
use seamlit_asset::Syntax;

/// "No `vt` / `vn` index" in a corner.
pub(super) const MISSING: u32 = u32::MAX;

/// An index out of range whatever the file holds (zero, or past `u32`); the index as
/// written is kept in [`Chunk::invalid`].
pub(super) const INVALID: u32 = u32::MAX - 1;

/// A face corner as `[v, vt, vn]` zero-based indices (or [`MISSING`], [`INVALID`]).
pub(super) type Corner = [u32; 3];

/// The common corners `v`, `v/vt`, `v//vn` and `v/vt/vn` with indices of 1 to 9 digits,
/// not 0, at the start of `text`, in one pass: the corner and its length. `None` for
/// anything else (which [`corner`] reads the long way).
pub(super) fn simple_corner(text: &[u8]) -> Option<(Corner, usize)> {
    let mut corner = [MISSING; 3];
    let mut slot = 0;
    let mut value = 0u32;
    let mut digits = 0;
    let mut length = text.len();
    for (i, &b) in text.iter().enumerate() {
        match b {
            b'0'..=b'9' => {
                digits += 1;
                if digits > 9 {
                    return None;
                }
                value = value * 10 + u32::from(b - b'0');
            }
            b'/' => {
                if digits > 0 {
                    corner[slot] = value.checked_sub(1)?;
                } else if slot != 1 {
                    // Only `vt` may be left out between separators (`v//vn`).
                    return None;
                }
                slot += 1;
                if slot > 2 {
                    return None;
                }
                value = 0;
                digits = 0;
            }
            b if end_of_word(b) => {
                length = i;
                break;
            }
            _ => return None,
        }
    }
    if digits == 0 {
        return None;
    }
    corner[slot] = value.checked_sub(1)?;
    Some((corner, length))
}

/// Parses a face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`: the corner, and per slot the
/// index as written where the corner cannot hold it: a negative index (the corner holds 0
/// until it is resolved) and one out of range whatever the file holds (the corner holds
/// [`INVALID`]).
pub(super) fn corner(word: &[u8]) -> Result<(Corner, [Option<i64>; 3]), ChunkError> {
    let mut c = [MISSING; 3];
    let mut kept = [None; 3];
    let mut rest = word;
    // A fourth slot only to report a corner of four indices.
    for slot in 0..4 {
        if rest.is_empty() && slot > 0 {
            break;
        }
        let (field, tail) = match rest.iter().position(|&b| b == b'/') {
            Some(at) => (&rest[..at], &rest[at + 1..]),
            None => (rest, &[][..]),
        };
        // `v/vt/` or `v//`: a trailing separator with nothing after it.
        let ends = tail.is_empty() && field.len() < rest.len();
        rest = tail;
        if slot > 2 {
            return Err(ChunkError::Syntax(Syntax::CornerIndices { corner: text(word).into() }));
        }
        if field.is_empty() && slot > 0 {
            if ends {
                break;
            }
            continue;
        }
        let index = integer(field).ok_or_else(|| {
            ChunkError::Syntax(Syntax::NotAnIndex {
                corner: text(word).into(),
                found: text(field).into(),
            })
        })?;
        c[slot] = match index {
            i if i < 0 => 0,
            // Zero, or past `u32`: out of range whatever the file holds.
            i => u32::try_from(i - 1).map_or(INVALID, |i| i.min(INVALID)),
        };
        // Resolved (or found out of range) in `assemble`.
        if index < 0 || c[slot] == INVALID {
            kept[slot] = Some(index);
        }
    }
    Ok((c, kept))
}

#[cfg(test)]
mod tests {
    use super::simple_corner;

    #[test]
    fn simple_corners() {
        let m = u32::MAX;
        assert_eq!(simple_corner(b"7"), Some(([6, m, m], 1)));
        assert_eq!(simple_corner(b"7/8"), Some(([6, 7, m], 3)));
        assert_eq!(simple_corner(b"7//9 1"), Some(([6, m, 8], 4)));
        assert_eq!(simple_corner(b"7/8/9\n"), Some(([6, 7, 8], 5)));
        // Left to the general reader: zero, negative, empty, too many or too long.
        for word in ["0", "-1", "1/-1", "/1", "1/", "1//", "1/2/", "1/2/3/4", "1234567890", "1x"] {
            assert_eq!(simple_corner(word.as_bytes()), None, "{word}");
        }
    }
}
