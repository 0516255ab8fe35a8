//! Caster culling on the GPU (Bittner 2011, DigitalRune) for every shadow view of a frame at
//! once: receiver masks in each view's light space, max pyramids of each view's shadow map, of
//! its mask and of the camera's depth, and the two-phase caster tests of `cull.wgsl`. Every
//! instance has one indirect draw per view whose instance count the tests set to 0 or 1.
//! Nothing waits on the GPU: stage counts and per-object outcomes come back a frame or two
//! later, per view, like the other counters.
//!
//! One frame, after the camera prepass and the visible flags:
//!
//! ```text
//! encode_first_phase   per view: GEOM/BVOL raster at the mask's size; FRAG's taps from the
//!                      camera's fragments (every view in one pass); the masks' pyramids (or
//!                      the oracle's casters); the camera depth's pyramid for DigitalRune;
//!                      then the first phase: visible receivers (GEOM, FRAG) and last
//!                      frame's light-visible casters
//! (technique)          per view: those casters into the view's map
//! encode_second_phase  per view: the map's max pyramid; every caster through light frustum,
//!                      occlusion, then the mask or the shadow volume against the camera
//! (technique)          per view: the survivors, on top
//! encode_far_ends      dr-progressive: the finished maps' far ends for the next frame
//! ```
//!
//! Long-lived: pipelines and the buffers below, which follow the scene, the map size and the
//! number of views. Per frame: the parameters, and the bind groups in [`CullPass`], which
//! `encode_first_phase` returns for the later steps.

mod gpu_data;
mod pipelines;
mod resources;
mod results;

use glam::Mat4;

use gpu_data::{CullFrameGpu, CullViewGpu};
#[cfg(test)]
pub(crate) use pipelines::shader_sources;
use pipelines::{CullPipelines, SharedLayouts};
pub use resources::MAX_MASK_SIZE;
use resources::{CameraPyramid, SceneResources, SizedKey, SizedResources};
use results::CullResults;
pub use results::{CullResult, ViewCull};

use super::codes::{COUNTER_SLOTS, method_bits as bits};
use super::{CasterOutcome, Method};
use crate::gpu::{GpuContext, GpuCounters, buffer_entry, color_attachment, depth_pass, view_entry};
use crate::scene_gpu::{DrawList, SceneGpu};
use crate::shadow_view::{ShadowSettings, ShadowView, ViewBuffer};

const WORKGROUP: u32 = 64;

/// Why GPU culling could not run a frame.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CullError {
    #[error("GPU culling has no {what} for this frame (prepare was not called)")]
    NotPrepared { what: &'static str },
    #[error("'{method}' does not cull on the GPU")]
    CpuMethod { method: &'static str },
    #[error("{views} shadow views, but culling was prepared for {capacity}")]
    TooManyViews { views: u32, capacity: u32 },
}

/// What the long-lived resources follow: the technique's depth array and the camera.
pub struct CullTargets<'a> {
    /// Side of every view's square, texels.
    pub resolution: u32,
    /// Views the buffers hold (the depth array's layers).
    pub capacity: u32,
    /// Changes whenever the technique replaces its depth array.
    pub maps_generation: u64,
    /// The method's depth array, every layer (the occlusion pyramids' base).
    pub shadow_maps: &'a wgpu::TextureView,
    pub views: &'a ViewBuffer,
    pub camera_size: (u32, u32),
    pub camera_depth: &'a wgpu::TextureView,
}

/// One frame's inputs.
pub struct CullFrame<'a> {
    pub method: Method,
    pub frame_index: u64,
    pub views: &'a [ShadowView],
    pub view_buffer: &'a ViewBuffer,
    pub camera_clip_from_world: Mat4,
    pub shadow: &'a ShadowSettings,
    pub casters_total: u32,
    /// For incremental updates: the maps hold nothing usable (first frame, new light, scene
    /// or exclusions): cleared, every caster drawn.
    pub full_redraw: bool,
    pub visible_flags: &'a wgpu::Buffer,
    pub frame_bind_group: &'a wgpu::BindGroup,
    /// The camera's depth (for the EQUAL-tested receiver passes) and its draws.
    pub camera_depth: &'a wgpu::TextureView,
    pub camera_draws: &'a DrawList,
    pub indirect_first_instance: bool,
    /// The reference maps' depth and caster ids (arrays); drawn already for `oracle`.
    pub reference: (&'a wgpu::TextureView, &'a wgpu::TextureView),
    /// One view of each layer of the method's maps (incremental updates clear there).
    pub shadow_layers: &'a [wgpu::TextureView],
}

