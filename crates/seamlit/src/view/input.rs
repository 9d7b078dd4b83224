//! Keys and mouse buttons held in the viewer, turned into camera controller inputs.

use glam::Vec2;
use seamlit_scene::FpsInput;
use winit::event::{ElementState, MouseButton};
use winit::keyboard::{KeyCode, PhysicalKey};

/// What is held down, and the mouse motion gathered since the last frame.
#[derive(Debug, Default)]
pub struct Held {
    keys: Vec<KeyCode>,
    /// Left button: orbit.
    pub left: bool,
    /// Right button: FPS mouse look.
    pub right: bool,
    /// Middle button: pan.
    pub middle: bool,
    /// Last cursor position, pixels.
    pub cursor: Option<Vec2>,
    /// Cursor motion since the last frame, pixels.
    pub motion: Vec2,
    /// Scroll since the last frame, in steps (positive: away from the user, zoom in).
    pub scroll: f32,
}

impl Held {
    /// Records a key press or release.
    pub(crate) fn key(&mut self, key: PhysicalKey, state: ElementState) {
        let PhysicalKey::Code(code) = key else { return };
        match state {
            ElementState::Pressed if !self.keys.contains(&code) => self.keys.push(code),
            ElementState::Released => self.keys.retain(|k| *k != code),
            ElementState::Pressed => {}
        }
    }

    /// Records a mouse button.
    pub(crate) fn button(&mut self, button: MouseButton, state: ElementState) {
        let down = state == ElementState::Pressed;
        match button {
            MouseButton::Left => self.left = down,
            MouseButton::Right => self.right = down,
            MouseButton::Middle => self.middle = down,
            _ => {}
        }
    }

    /// Records a cursor position.
    pub(crate) fn cursor_moved(&mut self, to: Vec2) {
        if let Some(from) = self.cursor {
            self.motion += to - from;
        }
        self.cursor = Some(to);
    }

    /// Whether a key is held.
    #[must_use]
    pub(crate) fn is_down(&self, code: KeyCode) -> bool {
        self.keys.contains(&code)
    }

    /// The FPS controller's input for this frame: WASD, E/Space up, Q/Ctrl down, Shift fast,
    /// mouse look while the right button is held.
    #[must_use]
    pub(crate) fn fps_input(&self) -> FpsInput {
        let any = |codes: &[KeyCode]| codes.iter().any(|c| self.is_down(*c));
        FpsInput {
            forward: any(&[KeyCode::KeyW, KeyCode::ArrowUp]),
            back: any(&[KeyCode::KeyS, KeyCode::ArrowDown]),
            left: any(&[KeyCode::KeyA, KeyCode::ArrowLeft]),
            right: any(&[KeyCode::KeyD, KeyCode::ArrowRight]),
            up: any(&[KeyCode::KeyE, KeyCode::Space]),
            down: any(&[KeyCode::KeyQ, KeyCode::ControlLeft]),
            fast: any(&[KeyCode::ShiftLeft, KeyCode::ShiftRight]),
            mouse_delta: if self.right { self.motion } else { Vec2::ZERO },
        }
    }

    /// Forgets the motion and scroll of the frame just drawn.
    pub(crate) fn end_frame(&mut self) {
        self.motion = Vec2::ZERO;
        self.scroll = 0.0;
    }

    /// Releases everything (when the window loses focus).
    pub(crate) fn clear(&mut self) {
        *self = Self { cursor: self.cursor, ..Self::default() };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn held_keys_and_right_drag_become_fps_input() {
        let mut h = Held::default();
        h.key(PhysicalKey::Code(KeyCode::KeyW), ElementState::Pressed);
        h.key(PhysicalKey::Code(KeyCode::ShiftLeft), ElementState::Pressed);
        h.cursor_moved(Vec2::new(10.0, 10.0));
        h.cursor_moved(Vec2::new(15.0, 8.0));
        let i = h.fps_input();
        assert!(i.forward && i.fast && !i.back);
        assert_eq!(i.mouse_delta, Vec2::ZERO, "no look without the right button");
        h.button(MouseButton::Right, ElementState::Pressed);
        assert_eq!(h.fps_input().mouse_delta, Vec2::new(5.0, -2.0));
        h.end_frame();
        assert_eq!(h.fps_input().mouse_delta, Vec2::ZERO);
        h.key(PhysicalKey::Code(KeyCode::KeyW), ElementState::Released);
        assert!(!h.fps_input().forward);
    }
}
