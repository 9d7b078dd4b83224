//! The command line, as clap reads it (docs/design.md section 8).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use seamlit_io::LoadOptions;
use seamlit_mesh::{FixOptions, Mode, NormalPolicy, TangentMethod, Weighting, WeldTolerance};
use seamlit_render::{DebugView, LightingModel, ToneMapping};

/// seamlit makes multi-object 3D models light correctly: it welds positions across all
/// objects of a model and computes normals and tangents across the weld, so per-pixel
/// lighting with normal mapping shows no seam where one object meets the next.
///
/// Exit status: 0 success, 1 processing failure (no GPU, a write failed), 2 bad input or
/// usage (a malformed or missing file, a bad option).
#[derive(Debug, Parser)]
#[command(name = "seamlit", version, max_term_width = 100)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render the embedded demo: the Newell teapot as 32 objects with a brick normal map, in
    /// the three modes side by side (the paper's Figures 9, 11 and 12), plus the seam report
    /// before and after. Needs no files.
    Demo(DemoArgs),
    /// Compute seam-free normals and tangents and write the model out (glTF, GLB or OBJ).
    /// A folder in gives a folder out: its small models (under 8 MiB) are fixed several at a
    /// time, one per thread (RAYON_NUM_THREADS, default one per CPU), larger ones one at a
    /// time; what each says is printed in the folder's order.
    Fix(FixArgs),
    /// Print the seam report of a model as loaded and after each mode: how well normals and
    /// tangents agree where objects meet.
    Inspect(InspectArgs),
    /// Render a scene or model to a PNG (headless).
    Render(RenderArgs),
    /// Render the three modes (flat, object, model) side by side, labelled, into one PNG.
    Compare(CompareArgs),
    /// Open a window: fly or orbit the camera, switch mode, lighting, normal mapping, lights
    /// and debug views live.
    View(ViewArgs),
}

/// `seamlit demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Folder for flat.png, object.png, model.png, compare.png and teapot-fixed.glb (created
    /// if missing).
    #[arg(long, short, value_name = "DIR", default_value = "demo-out")]
    pub out: PathBuf,
    /// Size of each rendered view, WIDTHxHEIGHT pixels.
    #[arg(long, value_name = "WxH", default_value = "640x480", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Quads per patch side when tessellating the 32 Bezier patches. The demo's default is 8,
    /// where the other commands default to 16: at 8 the seams it shows are larger (up to 43.7
    /// degrees, against 22.1 at 16) and its renders are several times faster on a CPU
    /// renderer (lavapipe; figures in BENCHMARKS.md).
    #[arg(long, value_name = "N", default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=256))]
    pub tessellation: u32,
}

