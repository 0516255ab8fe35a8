// Casters into one shadow view: depth only, or depth and caster id (instance index + 1) for the
// reference map that error and oracle are measured against.
#import view/common.wgsl

// The view this pass renders.
@group(1) @binding(0) var<uniform> pass_view: ShadowView;

struct ShadowOut {
    // Invariant: the footprint test (culling/footprints.wgsl) rasterises the same triangles.
    @invariant @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) instance: u32,
}

@vertex
fn vs_shadow(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> ShadowOut {
    var out: ShadowOut;
    out.clip = shadow_clip_position(pass_view, instance, position);
    out.instance = instance;
    return out;
}

@fragment
fn fs_shadow_id(in: ShadowOut) -> @location(0) u32 {
    return in.instance + 1u;
}
