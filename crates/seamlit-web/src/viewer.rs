//! The page's viewer: WebGPU on a canvas, seamlit's renderer, an orbit camera.

use glam::Vec2;
use seamlit_io::job::{FixJob, Fixed, Inspection, fix_asset};
use seamlit_io::{Asset, Material};
use seamlit_mesh::{FixOptions, Mode, fix};
use seamlit_render::{
    DebugView, FrameDescriptor, FrameSettings, GpuContext, GpuScene, LightingModel, RenderError,
    Renderer, ToneMapping,
};
use seamlit_scene::{Camera, Facing, OrbitController};
use wasm_bindgen::prelude::*;
use web_sys::HtmlCanvasElement;

/// Multisampling of the page's frames: the count `seamlit render` uses where supported
/// (WebGPU guarantees 4 for the formats a canvas takes).
const SAMPLE_COUNT: u32 = seamlit_render::DEFAULT_SAMPLE_COUNT;

/// A model on the GPU twice: as loaded and as fixed, to switch between.
struct Shown {
    loaded: GpuScene,
    fixed: GpuScene,
    bounds: (glam::Vec3, glam::Vec3),
}

/// seamlit's renderer drawing into a canvas through the browser's WebGPU.
#[wasm_bindgen]
pub struct Viewer {
    ctx: GpuContext,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    renderer: Renderer,
    shown: Option<Shown>,
    show_fixed: bool,
    camera: Camera,
    orbit: OrbitController,
    settings: FrameSettings,
    marked: usize,
    /// The last dropped model's fixed file (its name and bytes) and its report (JSON).
    output: Option<Output>,
    /// How dropped models are fixed: the command line's defaults until the page's controls
    /// change them ([`Viewer::set_options`]).
    job: FixJob,
    /// The last dropped model, as loaded, to fix again when the options change.
    dropped: Option<(String, Asset)>,
}

/// What the page offers for the model it shows: the fixed file, the seam report (`seamlit
/// inspect --json`) and what the fix did.
struct Output {
    download: crate::files::Download,
    report: String,
    fixed: String,
}

fn js_error(context: &str, error: impl std::fmt::Display) -> JsError {
    JsError::new(&format!("{context}: {error}"))
}

