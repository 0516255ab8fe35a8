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
    // x, y: the camera view depths [near, far) in metres whose points this view shades.
    shades_depth_m: vec4<f32>,
    // x: this view's index; y, z, w: unused.
    index: vec4<u32>,
    padding: array<vec4<f32>, 2>,
}
