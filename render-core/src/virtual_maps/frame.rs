//! The virtual maps' frame: the levels as views, the page table's passes, the cull and the
//! page draws, and what comes back of them.

use bytemuck::Zeroable;

use super::gpu_data::{FrameCounts, VirtualParams, word};
use super::pipelines::TABLE_PASSES;
use super::punctual::POINT_MIPS;
use super::resources::{LEVEL_ENTRIES, Tables};
use super::{LIGHT_WGSL, VirtualTechnique};

use crate::culling::{CasterOutcome, Method};
use crate::geom::fit_clipmap_level;
use crate::gpu::{GpuContext, pass_label};
use crate::shadow_view::{LEVEL_PAGES, PAGE_TEXELS, ShadowView, ViewTarget};
use crate::technique::{
    DrawInput, InsetSources, ShadowPasses, ShadowReport, ShadowTechnique, TechniqueInput,
    ViewReport, VirtualPages,
};

/// Physical pages kept back from the first allocations for the fallback pages of pixels whose
/// own pages the pool refused (a quarter of a smaller pool); per face of a point light (per
/// chain).
const FALLBACK_PAGES: u32 = 16;

impl VirtualTechnique {
    /// This frame's parameters: the levels' squares, the pool, and whether every page is
    /// invalid.
    fn params(&self, invalidate_all: bool, moved: u32) -> VirtualParams {
        let mut params = VirtualParams::zeroed();
        let [columns, rows] = self.settings.atlas_pages();
        params.counts = [
            self.settings.levels,
            self.settings.pages,
            columns,
            u32::from(invalidate_all),
        ];
        params.tuning = [
            self.settings.finest_texel_m,
            self.settings.lod_bias,
            moved as f32,
            rows as f32,
        ];
        // The coarsest level's pages that refused pixels fall back to: a few cover the scene
        // (a few per face of a point light's cube).
        params.limits = [
            (FALLBACK_PAGES * self.chains()).min(self.settings.pages / 4),
            u32::from(self.settings.separate_static),
            u32::from(self.settings.receiver_mask)
                | (u32::from(self.settings.static_occlusion_applies()) << 1),
            self.face_mips,
        ];
        for (slot, first) in params.first_page.iter_mut().zip(&self.first_pages) {
            *slot = [first[0], first[1], 0, 0];
        }
        params
    }

