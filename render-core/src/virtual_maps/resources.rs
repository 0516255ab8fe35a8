//! The virtual maps' GPU state: the physical atlas, the page table (flags, physical pages,
//! absolute pages per entry), the pool's owners and free list, the frame's drawn pages,
//! counters and their readback, the moved boxes, and the (caster, page) pairs and draws of
//! the cull. Long-lived; remade when the pool or the levels change (every page is then
//! invalid), the pairs and draws grown when a frame overflows them.

use super::gpu_data::{LEVEL_SLOTS, VirtualParams, word};
use super::pipelines::Pipelines;
use crate::gpu::{Asked, AsyncReadback, GpuContext, buffer, buffer_entry, view_entry};
use crate::scene::{Mobility, Scene};
use crate::scene_gpu::SceneGpu;
use crate::shadow_view::{LEVEL_PAGES, PAGE_TEXELS, SHADOW_FORMAT, VirtualSettings};

/// Entries of one level's table.
pub(super) const LEVEL_ENTRIES: u32 = LEVEL_PAGES * LEVEL_PAGES;
/// Cells of one level's hierarchy of page flags: mips 1 to 5 of its 32 x 32 pages.
pub(super) const HIERARCHY_CELLS: u32 = 256 + 64 + 16 + 4 + 1;

const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE;
/// The pairs are read back by tests (`oracle.rs` `read_pairs`).
const PAIRS_USAGE: wgpu::BufferUsages = STORAGE.union(wgpu::BufferUsages::COPY_SRC);

/// The pool and tables of one (pages, levels).
pub(super) struct Tables {
    pub pages: u32,
    pub page_layers: u32,
    pub levels: u32,
    pub params: wgpu::Buffer,
    pub flags: wgpu::Buffer,
    pub counters: wgpu::Buffer,
    pub slots: wgpu::Buffer,
    pub tags: wgpu::Buffer,
    pub owners: wgpu::Buffer,
    pub free_list: wgpu::Buffer,
    pub rendered: wgpu::Buffer,
    /// Per entry, two words: the blocks of its page that pixels read (the receiver mask).
    pub receiver_masks: wgpu::Buffer,
    /// When measuring: a bit per texel of each physical page that a tap reads.
    pub texel_bits: wgpu::Buffer,
    /// When measuring, the per-page oracle's texels: per physical page and layer, a bit per
    /// texel whose layer holds the nearest depth where a tap reads it shadowed.
    pub oracle_texels: wgpu::Buffer,
    /// Per level, the hierarchy of page flags (`tables.wgsl` `page_hierarchy`).
    pub hierarchy: wgpu::Buffer,
    /// Per physical page, the farthest static depth of each of its 8 x 8 blocks
    /// (`tables.wgsl` `static_depths`).
    pub static_depths: wgpu::Buffer,
    /// Per entry, two words: the stale blocks of its movable layer (`tables.wgsl`
    /// `stale_blocks`).
    pub stale_blocks: wgpu::Buffer,
    pub atlas: wgpu::Texture,
    pub atlas_view: wgpu::TextureView,
    pub readback: AsyncReadback,
}

