//! Per-layer culling in compute (Rákos 19.5, 19.6, without a geometry shader): before the maps
//! are drawn, every triangle of every caster a slot draws is tested against the slot's views
//! (frustum, and for a closed mesh the side facing the light) and the kept ones are listed per
//! slot, with an indirect draw each (`cull.wgsl`). A slot is one view (the traditional and
//! atlas paths) or one multiview group (kept where any of its views may see it).

use bytemuck::{Pod, Zeroable};

use crate::gpu::{
    FrameTimer, GpuContext, bind_group_layout, buffer, buffer_entry, compute_pipeline,
    pipeline_layout, shader_module, storage, uniform,
};
use crate::scene::Scene;
use crate::scene_gpu::SceneGpu;
use crate::shaders::compose;
use crate::shadow_map::cpu_casters::CpuCasters;
use crate::shadow_view::{LayeredPath, ShadowView};

/// Bits of `Params::counts.z` (`cull.wgsl`).
pub const CULL_FRUSTUM: u32 = 1;
pub const CULL_BACK_FACES: u32 = 2;
const JOB_CLOSED: u32 = 1;
const WORKGROUP: u32 = 64;
const MAX_GROUPS_X: u32 = 65_535;

/// The culling shader, as the renderer and the validation test compose it.
pub(crate) fn cull_source() -> String {
    compose("layered/cull.wgsl", &[])
}

/// One caster's triangles for one slot (`Job` in cull.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Job {
    first_index: u32,
    triangles: u32,
    base_vertex: i32,
    instance: u32,
    slot: u32,
    offset: u32,
    flags: u32,
    pad: u32,
}

/// One slot (`Slot` in cull.wgsl): its views and where its records start.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct SlotGpu {
    first_view: u32,
    views: u32,
    base: u32,
    pad: u32,
}

/// What a slot draws: views `first_view..first_view + views`, the casters any of them chose
/// (sorted), and where its views' lights are (a closed mesh around one of them keeps its
/// back faces: they are what that light sees first).
pub struct Slot {
    pub first_view: u32,
    pub views: u32,
    pub casters: Vec<u32>,
    pub lights: Vec<glam::Vec3>,
}

/// The culling pass and its buffers, grown as needed.
pub struct TriangleCull {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    jobs: wgpu::Buffer,
    slots: wgpu::Buffer,
    /// Kept triangles: three vertex indices and the instance with its view in the top byte.
    pub records: wgpu::Buffer,
    /// Per slot an indirect draw (`wgpu::util::DrawIndirectArgs`).
    pub draws: wgpu::Buffer,
    params: wgpu::Buffer,
    group: Option<(u64, wgpu::BindGroup)>,
    /// Bumped whenever the buffers the culled draws read change (records grown, another
    /// scene's vertices).
    pub generation: u64,
    /// The scene's vertex buffer the records index.
    vertices: Option<wgpu::Buffer>,
    /// Per mesh of the scene `closed.0`, whether it is closed.
    closed: (u64, Vec<bool>),
    /// This frame's triangles before culling, and the dispatch.
    pub triangles: u64,
    groups: [u32; 2],
    pub slot_count: u32,
}

impl TriangleCull {
    pub fn new(ctx: &GpuContext, frame: &wgpu::BindGroupLayout) -> Self {
        let device = &ctx.device;
        let layout = bind_group_layout(
            device,
            "Layered::cull",
            wgpu::ShaderStages::COMPUTE,
            &[
                storage(true),
                storage(true),
                storage(true),
                storage(true),
                storage(false),
                storage(false),
                uniform(),
            ],
        );
        let module = shader_module(device, "Layered::cull", cull_source());
        let pipeline = compute_pipeline(
            device,
            &module,
            Some(&pipeline_layout(device, "Layered::cull", &[frame, &layout])),
            "cull_triangles",
        );
        Self {
            pipeline,
            layout,
            jobs: buffer(
                device,
                "Layered::cull_jobs",
                32,
                wgpu::BufferUsages::STORAGE,
            ),
            slots: buffer(
                device,
                "Layered::cull_slots",
                16,
                wgpu::BufferUsages::STORAGE,
            ),
            records: buffer(
                device,
                "Layered::cull_records",
                16,
                wgpu::BufferUsages::STORAGE,
            ),
            draws: buffer(
                device,
                "Layered::cull_draws",
                16,
                wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::INDIRECT
                    | wgpu::BufferUsages::COPY_SRC,
            ),
            params: buffer(
                device,
                "Layered::cull_params",
                16,
                wgpu::BufferUsages::UNIFORM,
            ),
            group: None,
            generation: 0,
            vertices: None,
            closed: (u64::MAX, Vec::new()),
            triangles: 0,
            groups: [0, 0],
            slot_count: 0,
        }
    }

