//! Many shadow-casting lights (Rákos, "Massive number of shadow-casting lights with layered
//! rendering", GPU Pro 4, ch. 19): a view per spot light and six per point light (cube faces),
//! rendered by one of three paths (`paths.rs`: a pass per map, a multiview pass per group, or
//! one instanced atlas draw per mesh), and a light term that sums every light through its map
//! (`light.wgsl`). The sun does not light the frame: the scene's own lights do. The CPU methods
//! choose each view's casters here; the GPU methods cull each view as they cull cascades,
//! through a map technique of their own that renders a pass per map (`gpu_culled.rs`).
//!
//! Long-lived: pipelines, the depth array and the light records (growing as needed). Per
//! frame: the views (`lights.rs`), where they render (`targets.rs`), each view's casters.

mod cull;
mod culled;
mod gpu_culled;
mod lights;
mod paths;
mod probe;
mod statistics;
mod targets;

use std::time::Instant;

#[cfg(test)]
pub(crate) use cull::cull_source;
use cull::{Slot, TriangleCull, slots_of};
use culled::CulledDraws;
#[cfg(test)]
pub(crate) use culled::culled_sources;
use gpu_culled::GpuCulledMaps;
pub use lights::{LightRecord, LightViews, light_views};
use paths::{PathInput, Paths, draw_direct};
#[cfg(test)]
pub(crate) use paths::{atlas_source, multiview_source, traditional_source};
pub use probe::multiview_reaches_every_layer;
#[cfg(test)]
pub(crate) use probe::probe_source;
pub use statistics::PassCounts;
use statistics::PassStatistics;
use targets::LayeredMaps;
pub use targets::place;

use crate::cascades::Cascades;
use crate::culling::{CasterOutcome, Method};
use crate::gpu::{GpuContext, LogOnce};
use crate::scene_gpu::DrawList;
use crate::shadow_map::cpu_casters::CpuCasters;
use crate::shadow_map::{MapTechnique, ViewLayout};
use crate::shadow_view::{LayerCulling, LayeredPath, LayeredSettings, ShadowView, ViewTarget};
use crate::technique::{
    DrawInput, InsetSources, ShadowPasses, ShadowReport, ShadowTechnique, TechniqueInput,
    ViewReport,
};

/// The technique's light term (imported as `technique/light.wgsl` by the shading pass).
pub(crate) const LIGHT_WGSL: &str = "layered/light.wgsl";

/// The many-lights technique.
pub struct LayeredTechnique {
    maps: LayeredMaps,
    paths: Paths,
    cull: TriangleCull,
    culled: CulledDraws,
    statistics: PassStatistics,
    cpu: CpuCasters,
    /// The GPU methods' culling and maps.
    gpu: GpuCulledMaps,
    indirect_first_instance: bool,
    method: Method,
    /// The sun's cascades, when the sun shines too (the first views).
    sun: Option<Cascades>,
    last: LastFrame,
    fallbacks: LogOnce,
    culling_failures: LogOnce,
}

#[derive(Default)]
struct LastFrame {
    views: Vec<ShadowView>,
    /// The path that drew, after the adapter's fallbacks.
    path: LayeredPath,
    /// Render passes and draw calls the path recorded.
    passes: u32,
    draws: u32,
    triangles: u64,
    lights: usize,
    notes: Vec<String>,
    cpu_culling_ms: f64,
    /// CPU time of recording the path's passes and draws, milliseconds.
    cpu_submit_ms: f64,
    culling: LayerCulling,
    triangles_tested: u64,
    /// A GPU method culled and `gpu` rendered the maps.
    gpu_culled: bool,
}

