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
    /// Multiplies the image-based light of the renderer's environment
    /// ([`crate::Renderer::set_environment`]); PBR materials only.
    pub environment_intensity: f32,
    /// Turns the environment about +Y, degrees (counter-clockwise seen from above).
    pub environment_rotation_deg: f32,
    /// Draw the environment, blurred, behind the scene instead of [`FrameSettings::clear_color`]
    /// (when the renderer has one).
    pub environment_background: bool,
    /// How many lights cast shadows: the first this many directional and spot lights (at most
    /// 4) get a shadow map with filtered (3 x 3 PCF) edges; 0, the default, turns shadows off.
    pub shadow_maps: usize,
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
    /// ACES filmic, S. Hill's fit of the RRT and ODT (as the Khronos glTF Sample Viewer's
    /// "ACES Hill"): more contrast, highlights roll off to white.
    Aces,
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
            Self::Aces => 2,
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
            environment_intensity: 1.0,
            environment_rotation_deg: 0.0,
            environment_background: true,
            shadow_maps: 0,
        }
    }
}

/// Frame flag: normal mapping on.
pub(crate) const FLAG_NORMAL_MAPPING: u32 = 1;
/// Frame flag: flip green.
pub(crate) const FLAG_FLIP_GREEN: u32 = 2;
/// Frame flag: the target is not sRGB, so the shader encodes.
pub(crate) const FLAG_ENCODE_SRGB: u32 = 4;
/// Frame flag: the renderer has an environment; PBR materials add its light.
pub(crate) const FLAG_ENVIRONMENT: u32 = 8;
/// Frame flag: some lights have shadow maps.
pub(crate) const FLAG_SHADOWS: u32 = 16;

/// How blurred the environment behind the scene is: the specular mip of roughness 0.6.
const BACKGROUND_LOD: f32 = 3.0;

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
    pub environment_intensity: f32,
    /// The specular cube's last mip (roughness 1).
    pub environment_max_lod: f32,
    pub inv_view_proj: [[f32; 4]; 4],
    /// Cosine and sine of the environment's rotation about +Y.
    pub environment_rotation: [f32; 2],
    /// The specular mip the background shows.
    pub background_lod: f32,
    /// How far shadow lookups move along the normal, world units (against acne).
    pub shadow_normal_offset: f32,
}

/// What the frame uniforms take from beyond [`FrameSettings`]: the camera, the scene and the
/// renderer.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrameInputs<'a> {
    /// The camera the frame is seen through.
    pub camera: &'a CameraView,
    /// The TBN lines' length when [`FrameSettings::tbn_length`] is `None`.
    pub default_tbn_length: f32,
    /// The target is not sRGB, so the shader encodes.
    pub encode_srgb: bool,
    /// The renderer has an environment (PBR materials add its light).
    pub environment: bool,
    /// How far shadow lookups move along the normal, in world units; `None` when no light has
    /// a shadow map this frame.
    pub shadow_normal_offset: Option<f32>,
}

impl FrameSettings {
    /// The uniforms for this frame, given what they take from beyond the settings.
    pub(crate) fn to_raw(&self, inputs: &FrameInputs<'_>) -> FrameRaw {
        let FrameInputs {
            camera,
            default_tbn_length,
            encode_srgb,
            environment,
            shadow_normal_offset,
        } = *inputs;
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
        if environment {
            flags |= FLAG_ENVIRONMENT;
        }
        if shadow_normal_offset.is_some() {
            flags |= FLAG_SHADOWS;
        }
        let (sin, cos) = self.environment_rotation_deg.to_radians().sin_cos();
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
            environment_intensity: self.environment_intensity,
            environment_max_lod: (crate::environment::SPECULAR_MIPS - 1) as f32,
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            environment_rotation: [cos, sin],
            background_lod: BACKGROUND_LOD,
            shadow_normal_offset: shadow_normal_offset.unwrap_or(0.0),
        }
    }
}
