//! Recording GPU culling's passes for one frame: the masks and the first phase, the occlusion
//! pyramids and the second phase, the progressive far ends; every view in one dispatch, the
//! masks one render pass per view.

use super::footprints::Phase;
use super::resources::{SceneResources, SizedResources};
use super::{CullError, CullFrame, CullPass, FragmentMaskSource, GpuCulling, WORKGROUP};
use crate::culling::codes::{BOX_OUTLINE_VERTICES, method_bits as bits};
use crate::gpu::pass_label::{self, culling as steps};
use crate::gpu::{
    GpuContext, Scope, buffer_entry, color_attachment, depth_attachment, depth_pass, view_entry,
};
use crate::scene_gpu::SceneGpu;
use crate::shadow_view::ShadowView;

impl GpuCulling {
    /// Records the masks and the first phase: after it, each view's first shadow pass draws
    /// [`GpuCulling::view_draws`]. Returns what the later steps of this frame need.
    pub fn encode_first_phase(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
    ) -> Result<CullPass, CullError> {
        let scope = frame.timer.open_scope(pass_label::CULLING, encoder);
        let pass = self.first_phase(ctx, encoder, scene_gpu, frame, &scope);
        scope.close(encoder);
        pass
    }

    fn first_phase(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
        scope: &Scope<'_>,
    ) -> Result<CullPass, CullError> {
        let method = self.frame_bits(frame)?;
        let views = frame.views.len() as u32;
        let (sized, scene, camera) = self.resources()?;
        if views > scene.capacity || views > sized.key.capacity {
            return Err(CullError::TooManyViews {
                views,
                capacity: scene.capacity.min(sized.key.capacity),
            });
        }
        self.write_params(ctx, frame, method);
        let cull_group = self.cull_bind_group(ctx, scene_gpu, frame)?;
        let groups = scene.instance_count.div_ceil(WORKGROUP).max(1);
        scene.reset_selection(encoder, views);
        self.counters.clear(encoder);

        // One group for this frame's footprint passes and the changed region's clear.
        let footprint_group = (method & bits::FOOTPRINT != 0)
            .then(|| self.footprint_group(ctx, scene_gpu, (sized, scene)));
        scope.step(steps::MASKS, encoder, |encoder| {
            let groups = (&cull_group, footprint_group.as_ref());
            self.masks(ctx, encoder, scene_gpu, frame, method, groups)
        })?;
        let from_surface = self.fragment_mask_source == FragmentMaskSource::Surface;
        scope.step(steps::FRAGMENT_MASK, encoder, |encoder| {
            if method & bits::FRAG != 0 && from_surface && std::env::var("SL_SKIP_FM").is_err() {
                self.surface_mask(ctx, encoder, frame, sized);
            }
            let receiver_pipeline = if method & bits::FRAG != 0 {
                self.pipelines
                    .fragment_mask
                    .as_ref()
                    .filter(|_| !from_surface)
            } else if method & bits::ORACLE != 0 {
                self.pipelines.oracle.as_ref()
            } else {
                None
            };
            if let Some(pipeline) = receiver_pipeline {
                self.receiver_pass(ctx, encoder, scene_gpu, frame, pipeline, (sized, scene));
            }
        });
        scope.step(steps::PYRAMIDS, encoder, |encoder| {
            let reduce = &self.pipelines.reduce;
            if method & bits::MASK != 0 && std::env::var("SL_SKIP_MP").is_err() {
                sized
                    .mask
                    .reduce(encoder, (&reduce.mask, &reduce.level), views);
            }
            if method & bits::VOLUME != 0 {
                camera
                    .pyramid
                    .reduce(encoder, (&reduce.camera_depth, &reduce.level), 1);
            }
        });
        scope.step(steps::CASTER_TESTS, encoder, |encoder| {
            encoder.clear_buffer(&scene.footprint_draws, 0, None);
            dispatch(
                encoder,
                "GpuCulling::first_phase",
                &self.pipelines.first_phase,
                &cull_group,
                (groups, views),
            );
        });
        let pass = CullPass {
            bits: method,
            views,
            footprint_group,
            cull_group,
        };
        scope.step(steps::FOOTPRINTS, encoder, |encoder| {
            self.test_footprints(encoder, scene_gpu, frame, &pass, Phase::First)
        })?;
        Ok(pass)
    }

