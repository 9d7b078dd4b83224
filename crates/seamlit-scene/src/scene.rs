//! Scenes: models with transforms, processing options and material overrides, lights, and
//! named cameras, read from TOML (docs/design.md section 7). A model path alone is a scene too.

use std::ops::Range;
use std::path::{Path, PathBuf};

use glam::{EulerRot, Mat4, Quat, Vec3};
use seamlit_mesh::FixOptions;
use seamlit_render::{Light, LightingModel, ToneMapping};

use crate::camera::{Bounds, Camera};
use crate::error::{Invalid, SceneError};
use crate::lights::three_point_rig;
use crate::schema::{
    AnimationDef, CameraDef, LightDef, LightKind, LightingKind, MaterialDef, ModelDef, RenderDef,
    Scale, SceneFile, ToneMappingKind,
};

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

/// Scene text and name, for error positions.
struct Ctx<'a> {
    text: &'a str,
    file: &'a Path,
}

impl Ctx<'_> {
    /// 1-based line and column of a byte offset.
    fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let before = self.text.get(..offset).unwrap_or("");
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, column)
    }

    fn parse_error(&self, e: toml::de::Error) -> SceneError {
        let span = e.span().unwrap_or(0..0);
        let (line, column) = self.line_col(span.start);
        SceneError::Parse {
            path: self.file.to_path_buf(),
            line,
            column,
            key: self.key_at(&span, e.message().trim()),
            error: Box::new(e),
        }
    }

    /// The key an error is about: quoted in the message (unknown and missing fields), or the
    /// `key = value` whose value the span covers.
    fn key_at(&self, span: &Range<usize>, message: &str) -> Option<String> {
        if let Some(rest) = message.split('`').nth(1)
            && (message.starts_with("unknown field") || message.starts_with("missing field"))
        {
            return Some(rest.to_string());
        }
        let line_start = self.text.get(..span.start)?.rfind('\n').map_or(0, |i| i + 1);
        let line = self.text.get(line_start..)?.lines().next()?;
        let (key, _) = line.split_once('=')?;
        let key = key.trim().trim_matches('"');
        (!key.is_empty() && !key.starts_with('[')).then(|| key.to_string())
    }

    /// `[render]`, checked: the lighting model and the other options.
    fn render(
        &self,
        def: &RenderDef,
        span: &Range<usize>,
        base_dir: &Path,
    ) -> Result<(Option<LightingModel>, RenderOptions), SceneError> {
        let lighting = def.lighting.map(|l| match l {
            LightingKind::Pbr => LightingModel::Pbr,
            LightingKind::BlinnPhong => LightingModel::BlinnPhong,
            LightingKind::Phong => LightingModel::Phong,
            LightingKind::Lambert => LightingModel::Lambert,
            LightingKind::Gouraud => LightingModel::Gouraud,
        });
        let check = |key, value: Option<f32>, ok: fn(f32) -> bool, expected| match value {
            Some(value) if !ok(value) => {
                Err(self.invalid(span, Invalid::RenderValue { key, value, expected }))
            }
            _ => Ok(value),
        };
        let background = def.background;
        if let Some(b) = background
            && !b.iter().all(|c| (0.0..=1.0).contains(c))
        {
            return Err(self.invalid(span, Invalid::Background { value: b }));
        }
        let options = RenderOptions {
            environment: def.environment.as_deref().map(|e| EnvironmentChoice::parse(e, base_dir)),
            environment_intensity: check(
                "environment_intensity",
                def.environment_intensity,
                |v| v.is_finite() && v >= 0.0,
                "a number >= 0",
            )?,
            environment_rotation_deg: check(
                "environment_rotation",
                def.environment_rotation,
                f32::is_finite,
                "a number of degrees",
            )?,
            background,
            ambient: check("ambient", def.ambient, |v| v.is_finite() && v >= 0.0, "a number >= 0")?,
            tone_mapping: def.tone_mapping.map(|t| match t {
                ToneMappingKind::KhrPbrNeutral => ToneMapping::PbrNeutral,
                ToneMappingKind::Aces => ToneMapping::Aces,
                ToneMappingKind::None => ToneMapping::None,
            }),
            exposure: check(
                "exposure",
                def.exposure,
                |v| v.is_finite() && v > 0.0,
                "a number > 0",
            )?,
            shadows: def.shadows,
            animation: def.animation.as_ref().map(|a| match a {
                AnimationDef::Index(i) => AnimationChoice::Index(*i),
                AnimationDef::Name(n) => AnimationChoice::Name(n.clone()),
            }),
            time: check("time", def.time, |v| v.is_finite() && v >= 0.0, "seconds >= 0")?,
        };
        Ok((lighting, options))
    }

    fn invalid(&self, span: &Range<usize>, kind: Invalid) -> SceneError {
        SceneError::Invalid {
            path: self.file.to_path_buf(),
            line: self.line_col(span.start).0,
            kind,
        }
    }

    fn model(
        &self,
        def: ModelDef,
        base: &Path,
        span: Range<usize>,
    ) -> Result<SceneModel, SceneError> {
        if def.path.trim().is_empty() {
            return Err(self.invalid(&span, Invalid::EmptyModelPath));
        }
        let path = base.join(&def.path);
        let name = def.name.unwrap_or_else(|| file_stem(&path));
        let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
        let translate = def.translate.unwrap_or([0.0; 3]);
        let rotate = def.rotate.unwrap_or([0.0; 3]);
        let scale = match def.scale {
            None => [1.0; 3],
            Some(Scale::Uniform(s)) => [s; 3],
            Some(Scale::PerAxis(s)) => s,
        };
        if !finite(&translate) || !finite(&rotate) || !finite(&scale) {
            return Err(self.invalid(&span, Invalid::TransformNotFinite { model: name }));
        }
        if scale.contains(&0.0) {
            return Err(self.invalid(&span, Invalid::ZeroScale { model: name }));
        }
        let [rx, ry, rz] = rotate.map(f32::to_radians);
        let transform = Mat4::from_scale_rotation_translation(
            Vec3::from(scale),
            Quat::from_euler(EulerRot::ZYX, rz, ry, rx),
            Vec3::from(translate),
        );
        let fix = def.fix.unwrap_or_default();
        let non_negative = |a: f32| a.is_finite() && a >= 0.0;
        if !non_negative(fix.crease_angle_deg) || !non_negative(fix.tangent_angle_deg) {
            return Err(self.invalid(&span, Invalid::NegativeAngle { model: name }));
        }
        let materials = def
            .material
            .into_iter()
            .map(|m| self.material(m, base, &span, &name))
            .collect::<Result<Vec<_>, _>>()?;
        if let Some(value) = def.time.filter(|t| !(t.is_finite() && *t >= 0.0)) {
            return Err(self.invalid(&span, Invalid::ModelTime { model: name, value }));
        }
        let animation = def.animation.map(|a| match a {
            AnimationDef::Index(i) => AnimationChoice::Index(i),
            AnimationDef::Name(n) => AnimationChoice::Name(n),
        });
        let (time, variant) = (def.time, def.variant);
        Ok(SceneModel { name, path, transform, fix, materials, animation, time, variant })
    }

    fn material(
        &self,
        def: MaterialDef,
        base: &Path,
        span: &Range<usize>,
        model: &str,
    ) -> Result<MaterialOverride, SceneError> {
        let name = || model.to_owned();
        let bad = |key, expected| {
            self.invalid(span, Invalid::MaterialValue { model: name(), key, expected })
        };
        let base_color = match def.base_color.as_deref() {
            None => None,
            Some(&[r, g, b]) => Some([r, g, b, 1.0]),
            Some(&[r, g, b, a]) => Some([r, g, b, a]),
            Some(other) => {
                let found = other.len();
                return Err(self.invalid(span, Invalid::BaseColorLength { model: name(), found }));
            }
        };
        if base_color.is_some_and(|c| c.iter().any(|x| !(0.0..=1.0).contains(x))) {
            return Err(bad("base_color", "components must lie in 0..1"));
        }
        if def.specular.is_some_and(|c| c.iter().any(|x| !(x.is_finite() && *x >= 0.0))) {
            return Err(bad("specular", "components must be >= 0"));
        }
        if def.shininess.is_some_and(|s| !(s.is_finite() && s >= 0.0)) {
            return Err(bad("shininess", "must be >= 0"));
        }
        if def.normal_scale.is_some_and(|s| !s.is_finite()) {
            return Err(bad("normal_scale", "must be finite"));
        }
        let normal_texture = def.normal_texture.map(|t| {
            if t == "builtin:bricks" {
                NormalTexture::Bricks
            } else {
                NormalTexture::File(base.join(t))
            }
        });
        Ok(MaterialOverride {
            name: def.name,
            base_color,
            specular: def.specular,
            shininess: def.shininess,
            normal_texture,
            normal_scale: def.normal_scale,
            normal_green_down: def.normal_green_down,
            normal_mapping: def.normal_mapping,
            double_sided: def.double_sided,
        })
    }

    /// A `[[light]]` table: the checks every kind shares, then its own kind's.
    fn light(&self, def: &LightDef, span: Range<usize>) -> Result<Light, SceneError> {
        let check = LightCheck { parser: self, def, span: &span, kind: light_kind_name(def.kind) };
        let common = check.common()?;
        match def.kind {
            LightKind::Directional => check.directional(common),
            LightKind::Point => check.point(common),
            LightKind::Spot => check.spot(common),
        }
    }

    fn camera(&self, def: CameraDef, span: Range<usize>) -> Result<Camera, SceneError> {
        let name = def.name.trim().to_string();
        if name.is_empty() {
            return Err(self.invalid(&span, Invalid::EmptyCameraName));
        }
        let position = Vec3::from(def.position);
        let target = Vec3::from(def.target);
        let up = def.up.map_or(Vec3::Y, Vec3::from);
        if !(position.is_finite() && target.is_finite() && up.is_finite()) {
            return Err(self.invalid(&span, Invalid::CameraNotFinite { camera: name }));
        }
        if position.distance_squared(target) == 0.0 {
            return Err(self.invalid(&span, Invalid::PositionIsTarget { camera: name }));
        }
        let fov = def.fov_deg.unwrap_or(crate::camera::DEFAULT_FOV_Y_DEG);
        if !(fov > 0.0 && fov < 180.0) {
            return Err(self.invalid(&span, Invalid::FieldOfView { camera: name, fov_deg: fov }));
        }
        let near_ok = def.near.is_none_or(|n| n.is_finite() && n > 0.0);
        let far_ok = def.far.is_none_or(|f| f.is_finite() && f > def.near.unwrap_or(0.0));
        if !near_ok || !far_ok {
            return Err(self.invalid(&span, Invalid::NearFar { camera: name }));
        }
        Ok(Camera { name, position, target, up, fov_y_deg: fov, near: def.near, far: def.far })
    }
}

