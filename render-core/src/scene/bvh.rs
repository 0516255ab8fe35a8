//! Bounding volume hierarchy over instance boxes. STUB: replaced by the real BVH.

use crate::geom::{Aabb, Frustum};

/// A BVH over a list of boxes, answering which box indices overlap a query volume.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    boxes: Vec<Aabb>,
}

impl Bvh {
    pub fn build(boxes: &[Aabb]) -> Self {
        Self { boxes: boxes.to_vec() }
    }

    /// Updates node boxes after objects moved; the tree shape stays.
    pub fn refit(&mut self, boxes: &[Aabb]) {
        self.boxes = boxes.to_vec();
    }

    /// Appends to `out` the indices of boxes that intersect `frustum` (conservative box test).
    pub fn query_frustum(&self, frustum: &Frustum, out: &mut Vec<u32>) {
        out.extend((0..self.boxes.len() as u32).filter(|&i| frustum.intersects_aabb(&self.boxes[i as usize])));
    }

    /// Appends to `out` the indices of boxes that overlap `aabb`.
    pub fn query_aabb(&self, aabb: &Aabb, out: &mut Vec<u32>) {
        out.extend((0..self.boxes.len() as u32).filter(|&i| self.boxes[i as usize].overlaps(aabb)));
    }
}
