//! The scene's GPU copy: one vertex and index buffer for all meshes, one instance buffer, the
//! instances' bounds for GPU culling, and indirect draw lists. Long-lived per scene; instance
//! data is rewritten when objects move.

mod draw_list;
pub(crate) mod gpu_data;

use std::sync::atomic::{AtomicU64, Ordering};

use glam::{Mat3, Mat4};
use wgpu::util::DeviceExt;

pub use draw_list::DrawList;
use gpu_data::{FLAG_CASTER, FLAG_DYNAMIC, FLAG_RECEIVER, InstanceBounds, InstanceData, Vertex};

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
            // Storage too: shadow volumes build their quads from the vertices.
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
        });
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("SceneGpu::indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::STORAGE,
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

fn bounds_data(instances: &[Instance]) -> Vec<InstanceBounds> {
    let mut data: Vec<InstanceBounds> = instances
        .iter()
        .map(|inst| {
            let dynamic = if inst.mobility == crate::scene::Mobility::Dynamic {
                FLAG_DYNAMIC
            } else {
                0
            };
            let flags = shadow_flags(inst) | dynamic;
            let b = inst.aabb_in_world;
            InstanceBounds {
                min: b.min.to_array(),
                flags,
                max: b.max.to_array(),
                _pad: 0,
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

/// The vertex layout of [`Vertex`].
pub const VERTEX_LAYOUT: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
    array_stride: size_of::<Vertex>() as u64,
    step_mode: wgpu::VertexStepMode::Vertex,
    attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
};
