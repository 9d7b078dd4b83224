//! Scenes: models with transforms, processing options and material overrides, lights, and
//! named cameras, read from TOML (docs/design.md section 7). A model path alone is a scene too.

use std::path::{Path, PathBuf};

use glam::Mat4;
use seamlit_mesh::FixOptions;
use seamlit_render::{Light, LightingModel, ToneMapping};

use crate::camera::{Bounds, Camera};
use crate::error::{Invalid, SceneError};
use crate::lights::three_point_rig;
mod check;

use crate::schema::SceneFile;
use check::Ctx;

/// A scene, checked and with its paths resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The scene file, or `None` for a scene made from a model path or in code.
    pub source: Option<PathBuf>,
    /// The models, at least one.
    pub models: Vec<SceneModel>,
    /// The lights; empty means "use the default rig" ([`Scene::lights_or_default`]).
    pub lights: Vec<Light>,
    /// The cameras, in file order; empty means "frame the model"
    /// ([`Scene::cameras_or_default`]).
    pub cameras: Vec<Camera>,
    /// `[render] lighting`: the lighting equation the scene asks for; `None` leaves the choice
    /// to the program (seamlit: PBR for glTF models, Blinn-Phong otherwise).
    pub lighting: Option<LightingModel>,
    /// The rest of `[render]`: environment, background, ambient, tone mapping, exposure.
    pub render: RenderOptions,
}

/// `[render]` but for `lighting`: how the scene asks to be drawn. Each `None` leaves the
/// choice to the program (and a command-line flag overrides a value given here).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderOptions {
    /// `environment`: where image-based light comes from.
    pub environment: Option<EnvironmentChoice>,
    /// `environment_intensity`: multiplies the environment's light (>= 0).
    pub environment_intensity: Option<f32>,
    /// `environment_rotation`: degrees about +Y.
    pub environment_rotation_deg: Option<f32>,
    /// `background`: sRGB, 0..1.
    pub background: Option<[f32; 3]>,
    /// `ambient`: a grey ambient light, linear (0 = none).
    pub ambient: Option<f32>,
    /// `tone_mapping`.
    pub tone_mapping: Option<ToneMapping>,
    /// `exposure`: multiplies lit colours before tone mapping (> 0).
    pub exposure: Option<f32>,
    /// `shadows`: directional and spot lights cast shadows.
    pub shadows: Option<bool>,
    /// `animation`: the animation the model is posed by (a name or an index into the merged
    /// asset's animations, resolved by the program against what the files have).
    pub animation: Option<AnimationChoice>,
    /// `time`: seconds into the animation (>= 0).
    pub time: Option<f32>,
}

/// An animation, as a scene file or the command line names it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum AnimationChoice {
    /// The animation at this index.
    Index(usize),
    /// The first animation of this name.
    Name(String),
}

impl AnimationChoice {
    /// A number is an index, anything else a name.
    #[must_use]
    pub fn parse(text: &str) -> Self {
        text.parse().map_or_else(|_| Self::Name(text.to_owned()), Self::Index)
    }
}

/// Where image-based light comes from: `"none"`, `"builtin"` or a Radiance `.hdr` file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EnvironmentChoice {
    /// No image-based light.
    None,
    /// seamlit's procedural studio ([`seamlit_render::Environment::Builtin`]).
    Builtin,
    /// An equirectangular Radiance `.hdr` file.
    File(PathBuf),
}

impl EnvironmentChoice {
    /// `none`, `builtin`, or a path (resolved against `base_dir` when relative).
    #[must_use]
    pub fn parse(text: &str, base_dir: &Path) -> Self {
        match text {
            "none" => Self::None,
            "builtin" => Self::Builtin,
            path => Self::File(base_dir.join(path)),
        }
    }
}

/// One model placed in a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneModel {
    /// A name for messages (the scene's `name`, or the file stem).
    pub name: String,
    /// The model file, resolved against the scene file's folder.
    pub path: PathBuf,
    /// Model-to-world transform: translate * rotate (X, then Y, then Z) * scale.
    pub transform: Mat4,
    /// How the model is processed.
    pub fix: FixOptions,
    /// Material overrides, applied in order.
    pub materials: Vec<MaterialOverride>,
    /// `animation`: the animation this model is posed by (an index counts this model's own
    /// animations), instead of `[render]`'s.
    pub animation: Option<AnimationChoice>,
    /// `time`: seconds into it (>= 0), instead of `[render]`'s.
    pub time: Option<f32>,
    /// `variant`: the KHR_materials_variants variant drawn (`None`: the default materials).
    pub variant: Option<String>,
}

/// Changes to one material of a model (or all of them).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MaterialOverride {
    /// The material to change; `None` changes every material (and gives a model without
    /// materials one).
    pub name: Option<String>,
    /// Base colour factor, linear RGBA.
    pub base_color: Option<[f32; 4]>,
    /// Specular colour, linear RGB.
    pub specular: Option<[f32; 3]>,
    /// Blinn-Phong shininess exponent.
    pub shininess: Option<f32>,
    /// A normal map to use instead of the material's own.
    pub normal_texture: Option<NormalTexture>,
    /// Normal map strength.
    pub normal_scale: Option<f32>,
    /// Whether the normal map is in DirectX convention (green down).
    pub normal_green_down: Option<bool>,
    /// `Some(false)` removes the material's normal map.
    pub normal_mapping: Option<bool>,
    /// Whether back faces are drawn.
    pub double_sided: Option<bool>,
}