#[wasm_bindgen]
impl Viewer {
    /// Opens WebGPU on `canvas` (its width and height attributes give the frame's size).
    ///
    /// # Errors
    ///
    /// One line when the browser has no WebGPU or the adapter refuses a device.
    pub async fn create(canvas: HtmlCanvasElement) -> Result<Viewer, JsError> {
        if !wgpu::util::is_browser_webgpu_supported().await {
            return Err(JsError::new(
                "this browser has no WebGPU: seamlit's page needs it (Chrome or Edge 113+, \
                 Firefox 141+, Safari 26+), or use the command line",
            ));
        }
        let (width, height) = (canvas.width().max(1), canvas.height().max(1));
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::BROWSER_WEBGPU;
        let instance = wgpu::Instance::new(desc);
        let surface = instance
            .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
            .map_err(|e| js_error("WebGPU cannot draw into the canvas", e))?;
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: Some(&surface),
            ..Default::default()
        };
        let adapter = instance
            .request_adapter(&options)
            .await
            .map_err(|e| js_error("no WebGPU adapter", e))?;
        let limits = adapter.limits();
        let config = surface
            .get_default_config(&adapter, width, height)
            .ok_or_else(|| JsError::new("the WebGPU adapter cannot draw into the canvas"))?;
        let ctx = GpuContext::open(instance, adapter, limits)
            .await
            .map_err(|e| js_error("opening the WebGPU device", e))?;
        surface.configure(ctx.device(), &config);
        let renderer = Renderer::new(&ctx, config.format, SAMPLE_COUNT)
            .map_err(|e| js_error("creating the renderer", e))?;
        let camera = seamlit_scene::demo::camera();
        let orbit = OrbitController::looking_at(camera.position, camera.target);
        let settings =
            FrameSettings { lights: seamlit_scene::demo::lights(), ..FrameSettings::default() };
        Ok(Viewer {
            ctx,
            surface,
            config,
            renderer,
            shown: None,
            show_fixed: true,
            camera,
            orbit,
            settings,
            marked: 0,
            output: None,
            job: FixJob { report_as_loaded: true, ..FixJob::DEFAULT },
            dropped: None,
        })
    }

    /// The adapter, in one line (e.g. SwiftShader's).
    #[must_use]
    pub fn adapter(&self) -> String {
        self.ctx.describe()
    }

    /// Shows the embedded Newell teapot of `seamlit demo` (32 objects), tessellated
    /// `tessellation` times a patch side, with the demo's camera and lights.
    ///
    /// # Errors
    ///
    /// When fixing or uploading fails (one line).
    #[wasm_bindgen(js_name = showDemo)]
    pub fn show_demo(&mut self, tessellation: u32) -> Result<(), JsError> {
        let asset = seamlit_scene::demo::teapot_asset(tessellation)
            .map_err(|e| js_error("the demo teapot", e))?;
        let options = FixOptions::default();
        let fixed = Asset {
            model: fix(&asset.model, &options).map_err(|e| js_error("fixing", e))?,
            ..asset.clone()
        };
        self.show(&asset, &fixed, &options, Facing::PlusZ)?;
        self.output = None;
        self.camera = seamlit_scene::demo::camera();
        self.orbit = OrbitController::looking_at(self.camera.position, self.camera.target);
        // `seamlit demo`'s look: its lights, Blinn-Phong, the paper's ambient 0.05, no
        // environment, no shadows (what FrameSettings::default() also says for the rest).
        self.settings = FrameSettings {
            lights: seamlit_scene::demo::lights(),
            lighting_model: LightingModel::BlinnPhong,
            tone_mapping: ToneMapping::default_for(LightingModel::BlinnPhong),
            debug_view: self.settings.debug_view,
            ..FrameSettings::default()
        };
        Ok(())
    }

    /// Shows the model among the files dropped together (`names`, paths relative to what was
    /// dropped, and `contents`, their bytes; [`crate::files::pick_model`] picks the model, the
    /// rest are its side files: a glTF's buffers and images, an OBJ's material libraries and
    /// textures), as loaded and as fixed as `seamlit fix` fixes it ([`fix_asset`], the page's
    /// options), and writes the fixed file ([`Viewer::output_name`], [`Viewer::output_bytes`])
    /// and the reports ([`Viewer::report`], [`Viewer::summary`]). Returns a one-line summary.
    ///
    /// # Errors
    ///
    /// One line naming the file and the reason: a format the page does not read, a file the
    /// reader refuses, a missing side file, a model without triangles.
    #[wasm_bindgen(js_name = loadFiles)]
    pub fn load_files(
        &mut self,
        names: Vec<String>,
        contents: Vec<js_sys::Uint8Array>,
    ) -> Result<String, JsError> {
        let name = crate::files::pick_model(&names)
            .ok_or_else(|| JsError::new("no file was given"))?
            .to_owned();
        let files = names.into_iter().zip(contents.iter().map(js_sys::Uint8Array::to_vec));
        let asset = crate::files::read(&name, files.collect()).map_err(|e| JsError::new(&e))?;
        self.output = None;
        self.dropped = None;
        self.present(&name, &asset)?;
        self.dropped = Some((name.clone(), asset));
        let asset = &self.dropped.as_ref().expect("just set").1;
        Ok(format!(
            "{name}: {} objects, {} triangles; {} shared positions whose normals differ are \
             marked on it as loaded",
            asset.model.objects.len(),
            asset.model.triangle_count(),
            self.marked
        ))
    }

    /// Sets how dropped models are fixed and fixes the one shown again (its file and report
    /// follow). `json` holds `seamlit fix`'s options as the Python package sends them:
    /// `{"fix": {"crease_angle_deg": 30, "normals": "recompute", "tangents": "mikktspace"},
    /// "tangents_asked": true}` (members left out keep the command line's defaults).
    ///
    /// # Errors
    ///
    /// One line for options that do not parse; as [`Viewer::load_file`] for the refix.
    #[wasm_bindgen(js_name = setOptions)]
    pub fn set_options(&mut self, json: &str) -> Result<(), JsError> {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Options {
            #[serde(default)]
            fix: FixOptions,
            #[serde(default)]
            tangents_asked: bool,
        }
        let options: Options =
            serde_json::from_str(json).map_err(|e| js_error("the fix options", e))?;
        self.job =
            FixJob { options: options.fix, tangents_asked: options.tangents_asked, ..self.job };
        if let Some((name, asset)) = self.dropped.take() {
            // The same model again: the view stays where the user turned it.
            let (camera, orbit) = (self.camera.clone(), self.orbit);
            let presented = self.present(&name, &asset);
            self.dropped = Some((name, asset));
            presented?;
            (self.camera, self.orbit) = (camera, orbit);
        }
        Ok(())
    }

    /// The fixed file's name (`NAME.glb`, `NAME.vrm` for a VRM avatar, `NAME.zip` for an OBJ
    /// with its material libraries and textures), empty before a model was dropped.
    #[wasm_bindgen(getter, js_name = outputName)]
    #[must_use]
    pub fn output_name(&self) -> String {
        self.output.as_ref().map_or_else(String::new, |o| o.download.name.clone())
    }

    /// The fixed file's bytes: what `seamlit fix MODEL -o OUT` writes for the dropped model
    /// (several files as one zip).
    #[wasm_bindgen(getter, js_name = outputBytes)]
    #[must_use]
    pub fn output_bytes(&self) -> Vec<u8> {
        self.output.as_ref().map_or_else(Vec::new, |o| o.download.bytes.clone())
    }

    /// The seam report of the dropped model with the page's options: exactly the JSON
    /// `seamlit inspect --json MODEL` prints with the same flags.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn report(&self) -> String {
        self.output.as_ref().map_or_else(String::new, |o| o.report.clone())
    }

    /// What the fix did, as JSON: `seamlit fix`'s summary lines (`summary`), the seam reports
    /// as loaded and fixed, what changed per object, the options, the skins and the seams in
    /// motion ([`seamlit_io::job::Fixed::file_json`]), and the reader's and writer's warnings.
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn fixed(&self) -> String {
        self.output.as_ref().map_or_else(String::new, |o| o.fixed.clone())
    }

    /// Fixes the demo teapot at `tessellation` (1M triangles at 125) with `tangents`
    /// (`seamlit` or `mikktspace`) and returns `[triangles, milliseconds]`: the fix alone,
    /// on the page's one thread.
    ///
    /// # Errors
    ///
    /// As [`crate::timing::fix_demo_teapot`].
    #[wasm_bindgen(js_name = timeDemoFix)]
    pub fn time_demo_fix(tessellation: u32, tangents: &str) -> Result<Vec<f64>, JsError> {
        let t = crate::timing::fix_demo_teapot(tessellation, tangents, js_sys::Date::now)
            .map_err(|e| JsError::new(&e))?;
        Ok(vec![t.triangles as f64, t.ms])
    }

    /// How many shared positions are marked on the model as loaded: those whose objects'
    /// normals differ by more than a degree (the seam report's normal breaks).
    #[wasm_bindgen(getter)]
    #[must_use]
    pub fn marked(&self) -> usize {
        self.marked
    }

    /// Orbits the camera by a drag of `dx`, `dy` CSS pixels.
    pub fn rotate(&mut self, dx: f32, dy: f32) {
        self.orbit.rotate(Vec2::new(dx, dy));
    }

    /// Zooms by `steps` wheel steps (positive: closer).
    pub fn zoom(&mut self, steps: f32) {
        self.orbit.zoom(steps);
    }

    /// Chooses what is drawn: `lit`, `objects` (a flat colour per object: seams between
    /// objects show as colour borders) or `normals` (world normals as colour: a seam shows as
    /// a jump).
    ///
    /// # Errors
    ///
    /// For another name.
    #[wasm_bindgen(js_name = setView)]
    pub fn set_view(&mut self, view: &str) -> Result<(), JsError> {
        self.settings.debug_view = match view {
            "lit" => DebugView::Lit,
            "objects" => DebugView::ObjectIds,
            "normals" => DebugView::Normals,
            other => {
                return Err(JsError::new(&format!(
                    "unknown view {other:?} (lit, objects, normals)"
                )));
            }
        };
        Ok(())
    }

    /// Shows the model as fixed (`true`, the default) or as loaded.
    #[wasm_bindgen(js_name = setFixed)]
    pub fn set_fixed(&mut self, fixed: bool) {
        self.show_fixed = fixed;
    }

    /// Draws one frame into the canvas (a clear colour only while no model is shown).
    ///
    /// # Errors
    ///
    /// When the renderer fails (one line).
    pub fn draw(&mut self) -> Result<(), JsError> {
        let (wgpu::CurrentSurfaceTexture::Success(texture)
        | wgpu::CurrentSurfaceTexture::Suboptimal(texture)) = self.surface.get_current_texture()
        else {
            // Outdated or lost (the canvas changed): configure again, draw next time.
            self.surface.configure(self.ctx.device(), &self.config);
            return Ok(());
        };
        let view = texture.texture.create_view(&wgpu::TextureViewDescriptor::default());
        if let Some(shown) = &self.shown {
            let scene = if self.show_fixed { &shown.fixed } else { &shown.loaded };
            self.orbit.apply_to(&mut self.camera);
            let size = (self.config.width, self.config.height);
            let camera = self.camera.view(size.0 as f32 / size.1 as f32, Some(shown.bounds));
            let frame = FrameDescriptor { scene, camera: &camera, settings: &self.settings, size };
            self.renderer.render(&self.ctx, &frame, &view).map_err(|e| js_error("drawing", e))?;
        } else {
            clear(&self.ctx, &view, self.settings.clear_color);
        }
        self.ctx.queue().present(texture);
        Ok(())
    }
}

