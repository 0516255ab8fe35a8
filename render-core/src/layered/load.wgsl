// What the many-lights passes add to their geometry stage to measure it (Rákos 19.4 and
// 19.6; shadow_view/mod.rs GeometryLoad): `index.w` rounds of skinning-like work per vertex,
// and with `index.z` 1 a position behind the near plane, so nothing is rasterised.

fn loaded(view: ShadowView, clip: vec4<f32>) -> vec4<f32> {
    var out = clip;
    if (view.index.w > 0u) {
        // A chain of matrix products, as a skinned vertex's bones take. Its result is kept
        // only for a view index no view has, so the work is done and changes nothing.
        var m = view.light_clip_from_world;
        var p = clip;
        for (var i = 0u; i < view.index.w; i++) {
            p = m * p;
            m = m * view.world_from_light_clip;
        }
        out = select(out, p, view.index.x == 0xffffffffu);
    }
    if (view.index.z == 1u) {
        out = vec4<f32>(0.0, 0.0, -1.0, 1.0);
    }
    return out;
}
