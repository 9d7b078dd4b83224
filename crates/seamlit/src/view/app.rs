//! The viewer window: winit events, the wgpu surface, the scene renderer and the egui panel.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use glam::Vec2;
use image::RgbaImage;
use seamlit_io::Asset;
use seamlit_render::{
    CameraView, Environment, FrameDescriptor, FrameSettings, GpuContext, GpuEnvironment, GpuScene,
    IMAGE_FORMAT, Renderer,
};
use seamlit_scene::{Bounds, Camera, FpsController, OrbitController};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseScrollDelta, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use super::input::Held;
use super::panel::{self, Actions, Controller, Readout, Settings};
use crate::draw::Look;
use crate::failure::{Classify, Failure};
use crate::picture::save_png;
use crate::prepare::{FixOverride, Loaded, drawn_bounds};

/// How the viewer was started.
pub struct Options {
    /// The scene or model shown (for the title and messages).
    pub input: PathBuf,
    /// Initial window size.
    pub size: (u32, u32),
    /// Where screenshots go.
    pub screenshot: Option<PathBuf>,
    /// Close after this many frames (taking the screenshot first, if one is asked for).
    pub exit_after_frames: Option<u64>,
    /// The command line's fix flags (crease and weighting come from the panel).
    pub fix: FixOverride,
    /// The look from the flags and the scene (lighting, tone mapping, exposure and ambient
    /// come from the panel).
    pub look: Look,
    /// The environment, read before the window opens.
    pub environment: Option<Environment>,
    /// The animation and time to start at (the panel changes them).
    pub animation: crate::cli::AnimationFlags,
}

/// The window's GPU side.
struct Gfx {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    ctx: GpuContext,
    renderer: Renderer,
    environment: Option<GpuEnvironment>,
    scene: GpuScene,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    can_copy: bool,
}

/// What the panel gave this frame.
struct PanelOutput {
    /// The settings as the panel left them.
    settings: Settings,
    actions: Actions,
    /// The pointer is over the picture, not the panel: it moves the camera.
    pointer_free: bool,
    overlay: Overlay,
}

/// The panel as drawn over the scene.
struct Overlay {
    /// The panel's triangles.
    paint: Vec<egui::ClippedPrimitive>,
    pixels_per_point: f32,
    /// The panel's right edge, in physical pixels.
    panel_px: f32,
}

/// One frame of the window: the scene as `camera` sees it, the panel over it.
struct WindowFrame<'a> {
    camera: &'a CameraView,
    settings: &'a FrameSettings,
    overlay: &'a Overlay,
    /// Copy the frame for a screenshot.
    copy: bool,
}

