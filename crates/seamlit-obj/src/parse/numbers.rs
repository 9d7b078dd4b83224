//! Numbers in OBJ statements: `str::parse` of a plain decimal, faster, and bit for bit the
//! same; anything else goes to `str::parse`.
//!
//! Based on Clinger's fast path (W. D. Clinger, "How to read floating point numbers
//! accurately", PLDI 1990) as fast_float uses it (D. Lemire, "Number parsing at a gigabyte per
//! second", Software: Practice and Experience, 2021), with its eight-digits-at-once step
//! (`parse_eight_digits_unrolled` in fast_float and simdjson).

use super::words::{end_of_word, text};

/// Powers of ten exact in `f64` (up to 1e22; a number of 15 digits needs 1e15 at most).
const POWERS: [f64; 16] =
    [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15];

/// `str::parse::<f32>` of a plain decimal (`-12.375`) at the start of `text`, up to the end
/// of its word, faster: the value and the word's length. `None` for any other word (the
/// caller asks `str::parse`, which gives the same value for what this accepts).
///
/// The digits, at most 15, make an integer `m` exact in `f64`, and the fraction digits a
/// power `10^k` exact in `f64` (k <= 15), so `m / 10^k` is the `f64` nearest the decimal
/// (Clinger's fast path). Rounding that to `f32` gives the `f32` nearest the decimal unless
/// the `f64` lies exactly halfway between two `f32`s (no `f32` midpoint lies between the
/// decimal and its nearest `f64`, as midpoints are `f64`s); that case goes to `str::parse`.
/// Fraction digits are read eight at a time where eight follow.
pub(super) fn fast_f32(text: &[u8]) -> Option<(f32, usize)> {
    const MOST: usize = 15;
    let (negative, mut at) = match text.first()? {
        b'-' => (true, 1),
        b'+' => (false, 1),
        _ => (false, 0),
    };
    let mut mantissa: u64 = 0;
    let mut count = 0;
    while let Some(&b) = text.get(at).filter(|b| b.is_ascii_digit()) {
        if count == MOST {
            return None;
        }
        mantissa = mantissa * 10 + u64::from(b - b'0');
        count += 1;
        at += 1;
    }
    let mut fraction = 0;
    if text.get(at) == Some(&b'.') {
        at += 1;
        while let Some(digits) = text.get(at..at + 8).and_then(eight_digits) {
            if count + 8 > MOST {
                return None;
            }
            mantissa = mantissa * 100_000_000 + digits;
            count += 8;
            fraction += 8;
            at += 8;
        }
        while let Some(&b) = text.get(at).filter(|b| b.is_ascii_digit()) {
            if count == MOST {
                return None;
            }
            mantissa = mantissa * 10 + u64::from(b - b'0');
            count += 1;
            fraction += 1;
            at += 1;
        }
    }
    if count == 0 || text.get(at).is_some_and(|&b| !end_of_word(b)) {
        return None;
    }
    // At most 15 digits: exact in f64.
    let value = mantissa as f64 / POWERS[fraction];
    // 29 bits of the f64 significand are rounded off; exactly 1000...0 is a tie.
    if value.to_bits() & 0x1FFF_FFFF == 0x1000_0000 {
        return None;
    }
    #[expect(clippy::cast_possible_truncation, reason = "rounding to f32 is the point")]
    let value = value as f32;
    Some((if negative { -value } else { value }, at))
}

/// The value of eight ASCII digits (`None` if any byte is not a digit), with a few
/// multiplications instead of eight dependent steps (the technique of fast_float and
/// simdjson, `parse_eight_digits_unrolled`).
fn eight_digits(bytes: &[u8]) -> Option<u64> {
    let word = u64::from_le_bytes(bytes.try_into().ok()?);
    // Every byte 0x30..=0x39: high nibble 3, and still 3 after adding 6.
    let all_digits = word & 0xF0F0_F0F0_F0F0_F0F0 == 0x3030_3030_3030_3030
        && word.wrapping_add(0x0606_0606_0606_0606) & 0xF0F0_F0F0_F0F0_F0F0
            == 0x3030_3030_3030_3030;
    if !all_digits {
        return None;
    }
    // The first digit is the lowest byte: pairs, then quadruples, then the eight.
    let digits = word - 0x3030_3030_3030_3030;
    let pairs = digits.wrapping_mul(10).wrapping_add(digits >> 8);
    let mask = 0x0000_00FF_0000_00FF;
    let value = ((pairs & mask).wrapping_mul(100 + (1_000_000 << 32))
        + ((pairs >> 16) & mask).wrapping_mul(1 + (10_000 << 32)))
        >> 32;
    Some(value)
}

/// A number word as `str::parse::<f32>` reads it.
pub(super) fn float(word: &[u8]) -> Option<f32> {
    match fast_f32(word) {
        Some((value, _)) => Some(value),
        None => text(word).parse().ok(),
    }
}

