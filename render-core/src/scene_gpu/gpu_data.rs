//! GPU mirrors of the scene's vertices, per-instance data and per-instance bounds.
//! Keep in sync with `scene_gpu/instance.wgsl`.

use bytemuck::{Pod, Zeroable};

/// Interleaved vertex: position and normal in the mesh's local space.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}
const _: () = assert!(size_of::<Vertex>() == 24);

/// Bit in [`InstanceData::flags`] and [`InstanceBounds::flags`]: the instance casts shadows.
pub const FLAG_CASTER: u32 = 1;
/// Bit in [`InstanceData::flags`] and [`InstanceBounds::flags`]: the instance receives shadows.
pub const FLAG_RECEIVER: u32 = 2;
/// Bit in [`InstanceBounds::flags`]: the instance moves (incremental updates clear its boxes).
pub const FLAG_DYNAMIC: u32 = 4;

/// One instance. `normal_from_local` is the inverse transpose of the upper 3x3, one column per
/// `[f32; 4]` (the fourth component is padding).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct InstanceData {
    pub world_from_local: [[f32; 4]; 4],
    pub normal_from_local: [[f32; 4]; 3],
    pub base_color: [f32; 4],
    /// x: [`FLAG_CASTER`] | [`FLAG_RECEIVER`]; y, z, w: padding.
    pub flags: [u32; 4],
}
const _: () = assert!(size_of::<InstanceData>() == 144);

/// One instance's world-space box and flags (`InstanceBounds` in `instance.wgsl`), read by
/// the visibility pass and GPU culling.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct InstanceBounds {
    pub min: [f32; 3],
    /// [`FLAG_CASTER`] | [`FLAG_RECEIVER`] | [`FLAG_DYNAMIC`].
    pub flags: u32,
    pub max: [f32; 3],
    pub _pad: u32,
}
const _: () = assert!(size_of::<InstanceBounds>() == 32);
