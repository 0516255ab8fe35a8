//! Sweep-and-prune (Cohen et al. 1995, as Lloyd et al. use it for continuous clamping): the
//! ends of items' extents along one axis, kept sorted from frame to frame by insertion sort,
//! so that when the items and the light barely move between frames the sort costs a pass
//! over the list and a few local swaps. A sweep over the sorted ends then meets every pair
//! of items whose extents overlap.

/// One end of an item's extent.
#[derive(Clone, Copy, Debug)]
struct End {
    value: f32,
    item: u32,
    start: bool,
}

impl End {
    /// Sorted by value, starts before ends at equal values (touching extents overlap).
    fn before(&self, other: &End) -> bool {
        match self.value.total_cmp(&other.value) {
            std::cmp::Ordering::Less => true,
            std::cmp::Ordering::Equal => self.start && !other.start,
            std::cmp::Ordering::Greater => false,
        }
    }
}

/// The sorted ends of the last frame's extents.
#[derive(Default)]
pub(super) struct SweepAndPrune {
    ends: Vec<End>,
    /// Swaps the last sort took.
    pub swaps: u64,
}

impl SweepAndPrune {
    /// Calls `each(a, b)` once for every pair of items (indices into `extents`, low and high
    /// along the axis, `a < b`) whose extents overlap. Items whose extent is empty (low above
    /// high) meet none. The ends keep last frame's order where `extents` has as many items.
    pub fn overlaps(&mut self, extents: &[(f32, f32)], mut each: impl FnMut(u32, u32)) {
        if self.ends.len() != 2 * extents.len() {
            self.ends = (0..extents.len() as u32)
                .flat_map(|item| {
                    [true, false].map(|start| End {
                        value: 0.0,
                        item,
                        start,
                    })
                })
                .collect();
        }
        for end in &mut self.ends {
            let (low, high) = extents[end.item as usize];
            end.value = if end.start { low } else { high };
        }
        self.swaps = 0;
        for i in 1..self.ends.len() {
            let mut j = i;
            while j > 0 && self.ends[j].before(&self.ends[j - 1]) {
                self.ends.swap(j, j - 1);
                j -= 1;
                self.swaps += 1;
            }
        }
        let mut open: Vec<u32> = Vec::new();
        for end in &self.ends {
            let (low, high) = extents[end.item as usize];
            if low > high || low.is_nan() || high.is_nan() {
                continue;
            }
            if end.start {
                for &other in &open {
                    each(other.min(end.item), other.max(end.item));
                }
                open.push(end.item);
            } else if let Some(at) = open.iter().position(|&o| o == end.item) {
                open.swap_remove(at);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pairs(sweep: &mut SweepAndPrune, extents: &[(f32, f32)]) -> Vec<(u32, u32)> {
        let mut found = Vec::new();
        sweep.overlaps(extents, |a, b| found.push((a, b)));
        found.sort_unstable();
        found
    }

    fn brute_force(extents: &[(f32, f32)]) -> Vec<(u32, u32)> {
        let mut found = Vec::new();
        for a in 0..extents.len() {
            for b in a + 1..extents.len() {
                let (x, y) = (extents[a], extents[b]);
                if x.0 <= x.1 && y.0 <= y.1 && x.0 <= y.1 && y.0 <= x.1 {
                    found.push((a as u32, b as u32));
                }
            }
        }
        found
    }

    #[test]
    fn the_sweep_meets_every_overlapping_pair_and_only_those() {
        let extents = [(0.0, 2.0), (1.0, 3.0), (5.0, 6.0), (2.0, 2.0), (7.0, 4.0)];
        let mut sweep = SweepAndPrune::default();
        // Touching extents overlap; an empty one (7 > 4) meets nothing.
        assert_eq!(pairs(&mut sweep, &extents), vec![(0, 1), (0, 3), (1, 3)]);
    }

    #[test]
    fn moving_items_keep_the_order_and_the_sort_takes_few_swaps() {
        // 200 items drifting a little each frame: the same pairs as every pair tested, and a
        // frame that moves nothing sorts without a swap.
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) as f32 / (1u64 << 31) as f32
        };
        let mut extents: Vec<(f32, f32)> = (0..200)
            .map(|_| {
                let low = next() * 100.0;
                (low, low + next() * 3.0)
            })
            .collect();
        let mut sweep = SweepAndPrune::default();
        assert_eq!(pairs(&mut sweep, &extents), brute_force(&extents));
        let first = sweep.swaps;
        assert!(first > 1_000, "{first} swaps from a fresh order");
        for _ in 0..5 {
            for e in &mut extents {
                let shift = (next() - 0.5) * 0.2;
                *e = (e.0 + shift, e.1 + shift);
            }
            assert_eq!(pairs(&mut sweep, &extents), brute_force(&extents));
            assert!(sweep.swaps < first / 10, "{} swaps", sweep.swaps);
        }
        pairs(&mut sweep, &extents);
        assert_eq!(sweep.swaps, 0);
    }
}
