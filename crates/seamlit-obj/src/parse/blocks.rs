//! An OBJ file read in blocks of whole lines, and the words of a block's lines.
//!
//! The file is read in blocks of about a megabyte, each cut after its last line end, on a
//! thread of its own while the parsers work on the blocks already read; the buffers are
//! reused, and the text is never held whole. This is how rapidobj
//! (<https://github.com/guybrush77/rapidobj>) parallelises OBJ parsing: chunks cut at line
//! ends, parsed independently, their relative indices resolved afterwards.

use std::io::Read;
use std::sync::mpsc;

use super::ChunkError;
use super::numbers::fast_f32;
use super::words::{blank, end_of_word};
use seamlit_asset::NotText;

/// The UTF-8 byte-order mark, which some editors write before the first line.
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// The size of the blocks the file is read and parsed in (each is cut at its last line end).
pub(super) const BLOCK: usize = 1 << 20;

/// How many blocks the reader may read ahead of the parsers.
pub(super) const READ_AHEAD: usize = 4;

/// Reads `file` in blocks cut after their last line end and sends them, numbered, to the
/// parsers; buffers come back through `free` to be reused. A line longer than a block makes
/// its block grow (each byte is read and searched once, however long the line).
pub(super) fn read_blocks(
    mut file: impl Read,
    blocks: &mpsc::SyncSender<(usize, Vec<u8>)>,
    free: &mpsc::Receiver<Vec<u8>>,
) -> std::io::Result<()> {
    let mut carry: Vec<u8> = Vec::new();
    let mut index = 0;
    loop {
        let mut block = free.try_recv().unwrap_or_else(|_| Vec::with_capacity(BLOCK + 4096));
        block.clear();
        // The end of the previous block's last line, which holds no line end.
        block.append(&mut carry);
        let end = loop {
            let before = block.len();
            let got = (&mut file).take(BLOCK as u64).read_to_end(&mut block)?;
            if got < BLOCK {
                break true;
            }
            if let Some(at) = block[before..].iter().rposition(|&b| b == b'\n') {
                let cut = before + at + 1;
                carry.extend_from_slice(&block[cut..]);
                block.truncate(cut);
                break false;
            }
        };
        if index == 0 && block.starts_with(UTF8_BOM) {
            block.drain(..UTF8_BOM.len());
        }
        if (!block.is_empty() || index == 0) && blocks.send((index, block)).is_err() {
            return Ok(());
        }
        if end {
            return Ok(());
        }
        index += 1;
    }
}

/// The first statement line (not a comment) of `block` that holds a NUL byte, or invalid
/// UTF-8 in a statement other than a name's (`o`, `g`, `usemtl`, `mtllib`: a name that is not
/// UTF-8 is read as Windows-1252, `names.rs`), with what is wrong. A block of ASCII without NUL (nearly every OBJ file) is seen
/// to have none in one pass that vectorises; others are searched line by line.
pub(super) fn first_line_not_text(block: &[u8]) -> Option<(usize, ChunkError)> {
    // Bit 7 of `b | (b - 1)` is set for NUL (0 - 1 = 0xFF) and for every byte above 127.
    let ascii = |chunk: &[u8]| chunk.iter().fold(0, |any, &b| any | b | b.wrapping_sub(1)) < 0x80;
    if block.chunks(64).all(ascii) {
        return None;
    }
    block.split(|&b| b == b'\n').enumerate().find_map(|(i, line)| {
        let start = line.iter().position(|&b| !blank(b)).unwrap_or(line.len());
        let problem = if line[start..].starts_with(b"#") {
            return None;
        } else if line.contains(&0) {
            NotText::Nul
        } else if std::str::from_utf8(line).is_err() && !names_a_thing(&line[start..]) {
            NotText::InvalidUtf8
        } else {
            return None;
        };
        Some((i + 1, ChunkError::NotText(problem)))
    })
}

/// Whether a statement (its line from its first word) gives a name: `o`, `g`, `usemtl`,
/// `mtllib`.
fn names_a_thing(statement: &[u8]) -> bool {
    let keyword = statement.split(|&b| end_of_word(b)).next().unwrap_or_default();
    [&b"o"[..], b"g", b"usemtl", b"mtllib"].contains(&keyword)
}

/// A cursor over a block's text that yields the blank-separated words of the current line
/// (`None` at its end) and moves to the next line with [`Cursor::next_line`].
pub(super) struct Cursor<'a> {
    pub(super) text: &'a [u8],
    pub(super) at: usize,
}

impl<'a> Cursor<'a> {
    /// Skips blanks; whether a word follows on the current line.
    pub(super) fn skip_blanks(&mut self) -> bool {
        let text = self.text;
        while self.at < text.len() && blank(text[self.at]) {
            self.at += 1;
        }
        self.at < text.len() && text[self.at] != b'\n'
    }

    pub(super) fn word(&mut self) -> Option<&'a [u8]> {
        if !self.skip_blanks() {
            return None;
        }
        let text = self.text;
        let start = self.at;
        while self.at < text.len() && !end_of_word(text[self.at]) {
            self.at += 1;
        }
        Some(&text[start..self.at])
    }

    /// The next word: read in place as a number when it is a plain decimal.
    pub(super) fn number(&mut self) -> Option<Number<'a>> {
        if !self.skip_blanks() {
            return None;
        }
        if let Some((value, length)) = fast_f32(&self.text[self.at..]) {
            self.at += length;
            return Some(Number::Plain(value));
        }
        self.word().map(Number::Word)
    }

    /// The rest of the current line (without its line end).
    pub(super) fn rest(&self) -> &'a [u8] {
        let tail = &self.text[self.at..];
        &tail[..tail.iter().position(|&b| b == b'\n').unwrap_or(tail.len())]
    }

    pub(super) fn next_line(&mut self) {
        let tail = &self.text[self.at..];
        self.at += tail.iter().position(|&b| b == b'\n').map_or(tail.len(), |n| n + 1);
    }
}

/// A word read by [`Cursor::number`].
pub(super) enum Number<'a> {
    /// A plain decimal, read (always finite).
    Plain(f32),
    /// Any other word, for `str::parse`.
    Word(&'a [u8]),
}
