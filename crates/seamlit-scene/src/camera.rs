//! Perspective cameras: a named eye, target and field of view, turned into the view and
//! projection matrices the renderer takes; and the default camera that frames a model.

use glam::{Mat4, Vec3, Vec4};
use seamlit_render::CameraView;

/// How much of the image, each way, the default framing lets the model's bounds take.
pub const FRAME_FILL: f32 = 0.9;

/// Axis-aligned bounds in world space: `(min, max)`.
pub type Bounds = (Vec3, Vec3);

/// Which way a model faces, for the default camera ([`Camera::framing_facing`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Facing {
    /// +Z: glTF's convention (and VRM 1.0's).
    #[default]
    PlusZ,
    /// -Z: VRM 0.x avatars.
    MinusZ,
}

/// A named perspective camera looking from `position` at `target`.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// The name scenes and the command line select it by.
    pub name: String,
    /// Eye position, world space.
    pub position: Vec3,
    /// The point looked at, world space.
    pub target: Vec3,
    /// The up direction (need not be normalised or orthogonal to the view direction).
    pub up: Vec3,
    /// Vertical field of view, degrees, in (0, 180).
    pub fov_y_deg: f32,
    /// Near clip distance; `None` derives it from the scene's bounds.
    pub near: Option<f32>,
    /// Far clip distance; `None` derives it from the scene's bounds.
    pub far: Option<f32>,
}

/// The field of view of the default camera, degrees.
pub const DEFAULT_FOV_Y_DEG: f32 = 40.0;

impl Camera {
    /// A camera at `position` looking at `target`, Y up, with the default field of view and
    /// clip planes derived from the scene.
    #[must_use]
    pub fn look_at(name: impl Into<String>, position: Vec3, target: Vec3) -> Self {
        Self {
            name: name.into(),
            position,
            target,
            up: Vec3::Y,
            fov_y_deg: DEFAULT_FOV_Y_DEG,
            near: None,
            far: None,
        }
    }

    /// The default camera for a model with these bounds: a three-quarter view (from the front,
    /// +Z, 35 degrees to the right and 20 degrees above), as close as it can be while the eight
    /// corners of the bounds stay inside the middle [`FRAME_FILL`] of the image of aspect ratio
    /// `aspect` (width / height) both ways, and panned so that they sit centred in it. The
    /// distance and the pan are solved exactly for the corners (a bisection on the distance;
    /// the pan is the middle of the offsets that fit), as glTF viewers frame a model.
    #[must_use]
    pub fn framing(bounds: Bounds, aspect: f32) -> Self {
        Self::framing_facing(bounds, aspect, Facing::PlusZ)
    }

