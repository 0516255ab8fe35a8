// The culled draws of an atlas page: each record's view places its triangle in its tile.
#import layered/culled.wgsl
#import layered/tile.wgsl

@vertex
fn vs_culled_atlas(@builtin(vertex_index) vertex_index: u32) -> AtlasOut {
    let c = corner(vertex_index);
    let view = shadow_views[c.view];
    return in_tile(view, loaded(view, shadow_clip_position(view, c.instance, c.position)), page.x);
}