impl LayeredTechnique {
    /// `layouts`: group 0 of scene passes and one view alone.
    pub fn new(ctx: &GpuContext, layouts: [&wgpu::BindGroupLayout; 2]) -> Self {
        let maps = LayeredMaps::new(ctx);
        let paths = Paths::new(ctx, layouts, &maps.page);
        let runs = (paths.multiview_group() > 0, paths.has_atlas());
        Self {
            maps,
            cull: TriangleCull::new(ctx, layouts[0]),
            statistics: PassStatistics::new(ctx),
            culled: CulledDraws::new(ctx, layouts, runs),
            paths,
            cpu: CpuCasters::new(ctx),
            gpu: GpuCulledMaps::new(layouts),
            indirect_first_instance: ctx
                .features()
                .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE),
            method: Method::Vfc,
            sun: None,
            last: LastFrame::default(),
            fallbacks: LogOnce::default(),
            culling_failures: LogOnce::default(),
        }
    }

    /// The sun shines too, shadowed by these cascades (rendered first, by the same path), or
    /// not at all.
    pub fn set_sun(&mut self, cascades: Option<Cascades>) {
        self.sun = cascades;
    }

    /// The depth array the maps are in (the map technique's where a GPU method culled), for
    /// tests that read them back.
    pub fn depth_texture(&self) -> &wgpu::Texture {
        self.gpu_culled()
            .map_or(&self.maps.texture, MapTechnique::depth_texture)
    }

    /// The triangles each slot (a view, or a multiview group) kept in the last frame that
    /// culled. Blocks: for tests and reports.
    pub fn read_kept(&self, ctx: &GpuContext) -> Result<Vec<u32>, crate::gpu::GpuError> {
        self.cull.read_kept(ctx)
    }

    /// The pipeline statistics of the last frame's map passes, a pass each (none where the
    /// adapter has no pipeline-statistics queries). Blocks: for tests and the bench.
    pub fn read_pass_statistics(
        &self,
        ctx: &GpuContext,
    ) -> Result<Vec<PassCounts>, crate::gpu::GpuError> {
        self.statistics.read(ctx)
    }

    /// The culling this frame runs, its jobs prepared: none where it is off, where a record
    /// cannot name the view or the instance (more than 256 views, or 2^24 instances), or
    /// where its records would not fit a buffer the adapter binds (noted).
    fn cull_if_it_fits(
        &mut self,
        ctx: &GpuContext,
        input: &TechniqueInput<'_>,
        slots: &[Slot],
    ) -> LayerCulling {
        let culling = input.layered.culling;
        let views: u32 = slots.iter().map(|s| s.views).sum();
        if culling == LayerCulling::None || views > 256 || input.scene_gpu.instance_count >= 1 << 24
        {
            return LayerCulling::None;
        }
        let tests = (u32::from(culling.frustum()) * cull::CULL_FRUSTUM)
            | (u32::from(culling.back_faces()) * cull::CULL_BACK_FACES);
        match self
            .cull
            .prepare(ctx, (input.scene, input.scene_gpu), slots, tests)
        {
            Ok(()) => {
                self.culling_failures.clear();
                culling
            }
            Err(why) => {
                self.culling_failures.warn(
                    "per-layer culling's records do not fit a buffer this adapter binds: the \
                     maps are drawn unculled (the notes give the sizes)",
                );
                self.last.notes.push(why);
                LayerCulling::None
            }
        }
    }

    /// The path a request runs as here, and why it differs.
    fn path_for(&self, requested: LayeredPath) -> (LayeredPath, Option<&'static str>) {
        match requested {
            LayeredPath::Multiview if self.paths.multiview_group() == 0 => (
                LayeredPath::Traditional,
                Some(if self.paths.multiview_exposed() {
                    "this adapter's multiview draws only the first view of a pass (probed at \
                     start-up; lavapipe in Mesa 22.3 does): 'multiview' runs as 'traditional'"
                } else {
                    "this adapter has no MULTIVIEW: 'multiview' runs as 'traditional'"
                }),
            ),
            LayeredPath::Atlas if !self.paths.has_atlas() => (
                LayeredPath::Traditional,
                Some("this adapter has no CLIP_DISTANCES: 'atlas' runs as 'traditional'"),
            ),
            path => (path, None),
        }
    }
}

