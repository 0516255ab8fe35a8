//! Directional shadow maps, the first shadow technique: views of the sun chosen by a
//! [`ViewLayout`] (the single map: one view fitted to the camera's view, FOCUS: to the visible
//! receivers, `incr`: the whole scene, a map that persists between frames; `cascades/`: one
//! per slice of the view frustum), each in a layer of a depth array, its casters chosen by the
//! frame's method per view, and the reference maps of every caster the measures need.
//!
//! Long-lived: pipelines, textures (following resolution and layers), GPU culling, the CPU
//! casters' lists, the persistent map's key. Per frame: the layout, the views and the draw
//! lists.

pub(crate) mod cpu_casters;
mod layout;
pub(crate) mod maps;

use std::time::Instant;

use cpu_casters::CpuCasters;
pub use layout::{GivenViews, SunView, ViewLayout, WarpedSunView};
pub use maps::{CASTER_ID_FORMAT, MapKind};
use maps::{MapArrays, ViewPass};

use crate::culling::{CullError, CullFrame, CullTargets, FragmentMaskSource, GpuCulling, Method};
use crate::gpu::{GpuContext, LogOnce, pass_label};
use crate::shadow_view::{ShadowSettings, ShadowView};
use crate::technique::{
    DrawInput, InsetSources, ShadowPasses, ShadowReport, ShadowTechnique, TechniqueInput,
    ViewReport,
};

/// The technique's light term (imported as `technique/light.wgsl` by the shading pass).
pub(crate) const LIGHT_WGSL: &str = "shadow_map/light.wgsl";

/// The shadow-map technique.
pub struct MapTechnique {
    /// Which views this frame renders.
    layout: Box<dyn ViewLayout>,
    maps: MapArrays,
    cpu: CpuCasters,
    culling: GpuCulling,
    /// The method of the last frame, after fallbacks.
    method: Method,
    indirect_first_instance: bool,
    warned_no_indirect: LogOnce,
    /// Incremental updates: what the persistent maps were drawn for (scene, exclusions, and
    /// each view's light).
    static_map_key: Option<(u64, u64, Vec<[u32; 16]>)>,
    exclusions_version: u64,
    /// What the last frame drew, for its report and the inset: its views, whether GPU culling
    /// ran, what failed.
    last: LastFrame,
    failures: LogOnce,
}

#[derive(Default)]
struct LastFrame {
    views: Vec<ShadowView>,
    /// The shadow settings they were drawn with.
    shadow: ShadowSettings,
    /// Instances of the scene: the stride of per-view blocks.
    instances: u32,
    gpu_culled: bool,
    /// The reference maps were drawn (measuring, or for the oracle method).
    reference_drawn: bool,
    failure: Option<String>,
    cpu_culling_ms: f64,
}

