//! What the first volume step (`volumes/find.wgsl`) binds in group 2: the records it appends,
//! the receiver grid and the view's visible receiver points listed per grid cell
//! (`volumes/grid.wgsl`), and the camera's visible surface.

use crate::gpu::{bind_group_layout, buffer_entry, storage, texture, view_entry};
use crate::view::ViewTargets;

use super::scene::SceneVolumes;

/// Bytes of one listed receiver point (`vec4<f32>`).
const POINT_BYTES: u64 = 16;

/// The layout of group 2 of the find pipelines.
pub(super) fn find_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let surface = |sample_type| texture(sample_type, wgpu::TextureViewDimension::D2);
    let position = wgpu::TextureSampleType::Float { filterable: false };
    let mut entries = vec![storage(false); 8];
    entries.extend([
        surface(wgpu::TextureSampleType::Uint),
        surface(position),
        storage(false),
        storage(false),
        surface(position),
        storage(false),
        storage(false),
        storage(false),
        storage(false),
    ]);
    bind_group_layout(
        device,
        "Volumes::find_layout",
        wgpu::ShaderStages::COMPUTE,
        &entries,
    )
}

/// The view's visible receiver points, one slot per pixel, listed by grid cell each frame.
pub(super) struct ReceiverPoints {
    points: wgpu::Buffer,
}

impl ReceiverPoints {
    pub fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        let pixels = u64::from(size.0.max(1)) * u64::from(size.1.max(1));
        let points = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("Volumes::receiver_points"),
            size: pixels * POINT_BYTES,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        Self { points }
    }

    /// Group 2 of the find pipelines for this frame's `targets`.
    pub fn find_group(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        scene: &SceneVolumes,
        targets: &ViewTargets,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Volumes::find_group"),
            layout,
            entries: &[
                buffer_entry(0, &scene.quads),
                buffer_entry(1, &scene.caps),
                buffer_entry(2, &scene.draws),
                buffer_entry(3, &scene.kept),
                buffer_entry(4, &scene.intervals),
                buffer_entry(5, &scene.grid),
                buffer_entry(6, &scene.counters),
                buffer_entry(7, &scene.outcomes),
                view_entry(8, &targets.ids_view),
                view_entry(9, &targets.positions_view),
                buffer_entry(10, &scene.cells),
                buffer_entry(11, &self.points),
                view_entry(12, &targets.normals_view),
                buffer_entry(13, &scene.big),
                buffer_entry(14, &scene.strips),
                buffer_entry(15, &scene.fans),
                buffer_entry(16, &scene.anchors),
            ],
        })
    }
}