    /// The raster masks of every view (BVOL's boxes, GEOM's geometry and its widening) and
    /// `incr`'s changed region.
    fn masks(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
        method: u32,
        (cull_group, footprint_group): (&wgpu::BindGroup, Option<&wgpu::BindGroup>),
    ) -> Result<(), CullError> {
        let views = frame.views.len() as u32;
        let (sized, scene, _) = self.resources()?;
        let groups = scene.instance_count.div_ceil(WORKGROUP).max(1);
        if method & bits::MASK != 0 {
            encoder.clear_buffer(&sized.mask_bits, 0, None);
            if method & bits::GEOM != 0 {
                dispatch(
                    encoder,
                    "GpuCulling::receivers",
                    &self.pipelines.receivers,
                    cull_group,
                    (groups, views),
                );
            }
            let mask_group = self.mask_group(ctx, scene_gpu, frame, scene);
            // At the mask's full resolution the changed region is found texel by texel
            // against the map (`vs_moved_faces`); a coarser mask takes whole rectangles.
            let exact_changes =
                method & bits::INCREMENTAL != 0 && sized.mask_size == sized.key.resolution;
            let raster_bits = if exact_changes {
                method & !bits::INCREMENTAL
            } else {
                method
            };
            for (v, view) in (0..views).zip(frame.views) {
                let pass_view = frame
                    .view_buffer
                    .pass_group(v)
                    .ok_or(CullError::NotPrepared {
                        what: "view bind groups",
                    })?;
                let mask = MaskPass {
                    frame_group: frame.frame_bind_group,
                    mask_group: &mask_group,
                    pass_view,
                    view: v,
                };
                let mask_layer = &sized.mask_layers[v as usize];
                if method & bits::RASTER_MASK != 0 {
                    self.rasterise_mask(encoder, scene_gpu, scene, raster_bits, mask_layer, &mask);
                }
                let Some(layer) = frame
                    .shadow_layers
                    .get(view.target.layer as usize)
                    .filter(|_| method & bits::INCREMENTAL != 0)
                else {
                    continue;
                };
                if let Some(footprint_group) = footprint_group.filter(|_| exact_changes) {
                    self.mark_changes(encoder, scene, (mask_layer, layer), &mask);
                    self.clear_marked(encoder, view, layer, (footprint_group, &mask));
                } else {
                    self.clear_moved(encoder, scene, layer, view, &mask);
                }
            }
            if method & bits::GEOM != 0 && method & bits::FOOTPRINT != 0 {
                self.widen_masks(ctx, encoder, sized, views);
            }
        }
        Ok(())
    }

    /// Records each view's occlusion pyramid (of its map as the first phase left it) and the
    /// second phase; after it, each view's second shadow pass draws [`GpuCulling::view_draws`]
    /// on top of the first.
    pub fn encode_second_phase(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
        pass: &CullPass,
    ) -> Result<(), CullError> {
        let scope = frame.timer.open_scope(pass_label::CULLING, encoder);
        let tested = self.second_phase(encoder, scene_gpu, frame, pass, &scope);
        scope.close(encoder);
        tested?;
        if pass.bits & bits::INCREMENTAL != 0 {
            let (_, scene, _) = self.resources()?;
            encoder.copy_buffer_to_buffer(
                &scene_gpu.bounds_buffer,
                0,
                &scene.previous_bounds,
                0,
                None,
            );
        }
        self.counters.copy(encoder, frame.frame_index);
        if let Some(scene) = &mut self.scene {
            scene
                .state_readback
                .copy(encoder, &scene.state, frame.frame_index);
            // After this frame the states hold a light-visible set (encode_after_maps).
            scene.has_history = true;
        }
        self.results.submitted(
            frame.frame_index,
            frame.method,
            frame.casters_total,
            pass.views,
        );
        Ok(())
    }

