//! Group 0 of every scene pass: the frame uniforms, the scene's instances and the frame's
//! shadow views (`view/common.wgsl`). The layout and uniform buffer are long-lived; the bind
//! group follows the scene and the view buffer.

use super::gpu_data::FrameUniforms;
use crate::gpu::{GpuContext, bind_group_layout, buffer_entry, storage, uniform};
use crate::scene_gpu::SceneGpu;
use crate::shadow_view::ViewBuffer;

pub struct FrameBindings {
    pub layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    /// The group and what it was built for: scene id and view buffer generation.
    group: Option<((u64, u64), wgpu::BindGroup)>,
}

impl FrameBindings {
    pub fn new(device: &wgpu::Device) -> Self {
        let layout = bind_group_layout(
            device,
            "Frame::frame_layout",
            wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
            &[uniform(), storage(true), storage(true)],
        );
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("Frame::uniforms"),
            size: size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            layout,
            uniforms,
            group: None,
        }
    }

    /// Writes this frame's uniforms and returns group 0 for `scene_gpu` and `views`.
    pub fn prepare(
        &mut self,
        ctx: &GpuContext,
        uniforms: &FrameUniforms,
        scene_gpu: &SceneGpu,
        views: &ViewBuffer,
    ) -> wgpu::BindGroup {
        ctx.queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(uniforms));
        let key = (scene_gpu.id, views.generation());
        match &self.group {
            Some((k, group)) if *k == key => group.clone(),
            _ => {
                let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("Frame::frame_bind_group"),
                    layout: &self.layout,
                    entries: &[
                        buffer_entry(0, &self.uniforms),
                        buffer_entry(1, &scene_gpu.instance_buffer),
                        buffer_entry(2, views.buffer()),
                    ],
                });
                self.group = Some((key, group.clone()));
                group
            }
        }
    }
}
