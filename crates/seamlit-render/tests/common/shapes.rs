//! Procedural test shapes with analytic normals and tangents (shared by the tests and the
//! `frametime` example).

use std::f32::consts::PI;

use glam::{Vec2, Vec3, Vec4};
use image::RgbaImage;
use seamlit_mesh::Object;

/// A UV sphere of `radius` with `rings` x `segments` quads, latitudes `v0..v1` (0 = south
/// pole, 1 = north pole): normals outward, tangents along +U with w = +1, V up.
pub fn sphere(name: &str, radius: f32, rings: u32, segments: u32, v0: f32, v1: f32) -> Object {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut tangents = Vec::new();
    let mut uvs = Vec::new();
    for i in 0..=rings {
        let v = v0 + (v1 - v0) * i as f32 / rings as f32;
        let theta = v * PI;
        for j in 0..=segments {
            let u = j as f32 / segments as f32;
            let a = u * 2.0 * PI;
            let n = Vec3::new(theta.sin() * a.sin(), -theta.cos(), theta.sin() * a.cos());
            positions.push(n * radius);
            normals.push(n);
            tangents.push(Vec4::new(a.cos(), 0.0, -a.sin(), 1.0));
            uvs.push(Vec2::new(u * 4.0, v * 2.0));
        }
    }
    let row = segments + 1;
    let mut triangles = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) =
                (i * row + j, i * row + j + 1, (i + 1) * row + j + 1, (i + 1) * row + j);
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    let mut o = Object::new(name, positions, triangles).with_uvs(uvs);
    o.normals = Some(normals);
    o.tangents = Some(tangents);
    o
}

/// A brick-wall normal map: 4 rows of bricks with bevelled mortar grooves, V up the image.
pub fn brick_normal_map(size: u32) -> RgbaImage {
    let height = |x: f32, y: f32| {
        let rows = 4.0;
        let row = (y * rows).floor();
        let offset = if row % 2.0 == 0.0 { 0.0 } else { 0.5 };
        let bx = (x * 2.0 + offset).fract();
        let by = (y * rows).fract();
        let edge = bx.min(1.0 - bx).min((by.min(1.0 - by)) * 0.5);
        (edge / 0.04).min(1.0)
    };
    let s = size as f32;
    RgbaImage::from_fn(size, size, |i, j| {
        let x = (i as f32 + 0.5) / s;
        let y = 1.0 - (j as f32 + 0.5) / s;
        let e = 1.0 / s;
        let dx = (height(x + e, y) - height(x - e, y)) / (2.0 * e);
        let dy = (height(x, y + e) - height(x, y - e)) / (2.0 * e);
        let n = Vec3::new(-dx * 0.01, -dy * 0.01, 1.0).normalize();
        #[expect(
            clippy::cast_possible_truncation,
            reason = "a unit vector's component maps into 0..=255"
        )]
        let b = |c: f32| ((c * 0.5 + 0.5) * 255.0).round() as u8;
        image::Rgba([b(n.x), b(n.y), b(n.z), 255])
    })
}

/// A base-colour texture: a warm checker, 8x8 cells.
pub fn checker(size: u32) -> RgbaImage {
    RgbaImage::from_fn(size, size, |i, j| {
        if (i * 8 / size + j * 8 / size).is_multiple_of(2) {
            image::Rgba([220, 180, 140, 255])
        } else {
            image::Rgba([170, 120, 90, 255])
        }
    })
}