/// Where an overriding normal map comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NormalTexture {
    /// An image file (resolved against the scene file's folder).
    File(PathBuf),
    /// The brick normal map generated in code (`"builtin:bricks"` in a scene file).
    Bricks,
}

impl Scene {
    /// Reads a scene: a `.toml` file is parsed as a scene, any other path is taken as a model
    /// file and wrapped by [`Scene::from_model_path`].
    ///
    /// # Errors
    /// [`SceneError`] naming the file, line and key at fault.
    pub fn open(path: &Path) -> Result<Self, SceneError> {
        if is_scene_path(path) { Self::load(path) } else { Ok(Self::from_model_path(path)) }
    }

    /// Reads and checks a TOML scene file.
    ///
    /// # Errors
    /// [`SceneError::Read`] if the file cannot be read, [`SceneError::Parse`] for malformed
    /// TOML, unknown keys and wrong types, [`SceneError::Invalid`] for values out of range.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| SceneError::Read { path: path.to_path_buf(), source })?;
        let base = path.parent().unwrap_or_else(|| Path::new(""));
        let mut scene = Self::parse(&text, base, path)?;
        scene.source = Some(path.to_path_buf());
        Ok(scene)
    }

    /// Parses scene text. Relative model and texture paths resolve against `base_dir`;
    /// `file` names the scene in error messages.
    ///
    /// # Errors
    /// As [`Scene::load`], less the read error.
    pub fn parse(text: &str, base_dir: &Path, file: &Path) -> Result<Self, SceneError> {
        let ctx = Ctx { text, file };
        let parsed: SceneFile = toml::from_str(text).map_err(|e| ctx.parse_error(e))?;
        if parsed.model.is_empty() {
            return Err(SceneError::Invalid {
                path: file.to_path_buf(),
                line: 1,
                kind: Invalid::NoModel,
            });
        }
        let models = parsed
            .model
            .into_iter()
            .map(|m| {
                let span = m.span();
                ctx.model(m.into_inner(), base_dir, span)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let lights = parsed
            .light
            .into_iter()
            .map(|l| {
                let span = l.span();
                ctx.light(&l.into_inner(), span)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut cameras: Vec<Camera> = Vec::with_capacity(parsed.camera.len());
        for c in parsed.camera {
            let span = c.span();
            let camera = ctx.camera(c.into_inner(), span.clone())?;
            if cameras.iter().any(|other| other.name == camera.name) {
                return Err(ctx.invalid(&span, Invalid::DuplicateCamera { name: camera.name }));
            }
            cameras.push(camera);
        }
        let (lighting, render) = match parsed.render {
            Some(r) => {
                let span = r.span();
                ctx.render(&r.into_inner(), &span, base_dir)?
            }
            None => (None, RenderOptions::default()),
        };
        Ok(Self { source: None, models, lights, cameras, lighting, render })
    }

    /// A scene of one model file, with default options, no lights and no cameras (so the
    /// defaults apply).
    #[must_use]
    pub fn from_model_path(path: &Path) -> Self {
        Self {
            source: None,
            models: vec![SceneModel {
                name: file_stem(path),
                path: path.to_path_buf(),
                transform: Mat4::IDENTITY,
                fix: FixOptions::default(),
                materials: Vec::new(),
                animation: None,
                time: None,
                variant: None,
            }],
            lights: Vec::new(),
            cameras: Vec::new(),
            lighting: None,
            render: RenderOptions::default(),
        }
    }

    /// The scene's lights, or the default three-light rig when it names none.
    #[must_use]
    pub fn lights_or_default(&self) -> Vec<Light> {
        if self.lights.is_empty() { three_point_rig() } else { self.lights.clone() }
    }

    /// The scene's cameras, or one camera framing `bounds` for an image of aspect ratio
    /// `aspect` when it names none.
    #[must_use]
    pub fn cameras_or_default(&self, bounds: Bounds, aspect: f32) -> Vec<Camera> {
        if self.cameras.is_empty() {
            vec![Camera::framing(bounds, aspect)]
        } else {
            self.cameras.clone()
        }
    }

    /// The camera called `name`, or the first camera (`name` = `None`).
    ///
    /// # Errors
    /// A message listing the cameras there are when none has that name.
    pub fn find_camera<'a>(
        cameras: &'a [Camera],
        name: Option<&str>,
    ) -> Result<&'a Camera, String> {
        match name {
            None => cameras.first().ok_or_else(|| "the scene has no camera".to_string()),
            Some(n) => cameras.iter().find(|c| c.name == n).ok_or_else(|| {
                let names: Vec<&str> = cameras.iter().map(|c| c.name.as_str()).collect();
                format!("no camera named {n:?} (there are: {})", names.join(", "))
            }),
        }
    }
}

/// Whether a path names a scene file (extension `.toml`) rather than a model.
#[must_use]
pub fn is_scene_path(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}

fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| path.display().to_string(), |s| s.to_string_lossy().into_owned())
}

#[cfg(test)]
mod tests;