/// What passes from the first phase to the later steps of one frame.
pub struct CullPass {
    bits: u32,
    views: u32,
    cull_group: wgpu::BindGroup,
}

/// The mask of one view, as the light's view inset shows it.
pub struct MaskForInset<'a> {
    pub raster: &'a wgpu::TextureView,
    pub bits: &'a wgpu::Buffer,
    /// The view's first word in `bits`, and the mask's side in texels.
    pub bits_offset: u32,
    pub mask_size: u32,
    /// Shadow texels per mask texel.
    pub scale: u32,
    /// Which masks the method has: raster, fragment depths.
    pub raster_shown: bool,
    pub fragment_shown: bool,
}

/// Long-lived pipelines; resources follow the scene, the maps and the camera.
pub struct GpuCulling {
    pipelines: CullPipelines,
    frame_params: wgpu::Buffer,
    view_params: wgpu::Buffer,
    view_params_capacity: u32,
    counters: GpuCounters,
    sized: Option<SizedResources>,
    camera: Option<CameraPyramid>,
    scene: Option<SceneResources>,
    excluded: Vec<u32>,
    exclusions_changed: bool,
    results: CullResults,
}

impl GpuCulling {
    /// `frame_layout` is group 0 of scene passes; `pass_view_layout` one view alone.
    pub fn new(
        ctx: &GpuContext,
        frame_layout: &wgpu::BindGroupLayout,
        pass_view_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let device = &ctx.device;
        let pipelines = CullPipelines::new(
            ctx,
            &SharedLayouts {
                frame: frame_layout,
                pass_view: pass_view_layout,
            },
        );
        if pipelines.geometry.is_empty() {
            log::warn!(
                "no conservative rasterisation or line polygons: GEOM masks use bounding boxes"
            );
        }
        if pipelines.fragment_mask.is_none() {
            log::warn!(
                "no forced early depth tests (SHADER_EARLY_DEPTH_TEST): FRAG runs without its \
                 mask and the oracle method draws every caster in the light frustum"
            );
        }
        Self {
            pipelines,
            frame_params: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("GpuCulling::frame_params"),
                size: size_of::<CullFrameGpu>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            view_params: create_view_params(device, 1),
            view_params_capacity: 1,
            counters: GpuCounters::new(device, "GpuCulling::counters", COUNTER_SLOTS as usize),
            sized: None,
            camera: None,
            scene: None,
            excluded: Vec::new(),
            exclusions_changed: false,
            results: CullResults::default(),
        }
    }

    /// Whether `method` culls here (the CPU methods do not).
    pub fn handles(method: Method) -> bool {
        method.gpu_bits().is_some()
    }

    /// Leaves these instances out from the next frame on.
    pub fn exclude(&mut self, instances: &[u32]) {
        self.excluded = instances.to_vec();
        self.exclusions_changed = true;
    }

    /// Follows the scene, the technique's maps and the camera.
    pub fn prepare(&mut self, ctx: &GpuContext, scene_gpu: &SceneGpu, targets: &CullTargets<'_>) {
        let device = &ctx.device;
        let capacity = targets.capacity.max(1);
        let key = SizedKey {
            resolution: targets.resolution,
            capacity,
            maps_generation: targets.maps_generation,
            views_generation: targets.views.generation(),
        };
        if self.sized.as_ref().is_none_or(|s| s.key != key) {
            let sized = SizedResources::new(
                device,
                key,
                targets.shadow_maps,
                targets.views,
                &self.pipelines.reduce,
            );
            self.sized = Some(sized);
        }
        if self
            .camera
            .as_ref()
            .is_none_or(|c| c.size != targets.camera_size)
        {
            self.camera = Some(CameraPyramid::new(
                device,
                targets.camera_size,
                targets.camera_depth,
                &self.pipelines.reduce,
            ));
        }
        if self
            .scene
            .as_ref()
            .is_none_or(|s| s.scene_id != scene_gpu.id || s.capacity != capacity)
        {
            self.scene = Some(SceneResources::new(
                ctx,
                scene_gpu,
                capacity,
                &self.excluded,
            ));
            self.results.clear();
        } else if self.exclusions_changed
            && let Some(scene) = &self.scene
        {
            scene.write_exclusions(ctx, &self.excluded);
        }
        self.exclusions_changed = false;
        if capacity > self.view_params_capacity {
            self.view_params = create_view_params(device, capacity);
            self.view_params_capacity = capacity;
        }
        self.counters
            .ensure_words(device, (COUNTER_SLOTS * capacity) as usize);
    }