/// `seamlit fix`.
#[derive(Debug, Args)]
pub struct FixArgs {
    /// The model (.obj, .gltf, .glb, .vrm, .fbx, .usda/.usdc/.usdz or a Newell patch file), or
    /// a folder of models.
    #[arg(value_name = "INPUT")]
    pub input: PathBuf,
    /// Where to write: a .glb, .gltf, .obj, .vrm (from a .vrm), .usda or .usdc (from USD: a
    /// layer over the input) or .usdz (from USD: that layer, the input's layers and textures
    /// in one package) file; for a folder INPUT, a folder (created if missing) that receives one
    /// file per model, in the same subfolders as the input's, with each model's textures beside
    /// it (.gltf, .obj) or inside it (.glb; a VRM avatar stays a .vrm). glTF geometry that
    /// came meshopt- or Draco-compressed is written uncompressed (a line says so) unless
    /// --keep-compression is given; quantised attributes (KHR_mesh_quantization) stay
    /// quantised.
    #[arg(long, short, value_name = "OUTPUT")]
    pub output: PathBuf,
    /// For a folder INPUT: only the models directly in it, not those in its subfolders.
    #[arg(long)]
    pub no_recurse: bool,
    /// Output format for a folder INPUT (for a file, the OUTPUT extension decides).
    #[arg(long, value_enum, value_name = "FORMAT", default_value_t = OutFormat::Glb)]
    pub format: OutFormat,
    /// Which faces are averaged into a vertex's normal and tangent.
    #[arg(long, value_enum, value_name = "MODE", default_value_t = ModeArg::Model)]
    pub mode: ModeArg,
    /// Replace an existing OUTPUT file that is the INPUT itself.
    #[arg(long)]
    pub overwrite_input: bool,
    /// Write meshopt-compressed glTF (EXT_ or KHR_meshopt_compression) compressed again:
    /// compressed buffer views the fix did not touch keep their bytes, mode and filter; new
    /// normals, tangents, split vertices and indices are compressed losslessly. An input
    /// without compression is written as usual (a line says so); a Draco input or an .obj
    /// OUTPUT is refused.
    #[arg(long)]
    pub keep_compression: bool,
    /// Where objects that share a position are skinned differently there (the seam opens
    /// when the model moves): `match` gives every copy the same joints and weights (the
    /// copies' influences merged, the largest kept per set and renormalised; a joint an
    /// object's skin lacks is added to it); `keep` leaves the weights as authored.
    #[arg(long, value_enum, value_name = "POLICY", default_value_t = SkinSeamsArg::Match)]
    pub skin_seams: SkinSeamsArg,
    /// Times sampled per animation (evenly, from its start to its end) when the seams in
    /// motion are measured, before and after the fix.
    #[arg(long, value_name = "N", default_value_t = 30,
          value_parser = clap::value_parser!(u32).range(2..=100_000))]
    pub samples: u32,
    #[command(flatten)]
    pub fix: FixFlags,
    #[command(flatten)]
    pub load: LoadFlags,
}

/// `seamlit inspect`.
#[derive(Debug, Args)]
pub struct InspectArgs {
    /// The model (.obj, .gltf, .glb, .vrm, .fbx, .usda/.usdc/.usdz or a Newell patch file).
    #[arg(value_name = "INPUT")]
    pub input: PathBuf,
    /// Print JSON instead of a table: { "file", "as_loaded", "flat", "object", "model" },
    /// each a full seam report.
    #[arg(long)]
    pub json: bool,
    /// Also measure the seams in motion: pose the model at --samples times of `all` its
    /// animations, or of one named or numbered (0 is the first), and report per animation
    /// the largest gap between the copies of a shared position and the largest normal
    /// angle across the seam, as loaded and after `fix`, with the times they happen.
    #[arg(long, value_name = "all|NAME|INDEX")]
    pub animation: Option<String>,
    /// Times sampled per animation with --animation (evenly, from its start to its end).
    #[arg(long, value_name = "N", default_value_t = 30,
          value_parser = clap::value_parser!(u32).range(2..=100_000))]
    pub samples: u32,
    #[command(flatten)]
    pub fix: FixFlags,
    #[command(flatten)]
    pub load: LoadFlags,
}

/// `seamlit render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The PNG to write.
    #[arg(long, short, value_name = "OUT.png")]
    pub output: PathBuf,
    /// Replace every model's mode from the scene.
    #[arg(long, value_enum, value_name = "MODE")]
    pub mode: Option<ModeArg>,
    /// Render this many extra frames offscreen and print their timing (after one warm-up).
    #[arg(long, value_name = "N")]
    pub frames: Option<usize>,
    #[command(flatten)]
    pub scene: SceneArgs,
}

/// `seamlit compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The PNG to write: the flat, object and model renderings side by side, labelled.
    #[arg(long, short, value_name = "GRID.png")]
    pub output: PathBuf,
    #[command(flatten)]
    pub scene: SceneArgs,
}

/// `seamlit view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Start in this mode (the panel changes it).
    #[arg(long, value_enum, value_name = "MODE")]
    pub mode: Option<ModeArg>,
    /// Save a screenshot of the window to this PNG (with --exit-after-frames: once that many
    /// frames have been drawn; otherwise F12 saves to it).
    #[arg(long, value_name = "PNG")]
    pub screenshot: Option<PathBuf>,
    /// Close the window after this many frames (for tests and scripts).
    #[arg(long, value_name = "N")]
    pub exit_after_frames: Option<u64>,
    #[command(flatten)]
    pub scene: SceneArgs,
}

