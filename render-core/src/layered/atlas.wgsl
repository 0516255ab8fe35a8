// The atlas path: one instanced draw per mesh renders every map on a page of the atlas. An
// instance is a (caster, view) pair; its vertex shader places the triangle in the view's tile
// (layered/tile.wgsl, layered/paths.rs). Depth only. Composed with `enable clip_distances;`
// first.
#import view/common.wgsl
#import layered/tile.wgsl
#import layered/load.wgsl

// Per instance of the draws: x the scene instance, y the view.
@group(1) @binding(0) var<storage, read> pairs: array<vec2<u32>>;
// x: the page's side in texels.
@group(1) @binding(1) var<uniform> page: vec4<f32>;

@vertex
fn vs_atlas(@location(0) position: vec3<f32>, @builtin(instance_index) pair_index: u32) -> AtlasOut {
    let pair = pairs[pair_index];
    let view = shadow_views[pair.y];
    return in_tile(view, loaded(view, shadow_clip_position(view, pair.x, position)), page.x);
}
