//! The frame's shadow views on the GPU. Long-lived: one buffer, grown when a frame has more
//! views, with one bind group per view slot for the passes that render a single view.

use super::{ShadowView, ShadowViewGpu};
use crate::gpu::{GpuContext, bind_group_layout, uniform};

/// Every view of the frame (`array<ShadowView>`, storage) and each view alone (uniform).
pub struct ViewBuffer {
    buffer: wgpu::Buffer,
    capacity: u32,
    /// Bumped whenever `buffer` is replaced, so groups that bind it know to follow.
    generation: u64,
    layout: wgpu::BindGroupLayout,
    pass_groups: Vec<wgpu::BindGroup>,
    count: u32,
}

impl ViewBuffer {
    pub fn new(device: &wgpu::Device) -> Self {
        let layout = bind_group_layout(
            device,
            "ViewBuffer::pass_layout",
            wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
            &[uniform()],
        );
        let mut views = Self {
            buffer: create_buffer(device, 1),
            capacity: 1,
            generation: 0,
            layout,
            pass_groups: Vec::new(),
            count: 0,
        };
        views.pass_groups = views.create_pass_groups(device);
        views
    }

    /// Writes this frame's views, growing the buffer when needed.
    pub fn write(&mut self, ctx: &GpuContext, views: &[ShadowView]) {
        let count = views.len() as u32;
        if count > self.capacity {
            self.capacity = count.next_power_of_two();
            self.buffer = create_buffer(&ctx.device, self.capacity);
            self.generation += 1;
            self.pass_groups = self.create_pass_groups(&ctx.device);
        }
        let data: Vec<ShadowViewGpu> = (0..)
            .zip(views)
            .map(|(i, v)| ShadowViewGpu::new(v, i))
            .collect();
        if !data.is_empty() {
            ctx.queue
                .write_buffer(&self.buffer, 0, bytemuck::cast_slice(&data));
        }
        self.count = count;
    }

    /// Views written this frame.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// The whole buffer, bound as `array<ShadowView>`.
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }

    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The layout of [`ViewBuffer::pass_group`]: one uniform `ShadowView`.
    pub fn pass_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// View `index` alone, for a pass that renders it.
    pub fn pass_group(&self, index: u32) -> Option<&wgpu::BindGroup> {
        self.pass_groups.get(index as usize)
    }

    fn create_pass_groups(&self, device: &wgpu::Device) -> Vec<wgpu::BindGroup> {
        (0..u64::from(self.capacity))
            .map(|k| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("ViewBuffer::pass_group"),
                    layout: &self.layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &self.buffer,
                            offset: k * ShadowViewGpu::STRIDE,
                            size: wgpu::BufferSize::new(ShadowViewGpu::STRIDE),
                        }),
                    }],
                })
            })
            .collect()
    }
}

fn create_buffer(device: &wgpu::Device, capacity: u32) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("ViewBuffer::views"),
        size: u64::from(capacity.max(1)) * ShadowViewGpu::STRIDE,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::UNIFORM
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