impl MapTechnique {
    /// `frame_layout` is group 0 of scene passes, `pass_view_layout` one shadow view alone.
    pub fn new(
        ctx: &GpuContext,
        frame_layout: &wgpu::BindGroupLayout,
        pass_view_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        Self {
            layout: Box::new(SunView::default()),
            maps: MapArrays::new(
                ctx,
                frame_layout,
                pass_view_layout,
                ShadowSettings::default().resolution,
            ),
            cpu: CpuCasters::new(ctx),
            culling: GpuCulling::new(ctx, frame_layout, pass_view_layout),
            method: Method::None,
            indirect_first_instance: ctx
                .features()
                .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE),
            warned_no_indirect: LogOnce::default(),
            static_map_key: None,
            exclusions_version: 0,
            last: LastFrame::default(),
            failures: LogOnce::default(),
        }
    }

    /// The views the next frames render (the single map, a copy of it per layer, cascades).
    pub fn set_layout(&mut self, layout: Box<dyn ViewLayout>) {
        self.layout = layout;
    }

    /// Where FRAG's mask comes from (the prepass's surface, or a second camera pass).
    pub fn set_fragment_mask_source(&mut self, source: FragmentMaskSource) {
        self.culling.set_fragment_mask_source(source);
    }

    /// The method's depth array, for tests that read its layers back.
    pub fn depth_texture(&self) -> &wgpu::Texture {
        self.maps.depth_texture()
    }

    /// The method's maps, the reference maps and the reference's caster ids, every layer
    /// (another technique's light term reads them: many lights culled on the GPU), with the
    /// generation that changes whenever they are replaced.
    pub(crate) fn map_arrays(&self) -> (u64, [&wgpu::TextureView; 3]) {
        let (reference, ids) = self.maps.reference_arrays();
        (
            self.maps.generation(),
            [self.maps.depth_array(), reference, ids],
        )
    }

    /// Whether an incremental update needs last frame's maps under the same light, scene and
    /// exclusions; anything else redraws them whole. Updates the key.
    fn full_redraw(&mut self, input: &TechniqueInput<'_>, views: &[ShadowView]) -> bool {
        let key = (self.method == Method::Incr).then(|| {
            (
                input.scene_gpu.id,
                self.exclusions_version,
                views
                    .iter()
                    .map(|v| {
                        v.light
                            .light_clip_from_world
                            .to_cols_array()
                            .map(f32::to_bits)
                    })
                    .collect(),
            )
        });
        let full = key.is_none() || key != self.static_map_key;
        self.static_map_key = key;
        full
    }

    /// Each view's casters into its map, from the CPU's draw lists.
    fn draw_lists(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        input: &TechniqueInput<'_>,
        draw: &DrawInput<'_>,
        map: MapKind,
    ) {
        let label = match map {
            MapKind::Method => pass_label::SHADOW_MAP,
            MapKind::Reference => pass_label::REFERENCE_MAP,
        };
        for (v, view) in (0..).zip(draw.views) {
            let (Some(pass_group), Some(list)) = (
                draw.view_buffer.pass_group(v),
                match map {
                    MapKind::Method => self.cpu.draws(v as usize),
                    MapKind::Reference => Some(self.cpu.reference()),
                },
            ) else {
                continue;
            };
            let query = draw.timer.begin_pass(label, encoder);
            self.maps.draw_list(
                encoder,
                view_pass(view, draw.frame_group, pass_group, query.as_ref()),
                (input.scene_gpu, list, draw.indirect_first_instance),
                map,
            );
            draw.timer.end_pass(encoder, query);
        }
    }

    /// The GPU methods: masks and first phase, each view's casters, the occlusion pyramids
    /// and second phase, the survivors (culling/gpu).
    fn draw_culled(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: &TechniqueInput<'_>,
        draw: &DrawInput<'_>,
        full_redraw: bool,
    ) -> Result<(), CullError> {
        let frame = CullFrame {
            method: self.method,
            frame_index: input.frame_index,
            views: draw.views,
            view_buffer: draw.view_buffer,
            camera_clip_from_world: draw.camera_clip_from_world,
            shadow: input.shadow,
            casters_total: self.cpu.casters_total(),
            full_redraw,
            visible_flags: draw.visible_flags,
            frame_bind_group: draw.frame_group,
            camera_depth: &draw.targets.depth_view,
            surface: (
                &draw.targets.ids_view,
                &draw.targets.positions_view,
                &draw.targets.normals_view,
            ),
            camera_draws: draw.camera_draws,
            indirect_first_instance: draw.indirect_first_instance,
            reference: self.maps.reference_arrays(),
            shadow_layers: self.maps.depth_layers(),
            timer: draw.timer,
        };
        let pass = self
            .culling
            .encode_first_phase(draw.ctx, encoder, input.scene_gpu, &frame)?;
        // Incremental updates keep last frame's maps (every other method redraws them).
        self.draw_culled_views(encoder, input, draw, full_redraw)?;
        self.culling
            .encode_second_phase(encoder, input.scene_gpu, &frame, &pass)?;
        self.draw_culled_views(encoder, input, draw, false)?;
        self.culling
            .encode_after_maps(encoder, input.scene_gpu, &frame, &pass)
    }

    /// Every view's culled casters into its map, on top of what is there unless `clear`.
    fn draw_culled_views(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        input: &TechniqueInput<'_>,
        draw: &DrawInput<'_>,
        clear: bool,
    ) -> Result<(), CullError> {
        for (v, view) in (0..).zip(draw.views) {
            let not_prepared = |what| CullError::NotPrepared { what };
            let draws = self.culling.view_draws(v).ok_or(not_prepared("draws"))?;
            let pass_group = draw
                .view_buffer
                .pass_group(v)
                .ok_or(not_prepared("view bind groups"))?;
            let query = draw.timer.begin_pass(pass_label::SHADOW_MAP, encoder);
            self.maps.draw_indirect(
                encoder,
                view_pass(view, draw.frame_group, pass_group, query.as_ref()),
                input.scene_gpu,
                draws,
                clear,
            );
            draw.timer.end_pass(encoder, query);
        }
        Ok(())
    }

    fn view_report(&self, v: usize, view: &ShadowView) -> ViewReport {
        let light = &view.light;
        let texel = light.texel_size_m[0].max(light.texel_size_m[1]);
        let mut report = ViewReport {
            name: view.name.clone(),
            texel_size_m: light.texel_size_m,
            depth_range_m: light.depth_range_m,
            covers_whole_scene: light.covers_whole_scene,
            shades_depth_m: view
                .shades_depth_m
                .map(|d| (d.is_finite() && d.abs() < f32::MAX).then_some(d)),
            shades_by: view.shades_by,
            lispsm_n_m: light.warp.map(|w| w.n_m as f32),
            depth_bias_m: self.last.shadow.depth_bias_m
                + self.last.shadow.depth_bias_texels.max(0.0) * texel,
            pcf_m: self.last.shadow.pcf.width() as f32 * texel,
            ..ViewReport::default()
        };
        if !self.last.gpu_culled {
            report.stages = self.cpu.stages(v).to_vec();
            if let Some(list) = self.cpu.draws(v) {
                report.casters_rendered = list.len();
                report.triangles_shadow = list.triangles;
            }
        } else if let Some(counts) = self
            .culling
            .latest()
            .filter(|c| c.method == self.method)
            .and_then(|c| c.views.get(v))
        {
            report.stages.clone_from(&counts.stages);
            report.casters_rendered = counts.casters_rendered;
            report.triangles_shadow = counts.triangles;
        } else {
            report.stages = self.cpu.stages(v).to_vec();
        }
        report
    }
}

