//! Bounding volume hierarchy over instance boxes: a binned-SAH tree in one flat node array,
//! built and walked with explicit stacks (no recursion), refitted in place when objects move.

use glam::Vec3;

use crate::geom::{Aabb, Containment, Frustum};

/// A node with at most this many boxes is a leaf.
const MAX_LEAF_SIZE: usize = 4;
/// Bins per axis for the surface area heuristic.
const SAH_BINS: usize = 12;

#[derive(Clone, Copy, Debug)]
struct Node {
    aabb: Aabb,
    /// This node's boxes are `item_ids[first_item..first_item + item_count]`; for an inner node
    /// that is its whole subtree.
    first_item: u32,
    item_count: u32,
    /// The left child; the right child is the next node. 0 marks a leaf (the root is no child).
    left_child: u32,
}

impl Node {
    fn is_leaf(&self) -> bool {
        self.left_child == 0
    }

    fn item_range(&self) -> std::ops::Range<usize> {
        self.first_item as usize..(self.first_item + self.item_count) as usize
    }
}

/// A BVH over a list of boxes, answering which box indices overlap a query volume.
///
/// Children always come after their parent in the node array, so a reverse sweep updates the
/// tree bottom-up. Empty boxes are kept (a refit may give them a size) but never reported.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Box indices in leaf order: every node covers a contiguous range.
    item_ids: Vec<u32>,
    /// `item_boxes[k]` is the box of `item_ids[k]`, stored in leaf order for locality.
    item_boxes: Vec<Aabb>,
}

impl Bvh {
    pub fn build(boxes: &[Aabb]) -> Self {
        if boxes.is_empty() {
            return Self::default();
        }
        let centroids: Vec<Vec3> = boxes.iter().map(centroid_of).collect();
        let mut item_ids: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * boxes.len().div_ceil(MAX_LEAF_SIZE));
        nodes.push(Node {
            aabb: Aabb::EMPTY,
            first_item: 0,
            item_count: boxes.len() as u32,
            left_child: 0,
        });
        let mut pending = vec![0_usize];
        while let Some(index) = pending.pop() {
            let node = nodes[index];
            if node.item_count as usize <= MAX_LEAF_SIZE {
                continue;
            }
            let items = &mut item_ids[node.item_range()];
            let left_count = split_items(items, boxes, &centroids) as u32;
            let left_child = nodes.len();
            nodes[index].left_child = left_child as u32;
            nodes.push(Node {
                aabb: Aabb::EMPTY,
                first_item: node.first_item,
                item_count: left_count,
                left_child: 0,
            });
            nodes.push(Node {
                aabb: Aabb::EMPTY,
                first_item: node.first_item + left_count,
                item_count: node.item_count - left_count,
                left_child: 0,
            });
            pending.extend([left_child, left_child + 1]);
        }
        let item_boxes = item_ids.iter().map(|&id| boxes[id as usize]).collect();
        let mut bvh = Self {
            nodes,
            item_ids,
            item_boxes,
        };
        bvh.update_node_boxes();
        bvh
    }

    /// Updates node boxes after objects moved; the tree shape stays. A list of a different
    /// length than the one built from rebuilds the tree.
    pub fn refit(&mut self, boxes: &[Aabb]) {
        if boxes.len() != self.item_ids.len() {
            *self = Self::build(boxes);
            return;
        }
        for (slot, &id) in self.item_boxes.iter_mut().zip(&self.item_ids) {
            *slot = boxes[id as usize];
        }
        self.update_node_boxes();
    }

    /// Number of boxes the tree was built over, empty ones included.
    pub fn len(&self) -> usize {
        self.item_ids.len()
    }

    pub fn is_empty(&self) -> bool {
        self.item_ids.is_empty()
    }

    /// The box around every box in the tree.
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |root| root.aabb)
    }

    /// Appends to `out` the indices of boxes that intersect `frustum` (conservative box test).
    pub fn query_frustum(&self, frustum: &Frustum, out: &mut Vec<u32>) {
        self.collect(|aabb| frustum.classify_aabb(aabb), out);
    }

    /// Appends to `out` the indices of boxes that overlap `aabb`.
    pub fn query_aabb(&self, aabb: &Aabb, out: &mut Vec<u32>) {
        self.collect(
            |node_box| {
                if !node_box.overlaps(aabb) {
                    Containment::Outside
                } else if aabb.min.cmple(node_box.min).all() && node_box.max.cmple(aabb.max).all() {
                    Containment::Inside
                } else {
                    Containment::Intersects
                }
            },
            out,
        );
    }

    /// Appends to `out` the indices of boxes touched by the segment `origin + t * direction`,
    /// `t` in `[0, max_t]` (slab test; a zero direction tests the point `origin`).
    pub fn query_ray(&self, origin: Vec3, direction: Vec3, max_t: f32, out: &mut Vec<u32>) {
        let inv_direction = direction.recip();
        self.collect(
            |aabb| {
                if segment_hits_aabb(origin, inv_direction, max_t, aabb) {
                    Containment::Intersects
                } else {
                    Containment::Outside
                }
            },
            out,
        );
    }

    /// Walks the tree with `classify`, which must be monotone: a box inside an `Outside` box is
    /// `Outside`, a box inside an `Inside` box is not `Outside`. Whole `Inside` subtrees are
    /// added without further tests.
    fn collect(&self, classify: impl Fn(&Aabb) -> Containment, out: &mut Vec<u32>) {
        if self.nodes.is_empty() {
            return;
        }
        let mut pending: Vec<u32> = Vec::with_capacity(64);
        pending.push(0);
        while let Some(index) = pending.pop() {
            let node = &self.nodes[index as usize];
            match classify(&node.aabb) {
                Containment::Outside => {}
                Containment::Inside => {
                    let range = node.item_range();
                    out.extend(
                        self.item_ids[range.clone()]
                            .iter()
                            .zip(&self.item_boxes[range])
                            .filter(|(_, aabb)| !aabb.is_empty())
                            .map(|(&id, _)| id),
                    );
                }
                Containment::Intersects if node.is_leaf() => {
                    for k in node.item_range() {
                        if classify(&self.item_boxes[k]) != Containment::Outside {
                            out.push(self.item_ids[k]);
                        }
                    }
                }
                Containment::Intersects => pending.extend([node.left_child + 1, node.left_child]),
            }
        }
    }

    fn update_node_boxes(&mut self) {
        for index in (0..self.nodes.len()).rev() {
            let node = self.nodes[index];
            self.nodes[index].aabb = if node.is_leaf() {
                self.item_boxes[node.item_range()]
                    .iter()
                    .fold(Aabb::EMPTY, |acc, b| acc.union(*b))
            } else {
                let left = node.left_child as usize;
                self.nodes[left].aabb.union(self.nodes[left + 1].aabb)
            };
        }
    }
}