impl Tables {
    pub fn new(ctx: &GpuContext, settings: &VirtualSettings) -> Self {
        let device = &ctx.device;
        let entries = u64::from(settings.levels * LEVEL_ENTRIES);
        let pages = u64::from(settings.pages);
        let atlas_pages = settings.atlas_pages();
        let asked = Asked {
            what: format!(
                "the virtual maps' pool: {} pages of {PAGE_TEXELS} x {PAGE_TEXELS} texels{}",
                settings.pages,
                if settings.page_layers() > 1 {
                    ", static casters apart"
                } else {
                    ""
                }
            ),
            remedy: "fewer pages (--pages)",
        };
        let atlas = ctx.texture(
            &asked,
            &wgpu::TextureDescriptor {
                label: Some("VirtualMaps::atlas"),
                size: wgpu::Extent3d {
                    width: atlas_pages[0] * PAGE_TEXELS,
                    height: atlas_pages[1] * settings.page_layers() * PAGE_TEXELS,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: SHADOW_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            },
        );
        let counters_size = (word::COUNT * 4) as u64;
        Self {
            pages: settings.pages,
            page_layers: settings.page_layers(),
            levels: settings.levels,
            params: buffer(
                device,
                "VirtualMaps::params",
                size_of::<VirtualParams>() as u64,
                wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            ),
            flags: buffer(
                device,
                "VirtualMaps::flags",
                entries * 4,
                STORAGE | wgpu::BufferUsages::COPY_SRC,
            ),
            counters: buffer(
                device,
                "VirtualMaps::counters",
                counters_size,
                STORAGE | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_SRC,
            ),
            slots: buffer(
                device,
                "VirtualMaps::slots",
                entries * 4,
                STORAGE | wgpu::BufferUsages::COPY_SRC,
            ),
            tags: buffer(device, "VirtualMaps::tags", entries * 8, STORAGE),
            owners: buffer(device, "VirtualMaps::owners", pages * 4, STORAGE),
            free_list: buffer(device, "VirtualMaps::free_list", pages * 4, STORAGE),
            rendered: buffer(device, "VirtualMaps::rendered", entries * 4, STORAGE),
            receiver_masks: buffer(
                device,
                "VirtualMaps::receiver_masks",
                entries * 8,
                STORAGE | wgpu::BufferUsages::COPY_SRC,
            ),
            texel_bits: buffer(
                device,
                "VirtualMaps::texel_bits",
                pages * u64::from(PAGE_TEXELS * PAGE_TEXELS / 8),
                STORAGE,
            ),
            oracle_texels: buffer(
                device,
                "VirtualMaps::oracle_texels",
                pages
                    * u64::from(settings.page_layers())
                    * u64::from(PAGE_TEXELS * PAGE_TEXELS / 8),
                STORAGE,
            ),
            hierarchy: buffer(
                device,
                "VirtualMaps::hierarchy",
                u64::from(settings.levels * HIERARCHY_CELLS) * 4,
                STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            ),
            static_depths: buffer(
                device,
                "VirtualMaps::static_depths",
                pages * 64 * 4,
                STORAGE,
            ),
            stale_blocks: buffer(
                device,
                "VirtualMaps::stale_blocks",
                entries * 8,
                STORAGE | wgpu::BufferUsages::COPY_SRC,
            ),
            atlas_view: atlas.create_view(&wgpu::TextureViewDescriptor::default()),
            atlas,
            readback: AsyncReadback::new(device, "VirtualMaps::counts", counters_size, 3),
        }
    }

    pub fn fits(&self, settings: &VirtualSettings) -> bool {
        self.pages == settings.pages
            && self.levels == settings.levels
            && self.page_layers == settings.page_layers()
    }

    pub fn write_params(&self, ctx: &GpuContext, params: &VirtualParams) {
        ctx.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }

    /// Group 1 of the shading pass and the truth's points.
    pub fn light_group(&self, device: &wgpu::Device, p: &Pipelines) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("VirtualMaps::light_group"),
            layout: &p.light_layout,
            entries: &[
                buffer_entry(0, &self.params),
                view_entry(1, &self.atlas_view),
                buffer_entry(2, &self.flags),
                buffer_entry(3, &self.slots),
                buffer_entry(4, &self.stale_blocks),
            ],
        })
    }
}

/// Buffers that follow the scene or grow: the moved boxes, per-instance index ranges, the
/// pairs and draws of the cull.
pub(super) struct Lists {
    pub moved: wgpu::Buffer,
    pub moved_capacity: u32,
    pub ranges: wgpu::Buffer,
    pub ranges_scene: Option<u64>,
    pub pairs: wgpu::Buffer,
    pub pairs_capacity: u32,
    pub draws: wgpu::Buffer,
    pub draws_capacity: u32,
    /// When measuring, the per-page oracle: per level its pairs in it, then a bit per pair
    /// (`draw.wgsl` `oracle`); as the pairs grow.
    pub oracle: wgpu::Buffer,
}