/// What `render`, `compare` and `view` read: a scene or a model, and the flags that override
/// the scene's settings.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// A scene file (.toml, see docs/scene.md) or a model file.
    #[arg(value_name = "SCENE_OR_MODEL")]
    pub input: PathBuf,
    #[command(flatten)]
    pub view: ViewFlags,
    #[command(flatten)]
    pub animation: AnimationFlags,
    #[command(flatten)]
    pub fix: FixFlags,
    #[command(flatten)]
    pub load: LoadFlags,
    /// The glTF material variant to draw (KHR_materials_variants; a name no model has is
    /// refused, listing those there are) [default: each model's `variant` key, else none: the
    /// default materials].
    #[arg(long, value_name = "NAME")]
    pub variant: Option<String>,
}

/// Which animation poses the model, and when; each flag replaces the scene's `[render]`
/// value. Without an animation, skinned models are drawn skinned in their nodes' rest pose.
#[derive(Debug, Args, Clone, Default)]
pub struct AnimationFlags {
    /// The glTF animation to pose the model by: its name or its index (`seamlit inspect`
    /// lists them) [default: the scene's `[render] animation`, else none: the rest pose].
    #[arg(long, value_name = "NAME|INDEX")]
    pub animation: Option<String>,
    /// Seconds into the animation (past its last keyframe the last values hold) [default: the
    /// scene's `[render] time`, else 0].
    #[arg(long, value_name = "SECONDS", value_parser = parse_non_negative, allow_negative_numbers = true)]
    pub time: Option<f32>,
}

/// How normals and tangents are computed; each flag replaces the scene's value.
#[derive(Debug, Args, Clone, Default)]
pub struct FixFlags {
    /// Crease angle in degrees: faces meeting at a sharper angle keep separate normals
    /// (default 60; 180 smooths everything, as the paper does).
    #[arg(long, value_name = "DEG", value_parser = parse_angle)]
    pub crease: Option<f32>,
    /// How close positions must be to be welded: a distance in model units, `rel:F` for a
    /// fraction F of the bounding-box diagonal (default rel:1e-6), or `exact` (equal bits,
    /// as the paper; the same as 0).
    #[arg(long, value_name = "X", value_parser = parse_tolerance)]
    pub weld_tolerance: Option<WeldTolerance>,
    /// How face normals are weighted in the average at a vertex (default angle).
    #[arg(long, value_enum, value_name = "W")]
    pub weighting: Option<WeightingArg>,
    /// Tangent generator (default: mikktspace for a model with a normal map and no
    /// tangents, as glTF viewers do; otherwise seamlit; none drops tangents).
    #[arg(long, value_enum, value_name = "T")]
    pub tangents: Option<TangentsArg>,
    /// Which normals are computed (default auto: objects that carry normals keep them and
    /// only the seams that smoothing each object alone made are repaired; authored hard
    /// edges and custom normals where objects meet stay; see docs/normals.md).
    #[arg(long, value_enum, value_name = "POLICY")]
    pub normals: Option<NormalsArg>,
}

impl FixFlags {
    /// `base` with every flag that was given applied.
    #[must_use]
    pub(crate) fn apply(&self, base: FixOptions) -> FixOptions {
        let mut o = base;
        if let Some(c) = self.crease {
            o.crease_angle_deg = c;
        }
        if let Some(t) = self.weld_tolerance {
            o.weld_tolerance = t;
        }
        if let Some(w) = self.weighting {
            o.weighting = w.into();
        }
        if let Some(t) = self.tangents {
            o.tangents = t.into();
        }
        if let Some(n) = self.normals {
            o.normals = n.into();
        }
        o
    }
}