/// The point a box is sorted by; empty or unbounded boxes sort at the origin.
fn centroid_of(aabb: &Aabb) -> Vec3 {
    let center = aabb.center();
    if aabb.is_empty() || !center.is_finite() {
        Vec3::ZERO
    } else {
        center
    }
}

/// Half the surface area of a box, zero for an empty one.
fn half_area(aabb: &Aabb) -> f32 {
    let e = aabb.extent();
    e.x * e.y + e.y * e.z + e.z * e.x
}

/// Reorders `items` (at least two) into a left and a right group and returns the size of the
/// left group, which is neither 0 nor all of them. Binned SAH over all three axes; items whose
/// centroids coincide are split in half.
fn split_items(items: &mut [u32], boxes: &[Aabb], centroids: &[Vec3]) -> usize {
    let centroid_bounds = Aabb::from_points(items.iter().map(|&i| centroids[i as usize]));
    let extent = centroid_bounds.extent();
    let bin_of = |axis: usize, item: u32| {
        let scale = SAH_BINS as f32 / extent[axis];
        let offset = (centroids[item as usize][axis] - centroid_bounds.min[axis]) * scale;
        (offset as usize).min(SAH_BINS - 1)
    };

    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if extent[axis] <= 0.0 || !extent[axis].is_finite() {
            continue;
        }
        let mut bin_boxes = [Aabb::EMPTY; SAH_BINS];
        let mut bin_counts = [0_usize; SAH_BINS];
        for &item in items.iter() {
            let bin = bin_of(axis, item);
            bin_boxes[bin] = bin_boxes[bin].union(boxes[item as usize]);
            bin_counts[bin] += 1;
        }
        // Cost of splitting after bin `k`: left area * left count + right area * right count.
        let mut left_costs = [0.0_f32; SAH_BINS];
        let (mut left_box, mut left_count) = (Aabb::EMPTY, 0);
        for k in 0..SAH_BINS - 1 {
            left_box = left_box.union(bin_boxes[k]);
            left_count += bin_counts[k];
            left_costs[k] = half_area(&left_box) * left_count as f32;
        }
        let (mut right_box, mut right_count) = (Aabb::EMPTY, 0);
        for k in (0..SAH_BINS - 1).rev() {
            right_box = right_box.union(bin_boxes[k + 1]);
            right_count += bin_counts[k + 1];
            let total_left = items.len() - right_count;
            if total_left == 0 || right_count == 0 {
                continue;
            }
            let cost = left_costs[k] + half_area(&right_box) * right_count as f32;
            if best.is_none_or(|(best_cost, _, _)| cost < best_cost) {
                best = Some((cost, axis, k));
            }
        }
    }

    if let Some((_, axis, split_bin)) = best {
        let left_count = partition_in_place(items, |item| bin_of(axis, item) <= split_bin);
        if left_count > 0 && left_count < items.len() {
            return left_count;
        }
    }
    // Coincident centroids (or an unusable extent): split by count along the longest axis.
    let axis = extent.max_position();
    let middle = items.len() / 2;
    items.select_nth_unstable_by(middle, |&a, &b| {
        centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
    });
    middle
}

