//! Pictures on disk: PNGs written to a temporary name and renamed, and labelled grids of
//! renderings (the `compare` and `demo` outputs), with text drawn from an embedded font
//! (Hack, from egui's default fonts).

use std::io::BufWriter;
use std::path::Path;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use image::{Rgba, RgbaImage};

/// Writes `image` as a PNG to `path`: first to a temporary file in the same folder, then
/// renamed over `path`, so that a failure never leaves a half-written file.
///
/// # Errors
/// The I/O or encoding error, with the path.
pub(crate) fn save_png(image: &RgbaImage, path: &Path) -> anyhow::Result<()> {
    crate::output::prepare_folder_of(path).map_err(|f| anyhow::anyhow!("{f}"))?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let write = || -> anyhow::Result<()> {
        let mut tmp =
            tempfile::Builder::new().prefix(".seamlit-").suffix(".png.tmp").tempfile_in(dir)?;
        {
            let mut w = BufWriter::new(tmp.as_file_mut());
            image.write_to(&mut w, image::ImageFormat::Png)?;
            std::io::Write::flush(&mut w)?;
        }
        // Temporary files are private (0600); the picture gets the usual permissions.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt as _;
            tmp.as_file().set_permissions(std::fs::Permissions::from_mode(0o644))?;
        }
        tmp.persist(path)?;
        Ok(())
    };
    write().map_err(|e| anyhow::anyhow!("{}: cannot write the image: {e}", path.display()))
}

/// The label font.
fn font() -> FontRef<'static> {
    #[expect(clippy::expect_used, reason = "the font is compiled in; a test parses it")]
    FontRef::try_from_slice(epaint_default_fonts::HACK_REGULAR).expect("the embedded font parses")
}

/// Width in pixels of `text` at `size` pixels.
#[must_use]
pub(crate) fn text_width(text: &str, size: f32) -> f32 {
    let font = font();
    let scaled = font.as_scaled(PxScale::from(size));
    text.chars().map(|c| scaled.h_advance(font.glyph_id(c))).sum()
}

/// Draws `text` with its top-left corner at `(x, y)`, `size` pixels tall, blending `color`
/// over the image.
pub(crate) fn draw_text(
    image: &mut RgbaImage,
    text: &str,
    x: f32,
    y: f32,
    size: f32,
    color: [u8; 3],
) {
    let font = font();
    let scaled = font.as_scaled(PxScale::from(size));
    let mut caret = x;
    let baseline = y + scaled.ascent();
    for c in text.chars() {
        let glyph = scaled.scaled_glyph(c);
        let id = glyph.id;
        let mut positioned = glyph;
        positioned.position = ab_glyph::point(caret, baseline);
        caret += scaled.h_advance(id);
        let Some(outline) = font.outline_glyph(positioned) else { continue };
        let b = outline.px_bounds();
        outline.draw(|gx, gy, coverage| {
            #[expect(
                clippy::cast_possible_truncation,
                reason = "whole pixels near the text (`as` saturates); off the image is dropped below"
            )]
            let (px, py) = (b.min.x as i64 + i64::from(gx), b.min.y as i64 + i64::from(gy));
            let (Ok(px), Ok(py)) = (u32::try_from(px), u32::try_from(py)) else { return };
            if px >= image.width() || py >= image.height() {
                return;
            }
            let a = coverage.clamp(0.0, 1.0);
            let p = image.get_pixel_mut(px, py);
            for (channel, ink) in p.0.iter_mut().zip(color) {
                #[expect(
                    clippy::cast_possible_truncation,
                    reason = "a blend of two bytes with `a` clamped to 0..=1 stays in 0..=255"
                )]
                let blended = (f32::from(*channel) * (1.0 - a) + f32::from(ink) * a).round() as u8;
                *channel = blended;
            }
        });
    }
}

/// Height of the label band above each panel, pixels.
pub const LABEL_BAND: u32 = 44;