/// How model files are read.
#[derive(Debug, Args, Clone)]
pub struct LoadFlags {
    /// Quads per patch side for Newell patch files.
    #[arg(long, value_name = "N", default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub tessellation: u32,
    /// Confines the files a USD stage names (layers it references, sublayers, payloads,
    /// textures) to the model's own folder and this one; repeat for more. Without it they are
    /// read wherever they resolve, as USD reads them; with it a layer outside is refused (the
    /// strict mode, for services). A .usdz output packs only files from the stage's folder
    /// and these, either way.
    #[arg(long = "asset-root", value_name = "DIR")]
    pub asset_roots: Vec<PathBuf>,
}

impl LoadFlags {
    /// `base` with these flags applied.
    pub fn options(&self, base: LoadOptions) -> LoadOptions {
        LoadOptions {
            tessellation: self.tessellation,
            asset_roots: self.asset_roots.clone(),
            ..base
        }
    }
}

/// What the picture shows.
#[derive(Debug, Args, Clone)]
pub struct ViewFlags {
    /// Image (or window) size, WIDTHxHEIGHT pixels.
    #[arg(long, value_name = "WxH", default_value = "800x600", value_parser = parse_size)]
    pub size: (u32, u32),
    /// The scene camera to look through (default: the first, or one framing the model).
    #[arg(long, value_name = "NAME")]
    pub camera: Option<String>,
    /// What each pixel shows: lit, or a debug view of the attributes.
    #[arg(long, value_enum, value_name = "VIEW", default_value_t = ViewArg::Lit)]
    pub view: ViewArg,
    /// The lighting equation [default: the scene's `[render] lighting`, else pbr when every
    /// model is glTF and blinn-phong otherwise].
    #[arg(long, value_enum, value_name = "MODEL")]
    pub lighting: Option<LightingArg>,
    /// How lit colours are brought into 0..1 [default: the scene's `tone_mapping`, else
    /// neutral for pbr, none otherwise].
    #[arg(long, value_enum, value_name = "MAP")]
    pub tone_mapping: Option<ToneMappingArg>,
    /// Multiplies the lit colour before tone mapping [default: the scene's `exposure`, else 1].
    #[arg(long, value_name = "X", value_parser = parse_positive)]
    pub exposure: Option<f32>,
    /// Ambient light (grey, linear; 0 = none) [default: the scene's `ambient`, else 0 where
    /// an environment lights pbr, 0.05, and 0.3 for pbr without an environment].
    #[arg(long, value_name = "X")]
    pub ambient: Option<f32>,
    /// Image-based light for pbr materials: none, builtin (a procedural studio, no file
    /// needed) or an equirectangular Radiance .hdr file [default: the scene's `environment`,
    /// else builtin when every model is glTF and lighting is pbr, none otherwise].
    #[arg(long, value_name = "none|builtin|PATH.hdr")]
    pub environment: Option<String>,
    /// Multiplies the environment's light [default: the scene's, else 1].
    #[arg(long, value_name = "F", value_parser = parse_non_negative)]
    pub environment_intensity: Option<f32>,
    /// Turns the environment about +Y, degrees, counter-clockwise seen from above; at 0 the
    /// middle of an .hdr panorama is at +Z, as in the Khronos glTF Sample Viewer at its
    /// default (its environmentRotation V is 90 - V here) [default: the scene's, else 0].
    #[arg(long, value_name = "DEGREES", allow_negative_numbers = true)]
    pub environment_rotation: Option<f32>,
    /// Background colour, sRGB 0..1, e.g. 1,1,1 [default: the scene's `background`, else the
    /// environment, blurred, when there is one, else dark grey].
    #[arg(long, value_name = "R,G,B", value_parser = parse_rgb)]
    pub background: Option<[f32; 3]>,
    /// Shadows from directional and spot lights (shadow maps with filtered edges, up to four
    /// lights) [default: the scene's `shadows`, else on].
    #[arg(long, value_enum, value_name = "on|off")]
    pub shadows: Option<Switch>,
    /// Switch normal mapping off.
    #[arg(long)]
    pub no_normal_map: bool,
    /// Draw each vertex's tangent (red), bitangent (green) and normal (blue) as lines.
    #[arg(long)]
    pub tbn: bool,
}

