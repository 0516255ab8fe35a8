//! The culled draws: each path draws the triangles per-layer culling kept (`cull.rs`), one
//! indirect draw per slot, fetching their vertices in the shader (`culled.wgsl`): a pass and a
//! draw per view, a multiview pass and a draw per group, or a pass per atlas page with one
//! multi-draw over its views.

use std::collections::HashMap;
use std::num::NonZeroU32;

use super::cull::TriangleCull;
use super::paths::{MapPass, PathInput, map_pass};
use super::targets::LayeredMaps;
use crate::gpu::{
    GpuContext, bind_group_layout, buffer_entry, pipeline_layout, shader_module, storage, uniform,
};
use crate::shaders::compose;
use crate::shadow_view::depth_pipeline;

/// The culled draws' shaders, as the renderer and the validation test compose them: a pass
/// per view, a multiview group, an atlas page (clip distances).
pub(crate) fn culled_sources() -> [(&'static str, String); 3] {
    [
        ("Layered::culled", compose("layered/culled.wgsl", &[])),
        (
            "Layered::culled_multiview",
            compose("layered/culled_multiview.wgsl", &[]),
        ),
        (
            "Layered::culled_atlas",
            format!(
                "enable clip_distances;\n{}",
                compose("layered/culled_atlas.wgsl", &[])
            ),
        ),
    ]
}

/// Long-lived pipelines of the culled draws, and this frame's bind group.
pub struct CulledDraws {
    group_layout: wgpu::BindGroupLayout,
    layout: wgpu::PipelineLayout,
    traditional: wgpu::RenderPipeline,
    multiview: Option<(wgpu::ShaderModule, HashMap<u32, wgpu::RenderPipeline>)>,
    atlas: Option<wgpu::RenderPipeline>,
    /// The bind group and the culling's generation it was made for.
    group: Option<(u64, wgpu::BindGroup)>,
}

impl CulledDraws {
    /// `layouts`: group 0 of scene passes and one view alone; `multiview` and `atlas`: whether
    /// those paths run here.
    pub fn new(
        ctx: &GpuContext,
        [frame, pass_view]: [&wgpu::BindGroupLayout; 2],
        (multiview, atlas): (bool, bool),
    ) -> Self {
        let device = &ctx.device;
        let group_layout = bind_group_layout(
            device,
            "Layered::culled",
            wgpu::ShaderStages::VERTEX,
            &[storage(true), storage(true), uniform()],
        );
        let layout = pipeline_layout(
            device,
            "Layered::culled",
            &[frame, pass_view, &group_layout],
        );
        let [(_, one), (_, group), (_, tiles)] = culled_sources();
        let module = shader_module(device, "Layered::culled", one);
        let traditional = depth_pipeline(
            device,
            (&layout, &module, "vs_culled"),
            None,
            (true, wgpu::CompareFunction::Less),
        );
        let multiview = multiview.then(|| {
            (
                shader_module(device, "Layered::culled_multiview", group),
                HashMap::new(),
            )
        });
        let atlas = atlas.then(|| {
            let module = shader_module(device, "Layered::culled_atlas", tiles);
            depth_pipeline(
                device,
                (&layout, &module, "vs_culled_atlas"),
                None,
                (true, wgpu::CompareFunction::Less),
            )
        });
        Self {
            group_layout,
            layout,
            traditional,
            multiview,
            atlas,
            group: None,
        }
    }

    /// The bind group of the culling's records, the scene's vertices and the page side, made
    /// again only when the culling's buffers change (`TriangleCull::generation`).
    pub fn prepare(&mut self, device: &wgpu::Device, cull: &TriangleCull, maps: &LayeredMaps) {
        if self
            .group
            .as_ref()
            .is_some_and(|(g, _)| *g == cull.generation)
        {
            return;
        }
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Layered::culled"),
            layout: &self.group_layout,
            entries: &[
                buffer_entry(0, &cull.records),
                buffer_entry(1, cull.vertices()),
                buffer_entry(2, &maps.page),
            ],
        });
        self.group = Some((cull.generation, group));
    }

    /// A pass per view, one indirect draw of its slot.
    pub fn draw_traditional(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (maps, cull): (&LayeredMaps, &TriangleCull),
        input: &PathInput<'_>,
    ) -> u32 {
        let Some((_, group)) = &self.group else {
            return 0;
        };
        let mut passes = 0;
        for (v, view) in (0..).zip(input.views) {
            let (Some(target), Some(pass_group)) = (
                maps.layers.get(view.target.layer as usize),
                input.view_buffer.pass_group(v),
            ) else {
                continue;
            };
            let pass = MapPass {
                target,
                mask: None,
                square: Some(view.target),
                pipeline: &self.traditional,
                groups: &[input.frame_group, pass_group, group],
            };
            map_pass(encoder, input, pass, |render| {
                render.draw_indirect(&cull.draws, 16 * u64::from(v));
            });
            passes += 1;
        }
        passes
    }

    /// A multiview pass per group of `group` views, one indirect draw of its slot.
    pub fn draw_multiview(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        (maps, cull): (&LayeredMaps, &TriangleCull),
        (input, group): (&PathInput<'_>, usize),
    ) -> Option<u32> {
        let (module, pipelines) = self.multiview.as_mut()?;
        let (_, bind_group) = self.group.as_ref()?;
        let groups = input.views.len().div_ceil(group.max(1));
        for g in 0..groups {
            let first = g * group;
            let count = (input.views.len() - first).min(group) as u32;
            let mask = NonZeroU32::new((1u32 << count) - 1);
            let pipeline = pipelines.entry(count).or_insert_with(|| {
                depth_pipeline(
                    &ctx.device,
                    (&self.layout, module, "vs_culled_multiview"),
                    mask,
                    (true, wgpu::CompareFunction::Less),
                )
            });
            let Some(pass_group) = input.view_buffer.pass_group(first as u32) else {
                continue;
            };
            let square = input.views[first].target;
            let Some(target) = maps.groups.get(g) else {
                continue;
            };
            let pass = MapPass {
                target,
                mask,
                square: Some(square),
                pipeline,
                groups: &[input.frame_group, pass_group, bind_group],
            };
            map_pass(encoder, input, pass, |render| {
                render.draw_indirect(&cull.draws, 16 * g as u64);
            });
        }
        Some(groups as u32)
    }

    /// A pass per atlas page, one multi-draw over its views' slots.
    pub fn draw_atlas(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (maps, cull): (&LayeredMaps, &TriangleCull),
        input: &PathInput<'_>,
    ) -> Option<u32> {
        let pipeline = self.atlas.as_ref()?;
        let (_, bind_group) = self.group.as_ref()?;
        let pass_group = input.view_buffer.pass_group(0)?;
        for (page, target) in (0..).zip(&maps.layers) {
            let first = input.views.iter().position(|v| v.target.layer == page);
            let count = input
                .views
                .iter()
                .filter(|v| v.target.layer == page)
                .count();
            let pass = MapPass {
                target,
                mask: None,
                square: None,
                pipeline,
                groups: &[input.frame_group, pass_group, bind_group],
            };
            map_pass(encoder, input, pass, |render| {
                if let Some(first) = first {
                    render.multi_draw_indirect(&cull.draws, 16 * first as u64, count as u32);
                }
            });
        }
        Some(maps.layers.len() as u32)
    }
}