impl Viewer {
    /// Fixes the model dropped as `name` ([`Viewer::job`]), shows it as loaded and fixed, and
    /// writes its fixed file and report.
    fn present(&mut self, name: &str, asset: &Asset) -> Result<(), JsError> {
        self.output = None;
        let refuse = |why: &str| JsError::new(&format!("{name}: {why}"));
        let mut fixed = asset.clone();
        let done = fix_asset(&mut fixed, &self.job).map_err(|e| refuse(&e.to_string()))?;
        // A VRM 0.x avatar faces -Z: seen from the front, as three-vrm shows it.
        let vrm0 = asset.document::<seamlit_io::GltfSource>().is_some_and(|s| s.is_vrm0());
        let facing = if vrm0 { Facing::MinusZ } else { Facing::PlusZ };
        self.show(asset, &fixed, &done.options, facing)?;
        self.settings = FrameSettings { debug_view: self.settings.debug_view, ..look(asset) };
        self.output = Some(output(name, asset, &fixed, &done)?);
        Ok(())
    }

    /// Puts `asset` as loaded and `fixed` on the GPU, framed by the default camera of
    /// `seamlit render`; marks the shared positions whose normals differ as loaded (welded
    /// with `options`' tolerance). The camera looks at the model's front (`facing`).
    fn show(
        &mut self,
        asset: &Asset,
        fixed: &Asset,
        options: &FixOptions,
        facing: Facing,
    ) -> Result<(), JsError> {
        let upload =
            |asset: &Asset| -> Result<GpuScene, RenderError> { GpuScene::upload(&self.ctx, asset) };
        // "As loaded" draws the file's own normals; a file without them is drawn as a viewer
        // that smooths each object on its own would (seamlit's object mode): its seams show.
        let mut loaded = if asset.model.objects.iter().all(|o| o.normals.is_some()) {
            asset.clone()
        } else {
            let per_object = FixOptions { mode: Mode::Object, ..*options };
            let model = fix(&asset.model, &per_object).map_err(|e| js_error("fixing", e))?;
            Asset { model, ..asset.clone() }
        };
        // The shared positions where the normals differ, marked on the model as loaded.
        let points = crate::marks::seam_points(&loaded.model, options.weld_tolerance)
            .map_err(|e| js_error("finding the seams", e))?;
        self.marked = points.len();
        if let (false, Some((min, max))) = (points.is_empty(), loaded.model.bounds()) {
            let mut marks = crate::marks::markers(&points, (max - min).length() * 0.006);
            marks.material = Some(loaded.materials.len());
            loaded.materials.push(Material {
                name: "seam marks".into(),
                base_color: [1.0, 0.05, 0.6, 1.0],
                ..Material::default()
            });
            loaded.model.objects.push(marks);
        }
        let loaded = upload(&loaded).map_err(|e| js_error("uploading the model", e))?;
        let fixed = upload(fixed).map_err(|e| js_error("uploading the fixed model", e))?;
        let bounds = fixed.bounds().unwrap_or((glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0)));
        let aspect = self.config.width as f32 / self.config.height as f32;
        self.camera = Camera::framing_facing(bounds, aspect, facing);
        self.orbit = OrbitController::looking_at(self.camera.position, self.camera.target);
        self.shown = Some(Shown { loaded, fixed, bounds });
        Ok(())
    }
}

