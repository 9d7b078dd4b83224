//! The TOML scene schema as serde reads it. These types mirror the file one to one; the
//! checked, resolved form is [`crate::Scene`]. docs/scene.md documents every key.

use serde::Deserialize;
use toml::Spanned;

use seamlit_mesh::FixOptions;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneFile {
    #[serde(default)]
    pub model: Vec<Spanned<ModelDef>>,
    #[serde(default)]
    pub light: Vec<Spanned<LightDef>>,
    #[serde(default)]
    pub camera: Vec<Spanned<CameraDef>>,
    pub render: Option<Spanned<RenderDef>>,
}

/// `[render]`: how the scene is drawn.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RenderDef {
    pub lighting: Option<LightingKind>,
    pub environment: Option<String>,
    pub environment_intensity: Option<f32>,
    pub environment_rotation: Option<f32>,
    pub background: Option<[f32; 3]>,
    pub ambient: Option<f32>,
    pub tone_mapping: Option<ToneMappingKind>,
    pub exposure: Option<f32>,
    pub shadows: Option<bool>,
    pub animation: Option<AnimationDef>,
    pub time: Option<f32>,
}

/// `[render] animation`: a name or an index.
#[derive(Debug, Deserialize)]
#[serde(untagged, expecting = "an animation's name or index")]
pub(crate) enum AnimationDef {
    Index(usize),
    Name(String),
}

/// The tone mappings a scene can ask for.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum ToneMappingKind {
    KhrPbrNeutral,
    Aces,
    None,
}

/// The lighting equations a scene can ask for.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum LightingKind {
    Pbr,
    BlinnPhong,
    Phong,
    Lambert,
    Gouraud,
}

/// `[[model]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ModelDef {
    pub path: String,
    pub name: Option<String>,
    #[serde(default)]
    pub translate: Option<[f32; 3]>,
    /// Degrees about X, then Y, then Z.
    #[serde(default)]
    pub rotate: Option<[f32; 3]>,
    #[serde(default)]
    pub scale: Option<Scale>,
    #[serde(default)]
    pub fix: Option<FixOptions>,
    #[serde(default)]
    pub material: Vec<MaterialDef>,
    pub animation: Option<AnimationDef>,
    pub time: Option<f32>,
    pub variant: Option<String>,
}

/// A uniform or per-axis scale.
#[derive(Debug, Deserialize)]
#[serde(untagged, expecting = "a number or an array of three numbers")]
pub(crate) enum Scale {
    Uniform(f32),
    PerAxis([f32; 3]),
}

/// `[[model.material]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MaterialDef {
    pub name: Option<String>,
    pub base_color: Option<Vec<f32>>,
    pub specular: Option<[f32; 3]>,
    pub shininess: Option<f32>,
    pub normal_texture: Option<String>,
    pub normal_scale: Option<f32>,
    pub normal_green_down: Option<bool>,
    pub normal_mapping: Option<bool>,
    pub double_sided: Option<bool>,
}

/// The kinds of light.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub(crate) enum LightKind {
    Directional,
    Point,
    Spot,
}

/// `[[light]]`: one flat table for every kind, so that errors keep their key and line; the
/// kind decides which keys are required.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LightDef {
    #[serde(rename = "type")]
    pub kind: LightKind,
    pub direction: Option<[f32; 3]>,
    pub position: Option<[f32; 3]>,
    pub color: Option<[f32; 3]>,
    pub intensity: Option<f32>,
    pub range: Option<f32>,
    pub inner_cone_deg: Option<f32>,
    pub outer_cone_deg: Option<f32>,
}

/// `[[camera]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CameraDef {
    pub name: String,
    pub position: [f32; 3],
    pub target: [f32; 3],
    pub up: Option<[f32; 3]>,
    pub fov_deg: Option<f32>,
    pub near: Option<f32>,
    pub far: Option<f32>,
}
