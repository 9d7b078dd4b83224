//! Lights, cameras and the frame's shading switches: the CPU-side description of what to draw.
//! The GPU layout of a light is `LightRaw`, built by `Light::to_raw` (both crate-private).
//!
//! Attenuation follows KHR_lights_punctual: a point or spot light at distance `d` delivers
//! `color * intensity * clamp(1 - (d / range)^4, 0, 1)^2 / d^2`, and a spot light is further
//! scaled by `t^2` with `t = clamp((cos a - cos outer) / (cos inner - cos outer), 0, 1)`,
//! `a` the angle from the cone's axis. A `range` of zero or less means no cut-off.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

/// A light source. Colours are linear RGB; `intensity` scales the colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Parallel light, like the sun. `direction` points from the light toward the scene.
    Directional {
        /// Direction the light travels (need not be normalised).
        direction: Vec3,
        /// Linear RGB colour.
        color: Vec3,
        /// Multiplier on `color`.
        intensity: f32,
    },
    /// A light at a point, fading smoothly to zero at `range`.
    Point {
        /// Position in world space.
        position: Vec3,
        /// Linear RGB colour.
        color: Vec3,
        /// Multiplier on `color`.
        intensity: f32,
        /// Distance at which the light's contribution reaches zero.
        range: f32,
    },
    /// A cone of light: full inside `inner_cone_deg`, fading to zero at `outer_cone_deg`
    /// (half-angles, degrees), with the same range attenuation as a point light.
    Spot {
        /// Position in world space.
        position: Vec3,
        /// Direction the cone points (need not be normalised).
        direction: Vec3,
        /// Linear RGB colour.
        color: Vec3,
        /// Multiplier on `color`.
        intensity: f32,
        /// Distance at which the light's contribution reaches zero.
        range: f32,
        /// Half-angle of full intensity, degrees.
        inner_cone_deg: f32,
        /// Half-angle where intensity reaches zero, degrees.
        outer_cone_deg: f32,
    },
}

impl Light {
    /// The light as the shader reads it: direction normalised, colour times intensity, cone
    /// angles as cosines.
    #[must_use]
    pub(crate) fn to_raw(self) -> LightRaw {
        let unit = |d: Vec3| d.try_normalize().unwrap_or(Vec3::NEG_Y).to_array();
        match self {
            Self::Directional { direction, color, intensity } => LightRaw {
                kind: LightRaw::DIRECTIONAL,
                direction: unit(direction),
                color: (color * intensity).to_array(),
                shadow: -1.0,
                ..LightRaw::zeroed()
            },
            Self::Point { position, color, intensity, range } => LightRaw {
                position: position.to_array(),
                kind: LightRaw::POINT,
                range,
                color: (color * intensity).to_array(),
                shadow: -1.0,
                ..LightRaw::zeroed()
            },
            Self::Spot {
                position,
                direction,
                color,
                intensity,
                range,
                inner_cone_deg,
                outer_cone_deg,
            } => {
                let outer = outer_cone_deg.clamp(0.0, 90.0);
                let inner = inner_cone_deg.clamp(0.0, outer);
                LightRaw {
                    position: position.to_array(),
                    kind: LightRaw::SPOT,
                    direction: unit(direction),
                    range,
                    color: (color * intensity).to_array(),
                    cos_inner: inner.to_radians().cos(),
                    cos_outer: outer.to_radians().cos(),
                    shadow: -1.0,
                    ..LightRaw::zeroed()
                }
            }
        }
    }
}

/// A light as the shaders read it from the light storage buffer (`Light` in `mesh.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct LightRaw {
    /// World position (point and spot).
    pub position: [f32; 3],
    /// [`LightRaw::DIRECTIONAL`], [`LightRaw::POINT`] or [`LightRaw::SPOT`].
    pub kind: u32,
    /// Unit direction the light travels (directional and spot).
    pub direction: [f32; 3],
    /// Range (point and spot); zero or less: no cut-off.
    pub range: f32,
    /// Linear colour times intensity.
    pub color: [f32; 3],
    /// Cosine of the inner cone half-angle (spot).
    pub cos_inner: f32,
    /// Cosine of the outer cone half-angle (spot).
    pub cos_outer: f32,
    /// The light's shadow-map layer; -1: no shadow.
    pub shadow: f32,
    /// Padding to 64 bytes.
    pub pad: [f32; 2],
}

impl LightRaw {
    /// `kind` of a directional light.
    pub(crate) const DIRECTIONAL: u32 = 0;
    /// `kind` of a point light.
    pub(crate) const POINT: u32 = 1;
    /// `kind` of a spot light.
    pub(crate) const SPOT: u32 = 2;
}

/// A camera as the renderer needs it: where the eye is and how it projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraView {
    /// World-to-view matrix.
    pub view: Mat4,
    /// View-to-clip matrix (wgpu depth range 0..1).
    pub projection: Mat4,
    /// Eye position in world space (for specular highlights).
    pub eye: Vec3,
}