impl Gfx {
    /// The window's next surface texture; `None` when there is none this frame (the surface
    /// is configured again when it was outdated or lost).
    fn acquire(&self) -> Option<wgpu::SurfaceTexture> {
        match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => Some(f),
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(self.ctx.device(), &self.config);
                None
            }
            _ => None,
        }
    }

    /// Draws the scene and the panel over it into `surface` and presents it, applying the
    /// panel's `textures` changes; returns the copy of the frame when `frame.copy` asks for
    /// one and the surface can be copied from.
    fn draw(
        &mut self,
        surface: wgpu::SurfaceTexture,
        frame: &WindowFrame<'_>,
        mut textures: egui::TexturesDelta,
    ) -> Result<Option<super::capture::Pending>, Failure> {
        // Drained now: egui asserts that no delta is dropped unapplied, even on an error.
        let texture_sets: Vec<_> = textures.set.drain().collect();
        let texture_frees: Vec<_> = textures.free.drain().collect();
        let (width, height) = (self.config.width, self.config.height);
        let target = surface.texture.create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder =
            self.ctx.device().create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("seamlit view"),
            });
        self.renderer
            .encode(
                &self.ctx,
                &mut encoder,
                &FrameDescriptor {
                    scene: &self.scene,
                    camera: frame.camera,
                    settings: frame.settings,
                    size: (width, height),
                },
                &target,
            )
            .processing()?;
        let extra = self.encode_panel(&mut encoder, &target, frame.overlay, &texture_sets);
        let readback = (frame.copy && self.can_copy).then(|| {
            super::capture::copy_to_buffer(
                self.ctx.device(),
                &mut encoder,
                &surface.texture,
                width,
                height,
            )
        });
        self.ctx.queue().submit(extra.into_iter().chain([encoder.finish()]));
        self.ctx.queue().present(surface);
        for id in &texture_frees {
            self.egui_renderer.free_texture(id);
        }
        Ok(readback)
    }

    /// Records the panel over `target`: the texture updates in `textures`, its buffers and
    /// its pass. Returns the command buffers egui-wgpu needs submitted before `encoder`.
    fn encode_panel(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        overlay: &Overlay,
        textures: &[(egui::TextureId, impl AsRef<[egui::epaint::ImageDelta]>)],
    ) -> Vec<wgpu::CommandBuffer> {
        let (device, queue) = (self.ctx.device(), self.ctx.queue());
        for (id, deltas) in textures {
            let deltas = deltas.as_ref();
            for delta in deltas {
                self.egui_renderer.update_texture(device, queue, *id, delta);
            }
        }
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: overlay.pixels_per_point,
        };
        let extra =
            self.egui_renderer.update_buffers(device, queue, encoder, &overlay.paint, &screen);
        let mut pass = encoder
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                })],
                ..Default::default()
            })
            .forget_lifetime();
        self.egui_renderer.render(&mut pass, &overlay.paint, &screen);
        extra
    }

    /// The screenshot: the frame copied into `readback`, or, when the surface could not be
    /// copied from, the scene (without the panel) rendered offscreen.
    fn screenshot(
        &self,
        readback: Option<super::capture::Pending>,
        frame: &WindowFrame<'_>,
    ) -> Result<RgbaImage, Failure> {
        if let Some(buffer) = readback {
            return super::capture::read(&self.ctx, buffer, self.config.format);
        }
        let mut offscreen = Renderer::new(&self.ctx, IMAGE_FORMAT, 1).processing()?;
        offscreen.set_environment(self.environment.clone());
        offscreen
            .render_to_image(
                &self.ctx,
                &FrameDescriptor {
                    scene: &self.scene,
                    camera: frame.camera,
                    settings: frame.settings,
                    size: (self.config.width, self.config.height),
                },
            )
            .processing()
    }
}

/// The viewer.
pub struct Viewer {
    options: Options,
    loaded: Loaded,
    asset: Asset,
    bounds: Bounds,
    cameras: Vec<Camera>,
    camera_names: Vec<String>,
    current: Camera,
    orbit: OrbitController,
    fps: FpsController,
    settings: Settings,
    applied: Settings,
    /// The model's animations (name, seconds), for the panel.
    animations: Vec<(String, f32)>,
    /// The models' material variants, for the panel.
    variants: Vec<String>,
    /// The moment the GPU scene is posed at; `None`: not posed since the last upload.
    posed: Option<crate::animate::Moment>,
    /// The models posed by their own `animation` key (the panel's animation poses the rest).
    own_moments: Vec<crate::animate::OwnMoment>,
    held: Held,
    gfx: Option<Gfx>,
    frames: u64,
    last_frame: Instant,
    frame_ms: f32,
    fix_ms: f32,
    status: String,
    screenshot_requested: bool,
    pending_textures: egui::TexturesDelta,
    /// Set when the viewer stopped because something failed.
    pub failure: Option<Failure>,
}

