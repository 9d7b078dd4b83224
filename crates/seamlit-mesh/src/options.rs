//! Options for [`crate::fix`], with named presets.

use serde::{Deserialize, Serialize};

/// Which objects' faces are averaged into a vertex's normal and tangent.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// Each triangle corner gets its face's normal and tangent (the paper's Figure 9).
    Flat,
    /// Smooth within each object only: the seams between objects stay (Figure 11).
    Object,
    /// Smooth across all objects of the model: the seams go (Figure 12).
    #[default]
    Model,
}

/// How face normals are weighted when they are averaged at a vertex.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Weighting {
    /// By the corner angle of each face at the vertex: independent of tessellation.
    #[default]
    Angle,
    /// By face area: large faces dominate.
    Area,
    /// By corner angle times face area.
    AngleArea,
    /// Every face counts once: the paper's plain average.
    Uniform,
}

/// How positions of different vertices are matched ("welded").
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WeldTolerance {
    /// A fraction of the model's bounding-box diagonal (the default: `1e-6`).
    Relative(f32),
    /// An absolute distance in model units. `Absolute(0.0)` is the same as [`Self::Exact`].
    Absolute(f32),
    /// Equal bits only (with `-0.0 == 0.0`), as the paper does.
    Exact,
}

impl Default for WeldTolerance {
    fn default() -> Self {
        Self::Relative(1e-6)
    }
}

/// The command line's spelling: `exact`, `rel:FRACTION` (of the bounding-box diagonal) or a
/// distance `>= 0` in model units (`0` is `exact`).
impl std::str::FromStr for WeldTolerance {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let bad =
            || format!("{s:?} is not a tolerance: use a distance >= 0, rel:FRACTION or exact");
        if s.eq_ignore_ascii_case("exact") {
            return Ok(Self::Exact);
        }
        let number = |t: &str| t.parse::<f32>().ok().filter(|v| v.is_finite() && *v >= 0.0);
        if let Some(rest) = s.strip_prefix("rel:") {
            return number(rest).map(Self::Relative).ok_or_else(bad);
        }
        match number(s) {
            Some(0.0) => Ok(Self::Exact),
            Some(d) => Ok(Self::Absolute(d)),
            None => Err(bad()),
        }
    }
}

/// The spelling [`WeldTolerance::from_str`](std::str::FromStr) reads: `exact`, `rel:1e-6`,
/// `0.001`.
impl std::fmt::Display for WeldTolerance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::Exact | Self::Absolute(0.0) => f.write_str("exact"),
            Self::Relative(r) => write!(f, "rel:{r:e}"),
            Self::Absolute(d) => write!(f, "{d}"),
        }
    }
}

impl WeldTolerance {
    /// The absolute tolerance for a model whose bounding-box diagonal is `diagonal`;
    /// `0.0` means exact bit equality.
    #[must_use]
    pub fn absolute(self, diagonal: f32) -> f32 {
        let t = match self {
            Self::Relative(r) => r * diagonal,
            Self::Absolute(a) => a,
            Self::Exact => 0.0,
        };
        if t.is_finite() && t > 0.0 { t } else { 0.0 }
    }
}

/// Which tangent generator runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TangentMethod {
    /// No tangents are computed (existing tangents are dropped).
    None,
    /// seamlit's own: per-face tangents from edge and UV deltas, smoothed across objects with
    /// the normals' grouping, split by handedness and tangent angle, Gram-Schmidt, handedness.
    #[default]
    Seamlit,
    /// MikkTSpace (through `bevy_mikktspace`), run over the whole model at once, for normal
    /// maps baked with MikkTSpace (Blender, Substance, xNormal).
    Mikktspace,
}

