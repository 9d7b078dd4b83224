//! Lights, cameras and the frame's shading switches: the CPU-side description of what to draw.
//! (GPU layouts are built from these by `to_raw()` functions elsewhere in this crate.)

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
}
