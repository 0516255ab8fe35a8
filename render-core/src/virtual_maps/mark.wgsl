// Page marking (virtual_maps/frame.rs): each visible receiver pixel marks the pages its PCF
// taps read at the level shading will read (`holding_level`); after allocation, a pixel one of
// whose pages the pool refused marks the coarsest level's pages under it (of its chain),
// which take physical pages kept back for them, so that it falls back to a coarser level,
// never to a hole. One thread per pixel.
#import virtual_maps/tables.wgsl

@group(2) @binding(0) var surface_ids: texture_2d<u32>;
@group(2) @binding(1) var surface_positions: texture_2d<f32>;
@group(2) @binding(2) var surface_normals: texture_2d<f32>;
// When measuring: per physical page, a bit per texel that a visible pixel's tap reads.
@group(2) @binding(3) var<storage, read_write> texel_bits: array<atomic<u32>>;
// When measuring, after the page draws (the oracle's texels, `mark_shadowed`).
@group(2) @binding(4) var page_atlas: texture_depth_2d;
@group(2) @binding(5) var<storage, read_write> oracle_texels: array<atomic<u32>>;

// The pages lookup `l`'s taps read marked, and with the receiver mask on or static casters
// apart (whose stale blocks are refreshed only where read), the blocks of those taps widened
// by a texel.
fn mark_taps(l: ShadowLookup) {
    let pages = tap_pages(l);
    let last = l.first + vec2<i32>(l.kernel - 1);
    for (var y = pages[0].y; y <= pages[1].y; y++) {
        for (var x = pages[0].x; x <= pages[1].x; x++) {
            let e = entry_of(l.view, vec2<i32>(x, y));
            if ((atomicOr(&page_flags[e], PAGE_MARKED) & PAGE_MARKED) == 0u) {
                atomicAdd(&counters.marked, 1u);
                atomicAdd(&counters.level_marked[l.view], 1u);
            }
            if (receiver_mask_on() || static_apart()) {
                // A texel more each way: the shading pass finds the taps from its own
                // interpolated position, which may land a texel over a block's edge.
                let blocks = block_bits(vec2<i32>(x, y), l.first - 1, last + 1);
                if (blocks.x != 0u) {
                    atomicOr(&receiver_masks[2u * e], blocks.x);
                }
                if (blocks.y != 0u) {
                    atomicOr(&receiver_masks[2u * e + 1u], blocks.y);
                }
            }
        }
    }
}

// Whether one of the pages lookup `l`'s taps read was refused.
fn taps_refused(l: ShadowLookup) -> bool {
    let pages = tap_pages(l);
    for (var y = pages[0].y; y <= pages[1].y; y++) {
        for (var x = pages[0].x; x <= pages[1].x; x++) {
            if ((atomicLoad(&page_flags[entry_of(l.view, vec2<i32>(x, y))]) & PAGE_REFUSED) != 0u) {
                return true;
            }
        }
    }
    return false;
}

// The receiver surface at pixel `id` that the light reaches (xyz: position; w: 0 where none),
// and its normal.
fn receiver_at(id: vec2<u32>) -> array<vec4<f32>, 2> {
    let size = textureDimensions(surface_ids);
    var out = array<vec4<f32>, 2>(vec4<f32>(0.0), vec4<f32>(0.0));
    if (any(id >= size) || frame.params.y == 0u) {
        return out;
    }
    let object = textureLoad(surface_ids, id, 0).x;
    if (object == 0u || (instances[object - 1u].flags.x & FLAG_RECEIVER) == 0u) {
        return out;
    }
    let p = textureLoad(surface_positions, id, 0).xyz;
    // Outside a spot's cone no light comes to shadow: no page is read there.
    if (!light_reaches(p)) {
        return out;
    }
    out[0] = vec4<f32>(p, 1.0);
    out[1] = vec4<f32>(textureLoad(surface_normals, id, 0).xyz, 0.0);
    return out;
}

@compute @workgroup_size(8, 8)
fn mark_pages(@builtin(global_invocation_id) id: vec3<u32>) {
    let surface = receiver_at(id.xy);
    if (surface[0].w == 0.0) {
        return;
    }
    let level = holding_level(surface[0].xyz, surface[1].xyz);
    if (level < level_count()) {
        mark_taps(shadow_lookup(surface[0].xyz, surface[1].xyz, level));
    }
}

