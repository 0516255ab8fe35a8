//! A perspective camera with reversed depth, and a robust orthonormal basis.

use glam::camera::rh::{proj::directx, view::look_to_mat4};
use glam::{DVec3, Mat4, Vec3};

/// A right-handed orthonormal basis `(right, up)` for a view direction. Uses +Y as the up
/// reference unless `forward` is nearly parallel to it, then +Z, so `look_at` never degenerates.
pub fn basis_for_direction(forward: DVec3) -> (DVec3, DVec3) {
    let forward = forward.try_normalize().unwrap_or(DVec3::NEG_Z);
    let up_reference = if forward.y.abs() > 0.999 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let right = forward.cross(up_reference).normalize();
    let up = right.cross(forward);
    (right, up)
}

/// A camera's `(right, up)` for a view direction and the world's up (+Y unless a scene says
/// otherwise): continuous in the direction however close to the vertical it looks (the right
/// vector follows the direction's part across `world_up`, which only vanishes looking exactly
/// along it; then +X for +Y, else any vector across it).
pub fn camera_basis(forward: DVec3, world_up: DVec3) -> (DVec3, DVec3) {
    let forward = forward.try_normalize().unwrap_or(DVec3::NEG_Z);
    let world_up = world_up.try_normalize().unwrap_or(DVec3::Y);
    let fallback = if world_up == DVec3::Y {
        DVec3::X
    } else {
        world_up.any_orthonormal_vector()
    };
    let right = forward.cross(world_up).try_normalize().unwrap_or(fallback);
    let up = right.cross(forward).normalize();
    (right, up)
}

/// The 12 edges of a box or frustum whose 8 corners are ordered as
/// [`Camera::frustum_corners_world`] orders them (corner k: x from bit 0, y from bit 1, the far
/// side from bit 2).
pub const BOX_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (1, 3),
    (3, 2),
    (2, 0),
    (4, 5),
    (5, 7),
    (7, 6),
    (6, 4),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// A pinhole camera. Depth is reversed (near maps to 1, far to 0) for precision over 0.01 m to
/// 10 km; the camera pass clears depth to 0 and keeps the greater value.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Camera {
    pub eye: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    pub fov_y_rad: f32,
    pub near_m: f32,
    pub far_m: f32,
    /// The world's up, which the picture's up follows: +Y unless set ([`Camera::with_up`]).
    pub world_up: Vec3,
}

impl Default for Camera {
    fn default() -> Self {
        Self::look_at(
            Vec3::new(0.0, 10.0, 30.0),
            Vec3::ZERO,
            60f32.to_radians(),
            0.1,
            2000.0,
        )
    }
}

impl Camera {
    /// A camera at `eye` looking at `target`; a target equal to the eye looks along -Z.
    pub fn look_at(eye: Vec3, target: Vec3, fov_y_rad: f32, near_m: f32, far_m: f32) -> Self {
        let forward = (target - eye).try_normalize().unwrap_or(Vec3::NEG_Z);
        Self {
            eye,
            forward,
            world_up: Vec3::Y,
            fov_y_rad,
            near_m,
            far_m,
        }
    }

    /// The same camera with the picture's up following `world_up` (for scenes that are not
    /// +Y up); a zero vector keeps +Y.
    #[must_use]
    pub fn with_up(self, world_up: Vec3) -> Self {
        Self {
            world_up: world_up.try_normalize().unwrap_or(Vec3::Y),
            ..self
        }
    }

    /// `(right, up)` in world space.
    pub fn basis(&self) -> (Vec3, Vec3) {
        let (right, up) = camera_basis(self.forward.as_dvec3(), self.world_up.as_dvec3());
        (right.as_vec3(), up.as_vec3())
    }

    pub fn view_from_world(&self) -> Mat4 {
        let (_, up) = self.basis();
        look_to_mat4(self.eye, self.forward, up)
    }

    /// Reversed-depth perspective projection.
    pub fn clip_from_view(&self, aspect: f32) -> Mat4 {
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        directx::perspective(self.fov_y_rad, aspect, self.far_m, self.near_m)
    }

    pub fn clip_from_world(&self, aspect: f32) -> Mat4 {
        self.clip_from_view(aspect) * self.view_from_world()
    }

    /// The cosine of the angle between the view direction and the frustum's corner rays
    /// (`aspect` = width / height): a point at distance `d` from the eye inside the frustum
    /// lies between view depths `d` times this and `d`.
    pub fn corner_cosine(&self, aspect: f64) -> f64 {
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let t = (f64::from(self.fov_y_rad) * 0.5).tan();
        1.0 / (1.0 + t * t * (1.0 + aspect * aspect)).sqrt()
    }