/// Which normals (and tangents) `fix` computes, and which it keeps as the model carries them.
/// See docs/normals.md.
///
/// An object *carries* normals when it has a normal for every vertex, each finite and
/// non-zero; an object whose normals are missing or unusable gets them computed under every
/// policy. Tangents follow the normals: an object whose normals are kept keeps its tangents
/// (re-orthogonalised where its normal changed, handedness kept), and gets them computed where
/// it has none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NormalPolicy {
    /// Objects that carry normals keep them, except at the seams that smoothing each object
    /// on its own made ([`Mode::Model`] only). At a position that two or more objects share,
    /// each copy's normal is judged from its own object's faces there: its face's normal
    /// (flat shading: an authored hard edge), its object's smooth normal (per-object
    /// smoothing: the seam), or neither (custom). Only the copies that carry their object's
    /// smooth normal and lie within the crease angle of each other get one normal, their
    /// weighted average, the same on every side (the seam-only repair). Every other normal
    /// stays bit for bit. [`crate::Changes::shared`] counts what was decided.
    #[default]
    Auto,
    /// As [`Self::Auto`], but at a position that objects share every copy counts as smooth,
    /// whatever its object's faces say: all copies whose normals lie within the crease angle
    /// of each other are averaged, authored hard edges between objects included (seamlit's
    /// rule before it told hard edges from seams).
    SmoothShared,
    /// Objects that carry normals keep them bit for bit everywhere, seams included; only
    /// missing normals are computed.
    Keep,
    /// Every normal and tangent is computed from the faces; the input ones are ignored (the
    /// paper's way, and seamlit's only behaviour before this option existed).
    Recompute,
}

/// Options of [`crate::fix`]. `FixOptions::default()` is what the `seamlit` binary uses.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FixOptions {
    /// Which faces are averaged: flat, per object, or the whole model.
    pub mode: Mode,
    /// How close two positions must be to count as one.
    pub weld_tolerance: WeldTolerance,
    /// How face normals are weighted.
    pub weighting: Weighting,
    /// Faces that meet across an edge at more than this angle (degrees) keep separate normals.
    /// `180` or more: no creases, every face at a position is averaged (the paper).
    pub crease_angle_deg: f32,
    /// Which tangent generator runs.
    pub tangents: TangentMethod,
    /// Face tangents further apart than this angle (degrees) are not averaged; `180` or more
    /// averages all of them.
    pub tangent_angle_deg: f32,
    /// Whether faces of opposite UV handedness (mirrored UVs) are kept apart when tangents are
    /// averaged. The paper averages them together.
    pub split_mirrored: bool,
    /// Which normals are computed and which are kept.
    pub normals: NormalPolicy,
}

impl FixOptions {
    /// The defaults: whole-model smoothing, a relative weld tolerance of 1e-6, angle weighting,
    /// a 60 degree crease, seamlit tangents within 45 degrees and split at mirrored UVs;
    /// normals the model carries are kept, with the seams between objects repaired
    /// ([`NormalPolicy::Auto`]).
    pub const DEFAULT: Self = Self {
        mode: Mode::Model,
        weld_tolerance: WeldTolerance::Relative(1e-6),
        weighting: Weighting::Angle,
        crease_angle_deg: 60.0,
        tangents: TangentMethod::Seamlit,
        tangent_angle_deg: 45.0,
        split_mirrored: true,
        normals: NormalPolicy::Auto,
    };

    /// The paper's semantics on the fast path: exact position equality, a uniform average of
    /// every face at a position (no crease, no tangent angle limit, no split at mirrored UVs),
    /// every normal computed ([`NormalPolicy::Recompute`]). The result equals the paper's
    /// algorithm (`reference::fix`, behind the `reference` feature) up to floating-point
    /// summation order.
    pub const PAPER: Self = Self {
        mode: Mode::Model,
        weld_tolerance: WeldTolerance::Exact,
        weighting: Weighting::Uniform,
        crease_angle_deg: 180.0,
        tangents: TangentMethod::Seamlit,
        tangent_angle_deg: 180.0,
        split_mirrored: false,
        normals: NormalPolicy::Recompute,
    };

    /// The paper's Figure 11: smoothing within each object only.
    pub const OBJECT: Self = Self { mode: Mode::Object, ..Self::DEFAULT };

    /// The paper's Figure 9: face normals and tangents.
    pub const FLAT: Self = Self { mode: Mode::Flat, ..Self::DEFAULT };

    /// These options with another mode (builder style).
    #[must_use]
    pub const fn with_mode(mut self, mode: Mode) -> Self {
        self.mode = mode;
        self
    }

    /// These options with another normal policy (builder style).
    #[must_use]
    pub const fn with_normals(mut self, normals: NormalPolicy) -> Self {
        self.normals = normals;
        self
    }
}

impl Default for FixOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}