/// Moves the items for which `goes_left` holds to the front; returns how many there are.
fn partition_in_place(items: &mut [u32], goes_left: impl Fn(u32) -> bool) -> usize {
    let mut left_count = 0;
    for k in 0..items.len() {
        if goes_left(items[k]) {
            items.swap(k, left_count);
            left_count += 1;
        }
    }
    left_count
}

/// Slab test of the segment `origin + t * direction`, `t` in `[0, max_t]`, against a box.
fn segment_hits_aabb(origin: Vec3, inv_direction: Vec3, max_t: f32, aabb: &Aabb) -> bool {
    if aabb.is_empty() {
        return false;
    }
    let mut t_enter = 0.0_f32;
    let mut t_exit = max_t;
    for axis in 0..3 {
        if inv_direction[axis].is_infinite() {
            // Parallel to this slab: inside it or never.
            if origin[axis] < aabb.min[axis] || origin[axis] > aabb.max[axis] {
                return false;
            }
            continue;
        }
        let t0 = (aabb.min[axis] - origin[axis]) * inv_direction[axis];
        let t1 = (aabb.max[axis] - origin[axis]) * inv_direction[axis];
        t_enter = t_enter.max(t0.min(t1));
        t_exit = t_exit.min(t0.max(t1));
    }
    t_enter <= t_exit
}

#[cfg(test)]
mod tests {
    use glam::camera::rh::proj::directx::{orthographic, perspective};
    use glam::camera::rh::view::look_at_mat4;

    use super::super::city::SplitMix64;
    use super::*;

    fn random_vec3(rng: &mut SplitMix64, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(
            rng.range_f32(lo, hi),
            rng.range_f32(lo, hi),
            rng.range_f32(lo, hi),
        )
    }

    /// Boxes scattered over a 200 m cube, some flat, some points, a few empty.
    fn random_boxes(rng: &mut SplitMix64, count: usize) -> Vec<Aabb> {
        (0..count)
            .map(|_| {
                if rng.chance(0.03) {
                    return Aabb::EMPTY;
                }
                let center = random_vec3(rng, -100.0, 100.0);
                let mut half = random_vec3(rng, 0.0, 6.0);
                if rng.chance(0.1) {
                    half.y = 0.0;
                }
                if rng.chance(0.05) {
                    half = Vec3::ZERO;
                }
                Aabb::new(center - half, center + half)
            })
            .collect()
    }

    fn random_frustum(rng: &mut SplitMix64) -> Frustum {
        let eye = random_vec3(rng, -150.0, 150.0);
        let target = eye
            + random_vec3(rng, -1.0, 1.0)
                .try_normalize()
                .unwrap_or(Vec3::NEG_Z);
        let forward = target - eye;
        let up = if forward.normalize().y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let view = look_at_mat4(eye, target, up);
        let near = rng.range_f32(0.1, 5.0);
        let far = near + rng.range_f32(10.0, 300.0);
        let projection = if rng.chance(0.5) {
            perspective(rng.range_f32(0.2, 2.5), rng.range_f32(0.3, 3.0), near, far)
        } else {
            let (w, h) = (rng.range_f32(1.0, 150.0), rng.range_f32(1.0, 150.0));
            orthographic(-w, w, -h, h, near - 50.0, far)
        };
        Frustum::from_clip_from_world(&(projection * view))
    }

