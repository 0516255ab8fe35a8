//! The scene as shadow volumes see it, built once per scene (and excluded set): every mesh's
//! edges (`edges.rs`), the casters with where their edges and triangles start among the
//! work items, and room for the records the silhouette passes append.

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::edges::{Edge, mesh_edges};
use super::pipelines::{
    BIG_CASTERS_BYTES, BIG_DISPATCH_BYTES, MAX_INTERVALS, MAX_SLICES, RECEIVER_CELLS,
};
use crate::technique::{VolumeFill, VolumePasses};

use crate::culling::codes::{OUTCOME_NOT_CASTER, OUTCOME_RENDERED};
use crate::gpu::buffer_entry;
use crate::scene::Scene;
use crate::scene_gpu::SceneGpu;

/// The bytes of the volume passes' counters (`COUNTERS` words in `volumes/find.wgsl`).
const COUNTERS_BYTES: u64 = 4 * 11;
/// The bytes of the indirect draws' arguments (`draws` in `volumes/find.wgsl`: eight of
/// four words), copied after the counters to be read back with them.
pub(super) const DRAWS_BYTES: u64 = 8 * 16;
/// Where the draws' arguments go in the counters buffer, and the bytes read back.
pub(super) const DRAWS_OFFSET: u64 = COUNTERS_BYTES;
pub(super) const READBACK_BYTES: u64 = COUNTERS_BYTES + DRAWS_BYTES;

/// One frame's counters as read back (`counters` in `volumes/find.wgsl`, then the draws'
/// arguments): how the volumes were counted and culled, what they drew, and their fill.
pub(super) fn read_counters(words: &[u32]) -> (VolumePasses, VolumeFill) {
    // Draw k's vertex count (`volumes/common.wgsl`: z-fail quads, caps at the casters,
    // moved caps and fan caps, then z-pass), and the fan caps, whose two triangles at the
    // fan's corner draw nothing (`fan_caps` in `volumes/find.wgsl`).
    let vertices = |k: usize| words[(DRAWS_OFFSET / 4) as usize + 4 * k];
    let caps: u32 = [1, 2, 3, 5, 6, 7].into_iter().map(vertices).sum();
    let passes = VolumePasses {
        z_pass: words[0],
        z_fail: words[1].saturating_sub(words[0]),
        intervals: words[4],
        big_casters: words[8],
        whole_past_budget: words[9],
        quad_triangles: (vertices(0) + vertices(4)) / 3,
        cap_triangles: (caps / 3).saturating_sub(2 * words[10]),
    };
    let fill = VolumeFill {
        fragments: u64::from(words[2]),
        stencil_writes: u64::from(words[3]),
    };
    (passes, fill)
}

/// `Caster` in `volumes/common.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct CasterGpu {
    instance: u32,
    first_edge: u32,
    first_triangle: u32,
    base_vertex: u32,
    edge_start: u32,
    triangle_start: u32,
    closed: u32,
    /// 1 where the mesh is convex (`MeshEdges::convex`).
    convex: u32,
    /// The mesh's own box (w unused): with the instance's transform, an oriented box.
    local_min: [f32; 4],
    local_max: [f32; 4],
}

/// The scene as the volumes see it: every mesh's edges, the casters, room for the records.
pub(super) struct SceneVolumes {
    pub scene_id: u64,
    pub excluded: Vec<u32>,
    pub casters: u32,
    pub edge_items: u32,
    pub triangle_items: u32,
    pub closed_meshes: u32,
    pub meshes: u32,
    pub scene_group: wgpu::BindGroup,
    pub draw_group: wgpu::BindGroup,
    pub quads: wgpu::Buffer,
    pub caps: wgpu::Buffer,
    /// Fan caps' records, and per caster its fan's corner (`volumes/records.wgsl`
    /// `append_fans`).
    pub fans: wgpu::Buffer,
    pub anchors: wgpu::Buffer,
    pub draws: wgpu::Buffer,
    pub kept: wgpu::Buffer,
    pub intervals: wgpu::Buffer,
    /// Per interval, the strips of the picture it is drawn across (`strips_word` in
    /// `volumes/find.wgsl`).
    pub strips: wgpu::Buffer,
    pub grid: wgpu::Buffer,
    /// Per grid cell, its visible receiver points' count and first index in the view's list
    /// (`volumes/grid.wgsl`).
    pub cells: wgpu::Buffer,
    /// The casters too big for the cull's workgroup, and what their own workgroups
    /// gathered (`volumes/big_casters.wgsl`).
    pub big: wgpu::Buffer,
    /// Their workgroups, copied from after the list for the indirect dispatches
    /// (`volumes/find_passes.rs`).
    pub big_dispatch: wgpu::Buffer,
    pub counters: wgpu::Buffer,
    pub outcomes: wgpu::Buffer,
    pub instances: u32,
    /// Per instance, its caster's index (`None`: not a caster).
    pub caster_of: Vec<Option<u32>>,
}

