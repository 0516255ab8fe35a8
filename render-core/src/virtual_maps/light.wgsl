// The virtual maps' "light reaching this point" (virtual_maps/mod.rs): the level resolution
// matching picks, or the first coarser one of its chain (the sun's clipmap, or a point
// light's face) whose square holds every tap and whose pages are
// resident (a refused page falls back, never to a hole), its PCF taps read through the page
// table from the physical atlas. The reference is the method's own: the technique culls no
// caster a page needs, so its error is measured against the exact shadow (truth/).
#import virtual_maps/pages.wgsl
#import metrics/measure.wgsl

@group(1) @binding(1) var page_atlas: texture_depth_2d;
@group(1) @binding(2) var<storage, read> page_flags: array<u32>;
@group(1) @binding(3) var<storage, read> page_slots: array<u32>;
// Per entry, the stale blocks of its movable layer (tables.wgsl `stale_blocks`).
@group(1) @binding(4) var<storage, read> stale_blocks: array<u32>;

struct LightReaching {
    method: f32,
    reference: f32,
    // The level that shades the point, and whether one does.
    view: u32,
    shaded: bool,
    added: vec3<f32>,
}

fn light_unshadowed(world_pos: vec3<f32>, geometric: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}

fn taps_resident(l: ShadowLookup) -> bool {
    let pages = tap_pages(l);
    let last = l.first + vec2<i32>(l.kernel - 1);
    for (var y = pages[0].y; y <= pages[1].y; y++) {
        for (var x = pages[0].x; x <= pages[1].x; x++) {
            let page = vec2<i32>(x, y);
            let e = entry_of(l.view, page);
            let flags = page_flags[e];
            if ((flags & PAGE_RESIDENT) == 0u) {
                return false;
            }
            // The blocks of a movable layer that went stale where no pixel read them are not
            // read until the layer is drawn again.
            if ((flags & PAGE_DYNAMIC_STALE) != 0u) {
                let stale = vec2<u32>(stale_blocks[2u * e], stale_blocks[2u * e + 1u]);
                if (any((block_bits(page, l.first, last) & stale) != vec2<u32>(0u))) {
                    return false;
                }
            }
        }
    }
    return true;
}

// Tap `t` (texels of the level's square) in the atlas's layer `layer`.
fn atlas_texel(l: ShadowLookup, t: vec2<i32>, layer: u32) -> vec2<i32> {
    return slot_texel(page_slots[entry_of(l.view, t / PAGE_TEXELS)], layer, t);
}

// The nearest caster's depth at tap `t`: of both layers where static casters are apart.
fn stored_depth(l: ShadowLookup, t: vec2<i32>) -> f32 {
    let first = textureLoad(page_atlas, atlas_texel(l, t, 0u), 0);
    if (!static_apart()) {
        return first;
    }
    return min(first, textureLoad(page_atlas, atlas_texel(l, t, 1u), 0));
}

// Fraction of kernel taps that see the light.
fn page_factor(l: ShadowLookup) -> f32 {
    var lit = 0.0;
    for (var j = 0; j < l.kernel; j++) {
        for (var i = 0; i < l.kernel; i++) {
            let t = l.first + vec2<i32>(i, j);
            let stored = stored_depth(l, t);
            lit += select(0.0, 1.0, tap_threshold(l, t) <= stored);
        }
    }
    return lit / f32(l.kernel * l.kernel);
}

fn light_reaching(world_pos: vec3<f32>, geometric: vec3<f32>, measuring: bool) -> LightReaching {
    var out = LightReaching(1.0, 1.0, 0u, false, vec3<f32>(0.0));
    // Outside a spot's cone no light comes to shadow (and no page was marked).
    if (!light_reaches(world_pos)) {
        return out;
    }
    let chain = chain_of(world_pos);
    for (var m = matched_mip(world_pos, geometric); m < chain_mips(); m++) {
        let level = mip_level(world_pos, chain, m);
        let l = shadow_lookup(world_pos, geometric, level);
        if (!lookup_contained(l) || !taps_resident(l)) {
            continue;
        }
        let lit = page_factor(l);
        out = LightReaching(lit, lit, level, true, vec3<f32>(0.0));
        break;
    }
    return out;
}