/// A face index as `str::parse::<i64>` reads it.
pub(super) fn integer(field: &[u8]) -> Option<i64> {
    let (negative, digits) = match field.first()? {
        b'-' => (true, &field[1..]),
        b'+' => (false, &field[1..]),
        _ => (false, field),
    };
    if digits.is_empty() || digits.len() > 18 {
        return text(field).parse().ok();
    }
    let mut value: i64 = 0;
    for &b in digits {
        if !b.is_ascii_digit() {
            return None;
        }
        value = value * 10 + i64::from(b - b'0');
    }
    Some(if negative { -value } else { value })
}

#[cfg(test)]
mod tests {
    use super::{eight_digits, fast_f32, float};

    /// splitmix64, for reproducible test inputs.
    fn next(state: &mut u64) -> u64 {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Where the fast path reads a number, it reads the whole word and the value
    /// `str::parse` gives, bit for bit.
    fn agrees(word: &str) -> bool {
        let Some((value, length)) = fast_f32(word.as_bytes()) else { return false };
        assert_eq!(length, word.len(), "{word}");
        let expected: f32 = word.parse().unwrap();
        assert_eq!(value.to_bits(), expected.to_bits(), "{word}: {value} vs {expected}");
        true
    }

    #[test]
    fn the_fast_path_gives_what_str_parse_gives() {
        let mut state = 1;
        let mut fast = 0;
        for _ in 0..200_000 {
            let x = f32::from_bits((next(&mut state) & 0xFFFF_FFFF) as u32);
            if !x.is_finite() {
                continue;
            }
            // Shortest round trip, fixed digits, and scaled to exporters' magnitudes.
            #[expect(clippy::cast_possible_truncation, reason = "a finite f32's exponent")]
            let scaled = x / 2f32.powi(x.abs().log2().floor() as i32 - 4);
            for word in [
                format!("{x}"),
                format!("{scaled}"),
                format!("{scaled:.6}"),
                format!("{:.9}", scaled / 7.0),
                format!("{:.3}", scaled * 1000.0),
                format!("{}", f64::from(scaled) / 3.0),
            ] {
                fast += usize::from(agrees(&word));
            }
        }
        // Random digit strings: signs, points anywhere, leading zeros, up to 20 digits.
        for _ in 0..200_000 {
            let r = next(&mut state);
            let digits = 1 + (r % 20) as usize;
            let mut word: String = match (r >> 8) % 3 {
                0 => "-".into(),
                1 => "+".into(),
                _ => String::new(),
            };
            let point = (r >> 16) as usize % (digits + 2);
            for k in 0..digits {
                if k == point {
                    word.push('.');
                }
                word.push(char::from(b'0' + (next(&mut state) % 10) as u8));
            }
            fast += usize::from(agrees(&word));
        }
        assert!(fast > 900_000, "only {fast} words took the fast path");
    }

    #[test]
    fn ties_and_other_words_are_left_to_str_parse() {
        // 16777217 = 2^24 + 1 lies halfway between the f32s 2^24 and 2^24 + 2.
        assert_eq!(fast_f32(b"16777217"), None);
        assert_eq!(float(b"16777217"), Some(16_777_216.0));
        for word in ["", "-", "+", ".", "-.", "1e5", "1.5e3", "inf", "nan", "1.2.3", "0x10", "1_0"]
        {
            assert_eq!(fast_f32(word.as_bytes()), None, "{word}");
        }
        // Sixteen digits or more.
        assert_eq!(fast_f32(b"1.234567890123456"), None);
        assert_eq!(fast_f32(b"0.000000000000001"), None);
        // A word ends at a blank or a line end, not at other bytes.
        assert_eq!(fast_f32(b"2.5 7"), Some((2.5, 3)));
        assert_eq!(fast_f32(b"-0.25\r\n"), Some((-0.25, 5)));
        assert_eq!(fast_f32(b"1.5/2"), None);
        assert_eq!(fast_f32(b"-0").map(|(v, _)| v.to_bits()), Some((-0.0f32).to_bits()));
        assert_eq!(fast_f32(b"5."), Some((5.0, 2)));
        assert_eq!(fast_f32(b".5"), Some((0.5, 2)));
    }

    #[test]
    fn eight_digits_at_once() {
        assert_eq!(eight_digits(b"12345678"), Some(12_345_678));
        assert_eq!(eight_digits(b"00000000"), Some(0));
        assert_eq!(eight_digits(b"99999999"), Some(99_999_999));
        assert_eq!(eight_digits(b"00000001"), Some(1));
        for bad in [b"1234567a", b"/2345678", b"1234:678", b"12 45678", b"1234567\n"] {
            assert_eq!(eight_digits(bad), None, "{bad:?}");
        }
        assert_eq!(eight_digits(b"1234567"), None);
    }
}