    /// [`Camera::framing`] for a model that faces `facing`: the same three-quarter view of its
    /// front (for [`Facing::MinusZ`], from -Z, 35 degrees to the model's right), as three-vrm
    /// turns a VRM 0.x avatar, which faces -Z by that version's convention, to face the viewer.
    #[must_use]
    pub fn framing_facing(bounds: Bounds, aspect: f32, facing: Facing) -> Self {
        let (min, max) = bounds;
        let center = (min + max) * 0.5;
        let (azimuth, elevation) = (35f32.to_radians(), 20f32.to_radians());
        let turn = match facing {
            Facing::PlusZ => 1.0,
            Facing::MinusZ => -1.0,
        };
        let back = Vec3::new(
            turn * azimuth.sin() * elevation.cos(),
            elevation.sin(),
            turn * azimuth.cos() * elevation.cos(),
        );
        let forward = -back;
        let right = forward.cross(Vec3::Y).normalize();
        let up = right.cross(forward);
        let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 1.0 };
        let tan_y = (DEFAULT_FOV_Y_DEG.to_radians() * 0.5).tan() * FRAME_FILL;
        let tan_x = tan_y * aspect;
        // Each corner in the camera's axes, relative to the centre: (right, up, depth).
        let corners: Vec<Vec3> = (0..8)
            .map(|i| {
                let c = Vec3::new(
                    if i & 1 == 0 { min.x } else { max.x },
                    if i & 2 == 0 { min.y } else { max.y },
                    if i & 4 == 0 { min.z } else { max.z },
                ) - center;
                Vec3::new(c.dot(right), c.dot(up), c.dot(forward))
            })
            .collect();
        // At distance d, the pan offsets along one axis that keep every corner inside:
        // |a - offset| <= (d + depth) * tan for each corner.
        let fit = |d: f32, axis: fn(Vec3) -> f32, tan: f32| {
            corners.iter().fold((f32::NEG_INFINITY, f32::INFINITY), |(lo, hi), &c| {
                let reach = (d + c.z) * tan;
                (lo.max(axis(c) - reach), hi.min(axis(c) + reach))
            })
        };
        let fits = |d: f32| {
            let (x, y) = (fit(d, |c| c.x, tan_x), fit(d, |c| c.y, tan_y));
            corners.iter().all(|c| d + c.z > 0.0) && x.0 <= x.1 && y.0 <= y.1
        };
        let radius = ((max - min).length() * 0.5).max(1e-6);
        // The sphere around the bounds fits at radius / sin(half angle): an upper bound.
        let (mut near, mut far) = (0.0, radius / tan_x.min(tan_y).atan().sin() + radius);
        for _ in 0..60 {
            let mid = 0.5 * (near + far);
            if fits(mid) { far = mid } else { near = mid }
        }
        // The pan that centres the corners' projected extent on one axis: their projections
        // (a - offset) / (d + depth) fall as the offset grows, so the sum of the largest and
        // the smallest has one zero, between the smallest and the largest a.
        let centre = |d: f32, axis: fn(Vec3) -> f32| {
            let spread = |o: f32| {
                let p = corners.iter().map(|&c| (axis(c) - o) / (d + c.z));
                let (lo, hi) =
                    p.fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
                lo + hi
            };
            let (mut lo, mut hi) =
                corners.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), &c| {
                    (l.min(axis(c)), h.max(axis(c)))
                });
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if spread(mid) > 0.0 { lo = mid } else { hi = mid }
            }
            0.5 * (lo + hi)
        };
        let pan = right * centre(far, |c| c.x) + up * centre(far, |c| c.y);
        let target = center + pan;
        Self::look_at("default", target - forward * far, target)
    }

    /// The world-to-view matrix (right-handed, looking down -Z).
    #[must_use]
    pub fn view_matrix(&self) -> Mat4 {
        look_at_safe(self.position, self.target, self.up)
    }

    /// Near and far clip distances: the camera's own, or (for those it leaves open) planes
    /// that enclose `bounds` with room to spare; without bounds, 0.01 and 1000.
    #[must_use]
    pub fn clip_planes(&self, bounds: Option<Bounds>) -> (f32, f32) {
        let (auto_near, auto_far) = match bounds {
            Some((min, max)) => {
                let center = (min + max) * 0.5;
                let radius = ((max - min).length() * 0.5).max(1e-6);
                let far = (self.position.distance(center) + radius) * 2.0;
                (far / 2000.0, far)
            }
            None => (0.01, 1000.0),
        };
        let near = self.near.unwrap_or(auto_near);
        let far = self.far.unwrap_or(auto_far).max(near * 2.0);
        (near, far)
    }

    /// The matrices for an image of aspect ratio `aspect` (width / height), wgpu depth range
    /// 0..1.
    #[must_use]
    pub fn view(&self, aspect: f32, bounds: Option<Bounds>) -> CameraView {
        let (near, far) = self.clip_planes(bounds);
        let aspect = if aspect.is_finite() && aspect > 0.0 { aspect } else { 1.0 };
        CameraView {
            view: self.view_matrix(),
            projection: perspective_rh(self.fov_y_deg.to_radians(), aspect, near, far),
            eye: self.position,
        }
    }
}