impl Viewer {
    /// A viewer of `loaded`, fixed with `settings` (mode, crease, weighting) and `options.fix`.
    ///
    /// # Errors
    /// Bad input when the fix fails or the camera name is unknown.
    pub(crate) fn new(
        loaded: Loaded,
        settings: Settings,
        camera: Option<&str>,
        options: Options,
    ) -> Result<Self, Failure> {
        let started = Instant::now();
        let asset = loaded.build(&fix_override(&options.fix, &settings))?;
        let fix_ms = started.elapsed().as_secs_f32() * 1e3;
        let moment = crate::animate::moment(&options.animation, &loaded, &asset, &options.input)?;
        let own_moments =
            crate::animate::own_moments(&options.animation, &loaded, &asset, &options.input)?;
        // Framed as first drawn: at the moment asked for (or at rest).
        let poses = crate::animate::poses(&asset, moment, &own_moments);
        let bounds = drawn_bounds(&asset, poses.as_deref());
        let aspect = options.size.0 as f32 / options.size.1 as f32;
        let cameras = loaded.cameras(bounds, aspect);
        let chosen = crate::prepare::pick_camera(&cameras, camera, &options.input)?;
        let index = cameras.iter().position(|c| c.name == chosen.name).unwrap_or(0);
        let camera_names = cameras.iter().map(|c| c.name.clone()).collect();
        let mut settings = settings;
        settings.camera = index;
        // An animation asked for plays from its start, unless a time was asked for too.
        let timed = options.animation.time.is_some() || loaded.scene.render.time.is_some();
        settings.playback = panel::Playback {
            animation: moment.animation,
            time: moment.time,
            playing: moment.animation.is_some() && !timed,
        };
        let animations = crate::animate::list(&asset);
        let variants = loaded.variant_names();
        let speed = (bounds.1 - bounds.0).length() * 0.3;
        Ok(Self {
            orbit: OrbitController::looking_at(chosen.position, chosen.target),
            fps: FpsController::looking_at(chosen.position, chosen.target, speed.max(1e-3)),
            current: chosen,
            applied: settings.clone(),
            settings,
            animations,
            variants,
            posed: None,
            own_moments,
            options,
            loaded,
            asset,
            bounds,
            cameras,
            camera_names,
            held: Held::default(),
            gfx: None,
            frames: 0,
            last_frame: Instant::now(),
            frame_ms: 0.0,
            fix_ms,
            status: String::new(),
            screenshot_requested: false,
            pending_textures: egui::TexturesDelta::default(),
            failure: None,
        })
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, failure: Failure) {
        self.failure = Some(failure);
        event_loop.exit();
    }

    fn create_gfx(&self, event_loop: &ActiveEventLoop) -> Result<Gfx, Failure> {
        let (w, h) = self.options.size;
        let attributes = Window::default_attributes()
            .with_title(format!("seamlit - {}", self.options.input.display()))
            .with_inner_size(PhysicalSize::new(w, h));
        let window = Arc::new(event_loop.create_window(attributes).processing()?);
        let instance = GpuContext::new_instance();
        let surface = instance.create_surface(window.clone()).processing()?;
        let ctx = GpuContext::for_surface(instance, &surface).processing()?;
        let (config, can_copy) = configure_surface(&surface, &ctx, window.inner_size())?;
        let format = config.format;
        let samples = if ctx.supported_sample_counts(format).contains(&4) { 4 } else { 1 };
        let mut renderer = Renderer::new(&ctx, format, samples).processing()?;
        let environment = self
            .options
            .environment
            .as_ref()
            .map(|e| GpuEnvironment::new(&ctx, e))
            .transpose()
            .processing()?;
        renderer.set_environment(environment.clone());
        crate::draw::warn_of_undrawn_textures(&ctx, &self.asset);
        let scene = GpuScene::upload(&ctx, &self.asset).processing()?;
        let egui_state = egui_state(&ctx, &window);
        let egui_renderer =
            egui_wgpu::Renderer::new(ctx.device(), format, egui_wgpu::RendererOptions::default());
        Ok(Gfx {
            window,
            surface,
            config,
            ctx,
            renderer,
            environment,
            scene,
            egui_state,
            egui_renderer,
            can_copy,
        })
    }