/// The layouts the scene's groups are made for.
pub(super) struct SceneLayouts<'a> {
    pub scene: &'a wgpu::BindGroupLayout,
    pub draw: &'a wgpu::BindGroupLayout,
}

impl SceneVolumes {
    /// What the volumes of `scene` are named as when their buffers do not fit.
    pub fn asked(scene: &Scene) -> crate::gpu::Asked {
        crate::gpu::Asked {
            what: format!(
                "the shadow volumes of {} objects ({} triangles)",
                scene.instances.len(),
                scene.triangle_count()
            ),
            remedy: "a smaller scene, or another technique (--shadow)",
        }
    }

    /// `excluded` sorted; `uniforms` the frame's `VolumeFrame`.
    pub fn new(
        device: &wgpu::Device,
        layouts: &SceneLayouts<'_>,
        uniforms: &wgpu::Buffer,
        (scene, scene_gpu): (&Scene, &SceneGpu),
        excluded: &[u32],
    ) -> Self {
        let mut edges: Vec<Edge> = Vec::new();
        let mut mesh_info = Vec::with_capacity(scene.meshes.len());
        let mut closed_meshes = 0;
        for mesh in &scene.meshes {
            let e = mesh_edges(&mesh.positions, &mesh.indices);
            closed_meshes += u32::from(e.closed);
            mesh_info.push((edges.len() as u32, e.edges.len() as u32, e.closed, e.convex));
            edges.extend(e.edges);
        }
        let mut casters = Vec::new();
        let (mut edge_items, mut triangle_items) = (0u32, 0u32);
        let mut outcomes = vec![OUTCOME_NOT_CASTER; scene.instances.len()];
        let mut caster_of = vec![None; scene.instances.len()];
        for (i, instance) in (0u32..).zip(&scene.instances) {
            let range = scene_gpu.instance_ranges[i as usize];
            if !instance.casts_shadow || excluded.binary_search(&i).is_ok() || range.index_count < 3
            {
                continue;
            }
            let (first_edge, edge_count, closed, convex) = mesh_info[instance.mesh as usize];
            let mesh = &scene.meshes[instance.mesh as usize];
            outcomes[i as usize] = OUTCOME_RENDERED;
            caster_of[i as usize] = Some(casters.len() as u32);
            casters.push(CasterGpu {
                instance: i,
                first_edge,
                first_triangle: range.first_index / 3,
                base_vertex: range.base_vertex as u32,
                edge_start: edge_items,
                triangle_start: triangle_items,
                closed: u32::from(closed),
                convex: u32::from(convex),
                local_min: mesh.aabb_in_local.min.extend(0.0).to_array(),
                local_max: mesh.aabb_in_local.max.extend(0.0).to_array(),
            });
            edge_items += edge_count;
            triangle_items += range.index_count / 3;
        }
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let keep = |mut v: Vec<u8>| {
            if v.is_empty() {
                v.resize(16, 0);
            }
            v
        };
        let edges_buffer = init(
            "Volumes::edges",
            &keep(bytemuck::cast_slice(&edges).to_vec()),
            wgpu::BufferUsages::STORAGE,
        );
        let casters_buffer = init(
            "Volumes::casters",
            &keep(bytemuck::cast_slice(&casters).to_vec()),
            wgpu::BufferUsages::STORAGE,
        );
        // Per interval, a quad at most twice per edge (an open mesh's edge between a lit and
        // an unlit triangle) and CAP_RECORDS cap records per triangle (`cap_slot` in
        // common.wgsl): room for one interval of every caster and as many again, which
        // casters with more intervals share (`within_room` in find.wgsl).
        let record_buffer = |label: &str, records: u32| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: u64::from(records.max(1)) * 8,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        };
        let quads = record_buffer("Volumes::quads", edge_items.saturating_mul(2 * 2));
        // A fan-capped caster's edge once per interval where it starts and where it ends.
        let fans = record_buffer("Volumes::fans", edge_items.saturating_mul(2 * 2));
        let caps = record_buffer("Volumes::caps", triangle_items.saturating_mul(CAP_RECORDS));
        let storage_buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        let draws = storage_buffer(
            "Volumes::draws",
            DRAWS_BYTES,
            wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_SRC,
        );
        let anchors = storage_buffer(
            "Volumes::fan_anchors",
            u64::from(casters.len() as u32) * 4,
            wgpu::BufferUsages::COPY_DST,
        );
        let kept = storage_buffer(
            "Volumes::kept",
            u64::from(casters.len() as u32) * 4,
            wgpu::BufferUsages::COPY_SRC,
        );
        let intervals = storage_buffer(
            "Volumes::intervals",
            u64::from(casters.len() as u32) * u64::from(MAX_INTERVALS) * 8,
            wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        );
        let strips = storage_buffer(
            "Volumes::interval_strips",
            u64::from(casters.len() as u32) * u64::from(MAX_INTERVALS) * 4,
            wgpu::BufferUsages::empty(),
        );
        let grid = storage_buffer(
            "Volumes::receiver_grid",
            grid_bytes(MAX_SLICES),
            wgpu::BufferUsages::COPY_DST,
        );
        let cells = storage_buffer(
            "Volumes::receiver_cells",
            u64::from(RECEIVER_CELLS) * 8,
            wgpu::BufferUsages::COPY_DST,
        );
        let big = storage_buffer(
            "Volumes::big_casters",
            BIG_CASTERS_BYTES,
            wgpu::BufferUsages::COPY_SRC,
        );
        let big_dispatch = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("Volumes::big_casters_dispatch"),
            size: BIG_DISPATCH_BYTES,
            usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let counters = storage_buffer(
            "Volumes::counters",
            READBACK_BYTES,
            wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        );
        let scene_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Volumes::scene_group"),
            layout: layouts.scene,
            entries: &[
                buffer_entry(0, uniforms),
                buffer_entry(1, &scene_gpu.vertex_buffer),
                buffer_entry(2, &scene_gpu.index_buffer),
                buffer_entry(3, &edges_buffer),
                buffer_entry(4, &casters_buffer),
                buffer_entry(5, &scene_gpu.bounds_buffer),
            ],
        });
        let draw_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Volumes::draw_group"),
            layout: layouts.draw,
            entries: &[
                buffer_entry(0, &quads),
                buffer_entry(1, &caps),
                buffer_entry(2, &intervals),
                buffer_entry(3, &kept),
                buffer_entry(4, &strips),
                buffer_entry(5, &fans),
                buffer_entry(6, &anchors),
            ],
        });
        Self {
            scene_id: scene_gpu.id,
            excluded: excluded.to_vec(),
            casters: casters.len() as u32,
            edge_items,
            triangle_items,
            closed_meshes,
            meshes: scene.meshes.len() as u32,
            scene_group,
            draw_group,
            quads,
            caps,
            fans,
            anchors,
            draws,
            kept,
            intervals,
            strips,
            grid,
            cells,
            big,
            big_dispatch,
            counters,
            outcomes: init(
                "Volumes::outcomes",
                &keep(bytemuck::cast_slice(&outcomes).to_vec()),
                wgpu::BufferUsages::STORAGE,
            ),
            instances: scene.instances.len() as u32,
            caster_of,
        }
    }
}

