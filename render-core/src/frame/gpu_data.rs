//! GPU mirrors of the frame's uniforms, per-instance data and vertices.
//! Keep in sync with `frame/common.wgsl`.

use bytemuck::{Pod, Zeroable};

/// Interleaved vertex: position and normal in the mesh's local space.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}
const _: () = assert!(size_of::<Vertex>() == 24);

/// Bit in [`InstanceData::flags`]: the instance casts shadows.
pub const FLAG_CASTER: u32 = 1;
/// Bit in [`InstanceData::flags`]: the instance receives shadows.
pub const FLAG_RECEIVER: u32 = 2;

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

/// Bit in `FrameUniforms::params[3]`: tint objects by caster outcome.
pub const OVERLAY_CASTERS: u32 = 1;

/// Per-object outcome codes in the outcome buffer (keep in sync with camera.wgsl): 0 not a
/// caster, 1 rendered, 2 excluded, 3 + k culled by stage k.
pub fn outcome_code(outcome: super::CasterOutcome) -> u32 {
    match outcome {
        super::CasterOutcome::NotACaster => 0,
        super::CasterOutcome::Rendered => 1,
        super::CasterOutcome::Excluded => 2,
        super::CasterOutcome::Culled { stage } => 3 + stage as u32,
    }
}

/// The outcome for a code of [`outcome_code`].
pub fn outcome_from_code(code: u32) -> super::CasterOutcome {
    match code {
        0 => super::CasterOutcome::NotACaster,
        1 => super::CasterOutcome::Rendered,
        2 => super::CasterOutcome::Excluded,
        k => super::CasterOutcome::Culled {
            stage: (k - 3) as usize,
        },
    }
}

/// Per-frame constants shared by every pass.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    pub clip_from_world: [[f32; 4]; 4],
    pub light_clip_from_world: [[f32; 4]; 4],
    /// xyz: camera position; w: padding.
    pub eye_world: [f32; 4],
    /// xyz: unit vector towards the sun; w: sun illuminance scale.
    pub direction_to_sun: [f32; 4],
    /// xyz: light-space x axis in world; w: shadow texel size along x in metres.
    pub light_right: [f32; 4],
    /// xyz: light-space y axis in world; w: shadow texel size along y in metres.
    pub light_up: [f32; 4],
    /// xyz: direction the light travels; w: light depth range in metres.
    pub light_dir: [f32; 4],
    /// x: constant depth bias (m); y: slope bias (texels); z: normal offset (texels);
    /// w: shadow map size in texels.
    pub shadow: [f32; 4],
    /// x: PCF kernel width in texels (1, 2, 3 or 5); y: 1 when shadows are on; z: 1 when the
    /// frame measures error and oracle against the reference map; w: overlay bits
    /// ([`OVERLAY_CASTERS`]).
    pub params: [u32; 4],
}
const _: () = assert!(size_of::<FrameUniforms>() == 240);
