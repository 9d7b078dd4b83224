//! The viewer's egui panel: processing options (which re-run the fix), shading switches,
//! the animation (which one, play, pause, scrub), lights, cameras, and the frame time.

use egui::{ComboBox, DragValue, Slider, Ui};
use glam::Vec3;
use seamlit_mesh::{Mode, Weighting};
use seamlit_render::{DebugView, Light, LightingModel};

/// Which controller moves the camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Controller {
    /// Drag to orbit the target, scroll to zoom, middle-drag to pan.
    Orbit,
    /// WASD to move, right-drag to look, Shift to go faster.
    Fps,
}

/// The animation the viewer poses the model by.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Playback {
    /// An index into the model's animations; `None`: the rest pose.
    pub animation: Option<usize>,
    /// Seconds into it.
    pub time: f32,
    /// Whether the time runs (looping at the animation's end).
    pub playing: bool,
}

impl Playback {
    /// Runs the clock `dt` seconds on while playing, looping at `duration`.
    pub(crate) fn advance(&mut self, dt: f32, duration: f32) {
        if !self.playing || self.animation.is_none() {
            return;
        }
        self.time = if duration > 0.0 { (self.time + dt) % duration } else { 0.0 };
    }
}

/// Everything the panel edits.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Processing mode.
    pub mode: Mode,
    /// Crease angle, degrees.
    pub crease_deg: f32,
    /// Normal weighting.
    pub weighting: Weighting,
    /// Lighting equation.
    pub lighting: LightingModel,
    /// `--tone-mapping`; `None`: the lighting model's usual one.
    pub tone_mapping: Option<seamlit_render::ToneMapping>,
    /// `--exposure`.
    pub exposure: f32,
    /// `--ambient`; `None`: the lighting model's usual one.
    pub ambient: Option<f32>,
    /// Normal mapping on or off.
    pub normal_mapping: bool,
    /// What the pixels show.
    pub debug_view: DebugView,
    /// TBN lines.
    pub show_tbn: bool,
    /// The lights.
    pub lights: Vec<Light>,
    /// Index of the camera in use.
    pub camera: usize,
    /// Which controller moves it.
    pub controller: Controller,
    /// The animation, its time, and whether it plays.
    pub playback: Playback,
    /// The material variant drawn (KHR_materials_variants); `None`: the default materials.
    pub variant: Option<String>,
}

impl Settings {
    /// The part of the settings that needs a new fix when it changes.
    #[must_use]
    pub(crate) fn fix_key(&self) -> (Mode, u32, Weighting) {
        (self.mode, self.crease_deg.to_bits(), self.weighting)
    }
}

/// What the panel shows but does not edit.
pub struct Readout<'a> {
    /// Camera names.
    pub cameras: &'a [String],
    /// The model's animations: name and length in seconds.
    pub animations: &'a [(String, f32)],
    /// Smoothed frame time, milliseconds.
    pub frame_ms: f32,
    /// Time of the last fix, milliseconds.
    pub fix_ms: f32,
    /// Objects and triangles of the model.
    pub objects: usize,
    /// Triangles of the model.
    pub triangles: usize,
    /// The adapter.
    pub adapter: &'a str,
    /// The last message (an error of the last fix, a screenshot written).
    pub status: &'a str,
    /// The model's materials, for the list of the glTF extensions each uses.
    pub materials: &'a [seamlit_io::Material],
    /// The models' material variants (KHR_materials_variants).
    pub variants: &'a [String],
}

/// What the user asked for with a button.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Actions {
    /// Save a screenshot.
    pub screenshot: bool,
    /// Put the camera back where the scene had it.
    pub reset_camera: bool,
}

/// Draws the panel into `ui`, editing `s`.
pub(crate) fn draw(ui: &mut Ui, s: &mut Settings, r: &Readout<'_>) -> Actions {
    let mut actions = Actions::default();
    readout(ui, r);
    ui.separator();
    processing(ui, s);
    ui.separator();
    shading(ui, s);
    ui.separator();
    if !r.animations.is_empty() {
        animation(ui, &mut s.playback, r.animations);
        ui.separator();
    }
    actions.reset_camera = camera(ui, s, r.cameras);
    ui.separator();
    lights(ui, &mut s.lights);
    ui.separator();
    if !r.variants.is_empty() {
        variants(ui, &mut s.variant, r.variants);
        ui.separator();
    }
    materials(ui, r.materials);
    ui.separator();
    if ui.button("screenshot (F12)").clicked() {
        actions.screenshot = true;
    }
    if !r.status.is_empty() {
        ui.label(r.status);
    }
    actions
}

/// The material variants (KHR_materials_variants): the default materials or one variant's.
fn variants(ui: &mut Ui, chosen: &mut Option<String>, variants: &[String]) {
    ui.strong("Material variant");
    let shown = chosen.as_deref().unwrap_or("(default)").to_owned();
    ComboBox::from_label("variant").selected_text(shown).show_ui(ui, |ui| {
        ui.selectable_value(chosen, None, "(default)");
        for name in variants {
            ui.selectable_value(chosen, Some(name.clone()), name.as_str());
        }
    });
}

