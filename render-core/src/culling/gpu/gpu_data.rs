//! GPU mirrors of culling's per-frame and per-view parameters. Keep in sync with
//! `culling/cull_common.wgsl` (`CullFrame`, `CullView`) and `culling/pyramid.wgsl` (`Level`).

use bytemuck::{Pod, Zeroable};

/// `CullFrame`: shared by every view.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(super) struct CullFrameGpu {
    pub camera_clip_from_world: [[f32; 4]; 4],
    /// x: instance count (the stride of per-view blocks); y: view count; z: the camera
    /// pyramid's base size; w: 1 when the states hold last frame's light-visible casters.
    pub counts: [u32; 4],
    /// x, y: the camera's view in pixels; z, w: unused.
    pub camera: [u32; 4],
}
const _: () = assert!(size_of::<CullFrameGpu>() == 96);

/// `CullView`: one view's parameters.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(super) struct CullViewGpu {
    /// x: method bits; y: mask widening in texels; z: shadow texels per mask texel; w: the
    /// mask's side in texels.
    pub params: [u32; 4],
    /// x: how far a shadow volume starts before its caster, in normalised light depth.
    pub volume: [f32; 4],
    /// Words per view of x: the occlusion pyramid, y: the mask pyramid.
    pub pyramids: [u32; 4],
    /// x: the filter's reach in shadow texels.
    pub reach: [u32; 4],
}
const _: () = assert!(size_of::<CullViewGpu>() == 64);

/// `Level`: one reduce pass of a pyramid.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(super) struct LevelGpu {
    /// Destination offset and width, source offset and width (texels).
    pub level: [u32; 4],
    /// x: words per view of the pyramid; y: words per view of the mask bits.
    pub blocks: [u32; 4],
}
const _: () = assert!(size_of::<LevelGpu>() == 32);
