// The multiview path: one pass draws a group of maps, a layer each, and the view index picks
// the group's view (layered/paths.rs). Depth only.
#import view/common.wgsl
#import layered/load.wgsl

// The group's first view.
@group(1) @binding(0) var<uniform> pass_view: ShadowView;

struct MultiviewOut {
    // Invariant: every path must rasterise the same depths.
    @invariant @builtin(position) clip: vec4<f32>,
}

@vertex
fn vs_multiview(
    @location(0) position: vec3<f32>,
    @builtin(instance_index) instance: u32,
    @builtin(view_index) view_index: u32,
) -> MultiviewOut {
    var out: MultiviewOut;
    let view = shadow_views[pass_view.index.x + view_index];
    out.clip = loaded(view, shadow_clip_position(view, instance, position));
    return out;
}