/// Each material with the glTF material extensions it uses (drawn by the PBR lighting).
fn materials(ui: &mut Ui, materials: &[seamlit_io::Material]) {
    egui::CollapsingHeader::new(format!("materials ({})", materials.len())).show(ui, |ui| {
        for m in materials {
            let mut names = m.extensions.names();
            if m.unlit {
                names.insert(0, "KHR_materials_unlit");
            }
            let used = if names.is_empty() { "core".to_owned() } else { names.join(", ") };
            ui.label(format!("{}: {used}", m.name));
        }
    });
}

/// The heading, the model's size, the frame and fix times, the adapter.
fn readout(ui: &mut Ui, r: &Readout<'_>) {
    ui.heading("seamlit");
    ui.label(format!(
        "{}, {}",
        crate::table::count(r.objects, "object"),
        crate::table::count(r.triangles, "triangle")
    ));
    ui.label(format!(
        "frame {:.2} ms ({:.0} fps), fix {:.0} ms",
        r.frame_ms,
        1000.0 / r.frame_ms.max(1e-3),
        r.fix_ms
    ));
    ui.small(r.adapter);
}

/// Mode, crease angle and weighting: what re-runs the fix.
fn processing(ui: &mut Ui, s: &mut Settings) {
    ui.strong("Processing");
    ComboBox::from_label("mode").selected_text(mode_name(s.mode)).show_ui(ui, |ui| {
        for m in [Mode::Flat, Mode::Object, Mode::Model] {
            ui.selectable_value(&mut s.mode, m, mode_name(m));
        }
    });
    ui.add(Slider::new(&mut s.crease_deg, 0.0..=180.0).text("crease °"));
    ComboBox::from_label("weighting").selected_text(format!("{:?}", s.weighting)).show_ui(
        ui,
        |ui| {
            for w in [Weighting::Angle, Weighting::Area, Weighting::AngleArea, Weighting::Uniform] {
                ui.selectable_value(&mut s.weighting, w, format!("{w:?}"));
            }
        },
    );
}

/// Lighting model, normal mapping, debug view and TBN lines.
fn shading(ui: &mut Ui, s: &mut Settings) {
    ui.strong("Shading");
    ComboBox::from_label("lighting").selected_text(format!("{:?}", s.lighting)).show_ui(ui, |ui| {
        for l in [
            LightingModel::Pbr,
            LightingModel::BlinnPhong,
            LightingModel::Phong,
            LightingModel::Lambert,
            LightingModel::Gouraud,
        ] {
            ui.selectable_value(&mut s.lighting, l, format!("{l:?}"));
        }
    });
    ui.checkbox(&mut s.normal_mapping, "normal mapping");
    ComboBox::from_label("view").selected_text(format!("{:?}", s.debug_view)).show_ui(ui, |ui| {
        for v in [
            DebugView::Lit,
            DebugView::Normals,
            DebugView::Tangents,
            DebugView::BitangentSign,
            DebugView::Uvs,
            DebugView::ObjectIds,
            DebugView::LightingOnly,
            DebugView::Metallic,
            DebugView::Roughness,
            DebugView::Occlusion,
        ] {
            ui.selectable_value(&mut s.debug_view, v, format!("{v:?}"));
        }
    });
    ui.checkbox(&mut s.show_tbn, "TBN lines");
}

/// Which animation (or the rest pose), play and pause, back to the start, and the time.
fn animation(ui: &mut Ui, p: &mut Playback, animations: &[(String, f32)]) {
    ui.strong("Animation");
    let name = |i: Option<usize>| {
        i.and_then(|i| animations.get(i)).map_or("rest pose", |(n, _)| n.as_str()).to_owned()
    };
    ComboBox::from_label("animation").selected_text(name(p.animation)).show_ui(ui, |ui| {
        ui.selectable_value(&mut p.animation, None, "rest pose");
        for (i, (n, _)) in animations.iter().enumerate() {
            ui.selectable_value(&mut p.animation, Some(i), n);
        }
    });
    let duration = p.animation.and_then(|i| animations.get(i)).map_or(0.0, |a| a.1);
    p.time = p.time.min(duration);
    ui.add_enabled_ui(p.animation.is_some(), |ui| {
        ui.horizontal(|ui| {
            if ui.button(if p.playing { "pause" } else { "play" }).clicked() {
                p.playing = !p.playing;
            }
            if ui.button("start").clicked() {
                p.time = 0.0;
            }
        });
        ui.add(Slider::new(&mut p.time, 0.0..=duration).text("time (s)"));
    });
}

