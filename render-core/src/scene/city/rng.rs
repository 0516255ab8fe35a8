//! The city's random stream; the BVH tests borrow it for their random boxes.

/// `SplitMix64` (Steele, Lea, Flood 2014): tiny, fast and good enough to lay out a city.
#[derive(Clone, Debug)]
pub(in crate::scene) struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    pub(in crate::scene) fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    pub(in crate::scene) fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub(in crate::scene) fn unit_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1_u64 << 24) as f32
    }

    pub(in crate::scene) fn range_f32(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit_f32()
    }

    pub(in crate::scene) fn chance(&mut self, probability: f32) -> bool {
        self.unit_f32() < probability
    }

    /// Uniform in `0..n`; 0 when `n` is 0.
    pub(in crate::scene) fn below(&mut self, n: usize) -> usize {
        (((self.next_u64() >> 32) * n as u64) >> 32) as usize
    }
}