/// Places panels side by side, each under a band with its title (and a smaller subtitle),
/// on a dark background.
#[must_use]
pub(crate) fn labelled_row(panels: &[(RgbaImage, String, String)]) -> RgbaImage {
    let gap = 4;
    let height = panels.iter().map(|(p, ..)| p.height()).max().unwrap_or(1) + LABEL_BAND;
    let count = u32::try_from(panels.len()).unwrap_or(u32::MAX);
    let width = panels.iter().map(|(p, ..)| p.width()).sum::<u32>() + gap * count.saturating_sub(1);
    let mut out = RgbaImage::from_pixel(width.max(1), height, Rgba([18, 18, 22, 255]));
    let mut x0 = 0;
    for (panel, title, subtitle) in panels {
        image::imageops::replace(&mut out, panel, i64::from(x0), i64::from(LABEL_BAND));
        let centre =
            |t: &str, size: f32| x0 as f32 + (panel.width() as f32 - text_width(t, size)) / 2.0;
        // (text, top, size, colour): the title, then the subtitle under it.
        let lines = [(title, 3.0, 20.0, [240, 240, 240]), (subtitle, 26.0, 13.0, [170, 170, 180])];
        for (text, top, size, colour) in lines {
            draw_text(&mut out, text, centre(text, size).max(x0 as f32 + 4.0), top, size, colour);
        }
        x0 += panel.width() + gap;
    }
    out
}

/// A rectangle of pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// The window of `width` x `height` in which `a` and `b` (of one size) differ in the most
/// pixels (by more than `threshold` in some channel), or `None` when they differ in none.
/// Windows start on a 2-pixel grid; a summed-area table counts each in O(1).
#[must_use]
pub(crate) fn most_different_window(
    a: &RgbaImage,
    b: &RgbaImage,
    (width, height): (u32, u32),
    threshold: u8,
) -> Option<Rect> {
    let (w, h) = a.dimensions();
    if b.dimensions() != (w, h) || width == 0 || height == 0 || width > w || height > h {
        return None;
    }
    // sums[(y + 1) * (w + 1) + x + 1]: differing pixels in rows 0..=y, columns 0..=x.
    let stride = w as usize + 1;
    let mut sums = vec![0u32; stride * (h as usize + 1)];
    for y in 0..h {
        let mut row = 0;
        for x in 0..w {
            let (p, q) = (a.get_pixel(x, y).0, b.get_pixel(x, y).0);
            row += u32::from(p.iter().zip(q).any(|(&s, t)| s.abs_diff(t) > threshold));
            let i = (y as usize + 1) * stride + x as usize + 1;
            sums[i] = sums[i - stride] + row;
        }
    }
    let count = |x: u32, y: u32| {
        let (x0, y0, x1, y1) =
            (x as usize, y as usize, (x + width) as usize, (y + height) as usize);
        sums[y1 * stride + x1] + sums[y0 * stride + x0]
            - sums[y0 * stride + x1]
            - sums[y1 * stride + x0]
    };
    let mut best: Option<(u32, Rect)> = None;
    for y in (0..=h - height).step_by(2) {
        for x in (0..=w - width).step_by(2) {
            let n = count(x, y);
            if n > 0 && best.is_none_or(|(m, _)| n > m) {
                best = Some((n, Rect { x, y, width, height }));
            }
        }
    }
    best.map(|(_, r)| r)
}

/// `rect` of `image` enlarged `factor` times, each pixel a `factor` x `factor` block (nearest
/// neighbour: nothing smoothed in or out, so a seam looks exactly as sharp as it is).
#[must_use]
pub(crate) fn zoom(image: &RgbaImage, rect: Rect, factor: u32) -> RgbaImage {
    use image::imageops::{FilterType, crop_imm, resize};
    let window = crop_imm(image, rect.x, rect.y, rect.width, rect.height);
    resize(&*window, rect.width * factor, rect.height * factor, FilterType::Nearest)
}

/// Draws a 2-pixel frame just outside `rect` (the pixels inside stay as rendered), clipped
/// to the image.
pub(crate) fn frame(image: &mut RgbaImage, rect: Rect, colour: [u8; 3]) {
    let (w, h) = (i64::from(image.width()), i64::from(image.height()));
    let (x0, y0) = (i64::from(rect.x) - 2, i64::from(rect.y) - 2);
    let (x1, y1) = (i64::from(rect.x + rect.width) + 1, i64::from(rect.y + rect.height) + 1);
    for y in y0.max(0)..=y1.min(h - 1) {
        for x in x0.max(0)..=x1.min(w - 1) {
            let border = x < x0 + 2 || x > x1 - 2 || y < y0 + 2 || y > y1 - 2;
            if border && let (Ok(px), Ok(py)) = (u32::try_from(x), u32::try_from(y)) {
                image.put_pixel(px, py, Rgba([colour[0], colour[1], colour[2], 255]));
            }
        }
    }
}

