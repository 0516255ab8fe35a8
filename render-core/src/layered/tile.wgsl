// Where an atlas path puts a view's clip position: in the view's tile of the page, clip
// distances at the tile's edges keeping the triangle there as a viewport would.

struct AtlasOut {
    @invariant @builtin(position) clip: vec4<f32>,
    @builtin(clip_distances) tile: array<f32, 4>,
}

// The view's texel (x right, y down from its square's first texel) on a page `page_side`
// texels square, kept in clip space (times w) so the rasteriser interpolates as it does for
// the view alone.
fn in_tile(view: ShadowView, c: vec4<f32>, page_side: f32) -> AtlasOut {
    var out: AtlasOut;
    out.tile = array<f32, 4>(c.w - c.x, c.w + c.x, c.w - c.y, c.w + c.y);
    let side = f32(view.square.w);
    let origin = vec2<f32>(view.square.yz);
    let x = ((c.x + c.w) * 0.5 * side + origin.x * c.w) / page_side;
    let y = ((c.w - c.y) * 0.5 * side + origin.y * c.w) / page_side;
    out.clip = vec4<f32>(2.0 * x - c.w, c.w - 2.0 * y, c.z, c.w);
    return out;
}
