//! What the first volume step (`volumes/find.wgsl`) binds in group 2: the records it appends,
//! the receiver grid (`volumes/grid.wgsl`) and the camera's visible surface.

use crate::gpu::{bind_group_layout, buffer_entry, storage, texture, view_entry};
use crate::view::ViewTargets;

use super::scene::SceneVolumes;

/// The layout of group 2 of the find pipelines.
pub(super) fn find_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let surface = |sample_type| texture(sample_type, wgpu::TextureViewDimension::D2);
    let mut entries = vec![storage(false); 8];
    entries.extend([
        surface(wgpu::TextureSampleType::Uint),
        surface(wgpu::TextureSampleType::Float { filterable: false }),
    ]);
    bind_group_layout(
        device,
        "Volumes::find_layout",
        wgpu::ShaderStages::COMPUTE,
        &entries,
    )
}

/// Group 2 of the find pipelines for this frame's `targets`.
pub(super) fn find_group(
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
        ],
    })
}
