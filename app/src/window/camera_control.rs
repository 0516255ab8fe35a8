//! Camera control as in common 3D tools: fly with the right mouse button held (look around,
//! WASD / QE to move, wheel changes speed), orbit around a pivot with the middle button or
//! Alt + left button (wheel dollies), `F` frames the whole scene.

use glam::{Vec2, Vec3};
use render_core::geom::{Aabb, Camera};

use crate::scene_source::frame_scene;

/// Which drag is in progress.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drag {
    None,
    Fly,
    Orbit,
}

/// Movement keys currently held.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MoveKeys {
    pub forward: bool,
    pub back: bool,
    pub left: bool,
    pub right: bool,
    pub up: bool,
    pub down: bool,
    pub fast: bool,
}

/// Long-lived camera state: the camera plus the pivot and speed the user controls.
#[derive(Clone, Debug)]
pub struct CameraController {
    pub camera: Camera,
    /// Distance from the eye to the orbit pivot along the view direction.
    pub orbit_distance_m: f32,
    pub fly_speed_m_per_s: f32,
    pub drag: Drag,
}

/// Radians of rotation per pixel of mouse movement.
const LOOK_RAD_PER_PX: f32 = 0.004;
/// Pitch stays this far from straight up or down, so the view never flips.
const MAX_PITCH_RAD: f32 = 1.55;

impl CameraController {
    pub fn new(camera: Camera, orbit_distance_m: f32, scene_size_m: f32) -> Self {
        Self {
            camera,
            orbit_distance_m: orbit_distance_m.max(0.1),
            fly_speed_m_per_s: (scene_size_m * 0.05).clamp(1.0, 500.0),
            drag: Drag::None,
        }
    }

    /// A controller looking at the whole scene.
    pub fn framing(bounds: &Aabb, aspect: f32, fov_y_rad: f32) -> Self {
        let camera = frame_scene(bounds, aspect, fov_y_rad);
        let distance = (bounds.center() - camera.eye).length();
        Self::new(camera, distance, bounds.diagonal_length())
    }

    /// `F`: frame the whole scene, keeping the field of view.
    pub fn frame(&mut self, bounds: &Aabb, aspect: f32) {
        let speed = self.fly_speed_m_per_s;
        *self = Self::framing(bounds, aspect, self.camera.fov_y_rad);
        self.fly_speed_m_per_s = speed;
    }

    pub fn pivot(&self) -> Vec3 {
        self.camera.eye + self.camera.forward * self.orbit_distance_m
    }

    fn yaw_pitch(&self) -> (f32, f32) {
        let f = self.camera.forward;
        (f.z.atan2(f.x), f.y.clamp(-1.0, 1.0).asin())
    }

    fn set_yaw_pitch(&mut self, yaw: f32, pitch: f32) {
        let pitch = pitch.clamp(-MAX_PITCH_RAD, MAX_PITCH_RAD);
        self.camera.forward = Vec3::new(
            pitch.cos() * yaw.cos(),
            pitch.sin(),
            pitch.cos() * yaw.sin(),
        );
    }

    /// Mouse moved by `delta_px` during a drag.
    pub fn on_mouse_drag(&mut self, delta_px: Vec2) {
        if !delta_px.is_finite() {
            return;
        }
        let (yaw, pitch) = self.yaw_pitch();
        let (d_yaw, d_pitch) = (delta_px.x * LOOK_RAD_PER_PX, -delta_px.y * LOOK_RAD_PER_PX);
        match self.drag {
            Drag::None => {}
            Drag::Fly => self.set_yaw_pitch(yaw + d_yaw, pitch + d_pitch),
            Drag::Orbit => {
                let pivot = self.pivot();
                self.set_yaw_pitch(yaw + d_yaw, pitch + d_pitch);
                self.camera.eye = pivot - self.camera.forward * self.orbit_distance_m;
            }
        }
    }

    /// Wheel turned by `notches` (positive: away from the user).
    pub fn on_wheel(&mut self, notches: f32) {
        if !notches.is_finite() {
            return;
        }
        let factor = 1.2f32.powf(notches);
        if self.drag == Drag::Fly {
            self.fly_speed_m_per_s = (self.fly_speed_m_per_s * factor).clamp(0.05, 5000.0);
        } else {
            let pivot = self.pivot();
            self.orbit_distance_m = (self.orbit_distance_m / factor).clamp(0.1, 1.0e6);
            self.camera.eye = pivot - self.camera.forward * self.orbit_distance_m;
        }
    }

    /// Moves the eye for `dt_s` seconds of held keys (only while flying).
    pub fn update(&mut self, dt_s: f32, keys: MoveKeys) {
        if self.drag != Drag::Fly || !(dt_s.is_finite() && dt_s > 0.0) {
            return;
        }
        let (right, _) = self.camera.basis();
        let axis = |pos: bool, neg: bool| f32::from(u8::from(pos)) - f32::from(u8::from(neg));
        let direction = self.camera.forward * axis(keys.forward, keys.back)
            + right * axis(keys.right, keys.left)
            + Vec3::Y * axis(keys.up, keys.down);
        let speed = self.fly_speed_m_per_s * if keys.fast { 4.0 } else { 1.0 };
        self.camera.eye += direction.normalize_or_zero() * speed * dt_s.min(0.25);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn controller() -> CameraController {
        CameraController::new(
            Camera::look_at(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, 1.0, 0.1, 100.0),
            10.0,
            20.0,
        )
    }

    #[test]
    fn orbit_keeps_the_pivot_and_distance() {
        let mut c = controller();
        c.drag = Drag::Orbit;
        let pivot = c.pivot();
        c.on_mouse_drag(Vec2::new(150.0, -80.0));
        assert!((c.pivot() - pivot).length() < 1e-4);
        assert!(((c.camera.eye - pivot).length() - 10.0).abs() < 1e-3);
    }

    #[test]
    fn pitch_never_reaches_the_pole() {
        let mut c = controller();
        c.drag = Drag::Fly;
        c.on_mouse_drag(Vec2::new(0.0, -100_000.0));
        assert!(c.camera.forward.y < 1.0 && c.camera.forward.is_finite());
        assert!(c.camera.basis().0.is_finite());
    }

    #[test]
    fn fly_moves_only_while_flying_and_wheel_sets_speed() {
        let mut c = controller();
        let keys = MoveKeys {
            forward: true,
            ..MoveKeys::default()
        };
        c.update(0.1, keys);
        assert_eq!(c.camera.eye, Vec3::new(0.0, 0.0, 10.0));
        c.drag = Drag::Fly;
        let speed = c.fly_speed_m_per_s;
        c.update(0.1, keys);
        assert!((c.camera.eye.z - (10.0 - speed * 0.1)).abs() < 1e-4);
        c.on_wheel(1.0);
        assert!(c.fly_speed_m_per_s > speed);
    }

    #[test]
    fn framing_sees_the_whole_box() {
        let bounds = Aabb::new(
            Vec3::new(-500.0, 0.0, -300.0),
            Vec3::new(500.0, 200.0, 300.0),
        );
        let c = CameraController::framing(&bounds, 16.0 / 9.0, 1.0);
        let m = c.camera.clip_from_world(16.0 / 9.0);
        for corner in bounds.corners() {
            let p = m.project_point3(corner);
            assert!(
                p.x.abs() <= 1.0 && p.y.abs() <= 1.0 && (0.0..=1.0).contains(&p.z),
                "{corner} -> {p}"
            );
        }
    }
}
