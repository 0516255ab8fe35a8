//! GPU mirror of the frame uniforms. Keep in sync with `view/common.wgsl`.

use bytemuck::{Pod, Zeroable};

/// Bit in [`FrameUniforms::params`]`[3]`: tint objects by caster outcome.
pub const OVERLAY_CASTERS: u32 = 1;
/// Bit in [`FrameUniforms::params`]`[3]`: tint each point by the shadow view that shades it
/// (a cascade each).
pub const OVERLAY_VIEWS: u32 = 2;

/// Per-frame constants shared by every scene pass.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    pub clip_from_world: [[f32; 4]; 4],
    /// xyz: camera position; w: unused.
    pub eye_world: [f32; 4],
    /// xyz: unit view direction; w: a pixel's width one metre from the eye, in metres
    /// (`2 tan(fov / 2) / height`), for the undersampling measure.
    pub camera_forward: [f32; 4],
    /// xyz: unit vector towards the sun; w: sun illuminance scale.
    pub direction_to_sun: [f32; 4],
    /// x: constant depth bias (m); y: slope bias (texels); z: normal offset (texels); w: the
    /// cascades' blend band, a share of each one's depths (0: none).
    pub shadow: [f32; 4],
    /// x: PCF kernel width in texels (1, 2, 3 or 5); y: 1 when shadows are on; z: 1 when the
    /// frame measures error and oracle against the reference; w: overlay bits
    /// ([`OVERLAY_CASTERS`]).
    pub params: [u32; 4],
    /// x: shadow views this frame; y: instances (the stride of per-view blocks); z: how a point's
    /// view is chosen (0 by view depth, 1 by the first map that holds it); w: the depth bias
    /// in texels of each view, as the bits of an f32.
    pub views: [u32; 4],
    /// xyz: the point light that lights the frame and casts its shadows in place of the sun;
    /// w: its intensity over the sun's illuminance ([`crate::scene::Sun::ILLUMINANCE_LX`]),
    /// candela per lux (0: the sun lights the frame), so
    /// that intensity over distance squared is on the sun's scale.
    pub point_light: [f32; 4],
    /// xyz: that light's direction where it is a spot (unit); w: the cosine of its outer cone,
    /// [`NO_CONE`] where it shines every way.
    pub spot: [f32; 4],
    /// x: the cosine of the spot's inner cone; yzw: unused.
    pub spot_inner: [f32; 4],
}
const _: () = assert!(size_of::<FrameUniforms>() == 208);

/// [`FrameUniforms::spot`]`[3]` of a light without a cone (no cosine is this small).
pub const NO_CONE: f32 = -2.0;

/// [`FrameUniforms::point_light`], `spot` and `spot_inner` for `light` (`None`: the sun lights
/// the frame).
pub fn punctual_light_fields(light: Option<crate::scene::PointShadow>) -> [[f32; 4]; 3] {
    let point = light.map_or([0.0; 4], |l| {
        let scale = (l.intensity_cd / crate::scene::Sun::ILLUMINANCE_LX).max(1e-12);
        l.position.extend(scale).to_array()
    });
    let (spot, cos_inner) =
        light
            .and_then(|l| l.cone)
            .map_or(([0.0, -1.0, 0.0, NO_CONE], 1.0), |c| {
                (
                    c.direction.extend(c.outer_rad.cos()).to_array(),
                    c.inner_rad.cos(),
                )
            });
    [point, spot, [cos_inner, 0.0, 0.0, 0.0]]
}
