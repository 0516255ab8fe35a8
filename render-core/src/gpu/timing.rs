//! GPU time per pass from timestamp queries (wgpu-profiler), when the adapter has them.

use serde::Serialize;
use wgpu_profiler::{GpuProfiler, GpuProfilerQuery, GpuProfilerSettings, GpuTimerQueryResult};

use super::GpuContext;

/// Pass labels, shared by the renderer and readers of [`FrameReport::gpu`].
pub mod pass_label {
    pub const CAMERA_PREPASS: &str = "camera depth+id";
    pub const VISIBILITY: &str = "visible objects";
    pub const SHADOW_MAP: &str = "shadow map";
    /// Measurement only: the reference map of every caster. Not part of a method's cost.
    pub const REFERENCE_MAP: &str = "reference map (measure)";
    /// The GPU culling methods: receiver mask, pyramids and caster tests (both phases).
    pub const CULLING: &str = "mask + culling";
    /// Shadow volumes: the silhouettes and caps found in compute, the visible surface drawn
    /// again into the depth-stencil target, and the volumes into its stencil.
    pub const VOLUME_SILHOUETTES: &str = "silhouettes";
    pub const VOLUME_DEPTH: &str = "volume depth";
    pub const SHADOW_VOLUMES: &str = "shadow volumes";
    /// Virtual shadow maps: marking, the page table and the per-page cull, all in compute.
    pub const VIRTUAL_PAGES: &str = "pages";
    pub const SHADING: &str = "shading";
    pub const OVERLAYS: &str = "overlays";

    /// The steps of [`CULLING`], timed inside it (each summed over the frame's phases).
    pub mod culling {
        /// Clearing and drawing the raster masks (BVOL boxes, GEOM geometry, GEOM's widening)
        /// and `incr`'s changed region.
        pub const MASKS: &str = "masks";
        /// FRAG's taps (from the surface or a second camera pass), or the oracle's casters.
        pub const FRAGMENT_MASK: &str = "fragment mask";
        /// Mask and camera-depth pyramids, and the occlusion pyramids of the maps.
        pub const PYRAMIDS: &str = "pyramids";
        /// The per-caster compute tests (both phases, the far ends).
        pub const CASTER_TESTS: &str = "caster tests";
        /// The texel-exact footprint test, both phases and the light-visible re-test.
        pub const FOOTPRINTS: &str = "footprint test";
    }

    /// The steps of [`VIRTUAL_PAGES`], timed inside it.
    pub mod virtual_maps {
        /// Static occlusion: the farthest static depth of each block of the pages the last
        /// frame drew whole.
        pub const STATIC_DEPTHS: &str = "static depths";
        /// Pages released (moved boxes, left squares) and pages marked by visible pixels.
        pub const MARKING: &str = "marking";
        /// Free pages listed, marked pages given physical pages, eviction, the counts.
        pub const ALLOCATION: &str = "allocation";
        /// Each caster against the pages drawn this frame.
        pub const CULLING: &str = "page culling";
    }

    /// The steps of [`VOLUME_SILHOUETTES`], timed inside it.
    pub mod volumes {
        /// The visible receiver points marked into the grid along the light.
        pub const RECEIVER_GRID: &str = "receiver grid";
        /// Culling and clamping: each caster's occupied intervals (Lloyd's 3.1 and 3.2, on
        /// the GPU here, where the paper spends CPU time).
        pub const CULL_AND_CLAMP: &str = "cull + clamp";
        /// The casters too big for the cull's workgroup, gathered by workgroups of their
        /// own and finished (`volumes/big_casters.wgsl`).
        pub const BIG_CASTERS: &str = "big casters";
        /// Silhouette edges and caps as records for the draws.
        pub const EDGES: &str = "edges + caps";
    }
}

/// GPU time of one pass in one frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PassTiming {
    pub label: String,
    pub gpu_ms: f64,
    /// 0 for a pass of the frame, 1 for a step timed inside one, and so on.
    pub depth: u32,
}

/// Timestamps around each pass. Long-lived; results arrive one or more frames later, so the
/// window never waits for them. Without `TIMESTAMP_QUERY` it records nothing.
pub struct FrameTimer {
    profiler: Option<GpuProfiler>,
    timestamp_period: f32,
    warned_end_frame: bool,
}

impl FrameTimer {
    pub fn new(ctx: &GpuContext) -> Self {
        let enabled = ctx.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let settings = GpuProfilerSettings {
            enable_timer_queries: enabled,
            // Lavapipe crashed in vkCmdBeginDebugUtilsLabelEXT once the culling steps were
            // timed inside their scope; the groups only label captures for graphics debuggers.
            enable_debug_groups: false,
            max_num_pending_frames: 4,
        };
        let profiler = match GpuProfiler::new(&ctx.device, settings) {
            Ok(p) => Some(p),
            Err(e) => {
                log::warn!("GPU pass timing disabled: {e}");
                None
            }
        };
        Self {
            profiler,
            timestamp_period: ctx.queue.get_timestamp_period(),
            warned_end_frame: false,
        }
    }