/// `Mat4::look_at_rh` that tolerates an up vector parallel to the view direction (it picks
/// another up) and an eye on the target (it looks down -Z).
#[must_use]
pub fn look_at_safe(eye: Vec3, target: Vec3, up: Vec3) -> Mat4 {
    let dir = (target - eye).try_normalize().unwrap_or(Vec3::NEG_Z);
    let up = up.try_normalize().unwrap_or(Vec3::Y);
    let up = if dir.cross(up).length_squared() < 1e-8 {
        if dir.y.abs() > 0.9 { Vec3::Z } else { Vec3::Y }
    } else {
        up
    };
    look_to_rh(eye, dir, up)
}

/// A right-handed view matrix at `eye` looking along `dir` (both unit-free; `dir` and `up`
/// must not be parallel): the camera looks down its -Z axis with `up` toward +Y.
#[must_use]
pub fn look_to_rh(eye: Vec3, dir: Vec3, up: Vec3) -> Mat4 {
    let f = dir.normalize();
    let s = f.cross(up).normalize();
    let u = s.cross(f);
    Mat4::from_cols(
        Vec4::new(s.x, u.x, -f.x, 0.0),
        Vec4::new(s.y, u.y, -f.y, 0.0),
        Vec4::new(s.z, u.z, -f.z, 0.0),
        Vec4::new(-eye.dot(s), -eye.dot(u), eye.dot(f), 1.0),
    )
}

