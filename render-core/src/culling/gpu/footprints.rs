//! Recording the footprint test (culling/footprints.wgsl), the texel-exact stage after the
//! cheap pyramid tests: per view, the candidates' boxes rasterised in light space against the
//! mask (and in the second phase the map's depth), then the verdict (`cs_resolve_footprints`).

use super::encode::dispatch;
use super::resources::{FOOTPRINT_DRAW_BYTES, SceneResources, SizedResources};
use super::{CullError, CullFrame, CullPass, GpuCulling, WORKGROUP};
use crate::culling::codes::method_bits as bits;
use crate::gpu::{GpuContext, buffer_entry, depth_pass, view_entry};
use crate::scene_gpu::SceneGpu;

/// Which footprint test a pass runs.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Phase {
    /// Before anything is drawn: boxes against the mask alone.
    First,
    /// After the first phase's casters are drawn: against the map's depth as well.
    Second,
    /// After the maps are finished: the drawn casters' boxes against them and the mask, for
    /// which casters are front-most where they are needed (the next frame's first phase).
    LightVisible,
}

impl GpuCulling {
    /// This frame's group 1 of the footprint passes.
    pub(super) fn footprint_group(
        &self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
        (sized, scene): (&SizedResources, &SceneResources),
    ) -> wgpu::BindGroup {
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("GpuCulling::footprint_bind_group"),
            layout: &self.pipelines.footprint_layout,
            entries: &[
                buffer_entry(0, &self.frame_params),
                buffer_entry(1, &self.view_params),
                buffer_entry(2, &scene_gpu.bounds_buffer),
                buffer_entry(3, &scene.candidates),
                buffer_entry(4, &scene.state),
                buffer_entry(5, &sized.mask_bits),
                buffer_entry(6, &sized.widened),
                view_entry(7, &sized.mask_array),
            ],
        })
    }

    /// GEOM's mask widened by the filter's reach, once the masks are drawn.
    pub(super) fn widen_masks(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        sized: &SizedResources,
        views: u32,
    ) {
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("GpuCulling::widen_bind_group"),
            layout: &self.pipelines.widen_layout,
            entries: &[
                buffer_entry(0, &self.view_params),
                view_entry(1, &sized.mask_array),
                buffer_entry(2, &sized.widened_rows),
                buffer_entry(3, &sized.widened),
            ],
        });
        let groups = sized.mask_size.div_ceil(8);
        for (label, pipeline) in [
            ("GpuCulling::widen_rows", &self.pipelines.widen_rows),
            ("GpuCulling::widen_columns", &self.pipelines.widen_columns),
        ] {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(groups, groups, views.max(1));
        }
    }

    /// Each view's candidates' boxes into its layer of the maps, then the verdict: in the
    /// phases the marked ones are drawn and the others culled by the footprint; after the maps
    /// the drawn ones that were marked are the light's visible casters.
    pub(super) fn test_footprints(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
        pass: &CullPass,
        phase: Phase,
    ) -> Result<(), CullError> {
        // The group exists exactly for methods with the footprint test.
        let Some(group) = &pass.footprint_group else {
            return Ok(());
        };
        let (_, scene, _) = self.resources()?;
        let groups = (scene.instance_count.div_ceil(WORKGROUP).max(1), pass.views);
        let p = &self.pipelines;
        // Where the mask leaves few candidates their geometry, else their boxes.
        let geometry = pass.bits & bits::GEOMETRY_FOOTPRINT != 0;
        let (first, second) = if geometry {
            (&p.footprint_geometry_first, &p.footprint_geometry_second)
        } else {
            (&p.footprint_first, &p.footprint_second)
        };
        let (pipeline, resolve) = match phase {
            Phase::First => (first, &p.resolve),
            Phase::Second => (second, &p.resolve),
            Phase::LightVisible => {
                encoder.clear_buffer(&scene.footprint_draws, 0, None);
                dispatch(
                    encoder,
                    "GpuCulling::collect_drawn",
                    &p.collect_drawn,
                    &pass.cull_group,
                    groups,
                );
                (second, &p.resolve_light_visible)
            }
        };
        for (v, view) in (0..pass.views).zip(frame.views) {
            let not_prepared = |what| CullError::NotPrepared { what };
            let pass_view = frame
                .view_buffer
                .pass_group(v)
                .ok_or(not_prepared("view bind groups"))?;
            let layer = frame
                .shadow_layers
                .get(view.target.layer as usize)
                .ok_or(not_prepared("a layer of the shadow maps"))?;
            let mut render = depth_pass(encoder, "GpuCulling::footprints", layer, None, None);
            view.target.set_viewport(&mut render);
            render.set_pipeline(pipeline);
            render.set_bind_group(0, frame.frame_bind_group, &[]);
            render.set_bind_group(1, group, &[]);
            render.set_bind_group(2, pass_view, &[]);
            if geometry {
                render.set_vertex_buffer(0, scene_gpu.vertex_buffer.slice(..));
                let indices = scene_gpu.index_buffer.slice(..);
                render.set_index_buffer(indices, wgpu::IndexFormat::Uint32);
                let offset = scene.draws_offset(v);
                let draws = &scene.footprint_geometry;
                render.multi_draw_indexed_indirect(draws, offset, scene.instance_count);
            } else {
                let offset = u64::from(v) * FOOTPRINT_DRAW_BYTES;
                render.draw_indirect(&scene.footprint_draws, offset);
            }
        }
        dispatch(
            encoder,
            "GpuCulling::resolve_footprints",
            resolve,
            &pass.cull_group,
            groups,
        );
        Ok(())
    }
}
