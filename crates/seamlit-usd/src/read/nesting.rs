//! How deeply a text layer nests its brackets, measured before openusd parses it, and the
//! checks every layer passes before openusd reads it ([`checked`]: its size, its nesting):
//! the resolvers check every layer they open (on disk and in memory), the stage the root layer.

use std::io;

use openusd::ar;

/// The deepest nesting of `{`, `(` and `[` a text layer may have. openusd's text parser
/// recurses once a level: 20,000 nested prims or dictionaries overflowed the stack (an abort,
/// no error) and 3,000 took over a minute (the `usd` fuzz target, docs/usd.md). Real stages
/// nest prims tens of levels deep.
pub(super) const MAX_TEXT_NESTING: usize = 256;

/// The deepest nesting of `{`, `(` and `[` in usda text, outside strings (`"..."`, `'...'`,
/// their triple forms), asset paths (`@...@`, `@@@...@@@`) and `#` comments.
pub(super) fn text_nesting(text: &[u8]) -> usize {
    let (mut depth, mut deepest, mut i) = (0usize, 0usize, 0usize);
    while i < text.len() {
        match text[i] {
            b'#' => {
                i += text[i..].iter().position(|&c| c == b'\n').unwrap_or(text.len() - i);
            }
            quote @ (b'"' | b'\'' | b'@') => {
                let close: &[u8] =
                    if text[i..].starts_with(&[quote; 3]) { &text[i..i + 3] } else { &text[i..=i] };
                let mut j = i + close.len();
                // Inside: a backslash escapes the next byte (not in asset paths).
                while j < text.len() && !text[j..].starts_with(close) {
                    j += if text[j] == b'\\' && quote != b'@' { 2 } else { 1 };
                }
                i = j + close.len() - 1;
            }
            b'{' | b'(' | b'[' => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            b'}' | b')' | b']' => depth = depth.saturating_sub(1),
            _ => {}
        }
        i += 1;
    }
    deepest
}

/// `asset` where it holds at most `max_file_bytes` and, in text form, is nested no deeper
/// than openusd's parser survives; otherwise why not.
pub(super) fn checked(
    mut asset: Box<dyn ar::Asset>,
    max_file_bytes: u64,
) -> io::Result<Box<dyn ar::Asset>> {
    let size = asset.size()?;
    if size > max_file_bytes {
        return Err(io::Error::other(format!(
            "{size} bytes, more than the limit of {max_file_bytes} bytes"
        )));
    }
    let mut head = [0u8; 5];
    let read = io::Read::read(&mut asset, &mut head)?;
    io::Seek::seek(&mut asset, io::SeekFrom::Start(0))?;
    if head[..read] == *b"#usda" {
        let bytes = asset.read_all()?;
        let depth = text_nesting(&bytes);
        if depth > MAX_TEXT_NESTING {
            return Err(io::Error::other(format!(
                "brackets nested {depth} levels deep, more than the {MAX_TEXT_NESTING} seamlit reads"
            )));
        }
        return Ok(Box::new(io::Cursor::new(bytes)));
    }
    Ok(asset)
}

#[cfg(test)]
mod tests {
    use super::text_nesting;

    #[test]
    fn nesting_counts_brackets_outside_strings_paths_and_comments() {
        assert_eq!(text_nesting(br#"def "A" { def "B" { int[] x = [(1, 2)] } }"#), 4);
        assert_eq!(text_nesting(b"#usda 1.0 # {{{{\nx"), 0);
        assert_eq!(text_nesting(br#"string s = "{{{\"{{" asset a = @b[c].usd@"#), 0);
        assert_eq!(text_nesting(br#"string d = """{ " {""" custom = '''[[[''' "#), 0);
        assert_eq!(text_nesting(b"}}} ( ) ("), 1, "stray closers do not go below zero");
        assert_eq!(text_nesting(br#""unterminated {{{"#), 0);
    }
}