    /// The page table's passes, marking and the cull, timed as steps of one scope.
    fn encode_pages(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        draw: &DrawInput<'_>,
        (tables, groups): (&Tables, [&wgpu::BindGroup; 4]),
        (instances, moved, measure): (u32, u32, bool),
    ) {
        let [table_group, mark_group, cull_group, occlusion_group] = groups;
        let levels = tables.levels;
        let entries = (levels * LEVEL_ENTRIES).div_ceil(64);
        // The free lists and the rounds of allocation are one workgroup each (ordered:
        // allocate.wgsl).
        let sizes: [[u32; 2]; 11] = [
            [moved.div_ceil(64), levels],
            [entries, 1],
            [1, 1],
            [1, 1],
            [entries, 1],
            [1, 1],
            [1, 1],
            [1, 1],
            [1, 1],
            [entries, 1],
            [1, 1],
        ];
        let pixels = [
            draw.targets.width.div_ceil(8),
            draw.targets.height.div_ceil(8),
        ];
        let scope = draw.timer.open_scope(pass_label::VIRTUAL_PAGES, encoder);
        let dispatch = |encoder: &mut wgpu::CommandEncoder,
                        passes: &[(&wgpu::ComputePipeline, [u32; 2])],
                        group: Option<&wgpu::BindGroup>| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("VirtualMaps::pages"),
                timestamp_writes: None,
            });
            pass.set_bind_group(0, draw.frame_group, &[]);
            pass.set_bind_group(1, table_group, &[]);
            if let Some(group) = group {
                pass.set_bind_group(2, group, &[]);
            }
            for (pipeline, [x, y]) in passes {
                if *x > 0 && *y > 0 {
                    pass.set_pipeline(pipeline);
                    pass.dispatch_workgroups(*x, *y, 1);
                }
            }
        };
        let table = |range: std::ops::Range<usize>| -> Vec<(&wgpu::ComputePipeline, [u32; 2])> {
            range
                .map(|i| (&self.pipelines.tables[i], sizes[i]))
                .collect()
        };
        let occluding = usize::from(self.settings.static_occlusion_applies());
        if occluding == 1 {
            scope.step(pass_label::virtual_maps::STATIC_DEPTHS, encoder, |e| {
                let reduce = (&self.pipelines.occlusion, [tables.pages, 1]);
                dispatch(e, &[reduce], Some(occlusion_group));
            });
        }
        scope.step(pass_label::virtual_maps::MARKING, encoder, |e| {
            dispatch(e, &table(0..2), None);
            dispatch(e, &[(&self.pipelines.mark[0], pixels)], Some(mark_group));
        });
        scope.step(pass_label::virtual_maps::ALLOCATION, encoder, |e| {
            dispatch(e, &table(2..8), None);
            dispatch(e, &[(&self.pipelines.mark[1], pixels)], Some(mark_group));
            dispatch(e, &table(8..TABLE_PASSES.len()), None);
            if measure {
                e.clear_buffer(&tables.texel_bits, 0, None);
                let words = (tables.pages * 512).div_ceil(64);
                dispatch(
                    e,
                    &[
                        (&self.pipelines.mark[2], pixels),
                        (&self.pipelines.mark[3], [words, 1]),
                    ],
                    Some(mark_group),
                );
            }
        });
        scope.step(pass_label::virtual_maps::CULLING, encoder, |e| {
            if !self.draw_count {
                e.clear_buffer(&self.lists.draws, 0, None);
            }
            dispatch(
                e,
                &[(
                    &self.pipelines.cull[occluding],
                    [instances.div_ceil(64), levels],
                )],
                Some(cull_group),
            );
        });
        scope.close(encoder);
    }

    /// The drawn pages cleared and their casters drawn, one pass over the atlas.
    fn encode_draws(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        draw: &DrawInput<'_>,
        scene_gpu: &crate::scene_gpu::SceneGpu,
        (tables, group): (&Tables, &wgpu::BindGroup),
    ) -> Result<(), String> {
        let Some([clear, page]) = &self.pipelines.draws else {
            return Err(
                "this adapter has no CLIP_DISTANCES, which keep a page's casters in its place \
                 in the atlas: no page was drawn"
                    .to_owned(),
            );
        };
        let query = draw.timer.begin_pass(pass_label::SHADOW_MAP, encoder);
        let mut pass = crate::gpu::depth_pass(
            encoder,
            "VirtualMaps::draw",
            &tables.atlas_view,
            None,
            query
                .as_ref()
                .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
        );
        pass.set_bind_group(0, draw.frame_group, &[]);
        pass.set_bind_group(1, group, &[]);
        pass.set_pipeline(clear);
        pass.draw_indirect(&tables.counters, (word::CLEAR_ARGS * 4) as u64);
        pass.set_pipeline(page);
        self.draw_pairs(&mut pass, scene_gpu, tables);
        drop(pass);
        draw.timer.end_pass(encoder, query);
        Ok(())
    }

    /// The cull's (caster, page) pairs, its indirect draws.
    pub(super) fn draw_pairs(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        scene_gpu: &crate::scene_gpu::SceneGpu,
        tables: &Tables,
    ) {
        pass.set_vertex_buffer(0, scene_gpu.vertex_buffer.slice(..));
        pass.set_index_buffer(scene_gpu.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        let lists = &self.lists;
        if self.draw_count {
            pass.multi_draw_indexed_indirect_count(
                &lists.draws,
                0,
                &tables.counters,
                (word::DRAWS * 4) as u64,
                lists.draws_capacity,
            );
        } else {
            pass.multi_draw_indexed_indirect(&lists.draws, 0, lists.draws_capacity);
        }
    }

    fn bind_groups(
        &self,
        device: &wgpu::Device,
        tables: &Tables,
        draw: &DrawInput<'_>,
        scene_gpu: &crate::scene_gpu::SceneGpu,
    ) -> [wgpu::BindGroup; 6] {
        use crate::gpu::{buffer_entry, view_entry};
        let p = &self.pipelines;
        let l = &self.lists;
        let group = |label, layout, entries: &[wgpu::BindGroupEntry<'_>]| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout,
                entries,
            })
        };
        let t = draw.targets;
        [
            group(
                "VirtualMaps::tables",
                &p.tables_layout,
                &[
                    buffer_entry(0, &tables.params),
                    buffer_entry(1, &tables.flags),
                    buffer_entry(2, &tables.counters),
                    buffer_entry(3, &tables.slots),
                    buffer_entry(4, &tables.tags),
                    buffer_entry(5, &tables.owners),
                    buffer_entry(6, &tables.free_list),
                    buffer_entry(7, &tables.rendered),
                    buffer_entry(8, &l.moved),
                    buffer_entry(9, &tables.receiver_masks),
                    buffer_entry(10, &tables.hierarchy),
                    buffer_entry(11, &tables.static_depths),
                    buffer_entry(12, &tables.stale_blocks),
                ],
            ),
            group(
                "VirtualMaps::surface",
                &p.mark_layout,
                &[
                    view_entry(0, &t.ids_view),
                    view_entry(1, &t.positions_view),
                    view_entry(2, &t.normals_view),
                    buffer_entry(3, &tables.texel_bits),
                    view_entry(4, &tables.atlas_view),
                    buffer_entry(5, &tables.oracle_texels),
                ],
            ),
            group(
                "VirtualMaps::cull",
                &p.cull_layout,
                &[
                    buffer_entry(0, &l.ranges),
                    buffer_entry(1, &scene_gpu.bounds_buffer),
                    buffer_entry(2, &l.pairs),
                    buffer_entry(3, &l.draws),
                ],
            ),
            group(
                "VirtualMaps::occlusion",
                &p.occlusion_layout,
                &[view_entry(0, &tables.atlas_view)],
            ),
            group(
                "VirtualMaps::draw",
                &p.draw_layout,
                &[
                    buffer_entry(0, &tables.params),
                    buffer_entry(1, &tables.slots),
                    buffer_entry(2, &l.pairs),
                    buffer_entry(3, &tables.rendered),
                ],
            ),
            group(
                "VirtualMaps::oracle",
                &p.oracle_layout,
                &[
                    buffer_entry(0, &tables.oracle_texels),
                    buffer_entry(1, &l.oracle),
                ],
            ),
        ]
    }

    /// Level `level`'s part of the report: its casters are its (caster, page) draws, and
    /// where the frame was measured with every page it reads drawn, its oracle's pairs.
    fn view_report(&self, level: usize, view: &ShadowView) -> ViewReport {
        let light = &view.light;
        let counts = self.latest.as_ref().map(|(_, c)| c);
        let whole_and_measured = self.latest.as_ref().is_some_and(|(tag, _)| {
            let frame = self.frame_tags.iter().find(|f| f.0 == *tag);
            frame.is_some_and(|&(_, all_invalid, _, measured)| all_invalid && measured)
        });
        let texel = light.texel_size_m[0];
        let shadow = &self.shadow;
        ViewReport {
            name: view.name.clone(),
            casters_rendered: counts
                .and_then(|c| c.level_pairs.get(level).copied())
                .unwrap_or(0),
            casters_oracle: counts
                .filter(|_| whole_and_measured)
                .and_then(|c| c.level_oracle.get(level).copied()),
            texel_size_m: light.texel_size_m,
            depth_range_m: light.depth_range_m,
            shades_depth_m: [None, None],
            shades_by: view.shades_by,
            pcf_m: shadow.pcf.width() as f32 * texel,
            depth_bias_m: shadow.depth_bias_m + shadow.depth_bias_texels.max(0.0) * texel,
            ..ViewReport::default()
        }
    }
}

