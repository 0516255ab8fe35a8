//! What comes back from the GPU after a frame (pass times, visible counts, measurements, the
//! technique's counts) and the blocking reads tests and reports make of the last frame.

use std::collections::VecDeque;

use super::techniques::Family;
use super::{FrameRenderer, FrameReport, FrameSettings, SceneGpu};
use crate::culling::CasterOutcome;
use crate::gpu::{GpuContext, GpuError, PassTiming};
use crate::layered::LayeredTechnique;
use crate::metrics::Measured;
use crate::technique::combined_outcomes;
use crate::view::VisibilityCounts;

/// The newest results that have come back, and what the last frame asked for.
#[derive(Default)]
pub(super) struct Latest {
    pub gpu: Option<(u64, Vec<PassTiming>)>,
    pub visibility: Option<VisibilityCounts>,
    pub measured: Option<Measured>,
    gpu_frames_in_flight: VecDeque<u64>,
    /// Whether the last frame measured; older measurements are not reported after a switch.
    pub measuring: bool,
    /// CPU time of the last frame's camera culling (the BVH), milliseconds.
    pub camera_culling_ms: f64,
}

impl Latest {
    pub fn submitted(
        &mut self,
        frame_index: u64,
        settings: &FrameSettings,
        camera_culling_ms: f64,
    ) {
        self.gpu_frames_in_flight.push_back(frame_index);
        self.camera_culling_ms = camera_culling_ms;
        self.measuring = settings.measure;
    }
}

impl FrameRenderer {
    /// Takes GPU times, visible counts, measurements and the technique's counts that have
    /// come back, without waiting, and puts the newest into `report`. After
    /// [`GpuContext::wait_idle`] they belong to the last frame.
    pub fn collect_finished(&mut self, ctx: &GpuContext, report: &mut FrameReport) {
        // A non-blocking poll runs the map callbacks of finished work.
        if let Err(e) = ctx.device.poll(wgpu::PollType::Poll) {
            log::warn!("device poll failed: {e}");
        }
        let latest = &mut self.latest;
        while let Some(timings) = self.timer.take_finished() {
            let frame = latest
                .gpu_frames_in_flight
                .pop_front()
                .unwrap_or(self.frame_index);
            latest.gpu = Some((frame, timings));
        }
        if let Some(counts) = self.visibility.take_latest() {
            latest.visibility = Some(counts);
        }
        if let Some(m) = self.measure.take_latest() {
            latest.measured = Some(m);
        }
        if let Some((frame, timings)) = &latest.gpu {
            report.gpu.clone_from(timings);
            report.gpu_frame_index = Some(*frame);
        }
        let shadows = self.techniques.active_mut().collect();
        report.cpu.culling_ms = shadows.cpu_culling_ms + latest.camera_culling_ms;
        report.set_shadows(shadows);
        if let Some(refusal) = self.refused {
            report.shadow_failure = Some(refusal.to_owned());
        }
        if let Some(m) = latest.measured.as_ref().filter(|_| latest.measuring) {
            report.set_measured(m);
        }
        if let Some(v) = latest.visibility {
            report.counts.receivers_visible = Some(v.receivers_visible);
            report.counts.objects_visible = Some(v.objects_visible);
        }
    }

    /// Whether every result of the last frame has come back (headless frames wait for it).
    pub(super) fn last_frame_complete(&self) -> bool {
        let frame = self.frame_index;
        let latest = &self.latest;
        (self.observing || latest.visibility.is_some_and(|v| v.frame_index == frame))
            && (!latest.measuring
                || latest
                    .measured
                    .as_ref()
                    .is_some_and(|m| m.frame_index == frame))
            && (self.observing || self.techniques.active().has_results_of(frame))
    }

    /// What happened to each instance in the shadow pass, over every view (rendered where any
    /// view drew it): the last frame's for the CPU methods, the newest that came back for the
    /// GPU methods.
    pub fn caster_outcomes(&self) -> Vec<CasterOutcome> {
        combined_outcomes(&self.techniques.active().view_outcomes())
    }

    /// Per shadow view, what happened to each instance (as [`FrameRenderer::caster_outcomes`]).
    pub fn view_caster_outcomes(&self) -> Vec<Vec<CasterOutcome>> {
        self.techniques
            .active()
            .view_outcomes()
            .into_iter()
            .map(<[CasterOutcome]>::to_vec)
            .collect()
    }

    /// Which instances some pixel of the last frame shows. Blocks: for tests and reports.
    pub fn read_visible(
        &self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
    ) -> Result<Vec<bool>, GpuError> {
        crate::gpu::read_flags(
            ctx,
            &self.visibility.visible_flags,
            scene_gpu.instance_count,
            "visible flags",
        )
    }

