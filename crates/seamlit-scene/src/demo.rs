//! The demo scene that `seamlit demo` renders with no files: the Newell teapot (public domain,
//! embedded) tessellated patch by patch into 32 objects, a brick normal map generated in code,
//! three lights and a camera.

use glam::Vec3;
use seamlit_io::{Asset, IoError, Material};
use seamlit_render::Light;

use crate::camera::Camera;

/// The Newell teapot: 32 bicubic Bezier patches in the classic text format (public domain,
/// Martin Newell, 1975; from the 1991 `newell_teaset` distribution).
pub const TEAPOT: &str = include_str!("../../../assets/models/newell_teaset/teapot");

/// The demo's three lights: a warm key light from the upper left, a cool point light on the
/// right and a spot light from above and behind that rims the lid and handle.
#[must_use]
pub fn lights() -> Vec<Light> {
    vec![
        Light::Directional {
            direction: Vec3::new(0.5, -0.6, -0.6),
            color: Vec3::new(1.0, 0.93, 0.85),
            intensity: 0.85,
        },
        Light::Point {
            position: Vec3::new(5.0, 2.0, 3.0),
            color: Vec3::new(0.55, 0.7, 1.0),
            intensity: 0.8,
            range: 25.0,
        },
        Light::Spot {
            position: Vec3::new(-2.0, 7.0, -5.0),
            direction: Vec3::new(0.25, -0.75, 0.6),
            color: Vec3::new(1.0, 1.0, 1.0),
            intensity: 0.7,
            range: 30.0,
            inner_cone_deg: 20.0,
            outer_cone_deg: 35.0,
        },
    ]
}

/// The demo camera: in front of the teapot, slightly above, once the teapot stands with Y up
/// (see [`teapot_transform`]).
#[must_use]
pub fn camera() -> Camera {
    let mut c = Camera::look_at("demo", Vec3::new(2.2, 4.6, 7.6), Vec3::new(0.0, 1.4, 0.0));
    c.fov_y_deg = 38.0;
    c
}

/// The demo material: terracotta with a strong specular and a shallow brick normal map (texture
/// index 0 of the demo asset).
#[must_use]
pub fn material() -> Material {
    Material {
        name: "terracotta bricks".into(),
        base_color: [0.75, 0.36, 0.22, 1.0],
        base_color_texture: None,
        // Half the texture per patch: 2 x 4 large bricks, whose smooth faces show the shading.
        normal_texture: Some(seamlit_io::TextureRef {
            texture: 0,
            tex_coord: 0,
            transform: Some(seamlit_io::UvTransform {
                offset: [0.0, 0.0],
                rotation: 0.0,
                scale: [0.5, 0.5],
            }),
        }),
        // Shallow bricks: the smooth shading, and so the seams, stay visible under them.
        normal_scale: 0.5,
        specular: [0.6, 0.6, 0.6],
        shininess: 48.0,
        ..Material::default()
    }
}

/// The Newell data is Z up: this turns it Y up (a -90 degree turn about X).
#[must_use]
pub fn teapot_transform() -> glam::Mat4 {
    glam::Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2)
}

/// The demo's generated brick normal map as a texture (texture 0 of [`teapot_asset`], the
/// normal texture of [`material`]).
#[must_use]
pub fn bricks_texture() -> seamlit_io::Texture {
    crate::assemble::bricks_texture()
}

/// The demo teapot: the embedded patches tessellated into 32 objects of `tessellation` x
/// `tessellation` quads each (UVs = patch parameters), turned Y up, with the demo
/// [`material`] and the generated brick normal map as texture 0.
///
/// # Errors
/// None in practice: the embedded text is valid (a test checks it); the error is
/// [`seamlit_io::newell::parse`]'s.
pub fn teapot_asset(tessellation: u32) -> Result<Asset, IoError> {
    let mut asset = seamlit_io::newell::parse(TEAPOT, "teapot", tessellation)?;
    asset.materials = vec![material()];
    asset.textures = vec![crate::assemble::bricks_texture()];
    for object in &mut asset.model.objects {
        object.material = Some(0);
    }
    crate::assemble::place(&mut asset, teapot_transform());
    Ok(asset)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_teapot_is_the_32_patch_newell_file() {
        let mut lines = TEAPOT.lines();
        assert_eq!(lines.next().map(str::trim), Some("32"));
        // 32 patch lines, then the vertex count.
        assert_eq!(lines.nth(32).map(str::trim), Some("306"));
    }

    #[test]
    fn the_demo_teapot_is_32_textured_objects_standing_y_up() {
        let asset = teapot_asset(4).unwrap();
        assert_eq!(asset.model.objects.len(), 32);
        assert!(asset.model.objects.iter().all(|o| o.material == Some(0) && o.uvs.is_some()));
        assert_eq!(asset.model.triangle_count(), 32 * 2 * 4 * 4);
        let (min, max) = asset.model.bounds().unwrap();
        // The Newell teapot is about 6.4 units wide (spout to handle) and 3.15 tall (Z in
        // the file, Y here), standing on 0.
        assert!(min.y.abs() < 1e-4 && (max.y - 3.15).abs() < 0.01, "{min} {max}");
        assert!((max.x - min.x) > 5.5 && (max.x - min.x) < 6.5, "{min} {max}");
        let normal = asset.materials[0].normal_texture.as_ref().unwrap();
        assert!(asset.textures[normal.texture].image.is_some());
    }

    #[test]
    fn the_demo_has_three_lights_of_three_kinds() {
        let l = lights();
        assert!(matches!(
            l[..],
            [Light::Directional { .. }, Light::Point { .. }, Light::Spot { .. }]
        ));
    }

    #[test]
    fn z_up_becomes_y_up() {
        let p = teapot_transform().transform_point3(Vec3::Z);
        assert!((p - Vec3::Y).length() < 1e-6, "{p}");
    }
}