impl ShadowTechnique for VirtualTechnique {
    fn name(&self) -> &'static str {
        "virtual"
    }

    fn light_term(&self) -> (&'static str, &wgpu::BindGroupLayout) {
        (LIGHT_WGSL, &self.pipelines.light_layout)
    }

    /// Pages are culled by their own test (each caster against the pages drawn); the
    /// per-view methods of `culling/` do not run.
    fn effective_method(&self, _requested: Method) -> Method {
        Method::None
    }

    fn prepare(&mut self, ctx: &GpuContext, input: &TechniqueInput<'_>) -> Vec<ShadowView> {
        let limits = ctx.device.limits();
        let side = limits.max_texture_dimension_2d;
        self.settings = input.virtual_maps.clamped(side);
        self.pool_note = (self.settings.pages < input.virtual_maps.pages).then(|| {
            format!(
                "the pool holds {} pages, not the {} asked: the most this GPU's largest texture \
                 ({side} x {side}) holds",
                self.settings.pages, input.virtual_maps.pages
            )
        });
        self.face_mips = 0;
        self.first_pages.clear();
        let bounds = input.scene.bounds();
        if let Some(light) = input.point_light {
            // A point light's cube, or a spot's cone: `--levels` mips per face, at most
            // POINT_MIPS.
            self.face_mips = self.settings.levels.min(POINT_MIPS);
            let views = self.punctual_views(light, &bounds);
            self.settings.levels = views.len() as u32;
            self.ensure_tables(ctx);
            return views;
        }
        self.ensure_tables(ctx);
        let side = LEVEL_PAGES * PAGE_TEXELS;
        let mut views = Vec::new();
        for k in 0..self.settings.levels {
            let texel = f64::from(self.settings.finest_texel_m) * 2f64.powi(k as i32);
            let level = fit_clipmap_level(
                input.direction_to_sun,
                &bounds,
                input.camera.eye,
                texel,
                (LEVEL_PAGES, PAGE_TEXELS),
            );
            self.first_pages.push(level.first_page);
            views.push(ShadowView::covering_all_depths(
                &format!("level {k}"),
                level.light,
                ViewTarget::layer(0, side),
            ));
        }
        views
    }

    fn draw(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: &TechniqueInput<'_>,
        draw: &DrawInput<'_>,
    ) -> ShadowPasses {
        let ctx = draw.ctx;
        let scene_gpu = input.scene_gpu;
        let key = self.cache_key(input);
        let moved = self.moved_boxes(input.scene);
        let invalidate_all = !self.settings.cache
            || self.invalidate_next
            || self.key.as_ref() != Some(&key)
            || moved.is_none();
        self.key = Some(key);
        self.invalidate_next = false;
        let boxes = if invalidate_all {
            Vec::new()
        } else {
            moved.unwrap_or_default()
        };
        self.lists.write_moved(ctx, &boxes);
        if let Some((pairs, draws)) = self.grow_to.take() {
            self.lists.grow(&ctx.device, pairs, draws);
        }
        self.lists
            .follow_scene(ctx, (input.scene, scene_gpu), &self.excluded);
        let moved = (boxes.len() / 2) as u32;
        let Some(tables) = self.tables.as_ref() else {
            unreachable!("prepare made the tables");
        };
        tables.write_params(ctx, &self.params(invalidate_all, moved));
        encoder.clear_buffer(&tables.counters, 0, None);
        encoder.clear_buffer(&tables.hierarchy, 0, None);
        let [
            table_group,
            mark_group,
            cull_group,
            occlusion_group,
            draw_group,
            oracle_group,
        ] = self.bind_groups(&ctx.device, tables, draw, scene_gpu);
        let instances = scene_gpu.instance_count;
        self.encode_pages(
            encoder,
            draw,
            (
                tables,
                [&table_group, &mark_group, &cull_group, &occlusion_group],
            ),
            (instances, moved, input.measure),
        );
        self.failure = self
            .encode_draws(encoder, draw, scene_gpu, (tables, &draw_group))
            .err();
        if input.measure && self.failure.is_none() {
            let groups = [&table_group, &mark_group, &draw_group, &oracle_group];
            self.encode_oracle(encoder, draw, scene_gpu, (tables, groups));
        }
        if let Some(failure) = &self.failure {
            self.failures.warn(failure);
        }
        let tables = self.tables.as_mut().expect("tables");
        tables
            .readback
            .copy(encoder, &tables.counters, input.frame_index);
        self.frame_tags
            .push((input.frame_index, invalidate_all, moved, input.measure));
        if self.frame_tags.len() > 8 {
            self.frame_tags.remove(0);
        }
        self.views = draw.views.to_vec();
        self.shadow = *input.shadow;
        self.frame_group = Some(draw.frame_group.clone());
        self.casters_total = input.scene.caster_count() as u32;
        self.ensure_outcomes(&ctx.device, u64::from(instances) * draw.views.len() as u64);
        ShadowPasses {
            light_group: self.light_group.clone().expect("tables made it"),
            outcomes: self.outcomes.clone(),
        }
    }

    fn after_submit(&mut self) {
        if let Some(tables) = &mut self.tables {
            tables.readback.map_copied();
        }
    }

    fn collect(&mut self) -> ShadowReport {
        let levels = self.settings.levels as usize;
        if let Some((tag, bytes)) = self.tables.as_mut().and_then(|t| t.readback.take_latest()) {
            let words: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
            if let Some(counts) = FrameCounts::from_words(&words, levels) {
                if counts.overflow > 0 || counts.draws > self.lists.draws_capacity {
                    // Pages drawn without some casters: grow, and draw every page again.
                    self.grow_to = Some((
                        counts.pairs.saturating_mul(2),
                        counts.draws.saturating_mul(2),
                    ));
                    self.invalidate_next = true;
                }
                self.latest = Some((tag, counts));
            }
        }
        let views = (0..)
            .zip(&self.views)
            .map(|(k, v)| self.view_report(k, v))
            .collect();
        let mut notes: Vec<String> = self.pool_note.iter().cloned().collect();
        let pages = self.latest.as_ref().map(|(tag, c)| {
            let cache = self.frame_tags.iter().find(|f| f.0 == *tag);
            if c.overflow > 0 {
                notes.push(format!(
                    "{} (caster, page) pairs found no room in frame {tag}: the lists grew and every page is drawn again",
                    c.overflow
                ));
            }
            let mut pages = VirtualPages {
                pages_marked: c.marked,
                pages_resident: c.resident,
                pages_rendered: c.rendered,
                pages_refreshed: c.refreshed,
                caster_pages_masked: c.mask_culled,
                moved_pages_occluded: c.occlusion_spared,
                caster_pages_occluded: c.occlusion_culled,
                static_occlusion: self.settings.static_occlusion_applies(),
                cull_pages_spanned: c.cull_spanned,
                cull_flag_reads: c.cull_reads,
                receiver_mask: self.settings.receiver_mask,
                pages_refused: c.refused,
                cache_hit_rate: None,
                pages_evicted: c.evicted,
                pages_invalidated: c.invalidated,
                moved_boxes: cache.map_or(0, |f| f.2),
                all_invalidated: cache.is_some_and(|f| f.1),
                caster_pages: c.pairs,
                pool_pages: self.settings.pages,
                pool_mib: self.settings.pool_mib(),
                levels: self.settings.levels,
                finest_texel_m: self.settings.finest_texel_m,
                cache: self.settings.cache,
                separate_static: self.settings.separate_static,
                texels_rendered: u64::from(c.rendered * self.settings.page_layers() + c.refreshed)
                    * u64::from(PAGE_TEXELS * PAGE_TEXELS),
                texels_sampled: cache
                    .is_some_and(|f| f.3)
                    .then_some(u64::from(c.texels_sampled)),
            };
            pages.cache_hit_rate = (c.marked > 0)
                .then(|| f64::from(pages.pages_served()) / f64::from(c.marked));
            pages
        });
        ShadowReport {
            casters_total: self.casters_total,
            views,
            culled_frame_index: self.latest.as_ref().map(|(tag, _)| *tag),
            notes,
            failure: self.failure.clone(),
            virtual_pages: pages,
            ..ShadowReport::default()
        }
    }

    fn has_results_of(&self, frame_index: u64) -> bool {
        self.latest
            .as_ref()
            .is_some_and(|(tag, _)| *tag >= frame_index)
    }

    /// The page view, with the `light-view` overlay.
    fn draw_overlay(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        targets: &crate::view::ViewTargets,
        overlays: crate::technique::TechniqueOverlays,
    ) {
        if let (true, Some(tables), Some(frame_group)) =
            (overlays.light_view, &self.tables, &self.frame_group)
        {
            self.page_view.draw(
                device,
                encoder,
                targets,
                (frame_group, &tables.params, &tables.flags),
            );
        }
    }

    fn inset(&self, _view: u32) -> Option<InsetSources<'_>> {
        None
    }

    fn view_outcomes(&self) -> Vec<&[CasterOutcome]> {
        Vec::new()
    }

    fn exclude(&mut self, instances: &[u32]) {
        let mut sorted = instances.to_vec();
        sorted.sort_unstable();
        if sorted != self.excluded {
            self.excluded = sorted;
            self.exclusions_version += 1;
            self.lists.ranges_scene = None;
        }
    }
}