impl ShadowTechnique for LayeredTechnique {
    fn name(&self) -> &'static str {
        "lights"
    }

    fn light_term(&self) -> (&'static str, &wgpu::BindGroupLayout) {
        (LIGHT_WGSL, &self.maps.light_layout)
    }

    /// Every method culls each view; the GPU methods need indirect draws with a first
    /// instance, without which they run as `vfc`.
    fn effective_method(&self, requested: Method) -> Method {
        if requested.gpu_driven() && !self.indirect_first_instance {
            Method::Vfc
        } else {
            requested
        }
    }

    /// The sun shines only when asked for (its cascades are then the first views).
    fn sun_scale(&self) -> f32 {
        if self.sun.is_some() { 1.0 } else { 0.0 }
    }

    fn prepare(&mut self, ctx: &GpuContext, input: &TechniqueInput<'_>) -> Vec<ShadowView> {
        self.method = self.effective_method(input.method);
        let mut notes = Vec::new();
        if self.method != input.method {
            let message = format!(
                "this adapter has no INDIRECT_FIRST_INSTANCE: '{}' runs as 'vfc'",
                input.method.name()
            );
            self.fallbacks.warn(&message);
            notes.push(message);
        }
        let limits = ctx.device.limits();
        let max = LayeredSettings::MAX_RESOLUTION.min(limits.max_texture_dimension_2d);
        // A GPU method culls every view at its own map size, where this adapter binds that.
        let gpu_resolution = GpuCulledMaps::resolution(input.shadow.resolution, max);
        let mut gpu_lights = None;
        if self.method.gpu_driven() {
            let lights = light_views(input.scene, input.layered.lights, gpu_resolution);
            let views =
                lights.frusta.len() as u32 + self.sun.as_ref().map_or(0, ViewLayout::layers);
            let instances = input.scene_gpu.instance_count;
            match crate::culling::GpuCulling::fits(&limits, gpu_resolution, views, instances) {
                Ok(()) => gpu_lights = Some(lights),
                Err(unfit) => {
                    let message = format!(
                        "'{}' cannot cull these maps: {unfit}; they are culled by 'vfc'",
                        self.method.name()
                    );
                    self.fallbacks.warn(&message);
                    notes.push(message);
                    self.method = Method::Vfc;
                }
            }
        }
        let gpu = self.method.gpu_driven();
        let resolution = if gpu {
            gpu_resolution
        } else {
            input
                .shadow
                .resolution
                .clamp(LayeredSettings::MIN_RESOLUTION, max)
        };
        let path = if gpu {
            notes.extend(gpu_culling_notes(self.method, input.layered));
            LayeredPath::Traditional
        } else {
            let (path, fallback) = self.path_for(input.layered.path);
            if let Some(fallback) = fallback {
                self.fallbacks.warn(fallback);
                notes.push(fallback.to_owned());
            }
            path
        };
        let lights = gpu_lights
            .unwrap_or_else(|| light_views(input.scene, input.layered.lights, resolution));
        if lights.records.is_empty() {
            notes.push(format!(
                "this scene has no point or spot lights (glTF KHR_lights_punctual; \
                 builtin:hall has 32): only {} light",
                if self.sun.is_some() {
                    "the sun's and ambient"
                } else {
                    "ambient"
                }
            ));
        }
        // The sun's cascades first (the light term reads them as views 0..sun), then the
        // lights' views.
        let sun: Vec<ShadowView> = match &self.sun {
            Some(cascades) => cascades.views(input, self.method, resolution),
            None => Vec::new(),
        };
        let total = sun.len() + lights.frusta.len();
        let (targets, side, layers) = place(path, total, resolution, &limits);
        if targets.len() < total {
            notes.push(format!(
                "{} of {total} maps fit this adapter's textures; the rest are lit unshadowed",
                targets.len(),
            ));
        }
        let sun_views = sun.len().min(targets.len()) as u32;
        let mut records = lights.records;
        for r in &mut records {
            r.views[0] += sun_views;
            // A light whose views did not fit shines unshadowed.
            if r.views[0] + r.views[1] > targets.len() as u32 {
                r.views[1] = 0;
            }
        }
        let group = match path {
            LayeredPath::Multiview => self.paths.multiview_group(),
            _ => 0,
        };
        // The GPU methods' maps are the map technique's: a token array here.
        let (side, layers) = if gpu { (64, 1) } else { (side, layers) };
        self.maps
            .ensure(ctx, (side, layers, group), (&records, sun_views, gpu));
        self.last.path = path;
        self.last.gpu_culled = gpu;
        self.last.lights = records.len();
        self.last.notes = notes;
        let lights = lights
            .names
            .iter()
            .zip(lights.frusta)
            .map(|(name, light)| ShadowView {
                load: input.layered.load,
                ..ShadowView::covering_all_depths(name, light, ViewTarget::layer(0, resolution))
            });
        let views = sun
            .into_iter()
            .map(|view| ShadowView {
                load: input.layered.load,
                ..view
            })
            .chain(lights)
            .zip(targets)
            .map(|(view, target)| ShadowView { target, ..view })
            .collect();
        if gpu {
            self.gpu.prepare(ctx, input, (views, resolution))
        } else {
            views
        }
    }

    fn draw(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: &TechniqueInput<'_>,
        draw: &DrawInput<'_>,
    ) -> ShadowPasses {
        if self.last.gpu_culled {
            return self.draw_gpu_culled(encoder, input, draw);
        }
        let ctx = draw.ctx;
        let started = Instant::now();
        let frusta: Vec<_> = draw.views.iter().map(|v| &v.light).collect();
        let path = self.last.path;
        // The traditional path draws each view's own list; the others build theirs from the
        // views' choices.
        self.cpu.select(
            ctx,
            (input.scene, input.scene_gpu),
            self.method,
            &frusta,
            true,
        );
        self.last.cpu_culling_ms = started.elapsed().as_secs_f64() * 1000.0;
        let recording = Instant::now();
        // Slots: a view each, or a multiview group each, for the culling and multiview's draws
        // (a pass per map or an atlas page unculled draws each view's own list).
        let needs_slots =
            input.layered.culling != LayerCulling::None || path == LayeredPath::Multiview;
        let slots = if needs_slots {
            slots_of(path, &self.cpu, draw.views, self.paths.multiview_group())
        } else {
            Vec::new()
        };
        let culling = self.cull_if_it_fits(ctx, input, &slots);
        let path_input = PathInput {
            views: draw.views,
            view_buffer: draw.view_buffer,
            frame_group: draw.frame_group,
            scene_gpu: input.scene_gpu,
            casters: &self.cpu,
            timer: draw.timer,
            statistics: &self.statistics,
            indirect_first_instance: draw.indirect_first_instance,
        };
        self.statistics.begin_frame();
        let (passes, draws, triangles) = if culling == LayerCulling::None {
            self.last.triangles_tested = 0;
            draw_direct(
                (&mut self.paths, &self.maps, &self.cpu),
                (ctx, encoder),
                (path, &path_input, &slots),
            )
        } else {
            self.culled.prepare(&ctx.device, &self.cull, &self.maps);
            self.cull.encode(encoder, draw.frame_group, draw.timer);
            self.last.triangles_tested = self.cull.triangles;
            let both = (&self.maps, &self.cull);
            let passes = match path {
                LayeredPath::Traditional => {
                    Some(self.culled.draw_traditional(encoder, both, &path_input))
                }
                LayeredPath::Multiview => self.culled.draw_multiview(
                    ctx,
                    encoder,
                    both,
                    (&path_input, self.paths.multiview_group() as usize),
                ),
                LayeredPath::Atlas => self.culled.draw_atlas(encoder, both, &path_input),
            };
            (passes.unwrap_or(0), slots.len() as u32, self.cull.triangles)
        };
        self.statistics.resolve(encoder);
        self.last.culling = culling;
        self.last.cpu_submit_ms = recording.elapsed().as_secs_f64() * 1000.0;
        self.last.passes = passes;
        self.last.draws = draws;
        self.last.triangles = triangles;
        self.last.views = draw.views.to_vec();
        ShadowPasses {
            light_group: self.maps.light_group.clone(),
            outcomes: self.cpu.outcome_buffer().clone(),
        }
    }

    fn after_submit(&mut self) {
        if let Some(maps) = self.gpu_culled_mut() {
            maps.after_submit();
        }
    }

    fn collect(&mut self) -> ShadowReport {
        if let Some(maps) = self.gpu_culled_mut() {
            let mut report = maps.collect();
            let mut notes = self.last.notes.clone();
            notes.append(&mut report.notes);
            report.notes = notes;
            let drawn = |f: fn(&ViewReport) -> u64| report.views.iter().map(f).sum::<u64>();
            let draws = drawn(|v| u64::from(v.casters_rendered)) as u32;
            let triangles = drawn(|v| v.triangles_shadow);
            report.layered = Some(self.facts(draws, triangles));
            return report;
        }
        let views = (0..)
            .zip(&self.last.views)
            .map(|(v, view)| {
                let list = self.cpu.draws(v);
                ViewReport {
                    name: view.name.clone(),
                    stages: self.cpu.stages(v).to_vec(),
                    casters_rendered: list.map_or(0, DrawList::len),
                    triangles_shadow: list.map_or(0, |l| l.triangles),
                    texel_size_m: view.light.texel_size_m,
                    depth_range_m: view.light.depth_range_m,
                    ..ViewReport::default()
                }
            })
            .collect();
        ShadowReport {
            casters_total: self.cpu.casters_total(),
            views,
            notes: self.last.notes.clone(),
            cpu_culling_ms: self.last.cpu_culling_ms,
            layered: Some(self.facts(self.last.draws, self.last.triangles)),
            ..ShadowReport::default()
        }
    }

    fn has_results_of(&self, frame_index: u64) -> bool {
        self.gpu_culled()
            .is_none_or(|maps| maps.has_results_of(frame_index))
    }

    /// The light's view inset where a GPU method culled (its masks and culled casters).
    fn inset(&self, view: u32) -> Option<InsetSources<'_>> {
        self.gpu_culled()?.inset(view)
    }

    fn view_outcomes(&self) -> Vec<&[CasterOutcome]> {
        if let Some(maps) = self.gpu_culled() {
            return maps.view_outcomes();
        }
        (0..self.last.views.len())
            .map(|v| self.cpu.outcomes(v))
            .collect()
    }

    fn exclude(&mut self, instances: &[u32]) {
        self.cpu.exclude(instances);
        if let Some(maps) = self.gpu.technique_mut() {
            maps.exclude(instances);
        }
    }
}

