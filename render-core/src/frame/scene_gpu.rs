//! The scene's GPU copy: one vertex and index buffer for all meshes, one instance buffer, and
//! indirect draw lists. Long-lived per scene; instance data is rewritten when objects move.

use std::sync::atomic::{AtomicU64, Ordering};

use glam::{Mat3, Mat4};
use wgpu::util::DeviceExt;

use super::gpu_data::{FLAG_CASTER, FLAG_RECEIVER, InstanceData, Vertex};
use crate::gpu::GpuContext;
use crate::scene::{Instance, Scene};

/// Where a mesh's triangles live in the shared buffers.
#[derive(Clone, Copy, Debug)]
pub struct MeshRange {
    pub first_index: u32,
    pub index_count: u32,
    pub base_vertex: i32,
}

/// GPU buffers of one scene.
pub struct SceneGpu {
    /// Distinguishes scenes so renderers can rebuild bind groups when the scene changes.
    pub id: u64,
    pub vertex_buffer: wgpu::Buffer,
    pub index_buffer: wgpu::Buffer,
    pub instance_buffer: wgpu::Buffer,
    /// Per instance: the world-space box and caster / receiver bits, for GPU culling
    /// (`Bounds` in `culling/cull_common.wgsl`).
    pub bounds_buffer: wgpu::Buffer,
    pub mesh_ranges: Vec<MeshRange>,
    /// Per instance: its mesh's range.
    pub instance_ranges: Vec<MeshRange>,
    pub instance_count: u32,
}

static NEXT_SCENE_ID: AtomicU64 = AtomicU64::new(1);

impl SceneGpu {
    pub fn new(ctx: &GpuContext, scene: &Scene) -> Self {
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let mut mesh_ranges = Vec::with_capacity(scene.meshes.len());
        for mesh in &scene.meshes {
            mesh_ranges.push(MeshRange {
                first_index: indices.len() as u32,
                index_count: mesh.indices.len() as u32,
                base_vertex: vertices.len() as i32,
            });
            vertices.extend(
                mesh.positions
                    .iter()
                    .zip(&mesh.normals)
                    .map(|(p, n)| Vertex {
                        position: p.to_array(),
                        normal: n.to_array(),
                    }),
            );
            indices.extend_from_slice(&mesh.indices);
        }
        // wgpu rejects zero-sized vertex buffers in some paths; keep one dummy element.
        if vertices.is_empty() {
            vertices.push(Vertex {
                position: [0.0; 3],
                normal: [0.0, 1.0, 0.0],
            });
        }
        if indices.is_empty() {
            indices.extend([0, 0, 0]);
        }
        let instance_data = instance_data(&scene.instances);
        let device = &ctx.device;
        let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("SceneGpu::vertices"),
            contents: bytemuck::cast_slice(&vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("SceneGpu::indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let instance_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("SceneGpu::instances"),
            contents: bytemuck::cast_slice(&instance_data),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let bounds_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("SceneGpu::bounds"),
            contents: bytemuck::cast_slice(&bounds_data(&scene.instances)),
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
        });
        let instance_ranges = scene
            .instances
            .iter()
            .map(|i| mesh_ranges[i.mesh as usize])
            .collect();
        Self {
            id: NEXT_SCENE_ID.fetch_add(1, Ordering::Relaxed),
            vertex_buffer,
            index_buffer,
            instance_buffer,
            bounds_buffer,
            mesh_ranges,
            instance_ranges,
            instance_count: scene.instances.len() as u32,
        }
    }

    /// Rewrites the instance data of `moved` instances (after dynamic objects moved), one
    /// write per run of consecutive instances.
    pub fn update_instances(&self, ctx: &GpuContext, scene: &Scene, moved: &[u32]) {
        let mut sorted = moved.to_vec();
        sorted.sort_unstable();
        sorted.dedup();
        let mut k = 0;
        while k < sorted.len() {
            let first = sorted[k];
            let mut last = first;
            while k + 1 < sorted.len() && sorted[k + 1] == last + 1 {
                k += 1;
                last = sorted[k];
            }
            let data = instance_data(&scene.instances[first as usize..=last as usize]);
            let offset = u64::from(first) * size_of::<InstanceData>() as u64;
            ctx.queue
                .write_buffer(&self.instance_buffer, offset, bytemuck::cast_slice(&data));
            let bounds = bounds_data(&scene.instances[first as usize..=last as usize]);
            ctx.queue.write_buffer(
                &self.bounds_buffer,
                u64::from(first) * size_of::<InstanceBounds>() as u64,
                bytemuck::cast_slice(&bounds),
            );
            k += 1;
        }
    }
}

fn instance_data(instances: &[Instance]) -> Vec<InstanceData> {
    let mut data: Vec<InstanceData> = instances
        .iter()
        .map(|inst| {
            let normal = normal_from_local(&inst.world_from_local);
            let flags = shadow_flags(inst);
            InstanceData {
                world_from_local: inst.world_from_local.to_cols_array_2d(),
                normal_from_local: [
                    normal.x_axis.extend(0.0).to_array(),
                    normal.y_axis.extend(0.0).to_array(),
                    normal.z_axis.extend(0.0).to_array(),
                ],
                base_color: inst.base_color,
                flags: [flags, 0, 0, 0],
            }
        })
        .collect();
    if data.is_empty() {
        data.push(bytemuck::Zeroable::zeroed());
    }
    data
}

