//! The three ways to render a frame's maps (Rákos 19.3): a pass per map (`traditional`), a
//! pass per group of maps through multiview (`multiview`), or one instanced draw per mesh for
//! a whole page of an atlas (`atlas`). Each draws a view's casters as chosen per view
//! (`shadow_map`'s CPU casters); every path must give the same depths.

use std::collections::HashMap;
use std::num::NonZeroU32;

use wgpu::util::DrawIndexedIndirectArgs;

use super::cull::Slot;
use super::targets::LayeredMaps;
use crate::gpu::{
    FrameTimer, GpuContext, bind_group_layout, buffer_entry, depth_attachment, pass_label,
    pipeline_layout, shader_module, storage, uniform,
};
use crate::scene_gpu::{DrawList, SceneGpu};
use crate::shaders::compose;
use crate::shadow_map::cpu_casters::CpuCasters;
use crate::shadow_view::{LayeredPath, ShadowView, ViewBuffer, depth_pipeline};

/// The traditional path's shader, as the renderer and the validation test compose it.
pub(crate) fn traditional_source() -> String {
    compose("layered/traditional.wgsl", &[])
}

/// The multiview path's shader, as the renderer and the validation test compose it.
pub(crate) fn multiview_source() -> String {
    compose("layered/multiview.wgsl", &[])
}

/// The atlas path's shader (clip distances).
pub(crate) fn atlas_source() -> String {
    format!(
        "enable clip_distances;\n{}",
        compose("layered/atlas.wgsl", &[])
    )
}

/// What every path draws with this frame.
pub struct PathInput<'a> {
    pub views: &'a [ShadowView],
    pub view_buffer: &'a ViewBuffer,
    pub frame_group: &'a wgpu::BindGroup,
    pub scene_gpu: &'a SceneGpu,
    pub casters: &'a CpuCasters,
    pub timer: &'a FrameTimer,
    /// Each pass's pipeline statistics, where the adapter has them.
    pub statistics: &'a super::statistics::PassStatistics,
    pub indirect_first_instance: bool,
}

/// Long-lived pipelines and the per-frame draw lists of each path.
pub struct Paths {
    traditional: wgpu::RenderPipeline,
    /// Where multiview reaches every layer (`probe.rs`).
    multiview: Option<Multiview>,
    multiview_exposed: bool,
    atlas: Option<Atlas>,
}

struct Multiview {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    /// A pipeline per group size (its mask must equal the pass's).
    pipelines: HashMap<u32, wgpu::RenderPipeline>,
    /// Per group, the union of its views' casters.
    lists: Vec<DrawList>,
    /// The most views a pass may have on this adapter.
    max_views: u32,
}

struct Atlas {
    pipeline: wgpu::RenderPipeline,
    group_layout: wgpu::BindGroupLayout,
    pairs: wgpu::Buffer,
    group: wgpu::BindGroup,
    /// Per page, one instanced draw per mesh.
    lists: Vec<DrawList>,
}

impl Paths {
    /// `layouts`: group 0 of scene passes and one view alone.
    /// `layouts`: group 0 of scene passes and one view alone; `page`: the maps' page-side
    /// uniform (`LayeredMaps::page`).
    pub fn new(
        ctx: &GpuContext,
        [frame, pass_view]: [&wgpu::BindGroupLayout; 2],
        page: &wgpu::Buffer,
    ) -> Self {
        let device = &ctx.device;
        let layout = pipeline_layout(device, "Layered::layout", &[frame, pass_view]);
        let module = shader_module(device, "Layered::traditional", traditional_source());
        let traditional = depth_pipeline(
            device,
            (&layout, &module, "vs_layered"),
            None,
            (false, wgpu::CompareFunction::Less),
        );
        let max_views = device.limits().max_multiview_view_count.min(32);
        let multiview_exposed = ctx.features().contains(wgpu::Features::MULTIVIEW);
        let multiview = super::probe::multiview_reaches_every_layer(ctx).then(|| Multiview {
            module: shader_module(device, "Layered::multiview", multiview_source()),
            layout: pipeline_layout(device, "Layered::multiview_layout", &[frame, pass_view]),
            pipelines: HashMap::new(),
            lists: Vec::new(),
            max_views,
        });
        let atlas = ctx
            .features()
            .contains(wgpu::Features::CLIP_DISTANCES)
            .then(|| Atlas::new(ctx, frame, page));
        Self {
            traditional,
            multiview,
            multiview_exposed,
            atlas,
        }
    }

    /// Whether the adapter has the MULTIVIEW feature (whether or not it works).
    pub fn multiview_exposed(&self) -> bool {
        self.multiview_exposed
    }

    /// The most maps one multiview pass renders here (0: the adapter has no multiview).
    pub fn multiview_group(&self) -> u32 {
        self.multiview.as_ref().map_or(0, |m| m.max_views)
    }

    pub fn has_atlas(&self) -> bool {
        self.atlas.is_some()
    }

