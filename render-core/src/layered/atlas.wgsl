// The atlas path: one instanced draw per mesh renders every map on a page of the atlas. An
// instance is a (caster, view) pair; its vertex shader places the triangle in the view's tile
// and clip distances at the tile's edges keep it there, as a viewport would (layered/paths.rs).
// Depth only. Composed with `enable clip_distances;` first.
#import view/common.wgsl

// Per instance of the draws: x the scene instance, y the view.
@group(1) @binding(0) var<storage, read> pairs: array<vec2<u32>>;
// x: the page's side in texels.
@group(1) @binding(1) var<uniform> page: vec4<f32>;

struct AtlasOut {
    @invariant @builtin(position) clip: vec4<f32>,
    @builtin(clip_distances) tile: array<f32, 4>,
}

@vertex
fn vs_atlas(@location(0) position: vec3<f32>, @builtin(instance_index) pair_index: u32) -> AtlasOut {
    let pair = pairs[pair_index];
    let view = shadow_views[pair.y];
    let c = shadow_clip_position(view, pair.x, position);
    var out: AtlasOut;
    out.tile = array<f32, 4>(c.w - c.x, c.w + c.x, c.w - c.y, c.w + c.y);
    // The view's texel (x right, y down from its square's first texel) on the page, kept in
    // clip space (times w) so the rasteriser interpolates as it does for the view alone.
    let side = f32(view.square.w);
    let origin = vec2<f32>(view.square.yz);
    let x = ((c.x + c.w) * 0.5 * side + origin.x * c.w) / page.x;
    let y = ((c.w - c.y) * 0.5 * side + origin.y * c.w) / page.x;
    out.clip = vec4<f32>(2.0 * x - c.w, c.w - 2.0 * y, c.z, c.w);
    return out;
}
