//! A brick-wall normal map made in code: a height field of bricks and mortar, turned into
//! tangent-space normals by central differences (OpenGL convention: green points up the
//! image).

use image::{Rgba, RgbaImage};

/// Bricks per row and rows per image: the map tiles, so the pattern repeats seamlessly.
const BRICKS_PER_ROW: u32 = 4;
const ROWS: u32 = 8;

/// Height of the brick wall at texel `(x, y)` of a `size` x `size` image: 1 on a brick face,
/// 0 in the mortar, with a bevel between them. Rows alternate by half a brick. Wraps around.
#[must_use]
#[expect(
    clippy::cast_possible_truncation,
    reason = "row is a whole, non-negative number of rows below size / 8"
)]
pub(crate) fn brick_height(x: u32, y: u32, size: u32) -> f32 {
    let size = size.max(1) as f32;
    let (x, y) = (x as f32 + 0.5, y as f32 + 0.5);
    let row_h = size / ROWS as f32;
    let brick_w = size / BRICKS_PER_ROW as f32;
    let row = (y / row_h).floor();
    let shift = if row as u32 % 2 == 1 { brick_w * 0.5 } else { 0.0 };
    let fx = (x + shift).rem_euclid(brick_w);
    let fy = y.rem_euclid(row_h);
    // Distance to the nearest joint, in texels.
    let edge = fx.min(brick_w - fx).min(fy).min(row_h - fy);
    let mortar = row_h * 0.08;
    let bevel = row_h * 0.12;
    ((edge - mortar) / bevel).clamp(0.0, 1.0)
}

/// The brick normal map, `size` x `size` RGBA8 (linear data, `n * 0.5 + 0.5`). `strength`
/// scales the slopes: the relief in texels per unit of height.
#[must_use]
#[expect(
    clippy::cast_possible_truncation,
    reason = "rem_euclid(size) lies in 0..size, a u32; the encoded component is clamped to 0..=255"
)]
pub(crate) fn brick_normal_map(size: u32, strength: f32) -> RgbaImage {
    let size = size.max(4);
    let h = |x: i64, y: i64| {
        let s = i64::from(size);
        brick_height(x.rem_euclid(s) as u32, y.rem_euclid(s) as u32, size)
    };
    RgbaImage::from_fn(size, size, |x, y| {
        let (x, y) = (i64::from(x), i64::from(y));
        let dh_dx = (h(x + 1, y) - h(x - 1, y)) * 0.5 * strength;
        // Image rows run down; +Y of the normal map runs up the image.
        let dh_dup = (h(x, y - 1) - h(x, y + 1)) * 0.5 * strength;
        let n = glam::Vec3::new(-dh_dx, -dh_dup, 1.0).normalize();
        let enc = |c: f32| ((c * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8;
        Rgba([enc(n.x), enc(n.y), enc(n.z), 255])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_brick_face_is_flat_and_the_mortar_is_low() {
        // Size 256: rows 32 texels, bricks 64 wide. (32, 16) is the middle of a brick.
        assert_eq!(brick_height(32, 16, 256), 1.0);
        assert_eq!(brick_height(0, 16, 256), 0.0, "a vertical joint");
        assert_eq!(brick_height(32, 0, 256), 0.0, "a horizontal joint");
        // The next row is shifted by half a brick: its joint is at x = 32.
        assert_eq!(brick_height(32, 48, 256), 0.0);
        assert_eq!(brick_height(0, 48, 256), 1.0);
    }

    #[test]
    fn flat_texels_encode_straight_up_and_slopes_lean_away_from_the_rise() {
        let map = brick_normal_map(256, 8.0);
        // The middle of a brick: (0, 0, 1) encodes as (128, 128, 255).
        assert_eq!(map.get_pixel(32, 16).0, [128, 128, 255, 255]);
        // The left bevel of the brick at x in 0..64: height rises with x, so the normal
        // leans toward -x (red below 128), and green stays 128.
        let left = map.get_pixel(5, 16).0;
        assert!(left[0] < 100 && left[1] == 128, "{left:?}");
        let right = map.get_pixel(58, 16).0;
        assert!(right[0] > 156 && right[1] == 128, "{right:?}");
        // The top bevel (small y, near the image top): height rises going down the image,
        // i.e. falls going up, so the normal leans up the image: green above 128.
        let top = map.get_pixel(32, 5).0;
        assert!(top[1] > 156 && top[0] == 128, "{top:?}");
    }

    #[test]
    fn the_map_tiles_seamlessly() {
        let map = brick_normal_map(128, 8.0);
        for i in 0..128 {
            // Left and right columns, top and bottom rows: both sit in mortar or bevel in a
            // way that matches across the wrap (same x-slope sign pattern mirrored).
            let (l, r) = (map.get_pixel(0, i).0, map.get_pixel(127, i).0);
            assert_eq!(l[1], r[1], "row {i}");
            let (t, b) = (map.get_pixel(i, 0).0, map.get_pixel(i, 127).0);
            assert_eq!(t[0], b[0], "column {i}");
        }
    }
}
