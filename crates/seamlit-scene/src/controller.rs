//! Camera controllers as pure maths: an FPS controller (WASD, mouse look, a speed modifier)
//! and an orbit controller (drag to orbit, scroll to zoom, pan). The window code turns key
//! and mouse events into the inputs here; nothing in this file knows about windows.
//!
//! Angles: `yaw` turns about world +Y (counter-clockwise seen from above), `pitch` tilts up;
//! yaw = pitch = 0 looks down world -Z.

use glam::{Mat4, Vec2, Vec3};

use crate::camera::{Camera, look_at_safe};

/// Largest pitch either controller allows, degrees (just short of straight up or down).
pub const MAX_PITCH_DEG: f32 = 89.0;

/// The unit view direction for a yaw and pitch in degrees.
#[must_use]
pub fn direction(yaw_deg: f32, pitch_deg: f32) -> Vec3 {
    let (sy, cy) = yaw_deg.to_radians().sin_cos();
    let (sp, cp) = pitch_deg.to_radians().sin_cos();
    Vec3::new(-sy * cp, sp, -cy * cp)
}

/// Yaw and pitch (degrees) of a view direction; `(0, 0)` for a zero vector.
#[must_use]
pub fn yaw_pitch(direction: Vec3) -> (f32, f32) {
    let Some(d) = direction.try_normalize() else { return (0.0, 0.0) };
    let pitch = d.y.clamp(-1.0, 1.0).asin().to_degrees();
    let yaw =
        if d.x.abs() < 1e-7 && d.z.abs() < 1e-7 { 0.0 } else { (-d.x).atan2(-d.z).to_degrees() };
    (yaw, pitch.clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG))
}

/// The keys and mouse motion an FPS controller reads in one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FpsInput {
    /// W: move along the view direction.
    pub forward: bool,
    /// S: move against the view direction.
    pub back: bool,
    /// A: move left.
    pub left: bool,
    /// D: move right.
    pub right: bool,
    /// E / Space: move up (world +Y).
    pub up: bool,
    /// Q / Ctrl: move down.
    pub down: bool,
    /// Shift: move `fast_multiplier` times faster.
    pub fast: bool,
    /// Mouse motion in pixels since the last frame (+x right, +y down, as windows report it).
    pub mouse_delta: Vec2,
}

/// A first-person camera: position, yaw and pitch, moved by [`FpsInput`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FpsController {
    /// Eye position, world space.
    pub position: Vec3,
    /// Degrees about +Y; 0 looks down -Z.
    pub yaw_deg: f32,
    /// Degrees up from the horizon, within +-[`MAX_PITCH_DEG`].
    pub pitch_deg: f32,
    /// Walking speed, world units per second.
    pub speed: f32,
    /// Speed factor while the modifier is held.
    pub fast_multiplier: f32,
    /// Degrees turned per pixel of mouse motion.
    pub sensitivity_deg_per_px: f32,
}

impl FpsController {
    /// A controller at `eye` looking at `target`, moving at `speed` units per second.
    #[must_use]
    pub fn looking_at(eye: Vec3, target: Vec3, speed: f32) -> Self {
        let (yaw_deg, pitch_deg) = yaw_pitch(target - eye);
        Self {
            position: eye,
            yaw_deg,
            pitch_deg,
            speed,
            fast_multiplier: 4.0,
            sensitivity_deg_per_px: 0.15,
        }
    }

    /// The unit view direction.
    #[must_use]
    pub fn forward(&self) -> Vec3 {
        direction(self.yaw_deg, self.pitch_deg)
    }

    /// The unit direction to the right, horizontal.
    #[must_use]
    pub fn right(&self) -> Vec3 {
        direction(self.yaw_deg - 90.0, 0.0)
    }

    /// Applies one frame of input lasting `dt` seconds: mouse look first, then movement
    /// along the new view direction (diagonal moves are not faster than straight ones).
    pub fn update(&mut self, input: &FpsInput, dt: f32) {
        let d = input.mouse_delta * self.sensitivity_deg_per_px;
        self.yaw_deg = (self.yaw_deg - d.x).rem_euclid(360.0);
        self.pitch_deg = (self.pitch_deg - d.y).clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG);
        let axis = |plus: bool, minus: bool| f32::from(u8::from(plus)) - f32::from(u8::from(minus));
        let wish = self.forward() * axis(input.forward, input.back)
            + self.right() * axis(input.right, input.left)
            + Vec3::Y * axis(input.up, input.down);
        let Some(dir) = wish.try_normalize() else { return };
        let speed = if input.fast { self.speed * self.fast_multiplier } else { self.speed };
        if dt.is_finite() && dt > 0.0 {
            self.position += dir * speed * dt;
        }
    }

    /// The world-to-view matrix.
    #[must_use]
    pub fn view_matrix(&self) -> Mat4 {
        look_at_safe(self.position, self.position + self.forward(), Vec3::Y)
    }

    /// Writes the controller's pose into `camera` (position and target one unit ahead), keeping
    /// its name, field of view and clip planes.
    pub fn apply_to(&self, camera: &mut Camera) {
        camera.position = self.position;
        camera.target = self.position + self.forward();
        camera.up = Vec3::Y;
    }
}