    /// Re-runs the fix when mode, crease or weighting changed, and swaps the geometry; gives
    /// the objects their material variant's materials when that changed.
    fn refix_if_needed(&mut self) {
        let variant_changed = self.settings.variant != self.applied.variant;
        if self.settings.fix_key() == self.applied.fix_key() && !variant_changed {
            return;
        }
        self.applied = self.settings.clone();
        if variant_changed
            && let Err(f) = self.loaded.select_variant(self.settings.variant.as_deref(), false)
        {
            self.status = f.to_string();
            return;
        }
        let started = Instant::now();
        match self.loaded.build(&fix_override(&self.options.fix, &self.settings)) {
            Ok(asset) => {
                self.fix_ms = started.elapsed().as_secs_f32() * 1e3;
                if let Some(gfx) = &mut self.gfx
                    && let Err(e) = gfx.scene.replace_model(&gfx.ctx, &asset.model)
                {
                    self.status = format!("could not upload the model: {e}");
                }
                self.asset = asset;
                self.posed = None;
            }
            Err(f) => self.status = f.to_string(),
        }
    }

    /// Runs the animation's clock and poses the GPU scene where the moment changed.
    fn pose_if_needed(&mut self, dt: f32) {
        let playback = &mut self.settings.playback;
        let duration = playback.animation.and_then(|i| self.animations.get(i)).map_or(0.0, |a| a.1);
        playback.advance(dt, duration);
        let moment = crate::animate::Moment { animation: playback.animation, time: playback.time };
        let Some(gfx) = &mut self.gfx else { return };
        if self.posed == Some(moment) {
            return;
        }
        self.posed = Some(moment);
        if let Some(poses) = crate::animate::poses(&self.asset, moment, &self.own_moments)
            && let Err(e) = gfx.scene.set_pose(&gfx.ctx, &poses)
        {
            self.status = format!("could not pose the model: {e}");
        }
    }

    fn select_camera(&mut self, index: usize) {
        let Some(camera) = self.cameras.get(index) else { return };
        self.settings.camera = index;
        self.current = camera.clone();
        let speed = self.fps.speed;
        self.orbit = OrbitController::looking_at(camera.position, camera.target);
        self.fps = FpsController::looking_at(camera.position, camera.target, speed);
    }

    fn switch_controller(&mut self, to: Controller) {
        if to == Controller::Orbit && self.settings.controller == Controller::Fps {
            // Orbit a point as far ahead as the orbit was before.
            let target = self.fps.position + self.fps.forward() * self.orbit.distance;
            self.orbit = OrbitController::looking_at(self.fps.position, target);
        } else if to == Controller::Fps && self.settings.controller == Controller::Orbit {
            self.fps =
                FpsController::looking_at(self.orbit.eye(), self.orbit.target, self.fps.speed);
        }
        self.settings.controller = to;
    }

    /// Moves the camera by this frame's input.
    fn update_camera(&mut self, dt: f32, pointer_free: bool) {
        match self.settings.controller {
            Controller::Orbit => {
                if pointer_free {
                    if self.held.left {
                        self.orbit.rotate(self.held.motion);
                    }
                    if self.held.middle {
                        let h = self.gfx.as_ref().map_or(600.0, |g| g.config.height as f32);
                        self.orbit.pan(self.held.motion, h, self.current.fov_y_deg);
                    }
                    if self.held.scroll != 0.0 {
                        self.orbit.zoom(self.held.scroll);
                    }
                }
                self.orbit.apply_to(&mut self.current);
            }
            Controller::Fps => {
                let mut input = self.held.fps_input();
                if !pointer_free {
                    input.mouse_delta = Vec2::ZERO;
                }
                self.fps.update(&input, dt);
                self.fps.apply_to(&mut self.current);
            }
        }
        self.held.end_frame();
    }

    fn frame_settings(&self) -> FrameSettings {
        let s = &self.settings;
        let look = Look {
            lighting: s.lighting,
            tone_mapping: s.tone_mapping,
            exposure: s.exposure,
            ambient: s.ambient,
            ..self.options.look.clone()
        };
        FrameSettings {
            normal_mapping: s.normal_mapping,
            debug_view: s.debug_view,
            show_tbn: s.show_tbn,
            ..look.settings(s.lighting, s.lights.clone())
        }
    }