/// A right-handed perspective projection with a vertical field of view `fov_y` (radians),
/// mapping view depth `-near..-far` to wgpu's clip depth `0..1`.
#[must_use]
pub fn perspective_rh(fov_y: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    let h = 1.0 / (fov_y * 0.5).tan();
    let w = h / aspect;
    let r = far / (near - far);
    Mat4::from_cols(
        Vec4::new(w, 0.0, 0.0, 0.0),
        Vec4::new(0.0, h, 0.0, 0.0),
        Vec4::new(0.0, 0.0, r, -1.0),
        Vec4::new(0.0, 0.0, r * near, 0.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn project(view: &CameraView, p: Vec3) -> Vec3 {
        (view.projection * view.view).project_point3(p)
    }

    #[test]
    fn framing_puts_every_corner_of_the_bounds_inside_the_image() {
        let bounds = (Vec3::new(-3.0, 0.0, -2.0), Vec3::new(3.0, 3.0, 2.0));
        for aspect in [0.5, 1.0, 16.0 / 9.0] {
            let camera = Camera::framing(bounds, aspect);
            let view = camera.view(aspect, Some(bounds));
            for i in 0..8 {
                let corner = Vec3::new(
                    if i & 1 == 0 { bounds.0.x } else { bounds.1.x },
                    if i & 2 == 0 { bounds.0.y } else { bounds.1.y },
                    if i & 4 == 0 { bounds.0.z } else { bounds.1.z },
                );
                let ndc = project(&view, corner);
                assert!(ndc.x.abs() < 1.0 && ndc.y.abs() < 1.0, "{aspect}: {corner} -> {ndc}");
                assert!(ndc.z > 0.0 && ndc.z < 1.0, "{aspect}: depth {}", ndc.z);
            }
        }
    }

    /// The framing is tight: the corners' extent reaches the frame's fill on one axis and is
    /// centred on both.
    #[test]
    fn framing_is_tight_and_centred() {
        let boxes = [
            (Vec3::new(-3.0, 0.0, -2.0), Vec3::new(3.0, 3.0, 2.0)),
            // Long and low, like a fox or a truck.
            (Vec3::new(-0.2, 0.0, -1.5), Vec3::new(0.2, 0.6, 1.5)),
            (Vec3::splat(10.0), Vec3::new(10.5, 14.0, 10.5)),
        ];
        for bounds in boxes {
            for aspect in [0.5, 1.0, 16.0 / 9.0] {
                let camera = Camera::framing(bounds, aspect);
                let view = camera.view(aspect, Some(bounds));
                let ndc: Vec<Vec3> = (0..8)
                    .map(|i| {
                        project(
                            &view,
                            Vec3::new(
                                if i & 1 == 0 { bounds.0.x } else { bounds.1.x },
                                if i & 2 == 0 { bounds.0.y } else { bounds.1.y },
                                if i & 4 == 0 { bounds.0.z } else { bounds.1.z },
                            ),
                        )
                    })
                    .collect();
                let lo = ndc.iter().fold(Vec3::splat(f32::INFINITY), |a, &b| a.min(b));
                let hi = ndc.iter().fold(Vec3::splat(f32::NEG_INFINITY), |a, &b| a.max(b));
                let reach = hi.x.max(-lo.x).max(hi.y).max(-lo.y);
                assert!((reach - FRAME_FILL).abs() < 1e-3, "{bounds:?} {aspect}: reach {reach}");
                assert!((lo.x + hi.x).abs() < 1e-3, "{bounds:?} {aspect}: x {lo} {hi}");
                assert!((lo.y + hi.y).abs() < 1e-3, "{bounds:?} {aspect}: y {lo} {hi}");
            }
        }
    }

    #[test]
    fn the_target_projects_to_the_image_centre() {
        let camera = Camera::look_at("c", Vec3::new(4.0, 5.0, 6.0), Vec3::new(1.0, 0.0, -1.0));
        let ndc = project(&camera.view(1.5, None), camera.target);
        assert!(ndc.x.abs() < 1e-5 && ndc.y.abs() < 1e-5, "{ndc}");
    }

    #[test]
    fn looking_straight_down_still_gives_a_finite_view() {
        let m = look_at_safe(Vec3::new(0.0, 10.0, 0.0), Vec3::ZERO, Vec3::Y);
        assert!(m.is_finite());
        // The target is straight ahead: on the view's -Z axis.
        let p = m.transform_point3(Vec3::ZERO);
        assert!((p - Vec3::new(0.0, 0.0, -10.0)).length() < 1e-5, "{p}");
    }

    #[test]
    fn the_projection_maps_near_to_depth_0_and_far_to_depth_1() {
        let p = perspective_rh(90f32.to_radians(), 2.0, 0.5, 10.0);
        assert!((p.project_point3(Vec3::new(0.0, 0.0, -0.5)).z).abs() < 1e-6);
        assert!((p.project_point3(Vec3::new(0.0, 0.0, -10.0)).z - 1.0).abs() < 1e-6);
        // 90 degrees vertical: y = -z reaches the top edge; aspect 2: x = -2z the right edge.
        let q = p.project_point3(Vec3::new(4.0, 2.0, -2.0));
        assert!((q.x - 1.0).abs() < 1e-6 && (q.y - 1.0).abs() < 1e-6, "{q}");
    }

    #[test]
    fn the_view_matrix_maps_the_eye_to_the_origin_and_right_to_plus_x() {
        let m = look_to_rh(Vec3::new(1.0, 2.0, 3.0), Vec3::NEG_Z, Vec3::Y);
        assert!((m.transform_point3(Vec3::new(1.0, 2.0, 3.0))).length() < 1e-6);
        let p = m.transform_point3(Vec3::new(2.0, 3.0, 1.0));
        assert!((p - Vec3::new(1.0, 1.0, -2.0)).length() < 1e-6, "{p}");
    }

    #[test]
    fn explicit_clip_planes_win_over_derived_ones() {
        let mut camera = Camera::look_at("c", Vec3::Z * 5.0, Vec3::ZERO);
        camera.near = Some(0.5);
        camera.far = Some(50.0);
        assert_eq!(camera.clip_planes(Some((Vec3::splat(-1.0), Vec3::ONE))), (0.5, 50.0));
        camera.far = None;
        let (near, far) = camera.clip_planes(Some((Vec3::splat(-1.0), Vec3::ONE)));
        assert_eq!(near, 0.5);
        // Eye 5 from the centre, radius sqrt(3): the far plane lies beyond the farthest point.
        assert!(far > 5.0 + 3f32.sqrt(), "{far}");
    }
}