    /// The instances drawn into the method's shadow maps, in any view, sorted.
    pub fn drawn_casters(&self) -> Vec<u32> {
        (0..)
            .zip(self.caster_outcomes())
            .filter(|(_, o)| *o == CasterOutcome::Rendered)
            .map(|(i, _)| i)
            .collect()
    }

    /// The last frame's shadow views (where each rendered), for tests and reports.
    pub fn last_views(&self) -> &[crate::shadow_view::ShadowView] {
        self.frozen.as_ref().map_or(&[], |f| f.views.as_slice())
    }

    /// The many-lights technique's maps (a depth array: a layer per map, or atlas pages), as
    /// the last frame with it drew them; for tests.
    /// `None` before any frame drew them.
    pub fn lights_depth_texture(&self) -> Option<&wgpu::Texture> {
        self.techniques
            .layered()
            .map(LayeredTechnique::depth_texture)
    }

    /// The virtual maps' physical page of each page-table entry (where resident) after the
    /// last frame with them. Blocks: for tests.
    pub fn virtual_page_slots(&self, ctx: &GpuContext) -> Result<Vec<u32>, GpuError> {
        self.techniques
            .virtual_maps()
            .map_or(Ok(Vec::new()), |v| v.read_page_slots(ctx))
    }

    /// The virtual maps' physical atlas as the last frame with them left it; for tests.
    pub fn virtual_atlas(&self) -> Option<&wgpu::Texture> {
        self.techniques.virtual_maps()?.atlas()
    }

    /// The virtual maps' page-table flags after the last frame with them (empty before any
    /// frame used them; so are the other readers of a technique). Blocks: for tests.
    pub fn virtual_page_flags(&self, ctx: &GpuContext) -> Result<Vec<u32>, GpuError> {
        self.techniques
            .virtual_maps()
            .map_or(Ok(Vec::new()), |v| v.read_page_flags(ctx))
    }

    /// The virtual maps' receiver masks as the last frame left them (two words per entry).
    /// Blocks: for tests.
    pub fn virtual_receiver_masks(&self, ctx: &GpuContext) -> Result<Vec<[u32; 2]>, GpuError> {
        self.techniques
            .virtual_maps()
            .map_or(Ok(Vec::new()), |v| v.read_receiver_masks(ctx))
    }

    /// The virtual maps' (caster, page) pairs of the last frame, and which of them the
    /// per-page oracle holds (when it measured). Blocks: for tests.
    pub fn virtual_pairs(
        &self,
        ctx: &GpuContext,
    ) -> Result<Vec<crate::virtual_maps::DrawnPair>, GpuError> {
        self.techniques
            .virtual_maps()
            .map_or(Ok(Vec::new()), |v| v.read_pairs(ctx))
    }

    /// The virtual maps' hierarchy of page flags as the last frame left it (341 words per
    /// level). Blocks: for tests.
    pub fn virtual_page_hierarchy(&self, ctx: &GpuContext) -> Result<Vec<u32>, GpuError> {
        self.techniques
            .virtual_maps()
            .map_or(Ok(Vec::new()), |v| v.read_page_hierarchy(ctx))
    }

    /// The triangles per-layer culling kept for each slot (a view, or a multiview group) in
    /// the last frame that culled. Blocks: for tests and reports.
    pub fn lights_kept_triangles(&self, ctx: &GpuContext) -> Result<Vec<u32>, GpuError> {
        self.techniques
            .layered()
            .map_or(Ok(Vec::new()), |l| l.read_kept(ctx))
    }

    /// The pipeline statistics of the many-lights technique's last frame, a map pass each.
    /// Blocks: for tests and the bench.
    pub fn lights_pass_statistics(
        &self,
        ctx: &GpuContext,
    ) -> Result<Vec<crate::layered::PassCounts>, GpuError> {
        self.techniques
            .layered()
            .map_or(Ok(Vec::new()), |l| l.read_pass_statistics(ctx))
    }

    /// The last frame's intervals of `instance`'s shadow volume (metres along the light from
    /// the caster; empty when culled), with shadow volumes the frame's setup; `None` otherwise
    /// or for a non-caster. Blocks: for a click, tests and reports.
    pub fn read_volume_intervals(
        &self,
        ctx: &GpuContext,
        instance: u32,
    ) -> Result<Option<Vec<[f32; 2]>>, GpuError> {
        match self.techniques.volumes() {
            Some(volumes) if self.techniques.active_family() == Family::Volumes => {
                volumes.read_intervals(ctx, instance)
            }
            _ => Ok(None),
        }
    }

    /// The oracle flag of every instance from the last measured frame (in any view's oracle).
    /// Blocks: for tests and reports, never the window loop.
    pub fn read_oracle(
        &self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
    ) -> Result<Vec<bool>, GpuError> {
        self.measure
            .read_oracle(ctx, scene_gpu.instance_count, self.views.count())
    }
}