    /// This frame's jobs: every caster of every slot, its records' room and its slot's draw
    /// cleared; `tests` is `CULL_FRUSTUM | CULL_BACK_FACES` as asked. An error says why the
    /// frame cannot cull (its records would not fit a buffer the adapter binds).
    pub fn prepare(
        &mut self,
        ctx: &GpuContext,
        (scene, scene_gpu): (&Scene, &SceneGpu),
        slots: &[Slot],
        tests: u32,
    ) -> Result<(), String> {
        if self.closed.0 != scene_gpu.id {
            let closed = scene
                .meshes
                .iter()
                .map(|m| crate::volumes::edges::mesh_edges(&m.positions, &m.indices).closed)
                .collect();
            self.closed = (scene_gpu.id, closed);
        }
        let mut jobs = Vec::new();
        let mut gpu_slots = Vec::with_capacity(slots.len());
        let mut offset = 0u32;
        for (s, slot) in (0..).zip(slots) {
            let base = offset;
            for &i in &slot.casters {
                let range = scene_gpu.instance_ranges[i as usize];
                let instance = &scene.instances[i as usize];
                let mesh = instance.mesh as usize;
                let around = instance_around(instance, &slot.lights);
                let triangles = range.index_count / 3;
                if triangles == 0 {
                    continue;
                }
                jobs.push(Job {
                    first_index: range.first_index,
                    triangles,
                    base_vertex: range.base_vertex,
                    instance: i,
                    slot: s,
                    offset,
                    flags: if !around && self.closed.1.get(mesh).copied().unwrap_or(false) {
                        JOB_CLOSED
                    } else {
                        0
                    },
                    pad: 0,
                });
                offset += triangles;
            }
            gpu_slots.push(SlotGpu {
                first_view: slot.first_view,
                views: slot.views,
                base,
                pad: 0,
            });
        }
        let most = binding_limit(&ctx.device);
        let records = 16 * u64::from(offset.max(1));
        if records > most || bytes_of_len::<Job>(jobs.len()) > most {
            return Err(format!(
                "per-layer culling of {offset} triangles needs {} MB of records, more than this \
                 adapter binds ({} MB): the maps were drawn unculled",
                records >> 20,
                most >> 20
            ));
        }
        self.triangles = u64::from(offset);
        self.slot_count = slots.len() as u32;
        let device = &ctx.device;
        let mut grown = false;
        grown |= grow(device, &mut self.jobs, bytes_of_len::<Job>(jobs.len()));
        grown |= grow(
            device,
            &mut self.slots,
            bytes_of_len::<SlotGpu>(slots.len()),
        );
        grown |= grow(device, &mut self.records, records);
        grown |= grow(device, &mut self.draws, 16 * slots.len().max(1) as u64);
        if grown
            || self
                .group
                .as_ref()
                .is_none_or(|(id, _)| *id != scene_gpu.id)
        {
            self.group = Some((scene_gpu.id, self.bind_group(device, scene_gpu)));
            self.vertices = Some(scene_gpu.vertex_buffer.clone());
            self.generation += 1;
        }
        if !jobs.is_empty() {
            ctx.queue
                .write_buffer(&self.jobs, 0, bytemuck::cast_slice(&jobs));
        }
        if !gpu_slots.is_empty() {
            ctx.queue
                .write_buffer(&self.slots, 0, bytemuck::cast_slice(&gpu_slots));
            let draws: Vec<[u32; 4]> = gpu_slots.iter().map(|s| [0, 1, s.base * 3, 0]).collect();
            ctx.queue
                .write_buffer(&self.draws, 0, bytemuck::cast_slice(&draws));
        }
        let groups = offset.div_ceil(WORKGROUP);
        self.groups = [groups.min(MAX_GROUPS_X), groups.div_ceil(MAX_GROUPS_X)];
        let params = [jobs.len() as u32, offset, tests, self.groups[0]];
        ctx.queue
            .write_buffer(&self.params, 0, bytemuck::cast_slice(&params));
        Ok(())
    }

