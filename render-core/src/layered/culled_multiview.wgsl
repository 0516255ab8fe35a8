// The culled draws of a multiview group: the view index picks the group's view.
#import layered/culled.wgsl

@vertex
fn vs_culled_multiview(@builtin(vertex_index) vertex_index: u32, @builtin(view_index) view_index: u32) -> CulledOut {
    let c = corner(vertex_index);
    var out: CulledOut;
    let view = shadow_views[pass_view.index.x + view_index];
    out.clip = loaded(view, shadow_clip_position(view, c.instance, c.position));
    return out;
}
