// The traditional path: a pass per map, the casters from the scene's vertex buffer (as the
// shadow-map technique draws them), with the geometry load a bench asks for. Depth only.
#import view/common.wgsl
#import layered/load.wgsl

// The view this pass renders.
@group(1) @binding(0) var<uniform> pass_view: ShadowView;

struct LayeredOut {
    // Invariant: every path must rasterise the same depths.
    @invariant @builtin(position) clip: vec4<f32>,
}

@vertex
fn vs_layered(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> LayeredOut {
    var out: LayeredOut;
    out.clip = loaded(pass_view, shadow_clip_position(pass_view, instance, position));
    return out;
}