/// `--shadows`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Switch {
    /// On.
    On,
    /// Off.
    Off,
}

/// `--skin-seams`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SkinSeamsArg {
    /// Every copy of a shared position gets the same skin influences.
    Match,
    /// The skin weights stay as authored.
    Keep,
}

/// `--mode`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// Face normals and tangents (the paper's Figure 9).
    Flat,
    /// Smooth within each object: seams stay (Figure 11).
    Object,
    /// Smooth across all objects: seams go (Figure 12).
    Model,
}

impl From<ModeArg> for Mode {
    fn from(m: ModeArg) -> Self {
        match m {
            ModeArg::Flat => Self::Flat,
            ModeArg::Object => Self::Object,
            ModeArg::Model => Self::Model,
        }
    }
}

/// `--weighting`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum WeightingArg {
    /// By the corner angle at the vertex (independent of tessellation).
    Angle,
    /// By face area.
    Area,
    /// By corner angle times area.
    AngleArea,
    /// Every face once (the paper's plain average).
    Uniform,
}

impl From<WeightingArg> for Weighting {
    fn from(w: WeightingArg) -> Self {
        match w {
            WeightingArg::Angle => Self::Angle,
            WeightingArg::Area => Self::Area,
            WeightingArg::AngleArea => Self::AngleArea,
            WeightingArg::Uniform => Self::Uniform,
        }
    }
}

impl From<Weighting> for WeightingArg {
    fn from(w: Weighting) -> Self {
        match w {
            Weighting::Angle => Self::Angle,
            Weighting::Area => Self::Area,
            Weighting::AngleArea => Self::AngleArea,
            Weighting::Uniform => Self::Uniform,
        }
    }
}

/// `--tangents`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TangentsArg {
    /// seamlit's own, smoothed across objects like the normals.
    Seamlit,
    /// MikkTSpace over the whole model.
    Mikktspace,
    /// No tangents.
    None,
}

impl From<TangentsArg> for TangentMethod {
    fn from(t: TangentsArg) -> Self {
        match t {
            TangentsArg::Seamlit => Self::Seamlit,
            TangentsArg::Mikktspace => Self::Mikktspace,
            TangentsArg::None => Self::None,
        }
    }
}

/// `--normals`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NormalsArg {
    /// Keep the normals objects carry, repair them only at the seams per-object smoothing
    /// made (authored hard edges and custom normals between objects stay); compute the
    /// missing ones.
    Auto,
    /// As auto, but average every shared position within the crease, authored hard edges
    /// between objects included (the rule before seamlit told them apart).
    SmoothShared,
    /// Keep the normals objects carry everywhere, seams included; compute the missing ones.
    Keep,
    /// Compute every normal from the faces, ignoring the file's (the paper's way).
    Recompute,
}

impl From<NormalsArg> for NormalPolicy {
    fn from(n: NormalsArg) -> Self {
        match n {
            NormalsArg::Auto => Self::Auto,
            NormalsArg::SmoothShared => Self::SmoothShared,
            NormalsArg::Keep => Self::Keep,
            NormalsArg::Recompute => Self::Recompute,
        }
    }
}

/// `--format` of `fix` with a folder.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OutFormat {
    /// Binary glTF, textures embedded.
    Glb,
    /// glTF JSON with a .bin and the textures beside it.
    Gltf,
    /// Wavefront OBJ with a .mtl.
    Obj,
}

impl OutFormat {
    /// The file extension.
    #[must_use]
    pub(crate) fn extension(self) -> &'static str {
        match self {
            Self::Glb => "glb",
            Self::Gltf => "gltf",
            Self::Obj => "obj",
        }
    }
}

