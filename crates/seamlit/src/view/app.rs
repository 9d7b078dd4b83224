//! The viewer window: winit events, the wgpu surface, the scene renderer and the egui panel.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use glam::Vec2;
use image::RgbaImage;
use seamlit_io::Asset;
use seamlit_render::{
    Environment, FrameDescriptor, FrameSettings, GpuContext, GpuEnvironment, GpuScene,
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
use crate::prepare::{FixOverride, Loaded, bounds_of};

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
    pub fn new(
        loaded: Loaded,
        settings: Settings,
        camera: Option<&str>,
        options: Options,
    ) -> Result<Self, Failure> {
        let started = Instant::now();
        let asset = loaded.build(&fix_override(&options.fix, &settings))?;
        let fix_ms = started.elapsed().as_secs_f32() * 1e3;
        let bounds = bounds_of(&asset);
        let aspect = options.size.0 as f32 / options.size.1 as f32;
        let cameras = loaded.cameras(bounds, aspect);
        let chosen = crate::prepare::pick_camera(&cameras, camera, &options.input)?;
        let index = cameras.iter().position(|c| c.name == chosen.name).unwrap_or(0);
        let camera_names = cameras.iter().map(|c| c.name.clone()).collect();
        let mut settings = settings;
        settings.camera = index;
        let speed = (bounds.1 - bounds.0).length() * 0.3;
        Ok(Self {
            orbit: OrbitController::looking_at(chosen.position, chosen.target),
            fps: FpsController::looking_at(chosen.position, chosen.target, speed.max(1e-3)),
            current: chosen,
            applied: settings.clone(),
            settings,
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
        let caps = surface.get_capabilities(ctx.adapter());
        let format = caps
            .formats
            .iter()
            .copied()
            .find(wgpu::TextureFormat::is_srgb)
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| Failure::processing("the window surface offers no pixel format"))?;
        let can_copy = caps.usages.contains(wgpu::TextureUsages::COPY_SRC);
        let size = window.inner_size();
        let mut config = surface
            .get_default_config(ctx.adapter(), size.width.max(1), size.height.max(1))
            .ok_or_else(|| {
                Failure::processing("the window surface is not supported by the adapter")
            })?;
        config.format = format;
        config.usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | if can_copy { wgpu::TextureUsages::COPY_SRC } else { wgpu::TextureUsages::empty() };
        config.present_mode = wgpu::PresentMode::AutoVsync;
        surface.configure(ctx.device(), &config);
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
        let scene = GpuScene::upload(&ctx, &self.asset).processing()?;
        let egui_ctx = egui::Context::default();
        let max_texture = usize::try_from(ctx.device().limits().max_texture_dimension_2d).ok();
        let egui_state = egui_winit::State::new(
            egui_ctx,
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            max_texture,
        );
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

    /// Re-runs the fix when mode, crease or weighting changed, and swaps the geometry.
    fn refix_if_needed(&mut self) {
        if self.settings.fix_key() == self.applied.fix_key() {
            return;
        }
        self.applied = self.settings.clone();
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
            }
            Err(f) => self.status = f.to_string(),
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
        let now = Instant::now();
        let dt = (now - self.last_frame).as_secs_f32().min(0.25);
        self.last_frame = now;
        let ms = dt * 1e3;
        self.frame_ms = if self.frame_ms == 0.0 { ms } else { self.frame_ms * 0.9 + ms * 0.1 };

        let Some(gfx) = self.gfx.as_mut() else { return Ok(None) };
        // The panel.
        let raw = gfx.egui_state.take_egui_input(&gfx.window);
        let egui_ctx = gfx.egui_state.egui_ctx().clone();
        let mut settings = self.settings.clone();
        let adapter = gfx.ctx.describe();
        let readout = Readout {
            cameras: &self.camera_names,
            frame_ms: self.frame_ms,
            fix_ms: self.fix_ms,
            objects: self.asset.model.objects.len(),
            triangles: self.asset.model.triangle_count(),
            adapter: &adapter,
            status: &self.status,
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
        let paint = egui_ctx.tessellate(output.shapes, output.pixels_per_point);
        // Kept until a frame is drawn: a frame skipped below must not lose the font atlas.
        let mut textures = output.textures_delta;
        self.pending_textures.append(std::mem::take(&mut textures));
        let panel_px = panel_right * output.pixels_per_point;
        let ppp = output.pixels_per_point;

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
        self.refix_if_needed();
        self.update_camera(dt, pointer_free);

        let frame_settings = self.frame_settings();
        let Some(gfx) = self.gfx.as_mut() else { return Ok(None) };
        let (width, height) = (gfx.config.width, gfx.config.height);
        // The panel covers the left of the window: centre the picture in what is left of it.
        let visible = (width as f32 - panel_px).max(1.0);
        let mut view = self.current.view(visible / height as f32, Some(self.bounds));
        view.projection = glam::Mat4::from_scale(glam::Vec3::new(visible / width as f32, 1.0, 1.0))
            * view.projection;
        view.projection =
            glam::Mat4::from_translation(glam::Vec3::new(panel_px / width as f32, 0.0, 0.0))
                * view.projection;

        let frame = match gfx.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                gfx.surface.configure(gfx.ctx.device(), &gfx.config);
                return Ok(None);
            }
            _ => return Ok(None),
        };
        let texture_sets: Vec<_> = self.pending_textures.set.drain().collect();
        let texture_frees: Vec<_> = self.pending_textures.free.drain().collect();
        let target = frame.texture.create_view(&wgpu::TextureViewDescriptor::default());
        let device = gfx.ctx.device();
        let queue = gfx.ctx.queue();
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("seamlit view"),
        });
        gfx.renderer
            .encode(
                &gfx.ctx,
                &mut encoder,
                &FrameDescriptor {
                    scene: &gfx.scene,
                    camera: &view,
                    settings: &frame_settings,
                    size: (width, height),
                },
                &target,
            )
            .processing()?;
        for (id, deltas) in &texture_sets {
            for delta in deltas {
                gfx.egui_renderer.update_texture(device, queue, *id, delta);
            }
        }
        let screen =
            egui_wgpu::ScreenDescriptor { size_in_pixels: [width, height], pixels_per_point: ppp };
        let extra = gfx.egui_renderer.update_buffers(device, queue, &mut encoder, &paint, &screen);
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("egui"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &target,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Load,
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    ..Default::default()
                })
                .forget_lifetime();
            gfx.egui_renderer.render(&mut pass, &paint, &screen);
        }
        let take_shot = self.screenshot_requested
            || (self.options.screenshot.is_some()
                && self.options.exit_after_frames == Some(self.frames + 1));
        let readback = (take_shot && gfx.can_copy).then(|| {
            super::capture::copy_to_buffer(device, &mut encoder, &frame.texture, width, height)
        });
        queue.submit(extra.into_iter().chain([encoder.finish()]));
        queue.present(frame);
        for id in &texture_frees {
            gfx.egui_renderer.free_texture(id);
        }
        self.frames += 1;
        if !take_shot {
            return Ok(None);
        }
        self.screenshot_requested = false;
        let image = match readback {
            Some(buffer) => super::capture::read(&gfx.ctx, buffer, gfx.config.format)?,
            // The surface cannot be copied from: render the scene (without the panel) offscreen.
            None => {
                let mut offscreen = Renderer::new(&gfx.ctx, IMAGE_FORMAT, 1).processing()?;
                offscreen.set_environment(gfx.environment.clone());
                offscreen
                    .render_to_image(
                        &gfx.ctx,
                        &FrameDescriptor {
                            scene: &gfx.scene,
                            camera: &view,
                            settings: &frame_settings,
                            size: (width, height),
                        },
                    )
                    .processing()?
            }
        };
        Ok(Some(image))
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
                    match key.physical_key {
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
            }
            WindowEvent::MouseInput { state, button, .. }
                if !(response.consumed && state == ElementState::Pressed) =>
            {
                self.held.button(button, state);
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.held.cursor_moved(Vec2::new(position.x as f32, position.y as f32));
            }
            WindowEvent::MouseWheel { delta, .. } if !response.consumed => {
                self.held.scroll += match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
            }
            WindowEvent::RedrawRequested => match self.redraw() {
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
            },
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