    /// The eight corners of the view frustum between `near_m` and `far_m`, in world space, in f64:
    /// near plane first (bottom-left, bottom-right, top-left, top-right), then the far plane.
    pub fn frustum_corners_world(&self, aspect: f64, near_m: f64, far_m: f64) -> [DVec3; 8] {
        let eye = self.eye.as_dvec3();
        let forward = self
            .forward
            .as_dvec3()
            .try_normalize()
            .unwrap_or(DVec3::NEG_Z);
        let (right, up) = camera_basis(forward, self.world_up.as_dvec3());
        let tan_half_y = (f64::from(self.fov_y_rad) * 0.5).tan();
        let tan_half_x = tan_half_y * aspect;
        let mut corners = [DVec3::ZERO; 8];
        for (plane, depth) in [near_m, far_m].into_iter().enumerate() {
            for (k, (sx, sy)) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
                .into_iter()
                .enumerate()
            {
                corners[plane * 4 + k] = eye
                    + forward * depth
                    + right * (sx * tan_half_x * depth)
                    + up * (sy * tan_half_y * depth);
            }
        }
        corners
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal_even_looking_straight_down() {
        for forward in [
            DVec3::NEG_Y,
            DVec3::Y,
            DVec3::X,
            DVec3::new(0.3, -0.9, 0.1),
            DVec3::ZERO,
        ] {
            let bases = [
                basis_for_direction(forward),
                camera_basis(forward, DVec3::Y),
                camera_basis(forward, DVec3::Z),
            ];
            for (right, up) in bases {
                assert!(right.is_finite() && up.is_finite());
                assert!((right.length() - 1.0).abs() < 1e-9 && (up.length() - 1.0).abs() < 1e-9);
                assert!(right.dot(up).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn the_camera_turns_smoothly_through_the_vertical() {
        // 20 m above the target, moving to the side in steps of 1 mm: the picture's up turns
        // with the eye around the vertical and never jumps.
        let target = Vec3::ZERO;
        let up_at = |side_m: f32| {
            let eye = Vec3::new(side_m, 20.0, 0.0);
            Camera::look_at(eye, target, 1.0, 0.1, 100.0).basis().1
        };
        assert!(up_at(0.5).dot(up_at(3.0)) > 0.99, "same side, same up");
        let mut previous = up_at(-3.0);
        for step in -3000..=3000 {
            let side_m = step as f32 * 1e-3;
            if side_m == 0.0 {
                continue; // exactly above: +X, by convention
            }
            let up = up_at(side_m);
            let same_side = (side_m > 0.0) == (side_m - 1e-3 > 0.0);
            if same_side {
                assert!(
                    up.dot(previous) > 0.9999,
                    "{side_m} m: {up} after {previous}"
                );
            }
            previous = up;
        }
        // A pitch sweep down to the vertical at a fixed heading keeps the heading's up.
        for pitch_deg in (800..=899).map(|d| d as f32 * 0.1) {
            let pitch = -pitch_deg.to_radians();
            let forward = Vec3::new(pitch.cos() * 0.6, pitch.sin(), pitch.cos() * 0.8);
            let up = Camera::look_at(Vec3::ZERO, forward, 1.0, 0.1, 100.0)
                .basis()
                .1;
            let heading = Vec3::new(0.6, 0.0, 0.8);
            assert!(up.dot(heading) > 0.98, "pitch -{pitch_deg}°: up {up}");
        }
    }

    #[test]
    fn the_picture_follows_a_scenes_own_up() {
        let camera = Camera::look_at(Vec3::ZERO, Vec3::X, 1.0, 0.1, 100.0);
        assert!(camera.basis().1.abs_diff_eq(Vec3::Y, 1e-6));
        let z_up = camera.with_up(Vec3::Z);
        assert!(
            z_up.basis().1.abs_diff_eq(Vec3::Z, 1e-6),
            "{:?}",
            z_up.basis()
        );
        // A point above the camera in +Z lands in the upper half of the picture.
        let p = z_up
            .clip_from_world(1.0)
            .project_point3(Vec3::new(10.0, 0.0, 3.0));
        assert!(p.y > 0.1, "{p}");
        assert_eq!(camera.with_up(Vec3::ZERO).world_up, Vec3::Y);
    }

    #[test]
    fn reversed_depth_maps_near_to_one_and_far_to_zero() {
        let cam = Camera::look_at(Vec3::ZERO, Vec3::NEG_Z, 1.0, 0.5, 100.0);
        let m = cam.clip_from_world(1.5);
        let near = m.project_point3(Vec3::new(0.0, 0.0, -0.5));
        let far = m.project_point3(Vec3::new(0.0, 0.0, -100.0));
        assert!((near.z - 1.0).abs() < 1e-5, "{near}");
        assert!(far.z.abs() < 1e-5, "{far}");
    }

    #[test]
    fn frustum_corners_project_to_clip_corners() {
        let cam = Camera::look_at(
            Vec3::new(3.0, 4.0, 5.0),
            Vec3::new(-2.0, 0.0, 1.0),
            0.9,
            0.1,
            50.0,
        );
        let m = cam.clip_from_world(1.6);
        for (i, c) in cam.frustum_corners_world(1.6, 0.1, 50.0).iter().enumerate() {
            let p = m.project_point3(c.as_vec3());
            assert!(
                (p.x.abs() - 1.0).abs() < 1e-3 && (p.y.abs() - 1.0).abs() < 1e-3,
                "corner {i}: {p}"
            );
        }
    }
}