/// The camera among `cameras`, the controller and its keys; returns whether "reset" was
/// clicked.
fn camera(ui: &mut Ui, s: &mut Settings, cameras: &[String]) -> bool {
    ui.strong("Camera");
    ComboBox::from_label("camera")
        .selected_text(cameras.get(s.camera).map_or("-", String::as_str))
        .show_ui(ui, |ui| {
            for (i, name) in cameras.iter().enumerate() {
                ui.selectable_value(&mut s.camera, i, name);
            }
        });
    let mut reset = false;
    ui.horizontal(|ui| {
        ui.radio_value(&mut s.controller, Controller::Orbit, "orbit");
        ui.radio_value(&mut s.controller, Controller::Fps, "FPS");
        reset = ui.button("reset").clicked();
    });
    ui.small(match s.controller {
        Controller::Orbit => "drag: orbit · scroll: zoom · middle-drag: pan · Tab: FPS",
        Controller::Fps => {
            "WASD: move · E/Q: up/down · right-drag: look · Shift: fast · Tab: orbit"
        }
    });
    reset
}

/// Each light with its editor and a remove button, then buttons that add one.
fn lights(ui: &mut Ui, lights: &mut Vec<Light>) {
    ui.strong("Lights");
    let mut remove = None;
    for (i, light) in lights.iter_mut().enumerate() {
        ui.push_id(i, |ui| {
            ui.horizontal(|ui| {
                ui.label(format!("{} {}", i + 1, light_kind(light)));
                if ui.small_button("remove").clicked() {
                    remove = Some(i);
                }
            });
            edit_light(ui, light);
        });
    }
    if let Some(i) = remove {
        lights.remove(i);
    }
    ui.horizontal(|ui| {
        if ui.button("+ directional").clicked() {
            lights.push(Light::Directional {
                direction: Vec3::new(0.0, -1.0, -1.0),
                color: Vec3::ONE,
                intensity: 0.5,
            });
        }
        if ui.button("+ point").clicked() {
            lights.push(Light::Point {
                position: Vec3::new(0.0, 3.0, 3.0),
                color: Vec3::ONE,
                intensity: 0.8,
                range: 50.0,
            });
        }
    });
}

fn mode_name(m: Mode) -> &'static str {
    match m {
        Mode::Flat => "flat (Fig. 9)",
        Mode::Object => "object (Fig. 11)",
        Mode::Model => "model (Fig. 12)",
    }
}

fn light_kind(l: &Light) -> &'static str {
    match l {
        Light::Directional { .. } => "directional",
        Light::Point { .. } => "point",
        Light::Spot { .. } => "spot",
    }
}

fn vec3(ui: &mut Ui, label: &str, v: &mut Vec3, speed: f64) {
    ui.horizontal(|ui| {
        ui.label(label);
        ui.add(DragValue::new(&mut v.x).speed(speed));
        ui.add(DragValue::new(&mut v.y).speed(speed));
        ui.add(DragValue::new(&mut v.z).speed(speed));
    });
}

fn edit_light(ui: &mut Ui, light: &mut Light) {
    let (color, intensity) = match light {
        Light::Directional { direction, color, intensity } => {
            vec3(ui, "dir", direction, 0.02);
            (color, intensity)
        }
        Light::Point { position, color, intensity, range } => {
            vec3(ui, "pos", position, 0.05);
            ui.add(Slider::new(range, 0.1..=1000.0).logarithmic(true).text("range"));
            (color, intensity)
        }
        Light::Spot {
            position,
            direction,
            color,
            intensity,
            range,
            inner_cone_deg,
            outer_cone_deg,
        } => {
            vec3(ui, "pos", position, 0.05);
            vec3(ui, "dir", direction, 0.02);
            ui.add(Slider::new(range, 0.1..=1000.0).logarithmic(true).text("range"));
            ui.add(Slider::new(outer_cone_deg, 1.0..=89.0).text("outer °"));
            ui.add(Slider::new(inner_cone_deg, 0.0..=*outer_cone_deg).text("inner °"));
            (color, intensity)
        }
    };
    ui.horizontal(|ui| {
        let mut rgb = color.to_array();
        if ui.color_edit_button_rgb(&mut rgb).changed() {
            *color = Vec3::from(rgb);
        }
        ui.add(Slider::new(intensity, 0.0..=3.0).text("intensity"));
    });
}

#[cfg(test)]
mod tests {
    use super::Playback;

    #[test]
    fn playback_runs_only_while_playing_and_loops_at_the_end() {
        let mut p = Playback { animation: Some(0), time: 0.5, playing: true };
        p.advance(0.25, 1.0);
        assert!((p.time - 0.75).abs() < 1e-6, "{}", p.time);
        p.advance(0.5, 1.0);
        assert!((p.time - 0.25).abs() < 1e-6, "loops: {}", p.time);
        p.playing = false;
        p.advance(0.5, 1.0);
        assert!((p.time - 0.25).abs() < 1e-6, "paused: {}", p.time);
        let mut rest = Playback { animation: None, time: 0.0, playing: true };
        rest.advance(0.5, 1.0);
        assert_eq!(rest.time, 0.0, "the rest pose has no clock");
    }
}
