// Page marking (virtual_maps/passes.rs): each visible receiver pixel marks the pages its
// PCF taps read at the level shading will read (`holding_level`), and the coarsest level's
// pages under it, which are given physical pages first so that a pixel refused its own
// pages falls back to a coarser one, never to a hole. One thread per pixel.
#import virtual_maps/tables.wgsl

@group(2) @binding(0) var surface_ids: texture_2d<u32>;
@group(2) @binding(1) var surface_positions: texture_2d<f32>;
@group(2) @binding(2) var surface_normals: texture_2d<f32>;

fn mark_taps(l: ShadowLookup) {
    let pages = tap_pages(l);
    for (var y = pages[0].y; y <= pages[1].y; y++) {
        for (var x = pages[0].x; x <= pages[1].x; x++) {
            let e = entry_of(l.view, vec2<i32>(x, y));
            if ((atomicOr(&page_flags[e], PAGE_MARKED) & PAGE_MARKED) == 0u) {
                atomicAdd(&counters.marked, 1u);
                atomicAdd(&counters.level_marked[l.view], 1u);
            }
        }
    }
}

@compute @workgroup_size(8, 8)
fn mark_pages(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(surface_ids);
    if (any(id.xy >= size) || frame.params.y == 0u) {
        return;
    }
    let object = textureLoad(surface_ids, id.xy, 0).x;
    if (object == 0u || (instances[object - 1u].flags.x & FLAG_RECEIVER) == 0u) {
        return;
    }
    let p = textureLoad(surface_positions, id.xy, 0).xyz;
    let n = textureLoad(surface_normals, id.xy, 0).xyz;
    let last = level_count() - 1u;
    let level = holding_level(p, n);
    if (level <= last) {
        mark_taps(shadow_lookup(p, n, level));
    }
    if (level < last) {
        let coarsest = shadow_lookup(p, n, last);
        if (lookup_contained(coarsest)) {
            mark_taps(coarsest);
        }
    }
}