    /// The scene's vertex buffer the records index (a placeholder, the records, before the
    /// first frame).
    pub fn vertices(&self) -> &wgpu::Buffer {
        self.vertices.as_ref().unwrap_or(&self.records)
    }

    /// The culling dispatch, timed as one step.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame_group: &wgpu::BindGroup,
        timer: &FrameTimer,
    ) {
        let Some((_, group)) = &self.group else {
            return;
        };
        if self.triangles == 0 {
            return;
        }
        let query = timer.begin_pass(crate::gpu::pass_label::CULLING, encoder);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("Layered::cull"),
            timestamp_writes: query
                .as_ref()
                .and_then(wgpu_profiler::GpuProfilerQuery::compute_pass_timestamp_writes),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(1, group, &[]);
        pass.dispatch_workgroups(self.groups[0], self.groups[1], 1);
        drop(pass);
        timer.end_pass(encoder, query);
    }

    /// The triangles each slot kept in the last frame. Blocks: for tests and reports.
    pub fn read_kept(&self, ctx: &GpuContext) -> Result<Vec<u32>, crate::gpu::GpuError> {
        let size = 16 * u64::from(self.slot_count.max(1));
        let bytes = crate::gpu::read_buffer(ctx, &self.draws, size, "kept triangles")?;
        Ok(bytes
            .chunks_exact(16)
            .take(self.slot_count as usize)
            .map(|d| u32::from_le_bytes([d[0], d[1], d[2], d[3]]) / 3)
            .collect())
    }

    fn bind_group(&self, device: &wgpu::Device, scene_gpu: &SceneGpu) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Layered::cull"),
            layout: &self.layout,
            entries: &[
                buffer_entry(0, &self.jobs),
                buffer_entry(1, &self.slots),
                buffer_entry(2, &scene_gpu.index_buffer),
                buffer_entry(3, &scene_gpu.vertex_buffer),
                buffer_entry(4, &self.records),
                buffer_entry(5, &self.draws),
                buffer_entry(6, &self.params),
            ],
        })
    }
}

/// Whether `instance`'s box, grown by the views' near distance, holds one of `lights`.
fn instance_around(instance: &crate::scene::Instance, lights: &[glam::Vec3]) -> bool {
    let margin = glam::Vec3::splat(2.0 * crate::geom::NEAR_M);
    let b = instance.aabb_in_world;
    lights
        .iter()
        .any(|p| p.cmpge(b.min - margin).all() && p.cmple(b.max + margin).all())
}

/// The largest storage buffer this device binds whole.
fn binding_limit(device: &wgpu::Device) -> u64 {
    let limits = device.limits();
    limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size)
}

fn bytes_of_len<T>(len: usize) -> u64 {
    (len.max(1) * size_of::<T>()) as u64
}

/// Replaces `buffer` by one of at least `bytes` (a power of two) when it is smaller.
fn grow(device: &wgpu::Device, buffer: &mut wgpu::Buffer, bytes: u64) -> bool {
    if buffer.size() >= bytes {
        return false;
    }
    let most = binding_limit(device);
    *buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("Layered::cull_grown"),
        size: bytes.next_power_of_two().min(most.max(bytes)),
        usage: buffer.usage(),
        mapped_at_creation: false,
    });
    true
}

/// The slots of `path`: a view each, or a multiview group each with the union of its views'
/// casters.
pub(super) fn slots_of(
    path: LayeredPath,
    cpu: &CpuCasters,
    views: &[ShadowView],
    group: u32,
) -> Vec<Slot> {
    let group = match path {
        LayeredPath::Multiview => (group as usize).max(1),
        _ => 1,
    };
    (0..views.len().div_ceil(group))
        .map(|g| {
            let first = g * group;
            let range = first..first + (views.len() - first).min(group);
            let mut casters: Vec<u32> = range
                .clone()
                .flat_map(|v| cpu.chosen(v).iter().copied())
                .collect();
            if range.len() > 1 {
                casters.sort_unstable();
                casters.dedup();
            }
            Slot {
                first_view: first as u32,
                views: range.len() as u32,
                casters,
                lights: views[range]
                    .iter()
                    .filter_map(|v| v.light.perspective.map(|p| p.position))
                    .collect(),
            }
        })
        .collect()
}
