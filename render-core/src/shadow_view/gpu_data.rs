//! The GPU mirror of a shadow view. Keep in sync with `shadow_view/views.wgsl`.

use bytemuck::{Pod, Zeroable};

use super::{DepthMeasure, ShadowView};

/// `ShadowView` in `views.wgsl`: 256 bytes, the largest uniform-offset alignment wgpu allows,
/// so one buffer serves as the array of views and as one uniform slice per view.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ShadowViewGpu {
    pub light_clip_from_world: [[f32; 4]; 4],
    pub world_from_light_clip: [[f32; 4]; 4],
    /// xyz: light-space x axis in world; w: texel size along x in metres (per clip w for a
    /// warped view).
    pub light_right: [f32; 4],
    /// xyz: light-space y axis in world; w: texel size along y in metres (per w squared).
    pub light_up: [f32; 4],
    /// xyz: direction the light travels; w: depth range in metres (per w; per w squared for
    /// a perspective view).
    pub light_dir: [f32; 4],
    /// Layer, first texel x and y, side in texels (`square` in WGSL).
    pub square: [u32; 4],
    /// x, y: the camera depths whose points the view shades; z: how they are measured, 0 along
    /// the view direction, 1 from the eye (`DepthMeasure`); w: unused.
    pub shades_depth_m: [f32; 4],
    /// x: the view's index; y: 1 for a perspective view from a point (texels per w, depth
    /// metres per w squared); z: 1 when its passes rasterise nothing, w: rounds of extra
    /// vertex work (`GeometryLoad`).
    pub index: [u32; 4],
    /// A snapped view's texel grid (`TexelGrid`, `light_clip` in WGSL): xyz the light-space
    /// translation of `light_from_world`, w 1 when the view has a grid.
    pub grid_origin: [f32; 4],
    /// x, y: texels per metre; z, w: the map centre's light-space position in texels.
    pub grid: [f32; 4],
}
const _: () = assert!(size_of::<ShadowViewGpu>() == ShadowViewGpu::STRIDE as usize);

impl ShadowViewGpu {
    /// Bytes per view in the buffer.
    pub const STRIDE: u64 = 256;

    pub fn new(view: &ShadowView, index: u32) -> Self {
        let light = &view.light;
        let rows = light.light_from_world.transpose();
        let (right, up) = (rows.x_axis.truncate(), rows.y_axis.truncate());
        let t = view.target;
        // A warped view's texels and depth scale with the point's clip w (1 for orthographic).
        // A perspective view's texels scale with w and its metres of depth with w squared.
        let (texel, range) = match (light.warp, light.perspective) {
            (Some(w), _) => (w.texel_per_w, w.range_per_w),
            (None, Some(p)) => ([p.texel_per_w; 2], p.range_per_w2),
            (None, None) => (light.texel_size_m, light.depth_range_m),
        };
        Self {
            light_clip_from_world: light.light_clip_from_world.to_cols_array_2d(),
            world_from_light_clip: light.light_clip_from_world.inverse().to_cols_array_2d(),
            light_right: right.extend(texel[0]).to_array(),
            light_up: up.extend(texel[1]).to_array(),
            light_dir: light.light_direction.extend(range).to_array(),
            square: [t.layer, t.origin[0], t.origin[1], t.size],
            shades_depth_m: [
                view.shades_depth_m[0],
                view.shades_depth_m[1],
                match view.shades_by {
                    DepthMeasure::ViewDepth => 0.0,
                    DepthMeasure::EyeDistance => 1.0,
                },
                0.0,
            ],
            index: [
                index,
                u32::from(light.perspective.is_some()),
                u32::from(view.load.no_raster),
                view.load.vertex_work,
            ],
            grid_origin: light.grid.map_or([0.0; 4], |_| {
                light
                    .light_from_world
                    .w_axis
                    .truncate()
                    .extend(1.0)
                    .to_array()
            }),
            grid: light.grid.map_or([0.0; 4], |g| {
                [
                    g.per_metre[0],
                    g.per_metre[1],
                    g.centre_texel[0],
                    g.centre_texel[1],
                ]
            }),
        }
    }
}
