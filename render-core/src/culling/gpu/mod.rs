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

mod encode;
mod footprints;
mod frame;
mod gpu_data;
mod pipelines;
mod resources;
mod results;

pub use frame::{CullError, CullFrame, CullPass, CullTargets, FragmentMaskSource, MaskForInset};
use gpu_data::{CullFrameGpu, CullViewGpu};
#[cfg(test)]
pub(crate) use pipelines::shader_sources;
use pipelines::{CullPipelines, SharedLayouts};
pub use resources::MAX_MASK_SIZE;
use resources::{CameraPyramid, SceneResources, SizedKey, SizedResources, largest_binding};
use results::CullResults;
pub use results::{CullResult, ViewCull};

use super::codes::{COUNTER_SLOTS, method_bits as bits};
use super::{CasterOutcome, Method};
use crate::gpu::{GpuContext, GpuCounters, buffer_entry};
use crate::scene_gpu::SceneGpu;

const WORKGROUP: u32 = 64;

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
    fragment_mask_source: FragmentMaskSource,
    /// Why this frame's views cannot be culled here (buffers past the adapter's limits).
    unfit: Option<CullError>,
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
            fragment_mask_source: FragmentMaskSource::default(),
            unfit: None,
        }
    }

    /// Whether `method` culls here (the CPU methods do not).
    pub fn handles(method: Method) -> bool {
        method.gpu_bits().is_some()
    }

    /// Where FRAG's mask comes from (the surface targets by default; the camera pass to
    /// compare with).
    pub fn set_fragment_mask_source(&mut self, source: FragmentMaskSource) {
        self.fragment_mask_source = source;
    }

    /// Whether FRAG's mask can be built on this device from `source`: the camera pass needs
    /// forced early depth tests.
    fn fragment_mask_available(&self) -> bool {
        self.fragment_mask_source == FragmentMaskSource::Surface
            || self.pipelines.fragment_mask.is_some()
    }

    /// Leaves these instances out from the next frame on.
    pub fn exclude(&mut self, instances: &[u32]) {
        self.excluded = instances.to_vec();
        self.exclusions_changed = true;
    }

    /// Whether culling `views` views of maps `resolution` texels square over `instances`
    /// instances fits the buffers this adapter binds.
    pub fn fits(
        limits: &wgpu::Limits,
        resolution: u32,
        views: u32,
        instances: u32,
    ) -> Result<(), CullError> {
        let limit = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let (bytes, what) = largest_binding(resolution, views, instances);
        if bytes > limit {
            return Err(CullError::TooLarge {
                what,
                views,
                resolution,
                bytes,
                limit,
            });
        }
        Ok(())
    }

    /// Follows the scene, the technique's maps and the camera.
    pub fn prepare(&mut self, ctx: &GpuContext, scene_gpu: &SceneGpu, targets: &CullTargets<'_>) {
        let device = &ctx.device;
        let capacity = targets.capacity.max(1);
        // Buffers past what the adapter binds cannot be made: the frame culls nothing then,
        // and says why (`resources`).
        self.unfit = Self::fits(
            &device.limits(),
            targets.resolution,
            capacity,
            scene_gpu.instance_count,
        )
        .err();
        if self.unfit.is_some() {
            self.sized = None;
            return;
        }
        // Before the sized resources: the mask pyramid's groups hold the views' parameters.
        if capacity > self.view_params_capacity {
            self.view_params = create_view_params(device, capacity);
            self.view_params_capacity = capacity;
        }
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
                (targets.views, &self.view_params),
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
        if b & bits::FRAG != 0 && !self.fragment_mask_available() {
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
        let receivers_missing = if wanted & bits::FRAG != 0 {
            !self.fragment_mask_available()
        } else {
            self.pipelines.oracle.is_none()
        };
        if wanted & (bits::FRAG | bits::ORACLE) != 0 && receivers_missing {
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
        if let Some(unfit) = &self.unfit {
            return Err(unfit.clone());
        }
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
                u32::from(scene.has_history),
            ],
            camera: [camera.size.0, camera.size.1, 0, 0],
        };
        ctx.queue
            .write_buffer(&self.frame_params, 0, bytemuck::bytes_of(&params));
        let shadow = frame.shadow;
        let pcf_radius = shadow.pcf.width().div_ceil(2);
        let normal_offset = shadow.normal_offset_texels.max(0.0);
        // A receiver point's taps lie within half the kernel of its lookup, which the normal
        // offset moves by up to `normal_offset` texels (shadow_view/lookup.wgsl).
        let filter_reach = (normal_offset + 0.5 * (shadow.pcf.width() as f32 - 1.0)).ceil() as u32;
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
                    reach: [filter_reach, 0, 0, 0],
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
                buffer_entry(13, &scene.candidates),
                buffer_entry(14, &scene.footprint_draws),
                buffer_entry(15, &scene.footprint_geometry),
            ],
        }))
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
            raster_shown: b & bits::RASTER_MASK != 0,
            fragment_shown: b & bits::FRAG != 0,
        })
    }

    /// Per view and instance, state words (outcome code in the low byte), bound by the
    /// `casters` overlay and the inset.
    pub fn state_buffer(&self) -> Option<&wgpu::Buffer> {
        self.scene.as_ref().map(|s| &s.state)
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
    fn culling_that_would_bind_more_than_the_adapter_allows_says_what_and_how_much() {
        // lavapipe's limit: 128 MiB for one storage binding.
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: 128 << 20,
            ..wgpu::Limits::default()
        };
        // The hall's 72 views at 2048 texels: a 2048² mask of words per view, 1,152 MiB.
        let Err(CullError::TooLarge {
            what, bytes, limit, ..
        }) = GpuCulling::fits(&limits, 2048, 72, 15)
        else {
            panic!("72 masks of 2048² do not fit 128 MiB");
        };
        assert_eq!(
            (what, bytes, limit),
            ("receiver masks", 72 * 2048 * 2048 * 4, 128 << 20)
        );
        // At 512 texels they fit (72 MiB of masks, 24 of pyramids).
        assert_eq!(GpuCulling::fits(&limits, 512, 72, 15), Ok(()));
        // A city of 100,000 instances over 100 views: its indirect draws are the largest.
        let Err(CullError::TooLarge { what, .. }) = GpuCulling::fits(&limits, 512, 100, 100_000)
        else {
            panic!("100 views of 100,000 draws do not fit");
        };
        assert_eq!(what, "indirect draws");
        let message = GpuCulling::fits(&limits, 2048, 72, 15)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("1152 MiB") && message.contains("128 MiB"),
            "{message}"
        );
    }

    #[test]
    fn gpu_methods_are_the_gpu_driven_ones() {
        for m in Method::ALL {
            assert_eq!(GpuCulling::handles(m), m.gpu_driven(), "{}", m.name());
        }
    }
}