    fn sorted(mut ids: Vec<u32>) -> Vec<u32> {
        ids.sort_unstable();
        ids
    }

    fn brute_force(boxes: &[Aabb], accepts: impl Fn(&Aabb) -> bool) -> Vec<u32> {
        (0..boxes.len() as u32)
            .filter(|&i| accepts(&boxes[i as usize]))
            .collect()
    }

    /// Every node box encloses its children and leaves hold at most `MAX_LEAF_SIZE` boxes.
    fn assert_well_formed(bvh: &Bvh, boxes: &[Aabb]) {
        let encloses = |outer: &Aabb, inner: &Aabb| {
            inner.is_empty()
                || (outer.min.cmple(inner.min).all() && inner.max.cmple(outer.max).all())
        };
        for node in &bvh.nodes {
            if node.is_leaf() {
                assert!(node.item_count as usize <= MAX_LEAF_SIZE);
                for k in node.item_range() {
                    assert_eq!(bvh.item_boxes[k], boxes[bvh.item_ids[k] as usize]);
                    assert!(encloses(&node.aabb, &bvh.item_boxes[k]));
                }
            } else {
                let left = node.left_child as usize;
                assert!(left > 0 && encloses(&node.aabb, &bvh.nodes[left].aabb));
                assert!(encloses(&node.aabb, &bvh.nodes[left + 1].aabb));
            }
        }
        assert_eq!(
            sorted(bvh.item_ids.clone()),
            (0..boxes.len() as u32).collect::<Vec<_>>()
        );
    }

    fn assert_queries_match(bvh: &Bvh, boxes: &[Aabb], rng: &mut SplitMix64, rounds: usize) {
        for _ in 0..rounds {
            let frustum = random_frustum(rng);
            let mut got = Vec::new();
            bvh.query_frustum(&frustum, &mut got);
            assert_eq!(
                sorted(got),
                brute_force(boxes, |b| frustum.intersects_aabb(b))
            );

            let center = random_vec3(rng, -110.0, 110.0);
            let half = random_vec3(rng, 0.0, 40.0);
            let query = Aabb::new(center - half, center + half);
            let mut got = Vec::new();
            bvh.query_aabb(&query, &mut got);
            assert_eq!(sorted(got), brute_force(boxes, |b| b.overlaps(&query)));
        }
    }