/// Bytes of the receiver grid with its first `slices` slices: a word per cell, then three
/// per cell and slice (`volumes/grid.wgsl`).
pub(super) fn grid_bytes(slices: u32) -> u64 {
    u64::from(RECEIVER_CELLS) * 4 * (1 + 3 * u64::from(slices))
}

/// Cap records per triangle item (`CAP_RECORDS` in `common.wgsl`).
pub(crate) const CAP_RECORDS: u32 = 5;

/// The interval count's bits in a caster's `kept` word (`COUNT_BITS` in `common.wgsl`).
const COUNT_BITS: u32 = 0x3fff_ffff;

impl SceneVolumes {
    /// The last frame's intervals of `instance`'s volume (`None`: not a caster). Blocks.
    pub fn read_intervals(
        &self,
        ctx: &crate::gpu::GpuContext,
        instance: u32,
    ) -> Result<Option<Vec<[f32; 2]>>, crate::gpu::GpuError> {
        let Some(Some(caster)) = self.caster_of.get(instance as usize).copied() else {
            return Ok(None);
        };
        let kept: Vec<u32> = bytemuck::pod_collect_to_vec(&crate::gpu::read_buffer(
            ctx,
            &self.kept,
            u64::from(self.casters) * 4,
            "volume intervals",
        )?);
        let spans: Vec<[f32; 2]> = bytemuck::pod_collect_to_vec(&crate::gpu::read_buffer(
            ctx,
            &self.intervals,
            u64::from(self.casters) * u64::from(MAX_INTERVALS) * 8,
            "volume intervals",
        )?);
        let count = (kept[caster as usize] & COUNT_BITS).min(MAX_INTERVALS);
        let first = (caster * MAX_INTERVALS) as usize;
        Ok(Some(spans[first..first + count as usize].to_vec()))
    }
}