/// `--view`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ViewArg {
    /// Lit and textured.
    Lit,
    /// World-space normals as colour.
    Normals,
    /// World-space tangents as colour.
    Tangents,
    /// Bitangent sign: green +1, red -1.
    BitangentSign,
    /// Texture coordinates as red and green.
    Uv,
    /// A flat colour per object: where the seams are.
    Objects,
    /// Lighting on a white material.
    Lighting,
    /// Metalness as grey (PBR materials).
    Metallic,
    /// Roughness as grey (PBR materials).
    Roughness,
    /// Ambient occlusion as grey (PBR materials).
    Occlusion,
}

impl From<ViewArg> for DebugView {
    fn from(v: ViewArg) -> Self {
        match v {
            ViewArg::Lit => Self::Lit,
            ViewArg::Normals => Self::Normals,
            ViewArg::Tangents => Self::Tangents,
            ViewArg::BitangentSign => Self::BitangentSign,
            ViewArg::Uv => Self::Uvs,
            ViewArg::Objects => Self::ObjectIds,
            ViewArg::Lighting => Self::LightingOnly,
            ViewArg::Metallic => Self::Metallic,
            ViewArg::Roughness => Self::Roughness,
            ViewArg::Occlusion => Self::Occlusion,
        }
    }
}

/// `--lighting`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LightingArg {
    /// glTF metallic-roughness (the specification's Appendix B), per pixel.
    Pbr,
    /// Per-pixel Blinn-Phong.
    BlinnPhong,
    /// Per-pixel Phong.
    Phong,
    /// Per-pixel diffuse only.
    Lambert,
    /// Blinn-Phong per vertex (the paper's Figure 3).
    Gouraud,
}

impl From<LightingArg> for LightingModel {
    fn from(l: LightingArg) -> Self {
        match l {
            LightingArg::BlinnPhong => Self::BlinnPhong,
            LightingArg::Phong => Self::Phong,
            LightingArg::Lambert => Self::Lambert,
            LightingArg::Gouraud => Self::Gouraud,
            LightingArg::Pbr => Self::Pbr,
        }
    }
}

/// `--tone-mapping`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ToneMappingArg {
    /// Khronos PBR Neutral.
    #[value(alias = "khr-pbr-neutral")]
    Neutral,
    /// ACES filmic (S. Hill's fit, as the Khronos glTF Sample Viewer).
    Aces,
    /// Clamp to 0..1.
    None,
}

impl From<ToneMappingArg> for ToneMapping {
    fn from(t: ToneMappingArg) -> Self {
        match t {
            ToneMappingArg::Neutral => Self::PbrNeutral,
            ToneMappingArg::Aces => Self::Aces,
            ToneMappingArg::None => Self::None,
        }
    }
}

/// A finite number > 0.
fn parse_positive(s: &str) -> Result<f32, String> {
    s.trim()
        .parse::<f32>()
        .ok()
        .filter(|v| v.is_finite() && *v > 0.0)
        .ok_or_else(|| format!("{s:?} is not a number > 0"))
}

/// A finite number >= 0.
fn parse_non_negative(s: &str) -> Result<f32, String> {
    s.trim()
        .parse::<f32>()
        .ok()
        .filter(|v| v.is_finite() && *v >= 0.0)
        .ok_or_else(|| format!("{s:?} is not a number >= 0"))
}

/// `R,G,B`, each 0..=1.
fn parse_rgb(s: &str) -> Result<[f32; 3], String> {
    let parts: Vec<f32> = s
        .split(',')
        .map(|t| t.trim().parse::<f32>().ok().filter(|v| (0.0..=1.0).contains(v)))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("{s:?} is not R,G,B with each in 0..1 (e.g. 1,1,1)"))?;
    <[f32; 3]>::try_from(parts)
        .map_err(|_| format!("{s:?} is not R,G,B with each in 0..1 (e.g. 1,1,1)"))
}

/// `WIDTHxHEIGHT`, each 1..=16384.
fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{s:?} is not WIDTHxHEIGHT (e.g. 800x600)"))?;
    let dim = |t: &str| {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| (1..=16384).contains(v))
            .ok_or_else(|| format!("{t:?} in {s:?} is not a size in pixels (1 to 16384)"))
    };
    Ok((dim(w)?, dim(h)?))
}

