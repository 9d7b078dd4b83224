//! Light rigs: the default three-light rig a scene gets when it names no light.

use glam::Vec3;
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
