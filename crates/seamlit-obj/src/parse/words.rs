//! The bytes of a line that every parser step reads by: blanks, the ends of words, and
//! their text. Below `blocks.rs`, `numbers.rs` and `corners.rs`, which all use them.

/// A blank between words (space, tab, carriage return, form feed).
pub(super) fn blank(b: u8) -> bool {
    b == b' ' || b == b'\t' || b == b'\r' || b == 0x0c
}

/// A byte that ends a word: a blank or a line end.
pub(super) fn end_of_word(b: u8) -> bool {
    blank(b) || b == b'\n'
}

/// Text of the file (its invalid UTF-8 replaced, as when the whole file is read as text).
pub(super) fn text(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(bytes)
}
