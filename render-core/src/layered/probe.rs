//! Whether this device's multiview renders every view into its own layer. Some drivers expose
//! the feature and draw only the first view (lavapipe in Mesa 22.3, as Debian 12 ships it):
//! the multiview path then falls back to a pass per map, and the report says why.

use std::num::NonZeroU32;

use crate::gpu::{GpuContext, depth_attachment, read_texture_layer, shader_module};
use crate::shaders::compose;
use crate::shadow_view::SHADOW_FORMAT;

/// The probe's shader, as the renderer and the validation test compose it.
pub(crate) fn probe_source() -> String {
    compose("layered/multiview_probe.wgsl", &[])
}

/// Renders two views of a triangle at depths 0.25 and 0.75 into a two-layer depth array and
/// reads the second layer back: true when it holds 0.75. Blocks, once per device.
pub fn multiview_reaches_every_layer(ctx: &GpuContext) -> bool {
    ctx.probe_once("multiview reaches every layer", || probe(ctx))
}

fn probe(ctx: &GpuContext) -> bool {
    if !ctx.features().contains(wgpu::Features::MULTIVIEW)
        || ctx.device.limits().max_multiview_view_count < 2
    {
        return false;
    }
    let device = &ctx.device;
    let module = shader_module(device, "Layered::multiview_probe", probe_source());
    let mask = NonZeroU32::new(0b11);
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("Layered::multiview_probe"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_probe"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: SHADOW_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: None,
        multiview_mask: mask,
        cache: None,
    });
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("Layered::multiview_probe"),
        size: wgpu::Extent3d {
            width: 64,
            height: 64,
            depth_or_array_layers: 2,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SHADOW_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = super::targets::layer_range(&texture, 0, 2);
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("Layered::multiview_probe"),
    });
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("Layered::multiview_probe"),
            color_attachments: &[],
            depth_stencil_attachment: Some(depth_attachment(&view, Some(1.0))),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: mask,
        });
        pass.set_pipeline(&pipeline);
        pass.draw(0..3, 0..1);
    }
    ctx.queue.submit([encoder.finish()]);
    read_texture_layer(ctx, &texture, wgpu::TextureAspect::DepthOnly, 1).is_ok_and(|layer| {
        layer
            .bytes
            .get(..4)
            .is_some_and(|b| (f32::from_le_bytes([b[0], b[1], b[2], b[3]]) - 0.75).abs() < 1e-3)
    })
}