/// Inverse transpose of the upper 3x3; a singular transform keeps its own 3x3.
/// [`FLAG_CASTER`] | [`FLAG_RECEIVER`] as the shaders read them.
fn shadow_flags(inst: &Instance) -> u32 {
    (if inst.casts_shadow { FLAG_CASTER } else { 0 })
        | if inst.receives_shadow {
            FLAG_RECEIVER
        } else {
            0
        }
}

/// One instance's box and flags as `culling/cull_common.wgsl` reads them.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct InstanceBounds {
    min: [f32; 3],
    /// [`FLAG_CASTER`] | [`FLAG_RECEIVER`].
    flags: u32,
    max: [f32; 3],
    padding: u32,
}

fn bounds_data(instances: &[Instance]) -> Vec<InstanceBounds> {
    let mut data: Vec<InstanceBounds> = instances
        .iter()
        .map(|inst| {
            // Bit 4: moves (culling/cull_common.wgsl, `CULL_DYNAMIC`).
            let dynamic = if inst.mobility == crate::scene::Mobility::Dynamic {
                4
            } else {
                0
            };
            let flags = shadow_flags(inst) | dynamic;
            let b = inst.aabb_in_world;
            InstanceBounds {
                min: b.min.to_array(),
                flags,
                max: b.max.to_array(),
                padding: 0,
            }
        })
        .collect();
    if data.is_empty() {
        data.push(bytemuck::Zeroable::zeroed());
    }
    data
}

fn normal_from_local(world_from_local: &Mat4) -> Mat3 {
    let m = Mat3::from_mat4(*world_from_local);
    let det = m.determinant();
    if det.abs() > f32::EPSILON {
        m.inverse().transpose()
    } else {
        m
    }
}

/// Instances to draw in one pass, as indirect draw arguments. Long-lived, refilled per frame.
pub struct DrawList {
    label: &'static str,
    buffer: wgpu::Buffer,
    capacity: u32,
    args: Vec<wgpu::util::DrawIndexedIndirectArgs>,
    /// `args` as bytes for the upload, kept to avoid a per-frame allocation.
    bytes: Vec<u8>,
    pub triangles: u64,
}

impl DrawList {
    pub fn new(ctx: &GpuContext, label: &'static str) -> Self {
        Self {
            label,
            buffer: Self::create_buffer(ctx, label, 64),
            capacity: 64,
            args: Vec::new(),
            bytes: Vec::new(),
            triangles: 0,
        }
    }

    fn create_buffer(ctx: &GpuContext, label: &str, capacity: u32) -> wgpu::Buffer {
        ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: u64::from(capacity) * size_of::<wgpu::util::DrawIndexedIndirectArgs>() as u64,
            usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    pub fn len(&self) -> u32 {
        self.args.len() as u32
    }

    pub fn is_empty(&self) -> bool {
        self.args.is_empty()
    }

    /// Fills the list with `instances` and uploads it.
    pub fn upload(&mut self, ctx: &GpuContext, scene_gpu: &SceneGpu, instances: &[u32]) {
        self.args.clear();
        self.triangles = 0;
        for &i in instances {
            let range = scene_gpu.instance_ranges[i as usize];
            self.triangles += u64::from(range.index_count / 3);
            self.args.push(wgpu::util::DrawIndexedIndirectArgs {
                index_count: range.index_count,
                instance_count: 1,
                first_index: range.first_index,
                base_vertex: range.base_vertex,
                first_instance: i,
            });
        }
        if self.len() > self.capacity {
            self.capacity = self.len().next_power_of_two();
            self.buffer = Self::create_buffer(ctx, self.label, self.capacity);
        }
        if !self.args.is_empty() {
            self.bytes.clear();
            for a in &self.args {
                self.bytes.extend_from_slice(a.as_bytes());
            }
            ctx.queue.write_buffer(&self.buffer, 0, &self.bytes);
        }
    }

    /// Records the draws; uses one multi-draw when the device can start at any instance.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        scene_gpu: &SceneGpu,
        indirect_first_instance: bool,
    ) {
        if self.args.is_empty() {
            return;
        }
        pass.set_vertex_buffer(0, scene_gpu.vertex_buffer.slice(..));
        pass.set_index_buffer(scene_gpu.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        if indirect_first_instance {
            pass.multi_draw_indexed_indirect(&self.buffer, 0, self.len());
        } else {
            for a in &self.args {
                pass.draw_indexed(
                    a.first_index..a.first_index + a.index_count,
                    a.base_vertex,
                    a.first_instance..a.first_instance + 1,
                );
            }
        }
    }
}

/// The vertex layout of [`Vertex`].
pub const VERTEX_LAYOUT: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: size_of::<Vertex>() as u64,
    step_mode: wgpu::VertexStepMode::Vertex,
    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
};
