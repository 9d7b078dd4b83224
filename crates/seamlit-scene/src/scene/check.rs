//! Checking a parsed scene file: each model, light and camera table turned into its
//! [`super::Scene`] part, every error pointing at its line and column.

use std::ops::Range;
use std::path::Path;

use glam::{EulerRot, Mat4, Quat, Vec3};
use seamlit_render::{Light, LightingModel, ToneMapping};

use crate::camera::Camera;
use crate::error::{Invalid, SceneError};
use crate::schema::{
    AnimationDef, CameraDef, LightDef, LightKind, LightingKind, MaterialDef, ModelDef, RenderDef,
    Scale, ToneMappingKind,
};

use super::{
    AnimationChoice, EnvironmentChoice, MaterialOverride, NormalTexture, RenderOptions, SceneModel,
    file_stem,
};

/// Scene text and name, for error positions.
pub(super) struct Ctx<'a> {
    pub(super) text: &'a str,
    pub(super) file: &'a Path,
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

    pub(super) fn parse_error(&self, e: toml::de::Error) -> SceneError {
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
    pub(super) fn render(
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

    pub(super) fn invalid(&self, span: &Range<usize>, kind: Invalid) -> SceneError {
        SceneError::Invalid {
            path: self.file.to_path_buf(),
            line: self.line_col(span.start).0,
            kind,
        }
    }

    pub(super) fn model(
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
    pub(super) fn light(&self, def: &LightDef, span: Range<usize>) -> Result<Light, SceneError> {
        let check = LightCheck { parser: self, def, span: &span, kind: light_kind_name(def.kind) };
        let common = check.common()?;
        match def.kind {
            LightKind::Directional => check.directional(common),
            LightKind::Point => check.point(common),
            LightKind::Spot => check.spot(common),
        }
    }

    pub(super) fn camera(&self, def: CameraDef, span: Range<usize>) -> Result<Camera, SceneError> {
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