/// `top` above `bottom`, `gap` pixels apart, on the dark background of [`labelled_row`].
#[must_use]
pub(crate) fn stack(top: &RgbaImage, bottom: &RgbaImage, gap: u32) -> RgbaImage {
    let width = top.width().max(bottom.width());
    let mut out =
        RgbaImage::from_pixel(width, top.height() + gap + bottom.height(), Rgba([18, 18, 22, 255]));
    image::imageops::replace(&mut out, top, 0, 0);
    image::imageops::replace(&mut out, bottom, 0, i64::from(top.height() + gap));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_most_different_window_is_found_and_zoomed_pixel_for_pixel() {
        let a = RgbaImage::from_fn(40, 30, |x, y| {
            Rgba([u8::try_from(x * 5).unwrap(), u8::try_from(y * 7).unwrap(), 0, 255])
        });
        let mut b = a.clone();
        // A short vertical step (a seam) at x = 25, rows 10..20; one stray pixel elsewhere.
        for y in 10..20 {
            b.put_pixel(25, y, Rgba([255, 255, 255, 255]));
        }
        b.put_pixel(3, 3, Rgba([255, 255, 255, 255]));
        let window = most_different_window(&a, &b, (8, 6), 8).unwrap();
        assert!(window.x <= 25 && 25 < window.x + 8, "{window:?}");
        assert_eq!(window.height, 6);
        assert!(most_different_window(&a, &a, (8, 6), 8).is_none());
        let z = zoom(&b, window, 3);
        assert_eq!(z.dimensions(), (24, 18));
        for (x, y, p) in z.enumerate_pixels() {
            assert_eq!(p, b.get_pixel(window.x + x / 3, window.y + y / 3));
        }
        let mut framed = a.clone();
        frame(&mut framed, window, [255, 0, 0]);
        for y in window.y..window.y + window.height {
            for x in window.x..window.x + window.width {
                assert_eq!(framed.get_pixel(x, y), a.get_pixel(x, y), "inside is untouched");
            }
        }
        assert_eq!(framed.get_pixel(window.x - 1, window.y).0, [255, 0, 0, 255]);
    }

    #[test]
    fn text_puts_ink_inside_its_box_and_nowhere_else() {
        let mut img = RgbaImage::from_pixel(120, 40, Rgba([0, 0, 0, 255]));
        let w = text_width("model", 20.0);
        assert!(w > 30.0 && w < 100.0, "{w}");
        draw_text(&mut img, "model", 10.0, 5.0, 20.0, [255, 255, 255]);
        let mut inked = 0;
        for (x, y, p) in img.enumerate_pixels() {
            if p.0[0] > 0 {
                inked += 1;
                assert!(
                    x >= 9 && f64::from(x) <= 11.0 + f64::from(w) && (4..=30).contains(&y),
                    "ink at {x},{y}"
                );
            }
        }
        assert!(inked > 50, "{inked} pixels inked");
    }

    #[test]
    fn a_row_puts_panels_side_by_side_under_their_labels() {
        let a = RgbaImage::from_pixel(50, 30, Rgba([255, 0, 0, 255]));
        let b = RgbaImage::from_pixel(50, 30, Rgba([0, 0, 255, 255]));
        let row = labelled_row(&[(a, "a".into(), "".into()), (b, "b".into(), "".into())]);
        assert_eq!(row.dimensions(), (104, 30 + LABEL_BAND));
        assert_eq!(row.get_pixel(10, LABEL_BAND + 5).0, [255, 0, 0, 255]);
        assert_eq!(row.get_pixel(60, LABEL_BAND + 5).0, [0, 0, 255, 255]);
    }

    #[test]
    fn a_png_is_written_whole_or_not_at_all() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.png");
        save_png(&RgbaImage::new(4, 4), &path).unwrap();
        assert_eq!(image::open(&path).unwrap().width(), 4);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt as _;
            let mode = std::fs::metadata(&path).unwrap().permissions().mode();
            assert_eq!(mode & 0o777, 0o644, "{mode:o}");
        }
        // The name is taken by a folder: the final rename fails.
        let bad = dir.path().join("taken.png");
        std::fs::create_dir(&bad).unwrap();
        let e = save_png(&RgbaImage::new(4, 4), &bad).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{}: cannot write", bad.display())), "{e}");
        // Nothing but x.png and the folder is left: no temporary file.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
        // A missing folder is created (the rule of crate::output).
        let nested = dir.path().join("new/folder/x.png");
        save_png(&RgbaImage::new(4, 4), &nested).unwrap();
        assert!(nested.is_file());
    }
}