impl ShadowTechnique for MapTechnique {
    fn name(&self) -> &'static str {
        self.layout.name()
    }

    fn light_term(&self) -> (&'static str, &wgpu::BindGroupLayout) {
        (LIGHT_WGSL, self.maps.light_layout())
    }

    /// The GPU methods need indirect draws with a first instance; without, `vfc` (with a
    /// warning).
    fn effective_method(&self, requested: Method) -> Method {
        if requested.gpu_driven() && !self.indirect_first_instance {
            Method::Vfc
        } else {
            requested
        }
    }

    fn prepare(&mut self, ctx: &GpuContext, input: &TechniqueInput<'_>) -> Vec<ShadowView> {
        self.method = self.effective_method(input.method);
        if self.method != input.method {
            self.warned_no_indirect.warn(&format!(
                "this adapter has no INDIRECT_FIRST_INSTANCE: '{}' runs as 'vfc'",
                input.method.name()
            ));
        }
        let limits = ctx.device.limits();
        let resolution = input.shadow.resolution.clamp(
            ShadowSettings::MIN_RESOLUTION,
            ShadowSettings::MAX_RESOLUTION.min(limits.max_texture_dimension_2d),
        );
        let layers = self.layout.layers().min(limits.max_texture_array_layers);
        self.maps.ensure(ctx, resolution, layers);
        let mut views = self
            .layout
            .views(input, self.method, self.maps.resolution());
        views.truncate(self.maps.layers() as usize);
        views
    }

    fn draw(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: &TechniqueInput<'_>,
        draw: &DrawInput<'_>,
    ) -> ShadowPasses {
        let (ctx, method) = (draw.ctx, self.method);
        let full_redraw = self.full_redraw(input, draw.views);
        let started = Instant::now();
        let lights: Vec<_> = draw.views.iter().map(|v| &v.light).collect();
        let gpu = method.gpu_driven();
        self.cpu
            .select(ctx, (input.scene, input.scene_gpu), method, &lights, !gpu);
        let reference_drawn = input.measure || method == Method::Oracle;
        if reference_drawn {
            self.cpu.upload_reference(ctx, input.scene_gpu);
        }
        let cpu_culling_ms = started.elapsed().as_secs_f64() * 1000.0;
        // The resources stay prepared for CPU methods too: the inset shows their masks' size.
        self.culling.prepare(
            ctx,
            input.scene_gpu,
            &CullTargets {
                resolution: self.maps.resolution(),
                capacity: self.maps.layers(),
                maps_generation: self.maps.generation(),
                shadow_maps: self.maps.depth_array(),
                views: draw.view_buffer,
                camera_size: (draw.targets.width, draw.targets.height),
                camera_depth: &draw.targets.depth_view,
            },
        );
        // The oracle method reads the reference maps before its own maps are drawn.
        if method == Method::Oracle {
            self.draw_lists(encoder, input, draw, MapKind::Reference);
        }
        let mut failure = None;
        if gpu {
            if let Err(e) = self.draw_culled(encoder, input, draw, full_redraw) {
                let message = format!("{}: {e}; every caster was drawn instead", method.name());
                self.failures.warn(&message);
                failure = Some(message);
                self.cpu.select(
                    ctx,
                    (input.scene, input.scene_gpu),
                    Method::None,
                    &lights,
                    true,
                );
                self.draw_lists(encoder, input, draw, MapKind::Method);
            } else {
                self.failures.clear();
            }
        } else {
            self.draw_lists(encoder, input, draw, MapKind::Method);
        }
        if input.measure && method != Method::Oracle {
            self.draw_lists(encoder, input, draw, MapKind::Reference);
        }
        let gpu_culled = gpu && failure.is_none();
        self.last = LastFrame {
            views: draw.views.to_vec(),
            shadow: *input.shadow,
            instances: input.scene_gpu.instance_count,
            gpu_culled,
            reference_drawn,
            failure,
            cpu_culling_ms,
        };
        let outcomes = if gpu_culled {
            self.culling.state_buffer()
        } else {
            None
        };
        ShadowPasses {
            light_group: self.maps.light_group().clone(),
            outcomes: outcomes
                .unwrap_or_else(|| self.cpu.outcome_buffer())
                .clone(),
        }
    }

    fn after_submit(&mut self) {
        self.culling.after_submit();
    }

    fn collect(&mut self) -> ShadowReport {
        self.culling.collect();
        let views = (0..)
            .zip(&self.last.views)
            .map(|(v, view)| self.view_report(v, view))
            .collect();
        let culled_frame_index = self
            .culling
            .latest()
            .filter(|c| self.last.gpu_culled && c.method == self.method)
            .map(|c| c.frame_index);
        let mut notes = self.culling.device_notes(self.method);
        if self.layout.name() == "lispsm"
            && !self.method.static_light()
            && self.last.views.iter().any(|v| v.light.warp.is_none())
        {
            notes.push(
                "LiSPSM: the view looks (almost) along the light, so the map is uniform".to_owned(),
            );
        }
        ShadowReport {
            casters_total: self.cpu.casters_total(),
            casters_rendered: None,
            stages: Vec::new(),
            volume_fill: None,
            volume_passes: None,
            views,
            culled_frame_index,
            notes,
            failure: self.last.failure.clone(),
            cpu_culling_ms: self.last.cpu_culling_ms,
            layered: None,
            virtual_pages: None,
        }
    }

    fn has_results_of(&self, frame_index: u64) -> bool {
        !self.last.gpu_culled
            || (self
                .culling
                .latest()
                .is_some_and(|c| c.frame_index == frame_index)
                && self
                    .culling
                    .latest_outcomes()
                    .is_some_and(|(f, _)| f == frame_index))
    }

    fn inset(&self, view: u32) -> Option<InsetSources<'_>> {
        let target = self.last.views.get(view as usize)?.target;
        let (shadow_depth, reference_ids) = self.maps.layer(target.layer)?;
        let mask = self.culling.mask_for_inset(self.method, view)?;
        let outcomes = if self.last.gpu_culled {
            self.culling.state_buffer()?
        } else {
            self.cpu.outcome_buffer()
        };
        Some(InsetSources {
            shadow_depth,
            reference_ids,
            origin: target.origin,
            size: target.size,
            outcomes,
            outcomes_offset: view * self.last.instances,
            mask_raster: mask.raster,
            mask_bits: mask.bits,
            mask_offset: mask.bits_offset,
            mask_size: mask.mask_size,
            mask_scale: mask.scale,
            show_raster_mask: mask.raster_shown,
            show_fragment_mask: mask.fragment_shown,
            // Culled casters can be striped where the reference maps hold their ids.
            show_outcomes: self.last.reference_drawn,
        })
    }

    fn view_outcomes(&self) -> Vec<&[crate::culling::CasterOutcome]> {
        let views = self.last.views.len();
        if self.last.gpu_culled {
            self.culling
                .latest_outcomes()
                .map(|(_, o)| o.iter().take(views).map(Vec::as_slice).collect())
                .unwrap_or_default()
        } else {
            (0..views).map(|v| self.cpu.outcomes(v)).collect()
        }
    }

    fn exclude(&mut self, instances: &[u32]) {
        self.exclusions_version += 1;
        self.cpu.exclude(instances);
        self.culling.exclude(instances);
    }
}

/// One view's pass, timed by `query`.
fn view_pass<'a>(
    view: &'a ShadowView,
    frame_group: &'a wgpu::BindGroup,
    pass_group: &'a wgpu::BindGroup,
    query: Option<&'a wgpu_profiler::GpuProfilerQuery>,
) -> ViewPass<'a> {
    ViewPass {
        view,
        frame_group,
        pass_group,
        timestamp_writes: query
            .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
    }
}