/// The per-page oracle's buffer for `pairs` pairs.
fn oracle_buffer(device: &wgpu::Device, pairs: u32) -> wgpu::Buffer {
    let words = LEVEL_SLOTS as u64 + u64::from(pairs.div_ceil(32));
    buffer(
        device,
        "VirtualMaps::oracle",
        4 * words,
        STORAGE | wgpu::BufferUsages::COPY_SRC,
    )
}

/// Bytes of one `DrawIndexedIndirectArgs`.
const DRAW_BYTES: u64 = 20;

impl Lists {
    pub fn new(device: &wgpu::Device) -> Self {
        Self {
            moved: buffer(device, "VirtualMaps::moved", 32 * 64, STORAGE),
            moved_capacity: 64,
            ranges: buffer(device, "VirtualMaps::ranges", 16, STORAGE),
            ranges_scene: None,
            pairs: buffer(device, "VirtualMaps::pairs", 8 << 20, PAIRS_USAGE),
            pairs_capacity: 1 << 20,
            draws: buffer(
                device,
                "VirtualMaps::draws",
                DRAW_BYTES << 17,
                STORAGE | wgpu::BufferUsages::INDIRECT,
            ),
            draws_capacity: 1 << 17,
            oracle: oracle_buffer(device, 1 << 20),
        }
    }

    /// Each instance's indices in the scene's buffers, for the cull's draws, whether it is
    /// left out (`excluded`, sorted) and whether it may move.
    pub fn follow_scene(
        &mut self,
        ctx: &GpuContext,
        (scene, scene_gpu): (&Scene, &SceneGpu),
        excluded: &[u32],
    ) {
        if self.ranges_scene == Some(scene_gpu.id) {
            return;
        }
        let ranges: Vec<[u32; 4]> = (0..)
            .zip(scene_gpu.instance_ranges.iter().zip(&scene.instances))
            .map(|(i, (r, instance))| {
                let out = u32::from(excluded.binary_search(&i).is_ok());
                let movable = u32::from(instance.mobility != Mobility::Static);
                [
                    r.first_index,
                    r.index_count,
                    r.base_vertex as u32,
                    out | movable << 1,
                ]
            })
            .collect();
        self.ranges = buffer(
            &ctx.device,
            "VirtualMaps::ranges",
            (ranges.len() * 16) as u64,
            STORAGE,
        );
        ctx.queue
            .write_buffer(&self.ranges, 0, bytemuck::cast_slice(&ranges));
        self.ranges_scene = Some(scene_gpu.id);
    }

    /// The moved boxes into their buffer (min and max each), grown as needed.
    pub fn write_moved(&mut self, ctx: &GpuContext, boxes: &[[f32; 4]]) {
        let needed = (boxes.len() / 2) as u32;
        if needed > self.moved_capacity {
            self.moved_capacity = needed.next_power_of_two();
            self.moved = buffer(
                &ctx.device,
                "VirtualMaps::moved",
                32 * u64::from(self.moved_capacity),
                STORAGE,
            );
        }
        if !boxes.is_empty() {
            ctx.queue
                .write_buffer(&self.moved, 0, bytemuck::cast_slice(boxes));
        }
    }

    /// Room for at least `pairs` pairs and `draws` draws (after a frame overflowed).
    pub fn grow(&mut self, device: &wgpu::Device, pairs: u32, draws: u32) {
        if pairs > self.pairs_capacity {
            self.pairs_capacity = pairs.next_power_of_two();
            self.pairs = buffer(
                device,
                "VirtualMaps::pairs",
                8 * u64::from(self.pairs_capacity),
                PAIRS_USAGE,
            );
            self.oracle = oracle_buffer(device, self.pairs_capacity);
        }
        if draws > self.draws_capacity {
            self.draws_capacity = draws.next_power_of_two();
            self.draws = buffer(
                device,
                "VirtualMaps::draws",
                DRAW_BYTES * u64::from(self.draws_capacity),
                STORAGE | wgpu::BufferUsages::INDIRECT,
            );
        }
    }
}