// Whether every page lookup `l`'s taps read is resident and none of the blocks they read
// stale (as light.wgsl asks).
fn taps_resident(l: ShadowLookup) -> bool {
    let pages = tap_pages(l);
    let last = l.first + vec2<i32>(l.kernel - 1);
    for (var y = pages[0].y; y <= pages[1].y; y++) {
        for (var x = pages[0].x; x <= pages[1].x; x++) {
            let page = vec2<i32>(x, y);
            let e = entry_of(l.view, page);
            let flags = atomicLoad(&page_flags[e]);
            if ((flags & PAGE_RESIDENT) == 0u) {
                return false;
            }
            if ((flags & PAGE_DYNAMIC_STALE) != 0u) {
                let stale = vec2<u32>(
                    atomicLoad(&stale_blocks[2u * e]),
                    atomicLoad(&stale_blocks[2u * e + 1u]),
                );
                if (any((block_bits(page, l.first, last) & stale) != vec2<u32>(0u))) {
                    return false;
                }
            }
        }
    }
    return true;
}

// The lookup shading reads at the receiver surface of pixel `id` (light.wgsl
// `light_reaching`); a kernel of 0 where it reads none.
fn shading_lookup(id: vec2<u32>) -> ShadowLookup {
    let surface = receiver_at(id);
    var none: ShadowLookup;
    if (frame.params.z == 0u || surface[0].w == 0.0) {
        return none;
    }
    let p = surface[0].xyz;
    let n = surface[1].xyz;
    let chain = chain_of(p);
    for (var m = matched_mip(p, n); m < chain_mips(); m++) {
        let l = shadow_lookup(p, n, mip_level(p, chain, m));
        if (lookup_contained(l) && taps_resident(l)) {
            return l;
        }
    }
    return none;
}

// The physical page holding tap `t` of lookup `l`.
fn tap_slot(l: ShadowLookup, t: vec2<i32>) -> u32 {
    return page_slots[entry_of(l.view, t / PAGE_TEXELS)];
}

// When measuring, after allocation: the texels shading will read, at the level it will read
// them from, a bit each in their physical page.
@compute @workgroup_size(8, 8)
fn mark_sampled(@builtin(global_invocation_id) id: vec3<u32>) {
    let l = shading_lookup(id.xy);
    for (var j = 0; j < l.kernel; j++) {
        for (var i = 0; i < l.kernel; i++) {
            let t = l.first + vec2<i32>(i, j);
            let bit = texel_bit(t);
            atomicOr(&texel_bits[tap_slot(l, t) * 512u + bit.x], bit.y);
        }
    }
}

// When measuring, after the page draws (the per-page oracle): the texels whose taps shading
// reads shadowed, a bit each in their physical page's layer that holds the nearest depth
// there (both layers where they hold the same). The casters drawn there are the oracle's
// (draw.wgsl `fs_oracle`).
@compute @workgroup_size(8, 8)
fn mark_shadowed(@builtin(global_invocation_id) id: vec3<u32>) {
    let l = shading_lookup(id.xy);
    let layers = 1u + params.limits.y;
    for (var j = 0; j < l.kernel; j++) {
        for (var i = 0; i < l.kernel; i++) {
            let t = l.first + vec2<i32>(i, j);
            let slot = tap_slot(l, t);
            var depths = vec2<f32>(textureLoad(page_atlas, slot_texel(slot, 0u, t), 0), 1.0);
            if (layers == 2u) {
                depths.y = textureLoad(page_atlas, slot_texel(slot, 1u, t), 0);
            }
            let nearest = min(depths.x, depths.y);
            if (tap_threshold(l, t) <= nearest) {
                continue;
            }
            let bit = texel_bit(t);
            for (var layer = 0u; layer < layers; layer++) {
                if (depths[layer] == nearest) {
                    atomicOr(&oracle_texels[(slot * layers + layer) * 512u + bit.x], bit.y);
                }
            }
        }
    }
}

// When measuring: the texels marked, one thread per word.
@compute @workgroup_size(64)
fn count_sampled(@builtin(global_invocation_id) id: vec3<u32>) {
    if (frame.params.z == 0u || id.x >= params.counts.y * 512u) {
        return;
    }
    let bits = atomicLoad(&texel_bits[id.x]);
    if (bits != 0u) {
        atomicAdd(&counters.texels_sampled, countOneBits(bits));
    }
}

// After allocation: the coarsest level's pages for pixels whose own were refused.
@compute @workgroup_size(8, 8)
fn mark_fallback(@builtin(global_invocation_id) id: vec3<u32>) {
    if (atomicLoad(&counters.first_refused) == 0u) {
        return;
    }
    let surface = receiver_at(id.xy);
    if (surface[0].w == 0.0) {
        return;
    }
    let p = surface[0].xyz;
    let n = surface[1].xyz;
    let level = holding_level(p, n);
    let last = chain_levels(chain_of(p)).y - 1u;
    if (level < last && taps_refused(shadow_lookup(p, n, level))) {
        let coarsest = shadow_lookup(p, n, last);
        if (lookup_contained(coarsest)) {
            mark_taps(coarsest);
        }
    }
}