    /// Whether GPU times will be reported at all.
    pub fn has_gpu_timestamps(&self) -> bool {
        self.profiler
            .as_ref()
            .is_some_and(|p| p.settings().enable_timer_queries)
    }

    /// Opens a pass query; put its [`GpuProfilerQuery::render_pass_timestamp_writes`] into the
    /// pass descriptor and close it with [`FrameTimer::end_pass`] after the pass.
    pub fn begin_pass(
        &self,
        label: &str,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Option<GpuProfilerQuery> {
        self.profiler
            .as_ref()
            .map(|p| p.begin_pass_query(label, encoder))
    }

    /// Times everything recorded into `encoder` until [`FrameTimer::end_pass`], across passes.
    pub fn begin_scope(
        &self,
        label: &str,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Option<GpuProfilerQuery> {
        self.profiler
            .as_ref()
            .map(|p| p.begin_query(label, encoder))
    }

    /// Like [`FrameTimer::begin_scope`], for a scope whose steps are timed inside it
    /// ([`Scope::step`]); close it with [`Scope::close`] on every path.
    pub fn open_scope(&self, label: &str, encoder: &mut wgpu::CommandEncoder) -> Scope<'_> {
        Scope {
            timer: self,
            query: self.begin_scope(label, encoder),
        }
    }

    pub fn end_pass(&self, encoder: &mut wgpu::CommandEncoder, query: Option<GpuProfilerQuery>) {
        if let (Some(p), Some(q)) = (&self.profiler, query) {
            p.end_query(encoder, q);
        }
    }

    /// Resolves this frame's queries; call once per frame before finishing the encoder.
    pub fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(p) = &mut self.profiler {
            p.resolve_queries(encoder);
        }
    }

    /// Closes the frame; call after submitting it.
    pub fn end_frame(&mut self) {
        if let Some(p) = &mut self.profiler
            && let Err(e) = p.end_frame()
            && !self.warned_end_frame
        {
            self.warned_end_frame = true;
            log::warn!("GPU pass timings dropped: {e}");
        }
    }

    /// The oldest finished frame's pass times, if one has come back.
    pub fn take_finished(&mut self) -> Option<Vec<PassTiming>> {
        let results = self
            .profiler
            .as_mut()?
            .process_finished_frame(self.timestamp_period)?;
        let mut out = Vec::new();
        flatten(&results, 0, &mut out);
        Some(out)
    }
}

/// A timed scope whose steps are reported one level below it.
pub struct Scope<'t> {
    timer: &'t FrameTimer,
    query: Option<GpuProfilerQuery>,
}

impl Scope<'_> {
    /// Times what `record` puts into `encoder` as the step `label` of this scope.
    pub fn step<R>(
        &self,
        label: &str,
        encoder: &mut wgpu::CommandEncoder,
        record: impl FnOnce(&mut wgpu::CommandEncoder) -> R,
    ) -> R {
        let query = match (&self.timer.profiler, &self.query) {
            (Some(p), Some(parent)) => {
                Some(p.begin_query(label, encoder).with_parent(Some(parent)))
            }
            _ => None,
        };
        let result = record(encoder);
        self.timer.end_pass(encoder, query);
        result
    }

    pub fn close(self, encoder: &mut wgpu::CommandEncoder) {
        self.timer.end_pass(encoder, self.query);
    }
}

fn flatten(results: &[GpuTimerQueryResult], depth: u32, out: &mut Vec<PassTiming>) {
    for r in results {
        if let Some(time) = &r.time {
            out.push(PassTiming {
                label: r.label.clone(),
                gpu_ms: (time.end - time.start).max(0.0) * 1000.0,
                depth,
            });
        }
        flatten(&r.nested_queries, depth + 1, out);
    }
}

/// The passes summed by label, in order of first appearance (a frame has two shadow passes
/// per view with the culling methods, and each culling step runs in several phases).
pub fn summed_by_label(passes: &[PassTiming]) -> Vec<PassTiming> {
    let mut out: Vec<PassTiming> = Vec::new();
    for pass in passes {
        match out
            .iter_mut()
            .find(|t| t.label == pass.label && t.depth == pass.depth)
        {
            Some(total) => total.gpu_ms += pass.gpu_ms,
            None => out.push(pass.clone()),
        }
    }
    out
}