/// A camera circling a target: drag to orbit, scroll to zoom, pan to move the target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitController {
    /// The point orbited, world space.
    pub target: Vec3,
    /// Distance from the eye to the target, at least `min_distance`.
    pub distance: f32,
    /// Degrees about +Y of the view direction; 0 looks down -Z.
    pub yaw_deg: f32,
    /// Degrees up of the view direction (negative: looking down on the target).
    pub pitch_deg: f32,
    /// Degrees turned per pixel dragged.
    pub sensitivity_deg_per_px: f32,
    /// The closest the eye may come to the target.
    pub min_distance: f32,
}

impl OrbitController {
    /// A controller whose eye is at `eye`, orbiting `target`.
    #[must_use]
    pub fn looking_at(eye: Vec3, target: Vec3) -> Self {
        let (yaw_deg, pitch_deg) = yaw_pitch(target - eye);
        let distance = eye.distance(target).max(1e-4);
        Self {
            target,
            distance,
            yaw_deg,
            pitch_deg,
            sensitivity_deg_per_px: 0.3,
            min_distance: distance * 1e-3,
        }
    }

    /// The eye position.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        self.target - direction(self.yaw_deg, self.pitch_deg) * self.distance
    }

    /// Orbits by a mouse drag of `delta_px` pixels: dragging right swings the camera to the
    /// left around the target (the model seems to turn right), dragging down raises it.
    pub fn rotate(&mut self, delta_px: Vec2) {
        let d = delta_px * self.sensitivity_deg_per_px;
        self.yaw_deg = (self.yaw_deg - d.x).rem_euclid(360.0);
        self.pitch_deg = (self.pitch_deg - d.y).clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG);
    }

    /// Zooms by `steps` scroll steps: each step up brings the eye 10% closer.
    pub fn zoom(&mut self, steps: f32) {
        if steps.is_finite() {
            self.distance = (self.distance * 0.9f32.powf(steps)).max(self.min_distance);
        }
    }

    /// Pans by a drag of `delta_px` pixels in a viewport `viewport_height_px` tall seen with
    /// a vertical field of view of `fov_y_deg`: the point under the cursor stays under it.
    pub fn pan(&mut self, delta_px: Vec2, viewport_height_px: f32, fov_y_deg: f32) {
        if viewport_height_px.is_nan() || viewport_height_px <= 0.0 {
            return;
        }
        let forward = direction(self.yaw_deg, self.pitch_deg);
        let right = forward.cross(Vec3::Y).try_normalize().unwrap_or(Vec3::X);
        let up = right.cross(forward);
        let units_per_px =
            2.0 * self.distance * (fov_y_deg.to_radians() * 0.5).tan() / viewport_height_px;
        self.target += (-right * delta_px.x + up * delta_px.y) * units_per_px;
    }

    /// The world-to-view matrix.
    #[must_use]
    pub fn view_matrix(&self) -> Mat4 {
        look_at_safe(self.eye(), self.target, Vec3::Y)
    }

    /// Writes the controller's pose into `camera`, keeping its name, field of view and clip
    /// planes.
    pub fn apply_to(&self, camera: &mut Camera) {
        camera.position = self.eye();
        camera.target = self.target;
        camera.up = Vec3::Y;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-4
    }

    #[test]
    fn yaw_and_pitch_name_the_expected_directions() {
        assert!(close(direction(0.0, 0.0), Vec3::NEG_Z));
        assert!(close(direction(90.0, 0.0), Vec3::NEG_X));
        assert!(close(direction(-90.0, 0.0), Vec3::X));
        assert!(close(direction(0.0, 90.0), Vec3::Y));
        let (yaw, pitch) = yaw_pitch(Vec3::new(-1.0, 1.0, 0.0));
        assert!((yaw - 90.0).abs() < 1e-4 && (pitch - 45.0).abs() < 1e-4, "{yaw} {pitch}");
    }

    #[test]
    fn fps_w_walks_forward_and_shift_is_faster() {
        let mut c = FpsController::looking_at(Vec3::ZERO, Vec3::NEG_Z, 2.0);
        c.update(&FpsInput { forward: true, ..FpsInput::default() }, 0.5);
        assert!(close(c.position, Vec3::new(0.0, 0.0, -1.0)), "{}", c.position);
        c.update(&FpsInput { forward: true, fast: true, ..FpsInput::default() }, 0.5);
        assert!(close(c.position, Vec3::new(0.0, 0.0, -5.0)), "{}", c.position);
    }

    #[test]
    fn fps_strafes_right_and_diagonals_are_not_faster() {
        let mut c = FpsController::looking_at(Vec3::ZERO, Vec3::NEG_Z, 1.0);
        c.update(&FpsInput { right: true, ..FpsInput::default() }, 1.0);
        assert!(close(c.position, Vec3::X), "{}", c.position);
        let mut d = FpsController::looking_at(Vec3::ZERO, Vec3::NEG_Z, 1.0);
        d.update(&FpsInput { forward: true, left: true, ..FpsInput::default() }, 1.0);
        assert!((d.position.length() - 1.0).abs() < 1e-5);
        assert!(close(d.position, Vec3::new(-1.0, 0.0, -1.0) / 2f32.sqrt()), "{}", d.position);
        // Opposite keys cancel.
        let mut e = FpsController::looking_at(Vec3::ZERO, Vec3::NEG_Z, 1.0);
        e.update(&FpsInput { forward: true, back: true, ..FpsInput::default() }, 1.0);
        assert_eq!(e.position, Vec3::ZERO);
    }

    #[test]
    fn fps_mouse_right_turns_right_and_pitch_is_clamped() {
        let mut c = FpsController::looking_at(Vec3::ZERO, Vec3::NEG_Z, 1.0);
        c.sensitivity_deg_per_px = 1.0;
        c.update(&FpsInput { mouse_delta: Vec2::new(90.0, 0.0), ..FpsInput::default() }, 0.0);
        assert!(close(c.forward(), Vec3::X), "{}", c.forward());
        c.update(&FpsInput { mouse_delta: Vec2::new(0.0, -1000.0), ..FpsInput::default() }, 0.0);
        assert_eq!(c.pitch_deg, MAX_PITCH_DEG);
        assert!(c.view_matrix().is_finite());
    }

    #[test]
    fn orbit_round_trips_its_eye_and_keeps_its_distance_while_rotating() {
        let eye = Vec3::new(3.0, 2.0, 5.0);
        let target = Vec3::new(1.0, 0.5, -1.0);
        let mut o = OrbitController::looking_at(eye, target);
        assert!(close(o.eye(), eye), "{}", o.eye());
        o.rotate(Vec2::new(123.0, -40.0));
        assert!((o.eye().distance(target) - eye.distance(target)).abs() < 1e-4);
        assert_eq!(o.target, target);
    }

    #[test]
    fn orbit_drag_right_swings_the_eye_to_the_left() {
        let mut o = OrbitController::looking_at(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO);
        o.sensitivity_deg_per_px = 1.0;
        o.rotate(Vec2::new(90.0, 0.0));
        // Looking down -Z from +Z, the camera's left is -X.
        assert!(close(o.eye(), Vec3::new(-10.0, 0.0, 0.0)), "{}", o.eye());
    }

    #[test]
    fn orbit_zoom_scales_distance_and_respects_the_minimum() {
        let mut o = OrbitController::looking_at(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO);
        o.zoom(1.0);
        assert!((o.distance - 9.0).abs() < 1e-5);
        o.zoom(-1.0);
        assert!((o.distance - 10.0).abs() < 1e-4);
        o.zoom(1e6);
        assert_eq!(o.distance, o.min_distance);
    }

    #[test]
    fn orbit_pan_keeps_the_point_under_the_cursor() {
        // Eye at +Z looking at the origin, 90 degree fov, 100 px tall: at distance 10 the
        // view spans 20 units, 0.2 units per pixel. Dragging 10 px right moves the target 2
        // units left, so the world moves right with the cursor.
        let mut o = OrbitController::looking_at(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO);
        o.pan(Vec2::new(10.0, 0.0), 100.0, 90.0);
        assert!(close(o.target, Vec3::new(-2.0, 0.0, 0.0)), "{}", o.target);
        o.pan(Vec2::new(0.0, 10.0), 100.0, 90.0);
        assert!(close(o.target, Vec3::new(-2.0, 2.0, 0.0)), "{}", o.target);
        o.pan(Vec2::ONE, 0.0, 90.0);
        assert!(close(o.target, Vec3::new(-2.0, 2.0, 0.0)));
    }
}
