//! Virtual shadow maps (`--shadow virtual`), the technique engines ship today (Unreal
//! Engine 5, Blender's EEVEE): a clipmap of the sun, each level a 4096-texel square of
//! 128-texel pages centred on the camera, level k's texels 2^k times the finest. Only the
//! pages that visible pixels read are given physical pages of an atlas, and only those drawn;
//! drawn pages stay cached across frames until something moves through them or the light
//! moves. A point light takes the same path with its cube as the levels: six faces, each a
//! chain of mips from 16,384 texels square (the two finest as tiles of 4096) down to one page;
//! a spot light with one such chain along its cone, no page read outside it.
//!
//! ```text
//! prepare   the levels: a shadow view each (geom::fit_clipmap_level), on a texel grid fixed
//!           in light space, so a page keeps its place as the camera moves; or a point
//!           light's faces and their mips, or a spot's (punctual.rs `punctual_views`)
//! draw      in compute, no readback (allocate.wgsl, mark.wgsl, cull.wgsl): moved boxes
//!           invalidate their pages; pages that left their square are released, invalid
//!           ones (or all, when the light or the settings changed) drawn again where they
//!           are if marked, released if not (a page's depths round by its place in the
//!           atlas, so a page drawn in place holds the very depths it held); each visible
//!           receiver pixel marks the pages its PCF taps read at the level resolution matching
//!           picks; marked pages get physical pages in the order of their entries, the
//!           same on every run (where the pool runs out, cached pages nobody marked are
//!           evicted, and the pixels whose pages are still refused mark the coarsest
//!           level's, which take pages kept back for them);
//!           each caster against the pages drawn this frame, through the hierarchy of page
//!           flags; then one pass over the atlas (draw.wgsl):
//!           each drawn page cleared, each (caster, page) pair drawn with clip distances at the
//!           page's edges, by indirect draws; when measuring, the per-page oracle
//!           (oracle.rs): the pairs drawn again, kept where they hold a shadowed tap's texel
//! light     light.wgsl: the matched level, or the first coarser one whose pages are there
//! report    pages marked, resident, drawn, refused, and when measuring the texels pixels
//!           read and the oracle's pairs per level (a frame or more later)
//! ```

mod frame;
mod gpu_data;
mod oracle;
mod overlay;
mod pipelines;
mod punctual;
mod resources;

use crate::geom::Aabb;
use crate::gpu::{GpuContext, LogOnce};
use crate::scene::{Mobility, Scene};
use crate::shadow_view::{ShadowView, VirtualSettings};
use crate::technique::TechniqueInput;
use gpu_data::FrameCounts;
pub use oracle::DrawnPair;
use pipelines::Pipelines;
use resources::{HIERARCHY_CELLS, LEVEL_ENTRIES, Lists, Tables};

/// The technique's light term (imported as `technique/light.wgsl` by the shading pass).
pub(crate) const LIGHT_WGSL: &str = "virtual_maps/light.wgsl";

/// The composed shaders, for the naga validation test.
#[cfg(test)]
pub(crate) fn shader_sources() -> Vec<(String, String)> {
    let mut out: Vec<_> = pipelines::compute_sources()
        .into_iter()
        .map(|(label, source)| (label.to_owned(), source))
        .collect();
    out.push(("VirtualMaps::draw".to_owned(), pipelines::draw_source()));
    out.push((
        "VirtualMaps::page_view".to_owned(),
        overlay::shader_source(),
    ));
    out
}

/// What the cached pages were drawn for: the scene, the light, the levels' texels, the
/// casters left out, and whether static occlusion keeps its blocks' depths (turned on, it
/// needs them of every cached page). Any change invalidates every page.
#[derive(Clone, Debug, PartialEq)]
struct CacheKey {
    scene: u64,
    direction_to_sun: [u32; 3],
    /// Where the point light is, and a spot's direction and outer cone, when one casts the
    /// shadows.
    point_light: Option<[u32; 7]>,
    finest_texel_m: u32,
    static_occlusion: bool,
    exclusions: u64,
    /// The scene's bounds, which fix every level's depth range.
    bounds: [[u32; 3]; 2],
}