/// How a camera projects (see [`CameraDescriptor`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Perspective, with a vertical field of view in degrees.
    Perspective {
        /// Vertical field of view, degrees.
        fov_y_deg: f32,
    },
    /// Orthographic, showing `half_height` world units above and below the centre (and
    /// `half_height * aspect` to each side).
    Orthographic {
        /// World units from the centre to the top edge.
        half_height: f32,
    },
}

/// A camera for [`CameraView::look_at`]: where the eye is, where it looks, and how it
/// projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraDescriptor {
    /// Eye position, world space.
    pub eye: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// The world direction that is up in the picture.
    pub up: Vec3,
    /// Perspective or orthographic.
    pub projection: Projection,
    /// Width over height.
    pub aspect: f32,
    /// Near clip distance.
    pub near: f32,
    /// Far clip distance.
    pub far: f32,
}

impl CameraView {
    /// The camera `desc` describes: at `desc.eye` looking at `desc.target`, projecting into
    /// wgpu's depth range 0..1.
    #[must_use]
    pub fn look_at(desc: &CameraDescriptor) -> Self {
        let CameraDescriptor { eye, target, up, projection, aspect, near, far } = *desc;
        let projection = match projection {
            Projection::Perspective { fov_y_deg } => glam::camera::rh::proj::directx::perspective(
                fov_y_deg.to_radians(),
                aspect,
                near,
                far,
            ),
            Projection::Orthographic { half_height } => {
                let w = half_height * aspect;
                glam::camera::rh::proj::directx::orthographic(
                    -w,
                    w,
                    -half_height,
                    half_height,
                    near,
                    far,
                )
            }
        };
        Self { view: glam::camera::rh::view::look_at_mat4(eye, target, up), projection, eye }
    }

    /// `projection * view`.
    #[must_use]
    pub fn view_projection(&self) -> Mat4 {
        self.projection * self.view
    }
}

/// The lighting equation evaluated per pixel (or per vertex, for Gouraud).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LightingModel {
    /// Per-pixel Blinn-Phong (half vector). The default.
    #[default]
    BlinnPhong,
    /// Per-pixel Phong (reflection vector).
    Phong,
    /// Per-pixel diffuse only.
    Lambert,
    /// Blinn-Phong evaluated per vertex and interpolated (the paper's Figure 3).
    Gouraud,
    /// glTF 2.0 metallic-roughness (the specification's Appendix B), per pixel: Lambert
    /// diffuse, GGX distribution, height-correlated Smith visibility, Schlick Fresnel with
    /// F0 = 0.04 for dielectrics and the base colour for metals. Ambient light acts as a
    /// uniform environment (its specular part by Karis' analytic split-sum fit) and is
    /// darkened by the occlusion texture.
    Pbr,
}

impl LightingModel {
    /// The number the shader switches on.
    #[must_use]
    pub(crate) const fn to_raw(self) -> u32 {
        match self {
            Self::BlinnPhong => 0,
            Self::Phong => 1,
            Self::Lambert => 2,
            Self::Gouraud => 3,
            Self::Pbr => 4,
        }
    }
}

/// What the fragment shader outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DebugView {
    /// Lit and textured: the normal picture.
    #[default]
    Lit,
    /// World-space shading normal as colour (`n * 0.5 + 0.5`).
    Normals,
    /// World-space tangent as colour.
    Tangents,
    /// Bitangent sign: green for w = +1, red for w = -1.
    BitangentSign,
    /// Texture coordinates as red and green.
    Uvs,
    /// A distinct flat colour per object, to see where the seams are.
    ObjectIds,
    /// Lighting on a white material, no textures.
    LightingOnly,
    /// Metalness (metallic factor times the texture's blue channel) as grey.
    Metallic,
    /// Perceptual roughness (roughness factor times the texture's green channel) as grey.
    Roughness,
    /// Ambient occlusion as the material applies it (texture red channel by strength).
    Occlusion,
}

impl DebugView {
    /// The number the shader switches on.
    #[must_use]
    pub(crate) const fn to_raw(self) -> u32 {
        match self {
            Self::Lit => 0,
            Self::Normals => 1,
            Self::Tangents => 2,
            Self::BitangentSign => 3,
            Self::Uvs => 4,
            Self::ObjectIds => 5,
            Self::LightingOnly => 6,
            Self::Metallic => 7,
            Self::Roughness => 8,
            Self::Occlusion => 9,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_raw_is_64_bytes_and_normalises() {
        assert_eq!(size_of::<LightRaw>(), 64);
        let raw = Light::Spot {
            position: Vec3::ONE,
            direction: Vec3::new(0.0, 0.0, -2.0),
            color: Vec3::new(1.0, 0.5, 0.25),
            intensity: 2.0,
            range: 10.0,
            inner_cone_deg: 60.0,
            outer_cone_deg: 30.0,
        }
        .to_raw();
        assert_eq!(raw.kind, LightRaw::SPOT);
        assert_eq!(raw.direction, [0.0, 0.0, -1.0]);
        assert_eq!(raw.color, [2.0, 1.0, 0.5]);
        // An inner cone wider than the outer one is clamped to the outer one.
        assert_eq!(raw.cos_inner, raw.cos_outer);
        assert!((raw.cos_outer - 30f32.to_radians().cos()).abs() < 1e-7);
    }
}