    /// A pass per view, each clearing its layer.
    pub fn draw_traditional(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        maps: &LayeredMaps,
        input: &PathInput<'_>,
    ) -> u32 {
        let mut passes = 0;
        for (v, view) in (0..).zip(input.views) {
            let (Some(target), Some(pass_group), Some(list)) = (
                maps.layers.get(view.target.layer as usize),
                input.view_buffer.pass_group(v),
                input.casters.draws(v as usize),
            ) else {
                continue;
            };
            let pass = MapPass {
                target,
                mask: None,
                square: Some(view.target),
                pipeline: &self.traditional,
                groups: &[input.frame_group, pass_group],
            };
            map_pass(encoder, input, pass, |render| {
                list.draw(render, input.scene_gpu, input.indirect_first_instance);
            });
            passes += 1;
        }
        passes
    }

    /// A pass per slot (a group of consecutive views, each a layer), drawing the casters any
    /// of its views chose; `None` without multiview.
    pub fn draw_multiview(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        maps: &LayeredMaps,
        (input, slots): (&PathInput<'_>, &[super::cull::Slot]),
    ) -> Option<u32> {
        let m = self.multiview.as_mut()?;
        let group = m.max_views as usize;
        let groups = slots.len();
        while m.lists.len() < groups {
            m.lists.push(DrawList::new(ctx, "Layered::multiview_draws"));
        }
        for (list, slot) in m.lists.iter_mut().zip(slots) {
            list.upload(ctx, input.scene_gpu, &slot.casters);
        }
        for g in 0..groups {
            let first = g * group;
            let count = (input.views.len() - first).min(group) as u32;
            let pipeline = m.pipelines.entry(count).or_insert_with(|| {
                depth_pipeline(
                    &ctx.device,
                    (&m.layout, &m.module, "vs_multiview"),
                    NonZeroU32::new((1u32 << count) - 1),
                    (false, wgpu::CompareFunction::Less),
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
                mask: NonZeroU32::new((1u32 << count) - 1),
                square: Some(square),
                pipeline,
                groups: &[input.frame_group, pass_group],
            };
            map_pass(encoder, input, pass, |render| {
                m.lists[g].draw(render, input.scene_gpu, input.indirect_first_instance);
            });
        }
        Some(groups as u32)
    }

    /// A pass per page of the atlas, one instanced draw per mesh in it; `None` without clip
    /// distances.
    pub fn draw_atlas(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        maps: &LayeredMaps,
        input: &PathInput<'_>,
    ) -> Option<u32> {
        let atlas = self.atlas.as_mut()?;
        atlas.prepare(ctx, maps, input);
        for (target, list) in maps.layers.iter().zip(&atlas.lists) {
            let pass = MapPass {
                target,
                mask: None,
                square: None,
                pipeline: &atlas.pipeline,
                groups: &[input.frame_group, &atlas.group],
            };
            map_pass(encoder, input, pass, |render| {
                list.draw(render, input.scene_gpu, input.indirect_first_instance);
            });
        }
        Some(maps.layers.len() as u32)
    }

    /// The draws of the last frame's multiview passes, a pass each.
    pub fn multiview_lists(&self) -> impl Iterator<Item = &DrawList> {
        self.multiview.iter().flat_map(|m| m.lists.iter())
    }

    /// The draws of the last frame's atlas pages, a page each.
    pub fn atlas_lists(&self) -> impl Iterator<Item = &DrawList> {
        self.atlas.iter().flat_map(|a| a.lists.iter())
    }
}

/// A page's (caster, view) pairs by mesh: its first index, index count and base vertex.
type PagePairs = std::collections::BTreeMap<(u32, u32, i32), Vec<[u32; 2]>>;

impl Atlas {
    fn new(ctx: &GpuContext, frame: &wgpu::BindGroupLayout, page: &wgpu::Buffer) -> Self {
        let device = &ctx.device;
        let group_layout = bind_group_layout(
            device,
            "Layered::atlas_group",
            wgpu::ShaderStages::VERTEX,
            &[storage(true), uniform()],
        );
        let layout = pipeline_layout(device, "Layered::atlas_layout", &[frame, &group_layout]);
        let module = shader_module(device, "Layered::atlas", atlas_source());
        let pipeline = depth_pipeline(
            device,
            (&layout, &module, "vs_atlas"),
            None,
            (false, wgpu::CompareFunction::Less),
        );
        let pairs = pairs_buffer(device, 64);
        let group = atlas_group(device, &group_layout, &pairs, page);
        Self {
            pipeline,
            group_layout,
            pairs,
            group,
            lists: Vec::new(),
        }
    }

    /// The (caster, view) pairs of every page, grouped by mesh, and per page one instanced
    /// draw per mesh over its pairs.
    fn prepare(&mut self, ctx: &GpuContext, maps: &LayeredMaps, input: &PathInput<'_>) {
        let pages = maps.layers.len();
        let ranges = &input.scene_gpu.instance_ranges;
        // Per page, per mesh (its index range), the pairs.
        let mut by_page: Vec<PagePairs> = vec![PagePairs::default(); pages];
        for (v, view) in input.views.iter().enumerate() {
            let Some(page) = by_page.get_mut(view.target.layer as usize) else {
                continue;
            };
            for &i in input.casters.chosen(v) {
                let r = ranges[i as usize];
                page.entry((r.first_index, r.index_count, r.base_vertex))
                    .or_default()
                    .push([i, v as u32]);
            }
        }
        let mut pairs: Vec<[u32; 2]> = Vec::new();
        while self.lists.len() < pages {
            self.lists.push(DrawList::new(ctx, "Layered::atlas_draws"));
        }
        for (page, list) in by_page.iter().zip(&mut self.lists) {
            let mut args = Vec::with_capacity(page.len());
            for (&(first_index, index_count, base_vertex), p) in page {
                args.push(DrawIndexedIndirectArgs {
                    index_count,
                    instance_count: p.len() as u32,
                    first_index,
                    base_vertex,
                    first_instance: pairs.len() as u32,
                });
                pairs.extend_from_slice(p);
            }
            list.upload_args(ctx, args);
        }
        let bytes = (pairs.len().max(1) * 8) as u64;
        if self.pairs.size() < bytes {
            self.pairs = pairs_buffer(&ctx.device, bytes.next_power_of_two());
            self.group = atlas_group(&ctx.device, &self.group_layout, &self.pairs, &maps.page);
        }
        if !pairs.is_empty() {
            ctx.queue
                .write_buffer(&self.pairs, 0, bytemuck::cast_slice(&pairs));
        }
    }
}

fn pairs_buffer(device: &wgpu::Device, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("Layered::atlas_pairs"),
        size: bytes.max(8),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn atlas_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    pairs: &wgpu::Buffer,
    page: &wgpu::Buffer,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("Layered::atlas_group"),
        layout,
        entries: &[buffer_entry(0, pairs), buffer_entry(1, page)],
    })
}

/// One map pass: its target (every layer of it through multiview where `mask` says), the
/// square it draws in (none: the whole target), its pipeline and its bind groups in order.
#[derive(Clone, Copy)]
pub(super) struct MapPass<'a> {
    pub target: &'a wgpu::TextureView,
    pub mask: Option<NonZeroU32>,
    pub square: Option<crate::shadow_view::ViewTarget>,
    pub pipeline: &'a wgpu::RenderPipeline,
    pub groups: &'a [&'a wgpu::BindGroup],
}