    #[test]
    fn empty_and_single_box_trees_answer_queries() {
        let frustum =
            Frustum::from_clip_from_world(&orthographic(-10.0, 10.0, -10.0, 10.0, -10.0, 10.0));
        let everything = Aabb::new(Vec3::splat(-1e6), Vec3::splat(1e6));
        let empty = Bvh::build(&[]);
        let mut out = Vec::new();
        empty.query_frustum(&frustum, &mut out);
        empty.query_aabb(&everything, &mut out);
        empty.query_ray(Vec3::ZERO, Vec3::X, 10.0, &mut out);
        assert!(out.is_empty() && empty.is_empty() && empty.bounds().is_empty());

        let one = Bvh::build(&[Aabb::new(Vec3::ONE, Vec3::splat(2.0))]);
        assert_eq!(one.len(), 1);
        one.query_frustum(&frustum, &mut out);
        one.query_aabb(&everything, &mut out);
        one.query_ray(Vec3::ZERO, Vec3::ONE, 10.0, &mut out);
        assert_eq!(out, [0, 0, 0]);

        let only_empty = Bvh::build(&[Aabb::EMPTY, Aabb::EMPTY]);
        out.clear();
        only_empty.query_aabb(&everything, &mut out);
        only_empty.query_frustum(&frustum, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn frustum_and_box_queries_match_brute_force() {
        let mut rng = SplitMix64::new(7);
        for count in [2, 5, 37, 3000] {
            let boxes = random_boxes(&mut rng, count);
            let bvh = Bvh::build(&boxes);
            assert_well_formed(&bvh, &boxes);
            assert_queries_match(&bvh, &boxes, &mut rng, 150);
        }
    }

    #[test]
    fn frustum_holding_everything_returns_every_non_empty_box() {
        let mut rng = SplitMix64::new(11);
        let boxes = random_boxes(&mut rng, 500);
        let bvh = Bvh::build(&boxes);
        let view = look_at_mat4(Vec3::new(0.0, 0.0, 500.0), Vec3::ZERO, Vec3::Y);
        let projection = orthographic(-200.0, 200.0, -200.0, 200.0, 1.0, 1000.0);
        let frustum = Frustum::from_clip_from_world(&(projection * view));
        let mut got = Vec::new();
        bvh.query_frustum(&frustum, &mut got);
        assert_eq!(sorted(got), brute_force(&boxes, |b| !b.is_empty()));
    }

    #[test]
    fn ray_queries_match_brute_force() {
        let mut rng = SplitMix64::new(3);
        let boxes = random_boxes(&mut rng, 2000);
        let bvh = Bvh::build(&boxes);
        for round in 0..300 {
            let origin = random_vec3(&mut rng, -120.0, 120.0);
            let mut direction = random_vec3(&mut rng, -1.0, 1.0);
            if round % 10 == 0 {
                direction.y = 0.0;
            }
            let max_t = rng.range_f32(0.0, 400.0);
            let mut got = Vec::new();
            bvh.query_ray(origin, direction, max_t, &mut got);
            let inv = direction.recip();
            assert_eq!(
                sorted(got),
                brute_force(&boxes, |b| segment_hits_aabb(origin, inv, max_t, b))
            );
        }
        let mut hits = Vec::new();
        let unit = Bvh::build(&[Aabb::new(Vec3::ZERO, Vec3::ONE)]);
        unit.query_ray(Vec3::new(-1.0, 0.5, 0.5), Vec3::X, 0.9, &mut hits);
        unit.query_ray(Vec3::new(-1.0, 0.5, 0.5), Vec3::X, 1.1, &mut hits);
        unit.query_ray(Vec3::new(-1.0, 1.5, 0.5), Vec3::X, 9.0, &mut hits);
        assert_eq!(hits, [0]);
    }

    #[test]
    fn refit_after_moving_boxes_matches_brute_force() {
        let mut rng = SplitMix64::new(5);
        let mut boxes = random_boxes(&mut rng, 2500);
        let mut bvh = Bvh::build(&boxes);
        let node_count = bvh.nodes.len();
        for round in 0..4 {
            for aabb in &mut boxes {
                if rng.chance(0.2) {
                    let offset = random_vec3(&mut rng, -30.0, 30.0);
                    *aabb = if aabb.is_empty() && round % 2 == 0 {
                        Aabb::new(offset, offset + Vec3::ONE)
                    } else {
                        Aabb::new(aabb.min + offset, aabb.max + offset)
                    };
                }
            }
            bvh.refit(&boxes);
            assert_eq!(bvh.nodes.len(), node_count, "refit keeps the tree shape");
            assert_well_formed(&bvh, &boxes);
            assert_queries_match(&bvh, &boxes, &mut rng, 60);
        }
        boxes.truncate(10);
        bvh.refit(&boxes);
        assert_eq!(bvh.len(), 10);
        assert_queries_match(&bvh, &boxes, &mut rng, 20);
    }

    #[test]
    fn coincident_boxes_split_by_count() {
        let boxes = vec![Aabb::new(Vec3::ZERO, Vec3::ONE); 1000];
        let bvh = Bvh::build(&boxes);
        assert_well_formed(&bvh, &boxes);
        let mut out = Vec::new();
        bvh.query_aabb(&Aabb::new(Vec3::splat(0.5), Vec3::splat(0.6)), &mut out);
        assert_eq!(out.len(), 1000);
    }

    #[test]
    fn hundred_thousand_boxes_build_without_deep_recursion() {
        let mut rng = SplitMix64::new(9);
        // Boxes on a line with sizes spanning four orders of magnitude: a lopsided tree.
        let boxes: Vec<Aabb> = (0..100_000)
            .map(|i| {
                let x = i as f32 * 0.5;
                let size = 10.0_f32.powf(rng.range_f32(-2.0, 2.0));
                Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + size, size, size))
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        assert_eq!(bvh.len(), boxes.len());
        let mut out = Vec::new();
        let query = Aabb::new(Vec3::new(1000.0, -1.0, -1.0), Vec3::new(1010.0, 1.0, 1.0));
        bvh.query_aabb(&query, &mut out);
        assert_eq!(sorted(out), brute_force(&boxes, |b| b.overlaps(&query)));
    }
}
