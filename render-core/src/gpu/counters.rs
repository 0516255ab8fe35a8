//! A few `u32` counters that shaders add to atomically, cleared each frame and read back
//! without stalling. Long-lived; grown when a frame needs more (more shadow views).

use super::AsyncReadback;

/// Counters in one storage buffer plus a readback ring.
pub struct GpuCounters {
    label: String,
    buffer: wgpu::Buffer,
    readback: AsyncReadback,
    words: usize,
}

impl GpuCounters {
    pub fn new(device: &wgpu::Device, label: &str, words: usize) -> Self {
        let words = words.max(1);
        let size = (words * 4) as u64;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            label: label.to_owned(),
            buffer,
            readback: AsyncReadback::new(device, label, size, 3),
            words,
        }
    }

    /// Makes room for at least `words` counters; returns true when the buffer was replaced
    /// (bind groups that hold it must be rebuilt). Readbacks in flight are dropped.
    pub fn ensure_words(&mut self, device: &wgpu::Device, words: usize) -> bool {
        if words <= self.words {
            return false;
        }
        *self = Self::new(device, &self.label, words.next_power_of_two());
        true
    }

    /// The storage buffer shaders bind.
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }

    /// Zeroes the counters; record before the passes that count.
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.buffer, 0, None);
    }

    /// Records a copy of the counters for frame `tag`; record after the passes that count.
    pub fn copy(&mut self, encoder: &mut wgpu::CommandEncoder, tag: u64) {
        self.readback.copy(encoder, &self.buffer, tag);
    }

    /// Call after submit.
    pub fn after_submit(&mut self) {
        self.readback.map_copied();
    }

    /// The newest counters that have come back and their frame (needs a device poll first).
    pub fn take_latest(&mut self) -> Option<(u64, Vec<u32>)> {
        let (tag, bytes) = self.readback.take_latest()?;
        let mut words: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
        words.truncate(self.words);
        Some((tag, words))
    }
}
