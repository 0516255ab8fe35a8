//! The virtual maps' page view: with the `light-view` overlay, every level's pages in the
//! colours of what they did this frame (`overlay.wgsl`), in the top-left corner of the view
//! where the other techniques show their light's view.

use crate::gpu::{
    bind_group_layout, buffer_entry, color_attachment, pipeline_layout, storage, uniform,
};
use crate::overlays::LIGHT_VIEW_SIZE;
use crate::view::ViewTargets;

pub(super) fn shader_source() -> String {
    let palette = crate::palette::wgsl();
    crate::shaders::compose(
        "virtual_maps/overlay.wgsl",
        &[(crate::palette::WGSL_PATH, palette.as_str())],
    )
}

pub(super) struct PageView {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl PageView {
    pub fn new(device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let layout = bind_group_layout(
            device,
            "VirtualMaps::page_view",
            wgpu::ShaderStages::FRAGMENT,
            &[uniform(), storage(true)],
        );
        let module = crate::gpu::shader_module(device, "VirtualMaps::page_view", shader_source());
        let pipeline_layout =
            pipeline_layout(device, "VirtualMaps::page_view", &[frame_layout, &layout]);
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("VirtualMaps::page_view"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_pages"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_pages"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[Some(crate::view::targets::COLOR_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        Self { layout, pipeline }
    }

    /// Draws the page view into the top-left corner of `targets`' colour, keeping the rest.
    pub fn draw(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        targets: &ViewTargets,
        (frame_group, params, flags): (&wgpu::BindGroup, &wgpu::Buffer, &wgpu::Buffer),
    ) {
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("VirtualMaps::page_view"),
            layout: &self.layout,
            entries: &[buffer_entry(0, params), buffer_entry(1, flags)],
        });
        let side = (LIGHT_VIEW_SIZE as f32 * 1.5)
            .min(targets.width.min(targets.height) as f32 * 0.5)
            .max(1.0);
        let margin = (side * 0.05).round();
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("VirtualMaps::page_view"),
            color_attachments: &[Some(color_attachment(
                &targets.color_view,
                wgpu::LoadOp::Load,
            ))],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_viewport(margin, margin, side, side, 0.0, 1.0);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