/// The name of a light kind, as the scene file writes it.
fn light_kind_name(kind: LightKind) -> &'static str {
    match kind {
        LightKind::Directional => "directional",
        LightKind::Point => "point",
        LightKind::Spot => "spot",
    }
}

/// What every light has, checked: colour, intensity and range.
struct LightCommon {
    color: Vec3,
    intensity: f32,
    range: f32,
}

/// One `[[light]]` table being checked, with where its errors point.
struct LightCheck<'a, 'c> {
    parser: &'a Ctx<'c>,
    def: &'a LightDef,
    span: &'a Range<usize>,
    kind: &'static str,
}

impl LightCheck<'_, '_> {
    fn invalid(&self, kind: Invalid) -> SceneError {
        self.parser.invalid(self.span, kind)
    }

    /// The key's vector, which this kind needs.
    fn need(&self, v: Option<[f32; 3]>, key: &'static str) -> Result<Vec3, SceneError> {
        v.map(Vec3::from).ok_or_else(|| self.invalid(Invalid::LightNeeds { light: self.kind, key }))
    }

    /// An error where a key this kind does not have is present.
    fn forbid(&self, present: bool, key: &'static str) -> Result<(), SceneError> {
        if present {
            Err(self.invalid(Invalid::LightHasNo { light: self.kind, key }))
        } else {
            Ok(())
        }
    }