    /// Draws one frame; returns a screenshot when one was taken.
    fn redraw(&mut self) -> Result<Option<RgbaImage>, Failure> {
        let dt = self.tick();
        let Some(PanelOutput { settings: edited, actions, pointer_free, overlay }) =
            self.run_panel()
        else {
            return Ok(None);
        };
        self.apply_panel(edited, actions);
        self.refix_if_needed();
        self.pose_if_needed(dt);
        self.update_camera(dt, pointer_free);
        let Some(size) = self.gfx.as_ref().map(|g| (g.config.width, g.config.height)) else {
            return Ok(None);
        };
        let camera = self.camera_view(size, overlay.panel_px);
        let settings = self.frame_settings();
        let copy = self.screenshot_due();
        let Some(gfx) = self.gfx.as_mut() else { return Ok(None) };
        let Some(surface) = gfx.acquire() else { return Ok(None) };
        let frame = WindowFrame { camera: &camera, settings: &settings, overlay: &overlay, copy };
        let readback = gfx.draw(surface, &frame, std::mem::take(&mut self.pending_textures))?;
        self.frames += 1;
        if !copy {
            return Ok(None);
        }
        self.screenshot_requested = false;
        gfx.screenshot(readback, &frame).map(Some)
    }

    /// Whether this frame is kept as a screenshot: F12 or the panel's button was pressed, or
    /// it is the last frame of a run with `--screenshot` and `--exit-after-frames`.
    fn screenshot_due(&self) -> bool {
        self.screenshot_requested
            || (self.options.screenshot.is_some()
                && self.options.exit_after_frames == Some(self.frames + 1))
    }

    /// Advances the clock: returns the seconds since the last frame (at most a quarter) and
    /// updates the smoothed frame time.
    fn tick(&mut self) -> f32 {
        let now = Instant::now();
        let dt = (now - self.last_frame).as_secs_f32().min(0.25);
        self.last_frame = now;
        let ms = dt * 1e3;
        self.frame_ms = if self.frame_ms == 0.0 { ms } else { self.frame_ms * 0.9 + ms * 0.1 };
        dt
    }