/// Records `pass`, its target cleared, timed as a shadow-map pass and counted by the
/// pipeline statistics; `draw` records its draws.
pub(super) fn map_pass(
    encoder: &mut wgpu::CommandEncoder,
    input: &PathInput<'_>,
    pass: MapPass<'_>,
    draw: impl FnOnce(&mut wgpu::RenderPass<'_>),
) {
    let query = input.timer.begin_pass(pass_label::SHADOW_MAP, encoder);
    let mut render = depth_pass(encoder, pass.target, pass.mask, query.as_ref());
    if let Some(square) = pass.square {
        square.set_viewport(&mut render);
    }
    render.set_pipeline(pass.pipeline);
    for (i, group) in (0..).zip(pass.groups) {
        render.set_bind_group(i, *group, &[]);
    }
    let statistics = input.statistics.next();
    if let Some((set, index)) = statistics {
        render.begin_pipeline_statistics_query(set, index);
    }
    draw(&mut render);
    if statistics.is_some() {
        render.end_pipeline_statistics_query();
    }
    drop(render);
    input.timer.end_pass(encoder, query);
}

/// A depth pass on `target` (every layer of it through multiview where `mask` says), cleared.
fn depth_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    target: &wgpu::TextureView,
    mask: Option<NonZeroU32>,
    query: Option<&wgpu_profiler::GpuProfilerQuery>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("Layered::maps"),
        color_attachments: &[],
        depth_stencil_attachment: Some(depth_attachment(target, Some(1.0))),
        timestamp_writes: query
            .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
        occlusion_query_set: None,
        multiview_mask: mask,
    })
}

/// The unculled paths: each view's casters drawn whole. Passes, draws and triangles.
pub(super) fn draw_direct(
    (paths, maps, cpu): (&mut Paths, &LayeredMaps, &CpuCasters),
    (ctx, encoder): (&GpuContext, &mut wgpu::CommandEncoder),
    (path, input, slots): (LayeredPath, &PathInput<'_>, &[Slot]),
) -> (u32, u32, u64) {
    let (passes, lists): (u32, Vec<&crate::scene_gpu::DrawList>) = match path {
        LayeredPath::Traditional => {
            let passes = paths.draw_traditional(encoder, maps, input);
            let lists = (0..input.views.len()).filter_map(|v| cpu.draws(v));
            (passes, lists.collect())
        }
        LayeredPath::Multiview => {
            let groups = paths
                .draw_multiview(ctx, encoder, maps, (input, slots))
                .unwrap_or(0);
            (
                groups,
                paths.multiview_lists().take(groups as usize).collect(),
            )
        }
        LayeredPath::Atlas => {
            let pages = paths.draw_atlas(ctx, encoder, maps, input).unwrap_or(0);
            (pages, paths.atlas_lists().take(pages as usize).collect())
        }
    };
    (
        passes,
        lists.iter().map(|l| l.len()).sum(),
        lists.iter().map(|l| l.triangles).sum(),
    )
}
