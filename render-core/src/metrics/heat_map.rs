//! The error heat map overlay. Long-lived pipeline; the bind group follows the view targets.

use crate::gpu::{bind_group_layout, draw_fullscreen, fullscreen_pipeline, texture, view_entry};
use crate::palette;
use crate::shaders::compose;
use crate::view::targets::{COLOR_FORMAT, ViewTargets};

/// The heat map's shader, as the renderer and the validation test compose it.
pub(crate) fn shader_source() -> String {
    let palette = palette::wgsl();
    compose(
        "metrics/heat_map.wgsl",
        &[(palette::WGSL_PATH, palette.as_str())],
    )
}

pub struct HeatMapOverlay {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl HeatMapOverlay {
    pub fn new(device: &wgpu::Device) -> Self {
        let layout = bind_group_layout(
            device,
            "HeatMap::layout",
            wgpu::ShaderStages::FRAGMENT,
            &[texture(
                wgpu::TextureSampleType::Float { filterable: false },
                wgpu::TextureViewDimension::D2,
            )],
        );
        let target = wgpu::ColorTargetState {
            format: COLOR_FORMAT,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        };
        let pipeline = fullscreen_pipeline(
            device,
            "HeatMap",
            &shader_source(),
            "fs_heat_map",
            &layout,
            target,
        );
        Self { pipeline, layout }
    }

    /// Tints the colour target where the method's shadow differs from the reference's.
    pub fn draw(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        targets: &ViewTargets,
    ) {
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("HeatMap::bind_group"),
            layout: &self.layout,
            entries: &[view_entry(0, &targets.shadow_view)],
        });
        draw_fullscreen(
            encoder,
            "HeatMap::draw",
            &targets.color_view,
            (&self.pipeline, &bind_group),
        );
    }
}