    /// Runs the panel on this frame's input; `None` before the window exists.
    fn run_panel(&mut self) -> Option<PanelOutput> {
        let gfx = self.gfx.as_mut()?;
        let raw = gfx.egui_state.take_egui_input(&gfx.window);
        let egui_ctx = gfx.egui_state.egui_ctx().clone();
        let mut settings = self.settings.clone();
        let adapter = gfx.ctx.describe();
        let readout = Readout {
            cameras: &self.camera_names,
            animations: &self.animations,
            frame_ms: self.frame_ms,
            fix_ms: self.fix_ms,
            objects: self.asset.model.objects.len(),
            triangles: self.asset.model.triangle_count(),
            adapter: &adapter,
            status: &self.status,
            materials: &self.asset.materials,
            variants: &self.variants,
        };
        let mut actions = Actions::default();
        let mut panel_right = 0.0;
        let output = egui_ctx.run_ui(raw, |ui| {
            let shown =
                egui::Panel::left("settings").resizable(false).default_size(270.0).show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        actions = panel::draw(ui, &mut settings, &readout);
                    });
                });
            panel_right = shown.response.rect.max.x;
        });
        gfx.egui_state.handle_platform_output(&gfx.window, output.platform_output);
        let pointer_free = !egui_ctx.egui_wants_pointer_input() && !egui_ctx.is_pointer_over_egui();
        // Kept until a frame is drawn: a frame skipped later must not lose the font atlas.
        self.pending_textures.append(output.textures_delta);
        Some(PanelOutput {
            settings,
            actions,
            pointer_free,
            overlay: Overlay {
                paint: egui_ctx.tessellate(output.shapes, output.pixels_per_point),
                pixels_per_point: output.pixels_per_point,
                panel_px: panel_right * output.pixels_per_point,
            },
        })
    }

    /// Takes the settings as the panel left them, switching camera or controller where they
    /// changed, and records the buttons pressed.
    fn apply_panel(&mut self, mut settings: Settings, actions: Actions) {
        if settings.camera != self.settings.camera {
            self.select_camera(settings.camera);
            settings.camera = self.settings.camera;
        }
        if settings.controller != self.settings.controller {
            self.switch_controller(settings.controller);
        }
        self.settings = settings;
        if actions.reset_camera {
            self.select_camera(self.settings.camera);
        }
        self.screenshot_requested |= actions.screenshot;
    }

    /// The camera's view for a window of `width` x `height` pixels whose left `panel_px`
    /// pixels the panel covers: the picture is centred in what is left of it.
    fn camera_view(&self, (width, height): (u32, u32), panel_px: f32) -> CameraView {
        let visible = (width as f32 - panel_px).max(1.0);
        let mut view = self.current.view(visible / height as f32, Some(self.bounds));
        view.projection = glam::Mat4::from_scale(glam::Vec3::new(visible / width as f32, 1.0, 1.0))
            * view.projection;
        view.projection =
            glam::Mat4::from_translation(glam::Vec3::new(panel_px / width as f32, 0.0, 0.0))
                * view.projection;
        view
    }

    /// Esc quits, F12 takes a screenshot, Tab switches controller, 1 to 9 pick a camera.
    fn key_pressed(&mut self, event_loop: &ActiveEventLoop, key: PhysicalKey) {
        match key {
            PhysicalKey::Code(KeyCode::Escape) => event_loop.exit(),
            PhysicalKey::Code(KeyCode::F12) => self.screenshot_requested = true,
            PhysicalKey::Code(KeyCode::Tab) => {
                let to = match self.settings.controller {
                    Controller::Orbit => Controller::Fps,
                    Controller::Fps => Controller::Orbit,
                };
                self.switch_controller(to);
            }
            PhysicalKey::Code(code) => {
                if let Some(i) = digit(code) {
                    self.select_camera(i);
                }
            }
            PhysicalKey::Unidentified(_) => {}
        }
    }

    /// Draws a frame, saves the screenshot taken, and stops after a failure or the frames
    /// asked for.
    fn redraw_requested(&mut self, event_loop: &ActiveEventLoop) {
        match self.redraw() {
            Ok(shot) => {
                if let Some(image) = shot {
                    self.save_screenshot(&image);
                }
                if self.failure.is_some()
                    || self.options.exit_after_frames.is_some_and(|n| self.frames >= n)
                {
                    event_loop.exit();
                }
            }
            Err(f) => self.fail(event_loop, f),
        }
    }

    fn save_screenshot(&mut self, image: &RgbaImage) {
        let path = self
            .options
            .screenshot
            .clone()
            .unwrap_or_else(|| PathBuf::from("seamlit-screenshot.png"));
        match save_png(image, &path) {
            Ok(()) => {
                self.status = format!("saved {}", path.display());
                println!("{}", self.status);
            }
            // Asked for on the command line, a screenshot that cannot be written fails the
            // run (exit status 1); taken with F12, it is reported in the panel and on stderr.
            Err(e) if self.options.screenshot.is_some() => {
                self.failure = Some(Failure::Processing(e));
            }
            Err(e) => {
                self.status = format!("{e:#}");
                eprintln!("error: {}", self.status);
            }
        }
    }
}