/// The virtual shadow maps.
pub struct VirtualTechnique {
    pipelines: Pipelines,
    /// Why the pool has fewer pages than asked (the device's largest texture), for the notes.
    pool_note: Option<String>,
    page_view: overlay::PageView,
    /// Group 0 of the last frame's passes, for the page view.
    frame_group: Option<wgpu::BindGroup>,
    tables: Option<Tables>,
    lists: Lists,
    light_group: Option<wgpu::BindGroup>,
    /// Zeroed outcomes for the `casters` overlay (no caster is culled per view).
    outcomes: wgpu::Buffer,
    draw_count: bool,
    settings: VirtualSettings,
    key: Option<CacheKey>,
    /// Every instance's world bounds as the cached pages last saw them.
    seen_bounds: Vec<Aabb>,
    /// The next frame draws every page again (a frame overflowed the pairs).
    invalidate_next: bool,
    /// Room the pairs and draws need, learnt from a frame that overflowed them.
    grow_to: Option<(u32, u32)>,
    exclusions_version: u64,
    excluded: Vec<u32>,
    /// The levels of the last frame and its settings, for the report.
    views: Vec<ShadowView>,
    shadow: crate::shadow_view::ShadowSettings,
    first_pages: Vec<[i32; 2]>,
    /// Mips per face of the point light's cube this frame; 0 for the sun's clipmap.
    face_mips: u32,
    latest: Option<(u64, FrameCounts)>,
    /// Recent frames: index, every page invalid, moved boxes, measured.
    frame_tags: Vec<(u64, bool, u32, bool)>,
    casters_total: u32,
    failure: Option<String>,
    failures: LogOnce,
}

impl VirtualTechnique {
    pub fn new(ctx: &GpuContext, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let features = ctx.features();
        let device = &ctx.device;
        Self {
            pool_note: None,
            pipelines: Pipelines::new(
                device,
                frame_layout,
                features.contains(wgpu::Features::CLIP_DISTANCES),
            ),
            page_view: overlay::PageView::new(device, frame_layout),
            frame_group: None,
            tables: None,
            lists: Lists::new(device),
            light_group: None,
            outcomes: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("VirtualMaps::outcomes"),
                size: 16,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            draw_count: features.contains(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT),
            settings: VirtualSettings::default(),
            key: None,
            seen_bounds: Vec::new(),
            invalidate_next: true,
            grow_to: None,
            exclusions_version: 0,
            excluded: Vec::new(),
            views: Vec::new(),
            shadow: crate::shadow_view::ShadowSettings::default(),
            first_pages: Vec::new(),
            face_mips: 0,
            latest: None,
            frame_tags: Vec::new(),
            casters_total: 0,
            failure: None,
            failures: LogOnce::default(),
        }
    }

    /// The physical atlas, for tests that read it back.
    pub fn atlas(&self) -> Option<&wgpu::Texture> {
        self.tables.as_ref().map(|t| &t.atlas)
    }

    /// Each page-table entry's flags (level by level, 1,024 entries each, wrapped by the
    /// page's absolute position) as the last frame left them: bit 0 marked, 1 resident,
    /// 2 drawn this frame, 3 refused (`pages.wgsl`'s `PAGE_*`). Blocks: for tests.
    pub fn read_page_flags(&self, ctx: &GpuContext) -> Result<Vec<u32>, crate::gpu::GpuError> {
        self.read_table(ctx, |t| &t.flags, LEVEL_ENTRIES)
    }

    /// Each entry's receiver mask as the last frame left it: two words, a bit per block of
    /// 16 x 16 texels (row by row, 8 x 8) that a visible pixel read. Blocks: for tests.
    pub fn read_receiver_masks(
        &self,
        ctx: &GpuContext,
    ) -> Result<Vec<[u32; 2]>, crate::gpu::GpuError> {
        let words = self.read_table(ctx, |t| &t.receiver_masks, 2 * LEVEL_ENTRIES)?;
        Ok(words.chunks_exact(2).map(|w| [w[0], w[1]]).collect())
    }