    /// View `view`'s indirect draws (one per instance) in the shared buffer: the buffer, the
    /// byte offset and the count.
    pub fn view_draws(&self, view: u32) -> Option<(&wgpu::Buffer, u64, u32)> {
        self.scene
            .as_ref()
            .map(|s| (&s.draws, s.draws_offset(view), s.instance_count))
    }

    /// The method's bits on this device: without conservative rasterisation or line polygons
    /// GEOM takes boxes; without the receiver passes (no forced early depth tests) FRAG has no
    /// mask and the oracle method draws every caster in the light frustum.
    fn effective_bits(&self, method: Method) -> Option<u32> {
        let mut b = method.gpu_bits()?;
        if b & bits::GEOM != 0 && self.pipelines.geometry.is_empty() {
            b = (b & !bits::GEOM) | bits::BVOL;
        }
        if b & bits::FRAG != 0 && self.pipelines.fragment_mask.is_none() {
            b &= !(bits::FRAG | bits::MASK);
        }
        if b & bits::ORACLE != 0 && self.pipelines.oracle.is_none() {
            b = 0;
        }
        Some(b)
    }

    /// What the device changes about `method`, for the report.
    pub fn device_notes(&self, method: Method) -> Vec<String> {
        let mut notes = Vec::new();
        let Some(wanted) = method.gpu_bits() else {
            return notes;
        };
        if wanted & bits::GEOM != 0 && self.pipelines.geometry.is_empty() {
            notes.push(format!(
                "{}: no conservative rasterisation or line polygons, so receiver boxes stand in \
                 for their geometry",
                method.name()
            ));
        }
        if wanted & (bits::FRAG | bits::ORACLE) != 0 && self.pipelines.fragment_mask.is_none() {
            notes.push(format!(
                "{}: no forced early depth tests, so its receiver pass cannot run and it draws \
                 every caster in the light frustum",
                method.name()
            ));
        }
        notes
    }

    /// This frame's bits: an incremental update that must redraw everything has no mask.
    fn frame_bits(&self, frame: &CullFrame<'_>) -> Result<u32, CullError> {
        let b = self
            .effective_bits(frame.method)
            .ok_or(CullError::CpuMethod {
                method: frame.method.name(),
            })?;
        Ok(if b & bits::INCREMENTAL != 0 && frame.full_redraw {
            b & !bits::MASK
        } else {
            b
        })
    }

    fn resources(&self) -> Result<(&SizedResources, &SceneResources, &CameraPyramid), CullError> {
        let missing = |what| CullError::NotPrepared { what };
        Ok((
            self.sized.as_ref().ok_or(missing("masks and pyramids"))?,
            self.scene.as_ref().ok_or(missing("scene buffers"))?,
            self.camera.as_ref().ok_or(missing("camera pyramid"))?,
        ))
    }

    fn write_params(&self, ctx: &GpuContext, frame: &CullFrame<'_>, method: u32) {
        let Ok((sized, scene, camera)) = self.resources() else {
            return;
        };
        let params = CullFrameGpu {
            camera_clip_from_world: frame.camera_clip_from_world.to_cols_array_2d(),
            counts: [
                scene.instance_count,
                frame.views.len() as u32,
                camera.base,
                0,
            ],
            camera: [camera.size.0, camera.size.1, 0, 0],
        };
        ctx.queue
            .write_buffer(&self.frame_params, 0, bytemuck::bytes_of(&params));
        let shadow = frame.shadow;
        let pcf_radius = shadow.pcf.width().div_ceil(2);
        let normal_offset = shadow.normal_offset_texels.max(0.0);
        let views: Vec<CullViewGpu> = frame
            .views
            .iter()
            .map(|view| {
                let light = &view.light;
                let texel_m = light.texel_size_m[0].max(light.texel_size_m[1]);
                CullViewGpu {
                    params: [
                        method,
                        pcf_radius + normal_offset.ceil() as u32 + 1,
                        view.target.size / sized.mask_size,
                        sized.mask_size,
                    ],
                    volume: [
                        (normal_offset + 1.0) * texel_m / light.depth_range_m.max(1e-6),
                        0.0,
                        0.0,
                        0.0,
                    ],
                    pyramids: [sized.occlusion.words, sized.mask.words, 0, 0],
                }
            })
            .collect();
        ctx.queue
            .write_buffer(&self.view_params, 0, bytemuck::cast_slice(&views));
    }