impl LayeredTechnique {
    /// The map technique that culled and rendered the last frame's maps, if a GPU method did.
    fn gpu_culled(&self) -> Option<&MapTechnique> {
        self.gpu.technique().filter(|_| self.last.gpu_culled)
    }

    fn gpu_culled_mut(&mut self) -> Option<&mut MapTechnique> {
        self.gpu.technique_mut().filter(|_| self.last.gpu_culled)
    }

    /// A GPU method's frame: its culling and a pass per map, by the map technique.
    fn draw_gpu_culled(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: &TechniqueInput<'_>,
        draw: &DrawInput<'_>,
    ) -> ShadowPasses {
        let recording = Instant::now();
        let passes = self.gpu.draw(encoder, (input, draw), &mut self.maps);
        self.last.cpu_culling_ms = 0.0;
        self.last.cpu_submit_ms = recording.elapsed().as_secs_f64() * 1000.0;
        self.last.passes = draw.views.len() as u32;
        self.last.culling = LayerCulling::None;
        self.last.triangles_tested = 0;
        self.last.views = draw.views.to_vec();
        passes
    }

    /// What the last frame drew, for the report.
    fn facts(&self, draws: u32, triangles: u64) -> crate::technique::LayeredFacts {
        let last = &self.last;
        crate::technique::LayeredFacts {
            path: last.path,
            lights: last.lights as u32,
            maps: last.views.len() as u32,
            passes: last.passes,
            draws,
            triangles,
            cpu_submit_ms: last.cpu_submit_ms,
            multiview_group: self.paths.multiview_group(),
            culling: last.culling,
            triangles_tested: last.triangles_tested,
        }
    }
}

/// What a GPU method changes of the requested settings: it renders a pass per map, and culls
/// casters per view instead of triangles per layer.
fn gpu_culling_notes(method: Method, settings: &LayeredSettings) -> Vec<String> {
    let mut notes = Vec::new();
    if settings.path != LayeredPath::Traditional {
        notes.push(format!(
            "'{}' culls each view on the GPU and renders a pass per map: '{}' runs as \
             'traditional'",
            method.name(),
            settings.path.name()
        ));
    }
    if settings.culling != LayerCulling::None {
        notes.push(format!(
            "per-layer triangle culling runs with the CPU methods ('none', 'vfc'): '{}' culls \
             whole casters per view instead",
            method.name()
        ));
    }
    notes
}