    fn second_phase(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
        pass: &CullPass,
        scope: &Scope<'_>,
    ) -> Result<(), CullError> {
        let (sized, scene, _) = self.resources()?;
        if pass.bits & bits::OCCLUSION != 0 {
            scope.step(steps::PYRAMIDS, encoder, |encoder| {
                let reduce = &self.pipelines.reduce;
                sized
                    .occlusion
                    .reduce(encoder, (&reduce.depth, &reduce.level), pass.views);
            });
        }
        let groups = scene.instance_count.div_ceil(WORKGROUP).max(1);
        scope.step(steps::CASTER_TESTS, encoder, |encoder| {
            encoder.clear_buffer(&scene.footprint_draws, 0, None);
            dispatch(
                encoder,
                "GpuCulling::second_phase",
                &self.pipelines.second_phase,
                &pass.cull_group,
                (groups, pass.views),
            );
        });
        scope.step(steps::FOOTPRINTS, encoder, |encoder| {
            self.test_footprints(encoder, scene_gpu, frame, pass, Phase::Second)
        })
    }

    /// After every view's second shadow pass, for the next frame: which drawn casters the
    /// light sees (methods that draw them first), and for DigitalRune's progressive mode the
    /// pyramids of the finished maps and each caster's shadow-volume far end.
    pub fn encode_after_maps(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
        pass: &CullPass,
    ) -> Result<(), CullError> {
        let scope = frame.timer.open_scope(pass_label::CULLING, encoder);
        let done = self.after_maps(encoder, scene_gpu, frame, pass, &scope);
        scope.close(encoder);
        done
    }

    fn after_maps(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
        pass: &CullPass,
        scope: &Scope<'_>,
    ) -> Result<(), CullError> {
        if pass.bits & bits::TEMPORAL != 0 {
            scope.step(steps::FOOTPRINTS, encoder, |encoder| {
                self.test_footprints(encoder, scene_gpu, frame, pass, Phase::LightVisible)
            })?;
        }
        let (sized, scene, _) = self.resources()?;
        if pass.bits & bits::PROGRESSIVE == 0 {
            return Ok(());
        }
        scope.step(steps::PYRAMIDS, encoder, |encoder| {
            let reduce = &self.pipelines.reduce;
            sized
                .occlusion
                .reduce(encoder, (&reduce.depth, &reduce.level), pass.views);
        });
        let groups = scene.instance_count.div_ceil(WORKGROUP).max(1);
        scope.step(steps::CASTER_TESTS, encoder, |encoder| {
            dispatch(
                encoder,
                "GpuCulling::far_ends",
                &self.pipelines.far_ends,
                &pass.cull_group,
                (groups, pass.views),
            );
        });
        Ok(())
    }