    fn cull_bind_group(
        &self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
    ) -> Result<wgpu::BindGroup, CullError> {
        let (sized, scene, camera) = self.resources()?;
        Ok(ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("GpuCulling::cull_bind_group"),
            layout: &self.pipelines.cull_layout,
            entries: &[
                buffer_entry(0, &self.frame_params),
                buffer_entry(1, &self.view_params),
                buffer_entry(2, frame.view_buffer.buffer()),
                buffer_entry(3, &scene_gpu.bounds_buffer),
                buffer_entry(4, frame.visible_flags),
                buffer_entry(5, &scene.draws),
                buffer_entry(6, &scene.state),
                buffer_entry(7, self.counters.buffer()),
                buffer_entry(8, &scene.selection),
                buffer_entry(9, &sized.occlusion.buffer),
                buffer_entry(10, &sized.mask.buffer),
                buffer_entry(11, &scene.receiver_draws),
                buffer_entry(12, &camera.pyramid.buffer),
            ],
        }))
    }

    /// Records the masks and the first phase: after it, each view's first shadow pass draws
    /// [`GpuCulling::view_draws`]. Returns what the later steps of this frame need.
    pub fn encode_first_phase(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame: &CullFrame<'_>,
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

        if method & bits::MASK != 0 {
            encoder.clear_buffer(&sized.mask_bits, 0, None);
            if method & bits::GEOM != 0 {
                self.dispatch(
                    encoder,
                    "GpuCulling::receivers",
                    &self.pipelines.receivers,
                    &cull_group,
                    (groups, views),
                );
            }
            let mask_group = self.mask_group(ctx, scene_gpu, frame, scene);
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
                self.rasterise_mask(
                    encoder,
                    scene_gpu,
                    scene,
                    method,
                    &sized.mask_layers[v as usize],
                    &mask,
                );
                if method & bits::INCREMENTAL != 0
                    && let Some(layer) = frame.shadow_layers.get(view.target.layer as usize)
                {
                    self.clear_moved(encoder, scene, layer, view, &mask);
                }
            }
        }
        let receiver_pipeline = if method & bits::FRAG != 0 {
            self.pipelines.fragment_mask.as_ref()
        } else if method & bits::ORACLE != 0 {
            self.pipelines.oracle.as_ref()
        } else {
            None
        };
        if let Some(pipeline) = receiver_pipeline {
            self.receiver_pass(ctx, encoder, scene_gpu, frame, pipeline, (sized, scene));
        }
        if method & bits::MASK != 0 {
            let reduce = &self.pipelines.reduce;
            sized
                .mask
                .reduce(encoder, (&reduce.mask, &reduce.level), views);
        }
        if method & bits::VOLUME != 0 {
            let reduce = &self.pipelines.reduce;
            camera
                .pyramid
                .reduce(encoder, (&reduce.camera_depth, &reduce.level), 1);
        }
        self.dispatch(
            encoder,
            "GpuCulling::first_phase",
            &self.pipelines.first_phase,
            &cull_group,
            (groups, views),
        );
        Ok(CullPass {
            bits: method,
            views,
            cull_group,
        })
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
        let (sized, scene, _) = self.resources()?;
        if pass.bits & bits::OCCLUSION != 0 {
            let reduce = &self.pipelines.reduce;
            sized
                .occlusion
                .reduce(encoder, (&reduce.depth, &reduce.level), pass.views);
        }
        let groups = scene.instance_count.div_ceil(WORKGROUP).max(1);
        self.dispatch(
            encoder,
            "GpuCulling::second_phase",
            &self.pipelines.second_phase,
            &pass.cull_group,
            (groups, pass.views),
        );
        if pass.bits & bits::INCREMENTAL != 0 {
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
        }
        self.results.submitted(
            frame.frame_index,
            frame.method,
            frame.casters_total,
            pass.views,
        );
        Ok(())
    }

    /// After every view's second shadow pass, for DigitalRune's progressive mode: the pyramids
    /// of the finished maps and each caster's shadow-volume far end for the next frame.
    pub fn encode_far_ends(&self, encoder: &mut wgpu::CommandEncoder, pass: CullPass) {
        let (Ok((sized, scene, _)), true) = (self.resources(), pass.bits & bits::PROGRESSIVE != 0)
        else {
            return;
        };
        let reduce = &self.pipelines.reduce;
        sized
            .occlusion
            .reduce(encoder, (&reduce.depth, &reduce.level), pass.views);
        let groups = scene.instance_count.div_ceil(WORKGROUP).max(1);
        self.dispatch(
            encoder,
            "GpuCulling::far_ends",
            &self.pipelines.far_ends,
            &pass.cull_group,
            (groups, pass.views),
        );
    }

    /// One caster-test pass over every instance of every view.
    fn dispatch(
        &self,
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
            pass.draw(0..6, 0..scene.instance_count);
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
        let t = view.target;
        pass.set_viewport(
            t.origin[0] as f32,
            t.origin[1] as f32,
            t.size as f32,
            t.size as f32,
            0.0,
            1.0,
        );
        groups.bind(&mut pass);
        pass.set_pipeline(&self.pipelines.clear_moved);
        pass.draw(0..12, 0..scene.instance_count);
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

    /// Call after submit.
    pub fn after_submit(&mut self) {
        self.counters.after_submit();
        if let Some(scene) = &mut self.scene {
            scene.state_readback.map_copied();
        }
    }

    /// Takes what has come back (needs a device poll first).
    pub fn collect(&mut self) {
        if let Some((frame_index, words)) = self.counters.take_latest() {
            self.results.counters_arrived(frame_index, &words);
        }
        if let Some(scene) = &mut self.scene
            && let Some((frame_index, bytes)) = scene.state_readback.take_latest()
        {
            let words: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
            self.results
                .states_arrived(frame_index, &words, scene.instance_count);
        }
    }

    /// The newest counts that have come back.
    pub fn latest(&self) -> Option<&CullResult> {
        self.results.latest.as_ref()
    }

    /// The newest per-view, per-instance outcomes that have come back, and their frame.
    pub fn latest_outcomes(&self) -> Option<(u64, &[Vec<CasterOutcome>])> {
        self.results
            .latest_outcomes
            .as_ref()
            .map(|(f, o)| (*f, o.as_slice()))
    }

    /// View `view`'s mask under `method`, as the light's view inset shows it.
    pub fn mask_for_inset(&self, method: Method, view: u32) -> Option<MaskForInset<'_>> {
        let sized = self.sized.as_ref()?;
        let b = self.effective_bits(method).unwrap_or(0);
        Some(MaskForInset {
            raster: sized.mask_layers.get(view as usize)?,
            bits: &sized.mask_bits,
            bits_offset: view * sized.mask_size * sized.mask_size,
            mask_size: sized.mask_size,
            scale: sized.key.resolution / sized.mask_size,
            raster_shown: b & (bits::GEOM | bits::BVOL | bits::INCREMENTAL) != 0,
            fragment_shown: b & bits::FRAG != 0,
        })
    }

    /// Per view and instance, state words (outcome code in the low byte), bound by the
    /// `casters` overlay and the inset.
    pub fn state_buffer(&self) -> Option<&wgpu::Buffer> {
        self.scene.as_ref().map(|s| &s.state)
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

fn create_view_params(device: &wgpu::Device, capacity: u32) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("GpuCulling::view_params"),
        size: u64::from(capacity.max(1)) * size_of::<CullViewGpu>() as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gpu_methods_are_the_gpu_driven_ones() {
        for m in Method::ALL {
            assert_eq!(GpuCulling::handles(m), m.gpu_driven(), "{}", m.name());
        }
    }
}
