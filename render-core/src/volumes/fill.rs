//! The fill the shadow volumes cost (Lloyd et al.'s measure): when measuring or showing the
//! heat map, the frame's volume faces are drawn once more with the depth test off, and each
//! fragment is counted in total, where its volume's counting writes the stencil (behind the
//! visible surface for z-fail, in front of it for z-pass) and per pixel (`fs_fill` in `draw.wgsl`). The totals travel with the culling counters;
//! the per-pixel counts make the fill heat map (`fill_heat.wgsl`).

use super::pipelines::{DrawModules, StripPipelines, VolumePass, read_only_pass};
use crate::gpu::{
    bind_group_layout, buffer_entry, depth_texture, draw_fullscreen, fullscreen_pipeline,
    pipeline_layout, storage, uniform, view_entry,
};
use crate::view::ViewTargets;
use crate::view::targets::COLOR_FORMAT;

/// The groups and buffers a fill pass draws with.
pub(super) struct FillDraw<'a> {
    pub frame: &'a wgpu::BindGroup,
    pub scene: &'a wgpu::BindGroup,
    pub records: &'a wgpu::BindGroup,
    pub draws: &'a wgpu::Buffer,
    /// Whether the volumes are cut to their strips (`StripPipelines::draw`).
    pub cut: bool,
    /// Where the totals go: bytes 8 to 16 of the counters read back.
    pub counters: &'a wgpu::Buffer,
}

struct Counts {
    size: (u32, u32),
    buffer: wgpu::Buffer,
}

pub(super) struct Fill {
    layout: wgpu::BindGroupLayout,
    pipelines: StripPipelines,
    heat_layout: wgpu::BindGroupLayout,
    heat: wgpu::RenderPipeline,
    size_uniform: wgpu::Buffer,
    counts: Option<Counts>,
}

impl Fill {
    /// `layouts`: groups 0 to 2 of the volume draws; `modules` hold their vertex entries,
    /// `fs_fill` and `fs_fill_pass`.
    pub fn new(
        device: &wgpu::Device,
        layouts: [&wgpu::BindGroupLayout; 3],
        modules: &DrawModules,
        (format, depth_clamped): (wgpu::TextureFormat, bool),
    ) -> Self {
        let layout = bind_group_layout(
            device,
            "VolumeFill::layout",
            wgpu::ShaderStages::FRAGMENT,
            &[storage(false), depth_texture()],
        );
        let pipeline_layout = pipeline_layout(
            device,
            "VolumeFill::pipeline_layout",
            &[layouts[0], layouts[1], layouts[2], &layout],
        );
        let pipelines = StripPipelines::new(
            device,
            (&pipeline_layout, modules),
            (format, depth_clamped),
            VolumePass::Fill,
        );
        let heat_layout = bind_group_layout(
            device,
            "VolumeFill::heat_layout",
            wgpu::ShaderStages::FRAGMENT,
            &[storage(true), uniform()],
        );
        let heat = fullscreen_pipeline(
            device,
            "VolumeFill::heat",
            &heat_shader_source(),
            "fs_fill_heat",
            &heat_layout,
            wgpu::ColorTargetState {
                format: COLOR_FORMAT,
                blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                write_mask: wgpu::ColorWrites::ALL,
            },
        );
        Self {
            layout,
            pipelines,
            heat_layout,
            heat,
            size_uniform: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("VolumeFill::size"),
                size: 16,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            counts: None,
        }
    }

    /// Counts this frame's fill into the per-pixel buffer and the totals into the counters.
    /// `depth_stencil`: the volumes' target (its depth is not tested); `camera_depth`: the
    /// prepass's depth.
    pub fn draw(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        (targets, depth_stencil): (&ViewTargets, &wgpu::TextureView),
        draw: &FillDraw<'_>,
    ) {
        let size = (targets.width, targets.height);
        if self.counts.as_ref().is_none_or(|c| c.size != size) {
            self.counts = Some(Counts {
                size,
                buffer: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("VolumeFill::counts"),
                    size: (2 + u64::from(size.0) * u64::from(size.1)) * 4,
                    usage: wgpu::BufferUsages::STORAGE
                        | wgpu::BufferUsages::COPY_DST
                        | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
            });
            queue.write_buffer(
                &self.size_uniform,
                0,
                bytemuck::cast_slice(&[size.0, size.1, 0, 0]),
            );
        }
        let counts = &self.counts.as_ref().expect("made above").buffer;
        encoder.clear_buffer(counts, 0, None);
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("VolumeFill::group"),
            layout: &self.layout,
            entries: &[buffer_entry(0, counts), view_entry(1, &targets.depth_view)],
        });
        {
            let mut pass = read_only_pass(encoder, "VolumeFill::draw", None, depth_stencil);
            pass.set_bind_group(0, draw.frame, &[]);
            pass.set_bind_group(1, draw.scene, &[]);
            pass.set_bind_group(2, draw.records, &[]);
            pass.set_bind_group(3, &group, &[]);
            self.pipelines.draw(&mut pass, draw.draws, draw.cut);
        }
        encoder.copy_buffer_to_buffer(counts, 0, draw.counters, 8, 8);
    }

    /// The fill heat map over the colour target, from the last fill counted at its size.
    pub fn draw_heat(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        targets: &ViewTargets,
    ) {
        let Some(counts) = self
            .counts
            .as_ref()
            .filter(|c| c.size == (targets.width, targets.height))
        else {
            return;
        };
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("VolumeFill::heat_group"),
            layout: &self.heat_layout,
            entries: &[
                buffer_entry(0, &counts.buffer),
                buffer_entry(1, &self.size_uniform),
            ],
        });
        draw_fullscreen(
            encoder,
            "VolumeFill::heat",
            &targets.color_view,
            (&self.heat, &group),
        );
    }
}

/// The heat map's shader, with the palette.
pub(crate) fn heat_shader_source() -> String {
    let palette = crate::palette::wgsl();
    crate::shaders::compose(
        "volumes/fill_heat.wgsl",
        &[(crate::palette::WGSL_PATH, palette.as_str())],
    )
}