    /// Each level's hierarchy of page flags as the last frame left it: 341 words a level,
    /// mips 1 to 5 of its 32 x 32 pages by their place in its square (16 x 16 cells, then
    /// 8 x 8, ..., 1), row by row, bit 0 where a page under the cell was drawn whole, bit 1
    /// where one was refreshed. Blocks: for tests.
    pub fn read_page_hierarchy(&self, ctx: &GpuContext) -> Result<Vec<u32>, crate::gpu::GpuError> {
        self.read_table(ctx, |t| &t.hierarchy, HIERARCHY_CELLS)
    }

    /// Each entry's physical page (meaningful where it is resident) as the last frame left
    /// it. Blocks: for tests.
    pub fn read_page_slots(&self, ctx: &GpuContext) -> Result<Vec<u32>, crate::gpu::GpuError> {
        self.read_table(ctx, |t| &t.slots, LEVEL_ENTRIES)
    }

    /// A per-level table's words, `words_per_level` for each of the tables' levels.
    fn read_table(
        &self,
        ctx: &GpuContext,
        buffer: impl Fn(&Tables) -> &wgpu::Buffer,
        words_per_level: u32,
    ) -> Result<Vec<u32>, crate::gpu::GpuError> {
        let Some(tables) = &self.tables else {
            return Ok(Vec::new());
        };
        let buffer = buffer(tables);
        let bytes = crate::gpu::read_buffer(ctx, buffer, buffer.size(), "page table")?;
        let mut words: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
        words.truncate((tables.levels * words_per_level) as usize);
        Ok(words)
    }

    /// Tables for these settings (all pages invalid when they are new).
    fn ensure_tables(&mut self, ctx: &GpuContext) {
        if self.tables.as_ref().is_some_and(|t| t.fits(&self.settings)) {
            return;
        }
        // New buffers are zeroed: every entry empty, every physical page free.
        let tables = Tables::new(ctx, &self.settings);
        self.light_group = Some(tables.light_group(&ctx.device, &self.pipelines));
        self.tables = Some(tables);
        self.latest = None;
        self.invalidate_next = true;
    }

    /// The boxes (old and new) of instances that moved since the pages last saw them, as
    /// min/max pairs; `None` when the cache cannot follow (a new scene).
    fn moved_boxes(&mut self, scene: &Scene) -> Option<Vec<[f32; 4]>> {
        if self.seen_bounds.len() != scene.instances.len() {
            self.seen_bounds = scene.instances.iter().map(|i| i.aabb_in_world).collect();
            return None;
        }
        let mut boxes = Vec::new();
        for (seen, instance) in self.seen_bounds.iter_mut().zip(&scene.instances) {
            if instance.mobility == Mobility::Static || *seen == instance.aabb_in_world {
                continue;
            }
            for b in [*seen, instance.aabb_in_world] {
                boxes.push(b.min.extend(0.0).to_array());
                boxes.push(b.max.extend(0.0).to_array());
            }
            *seen = instance.aabb_in_world;
        }
        Some(boxes)
    }

    fn cache_key(&self, input: &TechniqueInput<'_>) -> CacheKey {
        let b = input.scene.bounds();
        CacheKey {
            scene: input.scene_gpu.id,
            direction_to_sun: input.direction_to_sun.to_array().map(f32::to_bits),
            point_light: input.point_light.map(|p| {
                let cone = p
                    .cone
                    .map_or([0.0; 4], |c| c.direction.extend(c.outer_rad).to_array());
                let [x, y, z] = p.position.to_array();
                [x, y, z, cone[0], cone[1], cone[2], cone[3]].map(f32::to_bits)
            }),
            finest_texel_m: self.settings.finest_texel_m.to_bits(),
            static_occlusion: self.settings.static_occlusion_applies(),
            exclusions: self.exclusions_version,
            bounds: [b.min, b.max].map(|v| v.to_array().map(f32::to_bits)),
        }
    }

    fn ensure_outcomes(&mut self, device: &wgpu::Device, words: u64) {
        if self.outcomes.size() < words * 4 {
            self.outcomes = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("VirtualMaps::outcomes"),
                size: (words * 4).next_power_of_two(),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
        }
    }
}