/// An angle in degrees, 0..=180.
fn parse_angle(s: &str) -> Result<f32, String> {
    s.parse::<f32>()
        .ok()
        .filter(|a| (0.0..=180.0).contains(a))
        .ok_or_else(|| format!("{s:?} is not an angle between 0 and 180 degrees"))
}

/// `exact`, `rel:F` or a distance.
/// A tolerance as `--weld-tolerance` spells it (the inverse of its parser): `exact`,
/// `rel:1e-6`, `0.001`.
#[must_use]
pub(crate) fn tolerance_flag(t: WeldTolerance) -> String {
    t.to_string()
}

/// A weighting as `--weighting` spells it: `angle`, `area`, `angle-area`, `uniform`.
#[must_use]
pub(crate) fn weighting_flag(w: Weighting) -> String {
    WeightingArg::from(w).to_possible_value().map_or_else(String::new, |v| v.get_name().to_owned())
}

fn parse_tolerance(s: &str) -> Result<WeldTolerance, String> {
    s.parse()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_tolerances_and_angles_parse_and_bad_ones_say_why() {
        assert_eq!(parse_size("800x600"), Ok((800, 600)));
        assert_eq!(parse_size("64X32"), Ok((64, 32)));
        assert!(parse_size("800").unwrap_err().contains("WIDTHxHEIGHT"));
        assert!(parse_size("0x10").unwrap_err().contains("1 to 16384"));
        assert_eq!(parse_tolerance("exact"), Ok(WeldTolerance::Exact));
        assert_eq!(parse_tolerance("0"), Ok(WeldTolerance::Exact));
        assert_eq!(parse_tolerance("0.001"), Ok(WeldTolerance::Absolute(0.001)));
        assert_eq!(parse_tolerance("rel:1e-5"), Ok(WeldTolerance::Relative(1e-5)));
        assert!(parse_tolerance("-1").is_err() && parse_tolerance("rel:x").is_err());
        assert_eq!(parse_angle("60"), Ok(60.0));
        assert!(parse_angle("200").is_err() && parse_angle("NaN").is_err());
    }

    /// The inspect header spells options as the flags do: each spelling parses back to the
    /// same value.
    #[test]
    fn options_are_spelled_as_their_flags() {
        for t in [
            WeldTolerance::Exact,
            WeldTolerance::Relative(1e-6),
            WeldTolerance::Relative(0.25),
            WeldTolerance::Absolute(0.001),
            WeldTolerance::Absolute(3.0),
        ] {
            assert_eq!(parse_tolerance(&tolerance_flag(t)), Ok(t), "{}", tolerance_flag(t));
        }
        assert_eq!(tolerance_flag(WeldTolerance::Relative(1e-6)), "rel:1e-6");
        for w in [Weighting::Angle, Weighting::Area, Weighting::AngleArea, Weighting::Uniform] {
            let spelled = weighting_flag(w);
            assert_eq!(WeightingArg::from_str(&spelled, false).map(Weighting::from), Ok(w));
        }
        assert_eq!(weighting_flag(Weighting::AngleArea), "angle-area");
    }

    #[test]
    fn flags_replace_only_what_they_name() {
        let flags = FixFlags { crease: Some(30.0), ..FixFlags::default() };
        let o = flags.apply(FixOptions::PAPER);
        assert_eq!(o.crease_angle_deg, 30.0);
        assert_eq!(o.normals, FixOptions::PAPER.normals);
        let keep = FixFlags { normals: Some(NormalsArg::Keep), ..FixFlags::default() };
        assert_eq!(keep.apply(FixOptions::DEFAULT).normals, NormalPolicy::Keep);
        assert_eq!(o.weighting, FixOptions::PAPER.weighting);
        assert_eq!(o.weld_tolerance, FixOptions::PAPER.weld_tolerance);
    }

    #[test]
    fn the_command_line_is_well_formed() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