/// The fixed file for the model dropped as `name`, as `seamlit fix` writes it
/// ([`crate::files::write`]), its seam report as `seamlit inspect --json` prints it, and what
/// the fix did.
fn output(name: &str, asset: &Asset, fixed: &Asset, done: &Fixed) -> Result<Output, JsError> {
    let (download, warnings) = crate::files::write(name, fixed).map_err(|e| JsError::new(&e))?;
    let inspection = Inspection::measure(&asset.model, &done.options)
        .map_err(|e| JsError::new(&format!("{name}: {e}")))?;
    let report = serde_json::to_string_pretty(&inspection.json(name, &done.options))
        .map_err(|e| js_error("the report", e))?;
    let fixed = done.file_json(name, &download.output, fixed.warnings.iter().chain(&warnings));
    let fixed = serde_json::to_string_pretty(&fixed).map_err(|e| js_error("the report", e))?;
    // `seamlit inspect --json` prints the document and a line end.
    Ok(Output { download, report: report + "\n", fixed })
}

/// Clears `view` to `colour` (linear RGBA).
fn clear(ctx: &GpuContext, view: &wgpu::TextureView, colour: [f32; 4]) {
    let mut encoder = ctx.device().create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("seamlit-web clear"),
    });
    let [r, g, b, a] = colour.map(f64::from);
    drop(encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("seamlit-web clear"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                store: wgpu::StoreOp::Store,
            },
        })],
        ..Default::default()
    }));
    ctx.queue().submit([encoder.finish()]);
}

/// The frame settings of `seamlit render MODEL --environment none --shadows off`: the model's
/// own lights (KHR_lights_punctual) or else the command line's three-point rig, PBR with its
/// default tone mapping and a uniform ambient light standing in for the environment (the page
/// has no environment map yet) for a glTF model, Blinn-Phong and the paper's ambient for the
/// others (OBJ, USD), as `seamlit render` chooses.
fn look(asset: &Asset) -> FrameSettings {
    let gltf = asset.document::<seamlit_io::GltfSource>().is_some();
    let lighting = if gltf { LightingModel::Pbr } else { LightingModel::BlinnPhong };
    let from_file: Vec<_> = asset
        .lights
        .iter()
        .map(|l| seamlit_scene::lights::from_gltf(l, glam::Mat4::IDENTITY))
        .collect();
    let lights =
        if from_file.is_empty() { seamlit_scene::lights::three_point_rig() } else { from_file };
    FrameSettings {
        lights,
        lighting_model: lighting,
        tone_mapping: ToneMapping::default_for(lighting),
        ambient: glam::Vec3::splat(if lighting == LightingModel::Pbr { 0.3 } else { 0.05 }),
        ..FrameSettings::default()
    }
}