    fn mask_group(
        &self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
        scene: &SceneResources,
    ) -> wgpu::BindGroup {
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("GpuCulling::mask_bind_group"),
            layout: &self.pipelines.mask_layout,
            entries: &[
                buffer_entry(0, &self.frame_params),
                buffer_entry(1, &self.view_params),
                buffer_entry(2, &scene_gpu.bounds_buffer),
                buffer_entry(3, frame.visible_flags),
                buffer_entry(4, &scene.state),
                buffer_entry(5, &scene.previous_bounds),
            ],
        })
    }

    /// One view's BVOL boxes and GEOM geometry of visible receivers into its mask layer.
    fn rasterise_mask(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        scene: &SceneResources,
        method: u32,
        mask_layer: &wgpu::TextureView,
        groups: &MaskPass<'_>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("GpuCulling::rasterise_mask"),
            color_attachments: &[Some(color_attachment(
                mask_layer,
                wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            ))],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        groups.bind(&mut pass);
        if method & bits::BVOL != 0 {
            pass.set_pipeline(&self.pipelines.boxes);
            pass.draw(0..BOX_OUTLINE_VERTICES, 0..scene.instance_count);
        }
        if method & bits::INCREMENTAL != 0 {
            pass.set_pipeline(&self.pipelines.moved_boxes);
            pass.draw(0..12, 0..scene.instance_count);
        }
        if method & bits::GEOM != 0 {
            pass.set_vertex_buffer(0, scene_gpu.vertex_buffer.slice(..));
            pass.set_index_buffer(scene_gpu.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
            for pipeline in &self.pipelines.geometry {
                pass.set_pipeline(pipeline);
                pass.multi_draw_indexed_indirect(
                    &scene.receiver_draws,
                    scene.draws_offset(groups.view),
                    scene.instance_count,
                );
            }
        }
    }

    /// Incremental updates: the moving objects' old and new boxes cleared in one view's map
    /// (to the far plane), before the casters that touch them are drawn again.
    fn clear_moved(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &SceneResources,
        layer: &wgpu::TextureView,
        view: &ShadowView,
        groups: &MaskPass<'_>,
    ) {
        let mut pass = depth_pass(encoder, "GpuCulling::clear_moved", layer, None, None);
        view.target.set_viewport(&mut pass);
        groups.bind(&mut pass);
        pass.set_pipeline(&self.pipelines.clear_moved);
        pass.draw(0..12, 0..scene.instance_count);
    }

    /// Incremental updates at full mask resolution: the moved boxes' faces into the mask
    /// where the map does not hold something nearer.
    fn mark_changes(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &SceneResources,
        (mask_layer, map_layer): (&wgpu::TextureView, &wgpu::TextureView),
        groups: &MaskPass<'_>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("GpuCulling::mark_changes"),
            color_attachments: &[Some(color_attachment(mask_layer, wgpu::LoadOp::Load))],
            depth_stencil_attachment: Some(depth_attachment(map_layer, None)),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        groups.bind(&mut pass);
        pass.set_pipeline(&self.pipelines.moved_faces);
        pass.draw(0..72, 0..scene.instance_count);
    }

    /// Incremental updates: the marked texels of one view's map cleared to the far plane.
    fn clear_marked(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        view: &ShadowView,
        map_layer: &wgpu::TextureView,
        (footprint_group, groups): (&wgpu::BindGroup, &MaskPass<'_>),
    ) {
        let mut pass = depth_pass(encoder, "GpuCulling::clear_marked", map_layer, None, None);
        view.target.set_viewport(&mut pass);
        pass.set_pipeline(&self.pipelines.clear_marked);
        pass.set_bind_group(0, groups.frame_group, &[]);
        pass.set_bind_group(1, footprint_group, &[]);
        pass.set_bind_group(2, groups.pass_view, &[]);
        pass.draw(0..3, 0..1);
    }

    /// FRAG's taps from the prepass's surface targets: every visible pixel, every view.
    fn surface_mask(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        frame: &CullFrame<'_>,
        sized: &SizedResources,
    ) {
        let (ids, positions, normals) = frame.surface;
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("GpuCulling::surface_mask_bind_group"),
            layout: &self.pipelines.surface_mask_layout,
            entries: &[
                buffer_entry(0, &self.view_params),
                buffer_entry(1, &sized.mask_bits),
                view_entry(5, ids),
                view_entry(6, positions),
                view_entry(7, normals),
            ],
        });
        let Ok((_, _, camera)) = self.resources() else {
            return;
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("GpuCulling::surface_mask"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipelines.surface_mask);
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.dispatch_workgroups(camera.size.0.div_ceil(8), camera.size.1.div_ceil(8), 1);
    }

    /// FRAG's taps or the oracle's casters, from the camera's visible fragments, every view in
    /// one pass.
    fn receiver_pass(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
        pipeline: &wgpu::RenderPipeline,
        (sized, scene): (&SizedResources, &SceneResources),
    ) {
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("GpuCulling::receivers_bind_group"),
            layout: &self.pipelines.receivers_layout,
            entries: &[
                buffer_entry(0, &self.view_params),
                buffer_entry(1, &sized.mask_bits),
                view_entry(2, frame.reference.0),
                view_entry(3, frame.reference.1),
                buffer_entry(4, &scene.selection),
            ],
        });
        let mut pass = depth_pass(
            encoder,
            "GpuCulling::receiver_pass",
            frame.camera_depth,
            None,
            None,
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, frame.frame_bind_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        frame
            .camera_draws
            .draw(&mut pass, scene_gpu, frame.indirect_first_instance);
    }
}

/// The groups of a pass that renders one view's mask or clears its changed region.
struct MaskPass<'a> {
    frame_group: &'a wgpu::BindGroup,
    mask_group: &'a wgpu::BindGroup,
    pass_view: &'a wgpu::BindGroup,
    view: u32,
}

impl MaskPass<'_> {
    fn bind(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(0, self.frame_group, &[]);
        pass.set_bind_group(1, self.mask_group, &[]);
        pass.set_bind_group(2, self.pass_view, &[]);
    }
}

/// One caster-test pass over every instance of every view.
pub(super) fn dispatch(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    group: &wgpu::BindGroup,
    (groups, views): (u32, u32),
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, group, &[]);
    pass.dispatch_workgroups(groups, views.max(1), 1);
}
