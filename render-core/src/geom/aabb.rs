//! Axis-aligned bounding boxes in any space; the space is named by the variable holding one.

use glam::{Mat4, Vec3};
use serde::{Deserialize, Serialize};

/// An axis-aligned box. An empty box has `min > max` and is the identity of [`Aabb::union`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    pub const EMPTY: Self = Self {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, Self::including)
    }

    pub fn is_empty(&self) -> bool {
        !(self.min.cmple(self.max).all())
    }

    #[must_use]
    pub fn including(self, p: Vec3) -> Self {
        Self::new(self.min.min(p), self.max.max(p))
    }

    #[must_use]
    pub fn union(self, other: Self) -> Self {
        Self::new(self.min.min(other.min), self.max.max(other.max))
    }

    #[must_use]
    pub fn intersection(self, other: Self) -> Self {
        Self::new(self.min.max(other.min), self.max.min(other.max))
    }

    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Size along each axis; zero for an empty box.
    pub fn extent(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    pub fn diagonal_length(&self) -> f32 {
        self.extent().length()
    }

    pub fn contains_point(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    pub fn overlaps(&self, other: &Self) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    pub fn corners(&self) -> [Vec3; 8] {
        let (a, b) = (self.min, self.max);
        [
            Vec3::new(a.x, a.y, a.z),
            Vec3::new(b.x, a.y, a.z),
            Vec3::new(a.x, b.y, a.z),
            Vec3::new(b.x, b.y, a.z),
            Vec3::new(a.x, a.y, b.z),
            Vec3::new(b.x, a.y, b.z),
            Vec3::new(a.x, b.y, b.z),
            Vec3::new(b.x, b.y, b.z),
        ]
    }

    /// The box around this box after an affine transform (Arvo's method).
    #[must_use]
    pub fn transformed(&self, to_from_self: &Mat4) -> Self {
        if self.is_empty() {
            return Self::EMPTY;
        }
        let center = to_from_self.transform_point3(self.center());
        let half = (self.max - self.min) * 0.5;
        let m = glam::Mat3::from_mat4(*to_from_self);
        let half_out = m.x_axis.abs() * half.x + m.y_axis.abs() * half.y + m.z_axis.abs() * half.z;
        Self::new(center - half_out, center + half_out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_is_identity_of_union() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        assert_eq!(Aabb::EMPTY.union(b), b);
        assert!(Aabb::EMPTY.is_empty());
        assert_eq!(Aabb::EMPTY.extent(), Vec3::ZERO);
    }

    #[test]
    fn transformed_matches_corner_transform() {
        let b = Aabb::new(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, 1.0, 5.0));
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 0.5, 1.0),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(10.0, -3.0, 4.0),
        );
        let expected = Aabb::from_points(b.corners().map(|c| m.transform_point3(c)));
        let got = b.transformed(&m);
        assert!((got.min - expected.min).abs().max_element() < 1e-4);
        assert!((got.max - expected.max).abs().max_element() < 1e-4);
    }
}