    /// `v`, which must be finite and not zero.
    fn nonzero(&self, v: Vec3, key: &'static str) -> Result<Vec3, SceneError> {
        if v.is_finite() && v.length_squared() > 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(Invalid::ZeroVector { light: self.kind, key }))
        }
    }

    /// Colour and intensity (at least 0) and, but for a directional light, range (above 0).
    fn common(&self) -> Result<LightCommon, SceneError> {
        let def = self.def;
        let color = def.color.map_or(Vec3::ONE, Vec3::from);
        let intensity = def.intensity.unwrap_or(1.0);
        if !color.is_finite()
            || color.min_element() < 0.0
            || !(intensity.is_finite() && intensity >= 0.0)
        {
            return Err(self.invalid(Invalid::NegativeLight { light: self.kind }));
        }
        let range = def.range.unwrap_or(100.0);
        if def.kind != LightKind::Directional && !(range.is_finite() && range > 0.0) {
            return Err(self.invalid(Invalid::Range { light: self.kind }));
        }
        Ok(LightCommon { color, intensity, range })
    }

    fn directional(&self, c: LightCommon) -> Result<Light, SceneError> {
        let def = self.def;
        self.forbid(def.position.is_some(), "position")?;
        self.forbid(def.range.is_some(), "range")?;
        self.forbid(def.inner_cone_deg.is_some() || def.outer_cone_deg.is_some(), "cone")?;
        let direction = self.nonzero(self.need(def.direction, "direction")?, "direction")?;
        Ok(Light::Directional { direction, color: c.color, intensity: c.intensity })
    }

    fn point(&self, c: LightCommon) -> Result<Light, SceneError> {
        let def = self.def;
        self.forbid(def.direction.is_some(), "direction")?;
        self.forbid(def.inner_cone_deg.is_some() || def.outer_cone_deg.is_some(), "cone")?;
        let position = self.need(def.position, "position")?;
        if !position.is_finite() {
            return Err(self.invalid(Invalid::PositionNotFinite));
        }
        Ok(Light::Point { position, color: c.color, intensity: c.intensity, range: c.range })
    }

    fn spot(&self, c: LightCommon) -> Result<Light, SceneError> {
        let def = self.def;
        let position = self.need(def.position, "position")?;
        let direction = self.nonzero(self.need(def.direction, "direction")?, "direction")?;
        let inner = def.inner_cone_deg.unwrap_or(20.0);
        let outer = def.outer_cone_deg.unwrap_or(30.0);
        if !(0.0 <= inner && inner <= outer && outer < 90.0 && position.is_finite()) {
            return Err(
                self.invalid(Invalid::Cones { inner_cone_deg: inner, outer_cone_deg: outer })
            );
        }
        Ok(Light::Spot {
            position,
            direction,
            color: c.color,
            intensity: c.intensity,
            range: c.range,
            inner_cone_deg: inner,
            outer_cone_deg: outer,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Scene, SceneError> {
        Scene::parse(text, Path::new("/scenes"), Path::new("/scenes/s.toml"))
    }

    fn err(text: &str) -> SceneError {
        match parse(text) {
            Ok(s) => panic!("expected an error, got {s:?}"),
            Err(e) => e,
        }
    }

    /// Whether `e` is a TOML error at `line`, about `key`.
    fn parse_error_at(e: &SceneError, at: usize, named: &str) -> bool {
        matches!(e, SceneError::Parse { line, key: Some(key), .. } if *line == at && key == named)
    }

    /// The kind of an [`SceneError::Invalid`] at `line`.
    fn invalid_at(e: &SceneError, at: usize) -> &Invalid {
        match e {
            SceneError::Invalid { line, kind, .. } if *line == at => kind,
            other => panic!("expected an invalid value at line {at}, got {other:?}"),
        }
    }

    #[test]
    fn a_full_scene_resolves_paths_transforms_lights_and_cameras() {
        let scene = parse(
            r#"
[[model]]
path = "teapot.obj"
translate = [1, 2, 3]
rotate = [0, 90, 0]
scale = 2
fix = { mode = "object", crease_angle_deg = 30, normals = "keep" }

[[model.material]]
base_color = [1, 0, 0]
normal_texture = "builtin:bricks"

[[light]]
type = "point"
position = [0, 5, 0]
range = 20

[[camera]]
name = "front"
position = [0, 0, 10]
target = [0, 0, 0]
fov_deg = 50
"#,
        )
        .unwrap();
        let m = &scene.models[0];
        assert_eq!(m.path, Path::new("/scenes/teapot.obj"));
        assert_eq!(m.name, "teapot");
        assert_eq!(m.fix.mode, seamlit_mesh::Mode::Object);
        assert_eq!(m.fix.crease_angle_deg, 30.0);
        assert_eq!(m.fix.normals, seamlit_mesh::NormalPolicy::Keep);
        // Unnamed FixOptions fields keep their defaults.
        assert_eq!(m.fix.weighting, FixOptions::DEFAULT.weighting);
        // Scale 2, then 90 degrees about Y (+X goes to -Z), then translate.
        let p = m.transform.transform_point3(Vec3::X);
        assert!((p - Vec3::new(1.0, 2.0, 1.0)).length() < 1e-5, "{p}");
        assert_eq!(m.materials[0].base_color, Some([1.0, 0.0, 0.0, 1.0]));
        assert_eq!(m.materials[0].normal_texture, Some(NormalTexture::Bricks));
        assert_eq!(
            scene.lights,
            vec![Light::Point {
                position: Vec3::new(0.0, 5.0, 0.0),
                color: Vec3::ONE,
                intensity: 1.0,
                range: 20.0
            }]
        );
        assert_eq!(scene.cameras[0].name, "front");
        assert_eq!(scene.cameras[0].fov_y_deg, 50.0);
    }

    #[test]
    fn an_unknown_key_is_named_with_its_line() {
        let e = err(
            "[[model]]\npath = \"a.obj\"\n\n[[camera]]\nname = \"c\"\nposition = [0,0,1]\ntarget = [0,0,0]\ncolour = 3\n",
        );
        assert!(matches!(&e, SceneError::Parse { column: 1, .. }), "{e}");
        assert!(parse_error_at(&e, 8, "colour"), "{e:?}");
        // What the user reads: the file, line and column, then toml's message, once.
        let text = e.to_string();
        assert!(
            text.starts_with("/scenes/s.toml: line 8, column 1: unknown field `colour`"),
            "{e}"
        );
        assert_eq!(text.matches("unknown field").count(), 1, "{e}");
    }

    #[test]
    fn a_wrong_type_is_named_with_its_key_and_line() {
        let e = err(
            "[[model]]\npath = \"a.obj\"\n\n[[camera]]\nname = \"c\"\nposition = [0,0,1]\ntarget = [0,0,0]\nfov_deg = \"wide\"\n",
        );
        assert!(parse_error_at(&e, 8, "fov_deg"), "{e:?}");
        assert!(e.to_string().contains("key `fov_deg`"), "{e}");
    }

    #[test]
    fn the_render_table_sets_environment_background_and_tone_mapping() {
        let scene = parse(
            "[[model]]\npath = \"a.obj\"\n[render]\nenvironment = \"sky.hdr\"\n\
             environment_intensity = 2\nenvironment_rotation = 90\nbackground = [1, 0.5, 0]\n\
             ambient = 0\ntone_mapping = \"aces\"\nexposure = 1.5\nshadows = false\n",
        )
        .unwrap();
        let r = &scene.render;
        assert_eq!(r.environment, Some(EnvironmentChoice::File(PathBuf::from("/scenes/sky.hdr"))));
        assert_eq!(r.environment_intensity, Some(2.0));
        assert_eq!(r.environment_rotation_deg, Some(90.0));
        assert_eq!(r.background, Some([1.0, 0.5, 0.0]));
        assert_eq!(r.ambient, Some(0.0));
        assert_eq!(r.tone_mapping, Some(ToneMapping::Aces));
        assert_eq!(r.exposure, Some(1.5));
        assert_eq!(r.shadows, Some(false));
        let builtin = parse("[[model]]\npath = \"a.obj\"\n[render]\nenvironment = \"builtin\"\n");
        assert_eq!(builtin.unwrap().render.environment, Some(EnvironmentChoice::Builtin));
        assert_eq!(
            parse("[[model]]\npath = \"a.obj\"\n").unwrap().render,
            RenderOptions::default()
        );
        let e = err("[[model]]\npath = \"a.obj\"\n[render]\nexposure = 0\n");
        assert!(
            matches!(
                invalid_at(&e, 3),
                Invalid::RenderValue { key: "exposure", value: 0.0, expected: "a number > 0" }
            ),
            "{e}"
        );
        let e = err("[[model]]\npath = \"a.obj\"\n[render]\nbackground = [2, 0, 0]\n");
        assert_eq!(invalid_at(&e, 3), &Invalid::Background { value: [2.0, 0.0, 0.0] });
        let e = err("[[model]]\npath = \"a.obj\"\n[render]\ntone_mapping = \"reinhard\"\n");
        assert!(parse_error_at(&e, 4, "tone_mapping"), "{e:?}");
    }

    #[test]
    fn the_render_table_names_an_animation_and_a_time() {
        let named =
            parse("[[model]]\npath = \"a.glb\"\n[render]\nanimation = \"Walk\"\ntime = 0.5\n");
        let r = named.unwrap().render;
        assert_eq!(r.animation, Some(AnimationChoice::Name("Walk".into())));
        assert_eq!(r.time, Some(0.5));
        let indexed = parse("[[model]]\npath = \"a.glb\"\n[render]\nanimation = 2\n");
        assert_eq!(indexed.unwrap().render.animation, Some(AnimationChoice::Index(2)));
        let e = err("[[model]]\npath = \"a.glb\"\n[render]\ntime = -1\n");
        assert!(
            matches!(
                invalid_at(&e, 3),
                Invalid::RenderValue { key: "time", value: -1.0, expected: "seconds >= 0" }
            ),
            "{e}"
        );
        let e = err("[[model]]\npath = \"a.glb\"\n[render]\nanimation = [1]\n");
        assert!(parse_error_at(&e, 4, "animation"), "{e:?}");
        assert_eq!(AnimationChoice::parse("3"), AnimationChoice::Index(3));
        assert_eq!(AnimationChoice::parse("Run"), AnimationChoice::Name("Run".into()));
    }

    #[test]
    fn a_model_names_its_own_animation_and_time() {
        let scene = parse("[[model]]\npath = \"a.glb\"\nanimation = \"Run\"\ntime = 1.5\n");
        let model = &scene.unwrap().models[0];
        assert_eq!(model.animation, Some(AnimationChoice::Name("Run".into())));
        assert_eq!(model.time, Some(1.5));
        let e = err("[[model]]\npath = \"a.glb\"\ntime = -1\n");
        assert_eq!(invalid_at(&e, 1), &Invalid::ModelTime { model: "a".into(), value: -1.0 });
    }

    #[test]
    fn the_render_table_chooses_the_lighting() {
        let scene = parse("[[model]]\npath = \"a.obj\"\n[render]\nlighting = \"pbr\"\n").unwrap();
        assert_eq!(scene.lighting, Some(LightingModel::Pbr));
        let scene =
            parse("[[model]]\npath = \"a.obj\"\n[render]\nlighting = \"blinn-phong\"\n").unwrap();
        assert_eq!(scene.lighting, Some(LightingModel::BlinnPhong));
        assert_eq!(parse("[[model]]\npath = \"a.obj\"\n").unwrap().lighting, None);
        let e = err("[[model]]\npath = \"a.obj\"\n[render]\nlighting = \"cel\"\n");
        assert!(parse_error_at(&e, 4, "lighting"), "{e:?}");
    }

    #[test]
    fn an_unknown_fix_option_is_an_error() {
        let e = err("[[model]]\npath = \"a.obj\"\n[model.fix]\ncrease = 30\n");
        assert!(parse_error_at(&e, 4, "crease"), "{e:?}");
        let e = err("[[model]]\npath = \"a.obj\"\n[model.fix]\nmode = \"smooth\"\n");
        assert!(parse_error_at(&e, 4, "mode"), "{e:?}");
    }

    #[test]
    fn a_missing_key_is_named() {
        let e =
            err("[[model]]\npath = \"a.obj\"\n[[camera]]\nposition = [0,0,1]\ntarget = [0,0,0]\n");
        assert!(parse_error_at(&e, 3, "name"), "{e:?}");
    }

    #[test]
    fn bad_values_are_rejected_with_the_line_of_their_table() {
        let cases: [(&str, usize, Invalid); 8] = [
            (
                "[[model]]\npath = \"a\"\n[[light]]\ntype = \"directional\"\n",
                3,
                Invalid::LightNeeds { light: "directional", key: "direction" },
            ),
            (
                "[[model]]\npath = \"a\"\n[[light]]\ntype = \"point\"\nposition = [0,1,0]\ndirection = [0,1,0]\n",
                3,
                Invalid::LightHasNo { light: "point", key: "direction" },
            ),
            (
                "[[model]]\npath = \"a\"\n[[light]]\ntype = \"spot\"\nposition = [0,1,0]\ndirection = [0,-1,0]\ninner_cone_deg = 40\nouter_cone_deg = 30\n",
                3,
                Invalid::Cones { inner_cone_deg: 40.0, outer_cone_deg: 30.0 },
            ),
            (
                "[[model]]\npath = \"a\"\n\n[[camera]]\nname = \"c\"\nposition = [0,0,1]\ntarget = [0,0,0]\nfov_deg = 0\n",
                4,
                Invalid::FieldOfView { camera: "c".into(), fov_deg: 0.0 },
            ),
            (
                "[[model]]\npath = \"a\"\nscale = [1, 0, 1]\n",
                1,
                Invalid::ZeroScale { model: "a".into() },
            ),
            (
                "[[model]]\npath = \"a\"\n[[model.material]]\nbase_color = [1, 0]\n",
                1,
                Invalid::BaseColorLength { model: "a".into(), found: 2 },
            ),
            (
                "[[model]]\npath = \"a\"\n[[camera]]\nname = \"c\"\nposition = [0,0,1]\ntarget = [0,0,0]\n[[camera]]\nname = \"c\"\nposition = [0,0,2]\ntarget = [0,0,0]\n",
                7,
                Invalid::DuplicateCamera { name: "c".into() },
            ),
            ("", 1, Invalid::NoModel),
        ];
        for (text, line, expected) in cases {
            let e = err(text);
            assert_eq!(invalid_at(&e, line), &expected, "{text:?}");
        }
    }

    #[test]
    fn malformed_toml_is_a_parse_error_with_a_position() {
        let e = err("[[model]]\npath = \"a.obj\nx = 1\n");
        assert!(matches!(e, SceneError::Parse { line: 2, .. }), "{e:?}");
    }

    #[test]
    fn a_model_path_is_a_scene_with_default_lights_and_camera() {
        let scene = Scene::open(Path::new("models/spot.obj")).unwrap();
        assert_eq!(scene.models.len(), 1);
        assert_eq!(scene.models[0].name, "spot");
        assert_eq!(scene.models[0].fix, FixOptions::DEFAULT);
        assert_eq!(scene.lights_or_default().len(), 3);
        let bounds = (Vec3::splat(-1.0), Vec3::ONE);
        let cameras = scene.cameras_or_default(bounds, 1.0);
        assert_eq!(cameras.len(), 1);
        assert_eq!(Scene::find_camera(&cameras, None).unwrap().name, "default");
        let e = Scene::find_camera(&cameras, Some("top")).unwrap_err();
        assert_eq!(e, "no camera named \"top\" (there are: default)");
    }

    #[test]
    fn a_missing_scene_file_names_the_file() {
        let e = Scene::open(Path::new("/nonexistent/scene.toml")).unwrap_err().to_string();
        assert!(e.starts_with("/nonexistent/scene.toml: cannot read"), "{e}");
    }
}
