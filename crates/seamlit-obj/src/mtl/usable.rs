//! An MTL library made readable: tobj refuses a whole library for one statement it cannot
//! parse (and panics on some), while a material statement must never cost the model its
//! geometry. Each line is read here first, by the MTL specification:
//!
//! - a colour (`Ka`, `Kd`, `Ks`, `Ke`) of one number is grey (`g` and `b` default to `r`);
//!   `xyz x [y z]` is CIE XYZ, converted to linear sRGB;
//! - `d -halo f` is a dissolve of `f` (the halo is not drawn);
//!
//! and what seamlit cannot use (a spectral colour `Ka spectral file.rfl`, a colour of two
//! numbers, a word where a number belongs, a texture statement without a file, an unknown
//! texture option) is left out or left alone, so that its material keeps the default, and
//! named in one warning per library.

use std::fmt::Write as _;
use std::path::Path;

use super::MapOptions;

/// A library's text as tobj is given it, and what was left at its default.
pub(super) struct Usable {
    pub(super) text: String,
    /// Per statement seamlit cannot use: its line (from 1), the statement, and why.
    pub(super) unusable: Vec<(usize, String, &'static str)>,
}

/// Reads `text` (a whole MTL library) line by line; see the module's documentation.
pub(super) fn usable(text: &str) -> Usable {
    let mut out = Usable { text: String::with_capacity(text.len()), unusable: Vec::new() };
    for (i, line) in text.lines().enumerate() {
        match read_line(line) {
            Line::Keep => out.text.push_str(line),
            Line::Rewrite(line) => out.text.push_str(&line),
            Line::Unusable(why) => {
                out.unusable.push((i + 1, line.trim().to_owned(), why));
                // An unknown texture option is named, the statement is still read.
                if why == UNKNOWN_OPTION {
                    out.text.push_str(line);
                }
            }
        }
        out.text.push('\n');
    }
    out
}

/// The one warning for a library's statements that seamlit cannot use (`None`: none).
pub(super) fn warning(
    library: &Path,
    unusable: &[(usize, String, &'static str)],
) -> Option<String> {
    let ((line, text, why), rest) = unusable.split_first()?;
    let mut warning =
        format!("{}:{line}: `{text}`: {why}; its material keeps the default", library.display());
    if !rest.is_empty() {
        let lines: Vec<String> = rest.iter().take(8).map(|(l, ..)| l.to_string()).collect();
        let more = if rest.len() > 8 { ", ..." } else { "" };
        write!(
            warning,
            " (and {} more statement(s) seamlit cannot use, on lines {}{more})",
            rest.len(),
            lines.join(", ")
        )
        .ok();
    }
    Some(warning)
}

/// What becomes of a line.
enum Line {
    Keep,
    Rewrite(String),
    Unusable(&'static str),
}

const UNKNOWN_OPTION: &str = "a texture option the MTL specification does not list, ignored";

/// Reads one line of a library.
fn read_line(line: &str) -> Line {
    // tobj splits on whitespace and reads the first words; a comment may end a line.
    let mut words = line.split_whitespace().take_while(|w| !w.starts_with('#'));
    let Some(keyword) = words.next() else { return Line::Keep };
    let args: Vec<&str> = words.collect();
    match keyword {
        "Ka" | "Kd" | "Ks" | "Ke" => colour(keyword, &args),
        "Ns" | "Ni" => match args.first().and_then(|w| number(w)) {
            Some(_) => Line::Keep,
            None => Line::Unusable("a number belongs here"),
        },
        "d" => match args.as_slice() {
            [w, ..] if number(w).is_some() => Line::Keep,
            ["-halo", w, ..] if number(w).is_some() => Line::Rewrite(format!("d {w}")),
            _ => Line::Unusable("a number belongs here"),
        },
        "illum" => match args.first().map(|w| w.parse::<u8>()) {
            Some(Ok(_)) => Line::Keep,
            _ => Line::Unusable("an illumination model number belongs here"),
        },
        _ if is_texture(keyword) => {
            let rest = line.trim_start()[keyword.len()..].trim();
            let options = MapOptions::parse(rest);
            if options.file.is_empty() {
                Line::Unusable("a texture statement without a file")
            } else if options.unknown {
                Line::Unusable(UNKNOWN_OPTION)
            } else {
                Line::Keep
            }
        }
        _ => Line::Keep,
    }
}

/// Whether `keyword` is a texture statement whose file seamlit or tobj reads.
fn is_texture(keyword: &str) -> bool {
    ["map_Ka", "map_Kd", "map_Ks", "map_Bump", "map_bump", "map_Ns", "map_ns", "map_NS"]
        .contains(&keyword)
        || ["bump", "map_d", "norm"].contains(&keyword)
}

/// A colour statement: `r [g b]`, `xyz x [y z]`, or `spectral file [factor]`.
fn colour(keyword: &str, args: &[&str]) -> Line {
    let numbers =
        |words: &[&str]| -> Option<Vec<f32>> { words.iter().map(|w| number(w)).collect() };
    match args {
        ["spectral", ..] => Line::Unusable("spectral colours (.rfl files) are not read"),
        ["xyz", rest @ ..] => match numbers(rest).as_deref() {
            Some(&[x]) => Line::Rewrite(rgb(keyword, xyz_to_rgb([x, x, x]))),
            Some(&[x, y, z]) => Line::Rewrite(rgb(keyword, xyz_to_rgb([x, y, z]))),
            _ => Line::Unusable("`xyz` needs one or three numbers"),
        },
        _ => match numbers(args).as_deref() {
            Some(&[r]) => Line::Rewrite(rgb(keyword, [r, r, r])),
            Some([_, _, _, ..]) => Line::Keep,
            Some(&[_, _]) => Line::Unusable("a colour needs one or three numbers, found two"),
            _ => Line::Unusable("a colour needs one or three numbers"),
        },
    }
}

fn rgb(keyword: &str, [r, g, b]: [f32; 3]) -> String {
    format!("{keyword} {r} {g} {b}")
}

/// A finite number (tobj reads numbers with `str::parse`).
fn number(word: &str) -> Option<f32> {
    word.parse::<f32>().ok().filter(|v| v.is_finite())
}

/// CIE XYZ to linear sRGB (D65; IEC 61966-2-1), negative components clamped to 0.
fn xyz_to_rgb([x, y, z]: [f32; 3]) -> [f32; 3] {
    let r = 3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z;
    let g = -0.969_266 * x + 1.876_010_8 * y + 0.041_556 * z;
    let b = 0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z;
    [r.max(0.0), g.max(0.0), b.max(0.0)]
}

#[cfg(test)]
mod tests {
    use super::usable;

    #[test]
    fn what_the_specification_allows_is_read_and_the_rest_is_named() {
        let u = usable(
            "newmtl m\nKs 0\nKa spectral x.rfl 1.0\nKd 1 0.5 0 # red\nd -halo 0.5\nKe 1 2\nNs many\nmap_Kd\n",
        );
        assert_eq!(u.text, "newmtl m\nKs 0 0 0\n\nKd 1 0.5 0 # red\nd 0.5\n\n\n\n");
        let lines: Vec<usize> = u.unusable.iter().map(|(l, ..)| *l).collect();
        assert_eq!(lines, [3, 6, 7, 8]);
    }

    #[test]
    fn xyz_white_is_rgb_white() {
        let u = usable("Kd xyz 0.950456 1 1.088754\n");
        let rgb: Vec<f32> = u.text.split_whitespace().skip(1).map(|w| w.parse().unwrap()).collect();
        for c in rgb {
            assert!((c - 1.0).abs() < 1e-3, "{c}");
        }
    }
}
