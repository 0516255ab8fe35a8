//! Indirect draw lists: instances to draw in one pass, chosen on the CPU.

use super::SceneGpu;
use crate::gpu::GpuContext;

/// Instances to draw in one pass, as indirect draw arguments. Long-lived, refilled per frame.
pub struct DrawList {
    label: &'static str,
    buffer: wgpu::Buffer,
    capacity: u32,
    args: Vec<wgpu::util::DrawIndexedIndirectArgs>,
    /// `args` as bytes for the upload, kept to avoid a per-frame allocation.
    bytes: Vec<u8>,
    pub triangles: u64,
}

impl DrawList {
    pub fn new(ctx: &GpuContext, label: &'static str) -> Self {
        Self {
            label,
            buffer: Self::create_buffer(ctx, label, 64),
            capacity: 64,
            args: Vec::new(),
            bytes: Vec::new(),
            triangles: 0,
        }
    }

    fn create_buffer(ctx: &GpuContext, label: &str, capacity: u32) -> wgpu::Buffer {
        ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: u64::from(capacity) * size_of::<wgpu::util::DrawIndexedIndirectArgs>() as u64,
            usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    pub fn len(&self) -> u32 {
        self.args.len() as u32
    }

    pub fn is_empty(&self) -> bool {
        self.args.is_empty()
    }

    /// Fills the list with `instances` and uploads it.
    pub fn upload(&mut self, ctx: &GpuContext, scene_gpu: &SceneGpu, instances: &[u32]) {
        let args = instances.iter().map(|&i| {
            let range = scene_gpu.instance_ranges[i as usize];
            wgpu::util::DrawIndexedIndirectArgs {
                index_count: range.index_count,
                instance_count: 1,
                first_index: range.first_index,
                base_vertex: range.base_vertex,
                first_instance: i,
            }
        });
        self.upload_args(ctx, args);
    }

    /// Fills the list with `args` (instanced draws too) and uploads it.
    pub fn upload_args(
        &mut self,
        ctx: &GpuContext,
        args: impl IntoIterator<Item = wgpu::util::DrawIndexedIndirectArgs>,
    ) {
        self.args.clear();
        self.args.extend(args);
        self.triangles = self
            .args
            .iter()
            .map(|a| u64::from(a.index_count / 3) * u64::from(a.instance_count))
            .sum();
        if self.len() > self.capacity {
            self.capacity = self.len().next_power_of_two();
            self.buffer = Self::create_buffer(ctx, self.label, self.capacity);
        }
        if !self.args.is_empty() {
            self.bytes.clear();
            for a in &self.args {
                self.bytes.extend_from_slice(a.as_bytes());
            }
            ctx.queue.write_buffer(&self.buffer, 0, &self.bytes);
        }
    }

    /// Records the draws; uses one multi-draw when the device can start at any instance.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        scene_gpu: &SceneGpu,
        indirect_first_instance: bool,
    ) {
        if self.args.is_empty() {
            return;
        }
        pass.set_vertex_buffer(0, scene_gpu.vertex_buffer.slice(..));
        pass.set_index_buffer(scene_gpu.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        if indirect_first_instance {
            pass.multi_draw_indexed_indirect(&self.buffer, 0, self.len());
        } else {
            for a in &self.args {
                pass.draw_indexed(
                    a.first_index..a.first_index + a.index_count,
                    a.base_vertex,
                    a.first_instance..a.first_instance + a.instance_count,
                );
            }
        }
    }
}
