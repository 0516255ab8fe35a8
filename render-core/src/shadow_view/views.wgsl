// One shadow view: a light projection and where in a depth texture it renders. A single map
// is one view, a cascade one each, a spot light one, a point light six. Keep in sync with
// shadow_view/gpu_data.rs (ShadowViewGpu): 256 bytes, so that one buffer is both the array
// of every view (storage) and, a slice each, the view of a pass (uniform).

struct ShadowView {
    light_clip_from_world: mat4x4<f32>,
    world_from_light_clip: mat4x4<f32>,
    // xyz: light-space x axis in world; w: texel size along x in metres.
    light_right: vec4<f32>,
    // xyz: light-space y axis in world; w: texel size along y in metres.
    light_up: vec4<f32>,
    // xyz: direction the light travels; w: depth range in metres.
    light_dir: vec4<f32>,
    // x: layer of the depth array; y, z: the first texel of its square; w: the square's side
    // in texels.
    square: vec4<u32>,
    // x, y: the camera depths [near, far) in metres whose points this view shades; z: 0 when
    // measured along the view direction, 1 from the eye (view/common.wgsl `shading_depth`).
    shades_depth_m: vec4<f32>,
    // x: this view's index; y: 1 for a perspective view from a point (a spot light, a cube
    // face: texels per w in light_right.w and light_up.w, depth metres per w squared in
    // light_dir.w); z: 1 when the many-lights passes rasterise nothing; w: rounds of extra
    // vertex work (shadow_view/mod.rs GeometryLoad, layered/load.wgsl).
    index: vec4<u32>,
    // A snapped view's texel grid (`light_clip`): xyz the light-space translation, w 1 when
    // the view has one.
    grid_origin: vec4<f32>,
    // x, y: texels per metre; z, w: the map centre's light-space position in texels.
    grid: vec4<f32>,
}

// Where view `view` places the world point: its light clip position. Every pass that puts
// a point or a vertex into a view calls this. A snapped (stabilised) view places it on its
// texel grid: light-space metres times texels per metre, less the centre's whole texels,
// over half the side; for a side that is a power of two every step after the first is exact,
// so two frames whose maps lie whole texels apart place the point exactly that many texels
// apart, and rasterise and compare the same depths (geom/light_fit.rs `TexelGrid`).
fn light_clip(view: ShadowView, world: vec3<f32>) -> vec4<f32> {
    let clip = view.light_clip_from_world * vec4<f32>(world, 1.0);
    if (view.grid_origin.w == 0.0) {
        return clip;
    }
    let light = vec2<f32>(
        dot(view.light_right.xyz, world) + view.grid_origin.x,
        dot(view.light_up.xyz, world) + view.grid_origin.y,
    );
    let texels = light * view.grid.xy - view.grid.zw;
    let half = 0.5 * f32(view.square.w);
    return vec4<f32>(texels / half, clip.z, 1.0);
}

// The cube face (geom/punctual.rs CUBE_FACES: +X, -X, +Y, -Y, +Z, -Z) of the major axis of
// `d`, a direction from a point light: the face whose view holds the point.
fn cube_face(d: vec3<f32>) -> u32 {
    let a = abs(d);
    if (a.x >= a.y && a.x >= a.z) {
        return select(0u, 1u, d.x < 0.0);
    }
    if (a.y >= a.z) {
        return 2u + select(0u, 1u, d.y < 0.0);
    }
    return 4u + select(0u, 1u, d.z < 0.0);
}
