// GEOM's mask widened by the filter's reach for the footprint test (culling/footprints.wgsl): a
// receiver point's PCF taps, moved by the normal offset, reach `CullView::reach` shadow texels
// beyond the texel the point falls in (which GEOM's conservative rasterisation marks), so a
// caster there can shadow it. A max filter over (2r + 1)^2 mask texels, r the reach in mask
// texels, in two passes (rows, then columns), a block of mask side squared per view
// (workgroup z is the view).
#import culling/cull_common.wgsl

@group(0) @binding(0) var<storage, read> cull_views: array<CullView>;
@group(0) @binding(1) var mask_raster: texture_2d_array<f32>;
@group(0) @binding(2) var<storage, read_write> rows: array<f32>;
@group(0) @binding(3) var<storage, read_write> widened: array<f32>;


@compute @workgroup_size(8, 8)
fn cs_widen_rows(@builtin(global_invocation_id) id: vec3<u32>) {
    let params = cull_views[id.z].params;
    let size = params.w;
    if (any(id.xy >= vec2<u32>(size)) || (params.x & METHOD_GEOM) == 0u) {
        return;
    }
    let r = i32(reach_in_mask_texels(cull_views[id.z]));
    var value = 0.0;
    for (var d = -r; d <= r; d++) {
        let x = i32(id.x) + d;
        if (x >= 0 && x < i32(size)) {
            value = max(value, textureLoad(mask_raster, vec2<i32>(x, i32(id.y)), id.z, 0).x);
        }
    }
    rows[id.z * size * size + id.y * size + id.x] = value;
}

@compute @workgroup_size(8, 8)
fn cs_widen_columns(@builtin(global_invocation_id) id: vec3<u32>) {
    let params = cull_views[id.z].params;
    let size = params.w;
    if (any(id.xy >= vec2<u32>(size)) || (params.x & METHOD_GEOM) == 0u) {
        return;
    }
    let r = i32(reach_in_mask_texels(cull_views[id.z]));
    let block = id.z * size * size;
    var value = 0.0;
    for (var d = -r; d <= r; d++) {
        let y = i32(id.y) + d;
        if (y >= 0 && y < i32(size)) {
            value = max(value, rows[block + u32(y) * size + id.x]);
        }
    }
    widened[block + id.y * size + id.x] = value;
}
