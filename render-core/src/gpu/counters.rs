//! A few `u32` counters that shaders add to atomically, cleared each frame and read back
//! without stalling. Long-lived.

use super::AsyncReadback;

/// `N` counters in one storage buffer plus a readback ring.
pub struct GpuCounters<const N: usize> {
    buffer: wgpu::Buffer,
    readback: AsyncReadback,
}

impl<const N: usize> GpuCounters<N> {
    pub fn new(device: &wgpu::Device, label: &str) -> Self {
        let size = (N * 4) as u64;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            buffer,
            readback: AsyncReadback::new(device, label, size, 3),
        }
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
    pub fn take_latest(&mut self) -> Option<(u64, [u32; N])> {
        let (tag, bytes) = self.readback.take_latest()?;
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
        let mut out = [0; N];
        out.copy_from_slice(words.get(..N)?);
        Some((tag, out))
    }
}
