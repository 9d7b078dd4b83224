//! Light rigs: the default three-light rig a scene gets when it names no light, and the
//! lights a glTF file carries (KHR_lights_punctual) as the renderer's.

use glam::{Mat4, Vec3};
use seamlit_io::{PunctualKind, PunctualLight};
use seamlit_render::Light;

/// The classic three-light rig, all directional so that it suits a model of any size: a warm
/// key light from the upper left front, a cool dimmer fill from the right, and a rim light
/// from behind and above that outlines the silhouette.
#[must_use]
pub fn three_point_rig() -> Vec<Light> {
    vec![
        Light::Directional {
            direction: Vec3::new(0.6, -0.7, -0.5),
            color: Vec3::new(1.0, 0.95, 0.88),
            intensity: 0.9,
        },
        Light::Directional {
            direction: Vec3::new(-0.8, -0.2, -0.4),
            color: Vec3::new(0.75, 0.85, 1.0),
            intensity: 0.35,
        },
        Light::Directional {
            direction: Vec3::new(-0.2, -0.5, 1.0),
            color: Vec3::new(1.0, 1.0, 1.0),
            intensity: 0.5,
        },
    ]
}

/// A glTF light (KHR_lights_punctual, in model space) as the renderer's, moved by `transform`
/// (the model's placement in the scene). Intensities pass through as they are (lux for
/// directional lights, candela for point and spot lights: the PBR model's units); a light
/// without a range gets no cut-off (range 0); cone angles go from radians to degrees.
#[must_use]
pub fn from_gltf(light: &PunctualLight, transform: Mat4) -> Light {
    let color = Vec3::from_array(light.color);
    let position = transform.transform_point3(light.position);
    let direction = transform.transform_vector3(light.direction);
    let range = light.range.unwrap_or(0.0);
    match light.kind {
        PunctualKind::Directional => {
            Light::Directional { direction, color, intensity: light.intensity }
        }
        PunctualKind::Point => Light::Point { position, color, intensity: light.intensity, range },
        PunctualKind::Spot { inner_cone_angle, outer_cone_angle } => Light::Spot {
            position,
            direction,
            color,
            intensity: light.intensity,
            range,
            inner_cone_deg: inner_cone_angle.to_degrees(),
            outer_cone_deg: outer_cone_angle.to_degrees(),
        },
    }
}

/// The direction a light travels, if it has one (directional and spot lights).
#[must_use]
pub fn light_direction(light: &Light) -> Option<Vec3> {
    match *light {
        Light::Directional { direction, .. } | Light::Spot { direction, .. } => Some(direction),
        Light::Point { .. } => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gltf_spot_light_is_placed_by_the_model_transform_with_its_cones_in_degrees() {
        let light = PunctualLight {
            name: "spot".into(),
            kind: PunctualKind::Spot {
                inner_cone_angle: std::f32::consts::FRAC_PI_6,
                outer_cone_angle: std::f32::consts::FRAC_PI_4,
            },
            color: [1.0, 0.5, 0.25],
            intensity: 40.0,
            position: Vec3::new(1.0, 2.0, 3.0),
            direction: Vec3::NEG_Z,
            range: None,
        };
        // Translate by +10 X after turning 90 degrees about Y (-Z goes to -X).
        let transform = Mat4::from_translation(Vec3::X * 10.0)
            * Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2);
        let Light::Spot {
            position,
            direction,
            color,
            intensity,
            range,
            inner_cone_deg,
            outer_cone_deg,
        } = from_gltf(&light, transform)
        else {
            panic!("a spot light stays a spot light");
        };
        assert!((position - Vec3::new(13.0, 2.0, -1.0)).length() < 1e-5, "{position}");
        assert!((direction - Vec3::NEG_X).length() < 1e-6, "{direction}");
        assert_eq!((color, intensity, range), (Vec3::new(1.0, 0.5, 0.25), 40.0, 0.0));
        assert!((inner_cone_deg - 30.0).abs() < 1e-4 && (outer_cone_deg - 45.0).abs() < 1e-4);
    }

    #[test]
    fn the_rig_has_a_key_a_fill_and_a_rim_light() {
        let rig = three_point_rig();
        assert_eq!(rig.len(), 3);
        let intensity = |l: &Light| match *l {
            Light::Directional { intensity, .. } => intensity,
            _ => panic!("the rig is directional"),
        };
        // The key is the brightest; the fill is the dimmest.
        assert!(intensity(&rig[0]) > intensity(&rig[2]) && intensity(&rig[2]) > intensity(&rig[1]));
        // Key and fill shine from the front (toward -Z, where the default camera looks), the
        // rim from behind (toward +Z), and all from above.
        let dirs: Vec<Vec3> = rig.iter().filter_map(light_direction).collect();
        assert!(dirs[0].z < 0.0 && dirs[1].z < 0.0 && dirs[2].z > 0.0);
        assert!(dirs.iter().all(|d| d.y < 0.0));
        // Key and fill come from opposite sides.
        assert!(dirs[0].x * dirs[1].x < 0.0);
    }
}
