//! Planes and convex volumes used for culling: a frustum is six inward-facing planes.

use glam::{Mat4, Vec3, Vec4};

use super::Aabb;

/// A plane `dot(normal, p) + d = 0`; points with a positive distance are inside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub normal: Vec3,
    pub d: f32,
}

impl Plane {
    /// From `(a, b, c, d)`, normalised so distances are in world units. A degenerate row gives a
    /// plane that keeps everything, never NaN.
    pub fn from_vec4(v: Vec4) -> Self {
        let len = v.truncate().length();
        if len > 0.0 && len.is_finite() {
            Self {
                normal: v.truncate() / len,
                d: v.w / len,
            }
        } else {
            Self {
                normal: Vec3::ZERO,
                d: 1.0,
            }
        }
    }

    pub fn signed_distance(&self, p: Vec3) -> f32 {
        self.normal.dot(p) + self.d
    }
}

/// The volume `clip_from_world` maps into wgpu's clip cube (x, y in [-1, 1], z in [0, 1]).
#[derive(Clone, Copy, Debug)]
pub struct Frustum {
    /// Left, right, bottom, top, near, far.
    pub planes: [Plane; 6],
}

/// How a box relates to a convex volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Containment {
    Outside,
    Intersects,
    Inside,
}

impl Frustum {
    /// Gribb-Hartmann plane extraction for a `[0, 1]` depth range. Works for perspective,
    /// orthographic and reversed-depth projections alike.
    pub fn from_clip_from_world(clip_from_world: &Mat4) -> Self {
        let m = clip_from_world.transpose();
        let (r0, r1, r2, r3) = (m.x_axis, m.y_axis, m.z_axis, m.w_axis);
        Self {
            planes: [
                Plane::from_vec4(r3 + r0),
                Plane::from_vec4(r3 - r0),
                Plane::from_vec4(r3 + r1),
                Plane::from_vec4(r3 - r1),
                Plane::from_vec4(r2),
                Plane::from_vec4(r3 - r2),
            ],
        }
    }

    /// Conservative box test: `Outside` only when one plane has the whole box behind it.
    pub fn classify_aabb(&self, aabb: &Aabb) -> Containment {
        if aabb.is_empty() {
            return Containment::Outside;
        }
        let mut result = Containment::Inside;
        for plane in &self.planes {
            let positive = Vec3::select(plane.normal.cmpge(Vec3::ZERO), aabb.max, aabb.min);
            let negative = Vec3::select(plane.normal.cmpge(Vec3::ZERO), aabb.min, aabb.max);
            if plane.signed_distance(positive) < 0.0 {
                return Containment::Outside;
            }
            if plane.signed_distance(negative) < 0.0 {
                result = Containment::Intersects;
            }
        }
        result
    }

    pub fn intersects_aabb(&self, aabb: &Aabb) -> bool {
        self.classify_aabb(aabb) != Containment::Outside
    }

    pub fn contains_point(&self, p: Vec3) -> bool {
        self.planes
            .iter()
            .all(|plane| plane.signed_distance(p) >= 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perspective_frustum_classifies_boxes() {
        use glam::camera::rh::{proj::directx::perspective, view::look_at_mat4};
        let view = look_at_mat4(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
        let proj = perspective(1.0, 1.0, 0.1, 100.0);
        let f = Frustum::from_clip_from_world(&(proj * view));
        let ahead = Aabb::new(Vec3::new(-1.0, -1.0, -11.0), Vec3::new(1.0, 1.0, -9.0));
        let behind = Aabb::new(Vec3::new(-1.0, -1.0, 1.0), Vec3::new(1.0, 1.0, 3.0));
        let crossing_far = Aabb::new(Vec3::new(-1.0, -1.0, -101.0), Vec3::new(1.0, 1.0, -99.0));
        assert_eq!(f.classify_aabb(&ahead), Containment::Inside);
        assert_eq!(f.classify_aabb(&behind), Containment::Outside);
        assert_eq!(f.classify_aabb(&crossing_far), Containment::Intersects);
        assert!(f.contains_point(Vec3::new(0.0, 0.0, -50.0)));
        assert!(!f.contains_point(Vec3::new(0.0, 0.0, -150.0)));
    }
}
