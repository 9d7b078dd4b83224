//! Per-frame switches: lights, lighting model, normal mapping, debug view, tone mapping.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use crate::{CameraView, DebugView, Light, LightingModel};

/// Everything about a frame that is not geometry or camera.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameSettings {
    /// The lights; any number, evaluated in one pass.
    pub lights: Vec<Light>,
    /// Ambient light, linear RGB, multiplied by the base colour.
    pub ambient: Vec3,
    /// Which lighting equation runs.
    pub lighting_model: LightingModel,
    /// Normal mapping for the whole frame (materials without a normal map never use one).
    pub normal_mapping: bool,
    /// Multiplies each material's normal-map strength (tangent-space x and y).
    pub normal_strength: f32,
    /// Flip the normal maps' green channel (for DirectX-convention maps), on top of each
    /// material's own `normal_green_down`.
    pub flip_green: bool,
    /// What the fragment shader outputs.
    pub debug_view: DebugView,
    /// Draw each vertex's tangent (red), bitangent (green) and normal (blue) as lines.
    pub show_tbn: bool,
    /// Length of the TBN lines in world units; `None`: 2% of the scene's bounding diagonal.
    pub tbn_length: Option<f32>,
    /// Background, linear RGBA.
    pub clear_color: [f32; 4],
    /// Multiplies the lit colour before tone mapping.
    pub exposure: f32,
    /// How lit colours (linear, unbounded) become displayable ones.
    pub tone_mapping: ToneMapping,
}

/// How lit colours, linear and unbounded, are mapped to 0..1 before the sRGB encoding.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ToneMapping {
    /// Clamp to 0..1 (the paper's pictures, and the analytic tests).
    #[default]
    None,
    /// Khronos PBR Neutral: colours up to about 0.76 pass unchanged (but for a small offset
    /// in the darks), brighter ones are compressed toward white with a little desaturation.
    /// <https://github.com/KhronosGroup/ToneMapping/tree/main/PBR_Neutral>
    PbrNeutral,
}

impl ToneMapping {
    /// The usual choice for a lighting model: PBR Neutral for [`LightingModel::Pbr`], none for
    /// the paper's models (whose pictures stay as they were).
    #[must_use]
    pub const fn default_for(model: LightingModel) -> Self {
        match model {
            LightingModel::Pbr => Self::PbrNeutral,
            _ => Self::None,
        }
    }

    /// The number the shader switches on.
    const fn to_raw(self) -> u32 {
        match self {
            Self::None => 0,
            Self::PbrNeutral => 1,
        }
    }
}

impl Default for FrameSettings {
    /// One white directional light from the upper right front, a little ambient light,
    /// Blinn-Phong, normal mapping on, a dark grey background, exposure 1, no tone mapping.
    fn default() -> Self {
        Self {
            lights: vec![Light::Directional {
                direction: Vec3::new(-0.4, -0.6, -0.7),
                color: Vec3::ONE,
                intensity: 1.0,
            }],
            ambient: Vec3::splat(0.05),
            lighting_model: LightingModel::default(),
            normal_mapping: true,
            normal_strength: 1.0,
            flip_green: false,
            debug_view: DebugView::default(),
            show_tbn: false,
            tbn_length: None,
            clear_color: [0.02, 0.02, 0.025, 1.0],
            exposure: 1.0,
            tone_mapping: ToneMapping::None,
        }
    }
}

/// Frame flag: normal mapping on.
pub(crate) const FLAG_NORMAL_MAPPING: u32 = 1;
/// Frame flag: flip green.
pub(crate) const FLAG_FLIP_GREEN: u32 = 2;
/// Frame flag: the target is not sRGB, so the shader encodes.
pub(crate) const FLAG_ENCODE_SRGB: u32 = 4;

/// The frame uniforms as the shaders read them (`Frame` in `mesh.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub(crate) struct FrameRaw {
    pub view_proj: [[f32; 4]; 4],
    pub eye: [f32; 3],
    pub light_count: u32,
    pub ambient: [f32; 3],
    pub lighting_model: u32,
    pub debug_view: u32,
    pub flags: u32,
    pub normal_strength: f32,
    pub tbn_length: f32,
    pub exposure: f32,
    pub tone_mapping: u32,
    pub pad: [u32; 2],
}

impl FrameSettings {
    /// The uniforms for this frame seen through `camera`. `default_tbn_length` is used when
    /// [`FrameSettings::tbn_length`] is `None`; `encode_srgb` when the target is not sRGB.
    pub(crate) fn to_raw(
        &self,
        camera: &CameraView,
        default_tbn_length: f32,
        encode_srgb: bool,
    ) -> FrameRaw {
        let view_proj: Mat4 = camera.view_projection();
        let mut flags = 0;
        if self.normal_mapping {
            flags |= FLAG_NORMAL_MAPPING;
        }
        if self.flip_green {
            flags |= FLAG_FLIP_GREEN;
        }
        if encode_srgb {
            flags |= FLAG_ENCODE_SRGB;
        }
        FrameRaw {
            view_proj: view_proj.to_cols_array_2d(),
            eye: camera.eye.to_array(),
            light_count: u32::try_from(self.lights.len()).unwrap_or(u32::MAX),
            ambient: self.ambient.to_array(),
            lighting_model: self.lighting_model.to_raw(),
            debug_view: self.debug_view.to_raw(),
            flags,
            normal_strength: self.normal_strength,
            tbn_length: self.tbn_length.unwrap_or(default_tbn_length),
            exposure: self.exposure,
            tone_mapping: self.tone_mapping.to_raw(),
            pad: [0; 2],
        }
    }
}
