//! Scripted motion of dynamic objects, such as cars driving along their lanes. A motion moves
//! one instance back and forth along a segment; [`Scene::animate`](super::Scene::animate)
//! poses every moving instance for a time in seconds, so a frame's scene follows from its time
//! alone (headless runs stay deterministic).

use glam::{Mat4, Quat, Vec3};

/// An instance driving along a straight segment and wrapping around at its end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    pub instance: u32,
    /// Where the segment starts, on the ground.
    pub start: Vec3,
    /// Unit direction of travel (the object's local +x).
    pub direction: Vec3,
    pub length_m: f32,
    /// Distance along the segment at time 0.
    pub offset_m: f32,
    pub speed_m_per_s: f32,
}

impl Motion {
    /// The instance's transform at `time_s`.
    pub fn world_from_local(&self, time_s: f64) -> Mat4 {
        let length = f64::from(self.length_m.max(1e-3));
        let distance = (f64::from(self.offset_m) + f64::from(self.speed_m_per_s) * time_s)
            .rem_euclid(length) as f32;
        let yaw = (-self.direction.z).atan2(self.direction.x);
        Mat4::from_rotation_translation(
            Quat::from_rotation_y(yaw),
            self.start + self.direction * distance,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motion_wraps_along_its_segment_and_faces_its_direction() {
        let motion = Motion {
            instance: 0,
            start: Vec3::new(10.0, 0.0, 5.0),
            direction: Vec3::NEG_Z,
            length_m: 50.0,
            offset_m: 5.0,
            speed_m_per_s: 10.0,
        };
        let at = |t: f64| motion.world_from_local(t).transform_point3(Vec3::ZERO);
        assert!((at(0.0) - Vec3::new(10.0, 0.0, 0.0)).length() < 1e-4);
        assert!((at(2.0) - Vec3::new(10.0, 0.0, -20.0)).length() < 1e-4);
        // 5 + 10 * 5 = 55 wraps to 5.
        assert!((at(5.0) - at(0.0)).length() < 1e-3);
        let nose = motion.world_from_local(1.0).transform_vector3(Vec3::X);
        assert!((nose - Vec3::NEG_Z).length() < 1e-5, "{nose}");
        assert!(at(-3.0).is_finite());
    }
}