/// Configures `surface` for a window of `size`: an sRGB format where there is one, vsync,
/// copyable where the surface allows it. Returns the configuration and whether frames can be
/// copied (for screenshots).
fn configure_surface(
    surface: &wgpu::Surface<'_>,
    ctx: &GpuContext,
    size: PhysicalSize<u32>,
) -> Result<(wgpu::SurfaceConfiguration, bool), Failure> {
    let caps = surface.get_capabilities(ctx.adapter());
    let format = caps
        .formats
        .iter()
        .copied()
        .find(wgpu::TextureFormat::is_srgb)
        .or_else(|| caps.formats.first().copied())
        .ok_or_else(|| Failure::processing("the window surface offers no pixel format"))?;
    let can_copy = caps.usages.contains(wgpu::TextureUsages::COPY_SRC);
    let mut config = surface
        .get_default_config(ctx.adapter(), size.width.max(1), size.height.max(1))
        .ok_or_else(|| Failure::processing("the window surface is not supported by the adapter"))?;
    config.format = format;
    config.usage = wgpu::TextureUsages::RENDER_ATTACHMENT
        | if can_copy { wgpu::TextureUsages::COPY_SRC } else { wgpu::TextureUsages::empty() };
    config.present_mode = wgpu::PresentMode::AutoVsync;
    surface.configure(ctx.device(), &config);
    Ok((config, can_copy))
}

/// egui's state for `window`, its textures limited to what the device allows.
fn egui_state(ctx: &GpuContext, window: &Window) -> egui_winit::State {
    let max_texture = usize::try_from(ctx.device().limits().max_texture_dimension_2d).ok();
    egui_winit::State::new(
        egui::Context::default(),
        egui::ViewportId::ROOT,
        window,
        Some(single(window.scale_factor())),
        None,
        max_texture,
    )
}

fn fix_override(base: &FixOverride, s: &Settings) -> FixOverride {
    let mut o = base.clone();
    o.mode = Some(s.mode);
    o.flags.crease = Some(s.crease_deg);
    o.flags.weighting = Some(s.weighting.into());
    o
}

impl Drop for Viewer {
    fn drop(&mut self) {
        // Textures egui asked for after the last frame drawn are of no use now.
        self.pending_textures.clear();
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.create_gfx(event_loop) {
            Ok(gfx) => {
                gfx.window.request_redraw();
                self.gfx = Some(gfx);
                self.posed = None;
                self.last_frame = Instant::now();
            }
            Err(f) => self.fail(event_loop, f),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gfx) = self.gfx.as_mut() else { return };
        let response = gfx.egui_state.on_window_event(&gfx.window, &event);
        let egui_keys = gfx.egui_state.egui_ctx().egui_wants_keyboard_input();
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                gfx.config.width = size.width.max(1);
                gfx.config.height = size.height.max(1);
                gfx.surface.configure(gfx.ctx.device(), &gfx.config);
            }
            WindowEvent::Focused(false) => self.held.clear(),
            WindowEvent::KeyboardInput { event: key, .. } => {
                if egui_keys && key.state == ElementState::Pressed {
                    return;
                }
                self.held.key(key.physical_key, key.state);
                if key.state == ElementState::Pressed && !key.repeat {
                    self.key_pressed(event_loop, key.physical_key);
                }
            }
            WindowEvent::MouseInput { state, button, .. }
                if !(response.consumed && state == ElementState::Pressed) =>
            {
                self.held.button(button, state);
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.held.cursor_moved(Vec2::new(single(position.x), single(position.y)));
            }
            WindowEvent::MouseWheel { delta, .. } if !response.consumed => {
                self.held.scroll += match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => single(p.y) / 40.0,
                };
            }
            WindowEvent::RedrawRequested => self.redraw_requested(event_loop),
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(gfx) = &self.gfx {
            gfx.window.request_redraw();
        }
    }
}

/// Keys 1 to 9: camera 0 to 8.
fn digit(code: KeyCode) -> Option<usize> {
    let keys = [
        KeyCode::Digit1,
        KeyCode::Digit2,
        KeyCode::Digit3,
        KeyCode::Digit4,
        KeyCode::Digit5,
        KeyCode::Digit6,
        KeyCode::Digit7,
        KeyCode::Digit8,
        KeyCode::Digit9,
    ];
    keys.iter().position(|k| *k == code)
}

/// `x`, one of winit's f64 window coordinates or scale factors, as the f32 that egui and the
/// camera controllers take.
#[expect(
    clippy::cast_possible_truncation,
    reason = "window coordinates and scale factors are far inside f32's range"
)]
fn single(x: f64) -> f32 {
    x as f32
}
