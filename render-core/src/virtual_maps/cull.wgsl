// Per-page caster culling (virtual_maps/frame.rs): each caster against the pages drawn this
// frame at each level, through the level's square of drawn pages and then page by page, and
// with the receiver mask on, against the blocks of the page that pixels read (Unreal 5.6's
// receiver mask); a caster over any of them gets one indirect draw with an instance per
// page, its (caster, entry) pairs listed for the page shader (virtual_maps/draw.wgsl).
// x: instance, y: level.
#import virtual_maps/tables.wgsl

struct DrawIndexedArgs {
    index_count: u32,
    instance_count: u32,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
}

// Per instance: first index, index count, base vertex (i32 bits), bit 0 when left out, bit 1
// when it may move (its depths go to the movable casters' layer where static ones are apart).
@group(2) @binding(0) var<storage, read> ranges: array<vec4<u32>>;
@group(2) @binding(1) var<storage, read> bounds: array<InstanceBounds>;
@group(2) @binding(2) var<storage, read_write> pairs: array<vec2<u32>>;
@group(2) @binding(3) var<storage, read_write> draws: array<DrawIndexedArgs>;

// Whether the caster draws into page (x, y) this frame: the page drawn whole, or for a
// movable caster also refreshed (`wanted`); with the receiver mask (`masked`), only where its
// texels `texels` cover a block that pixels read.
fn page_wanted(e: u32, wanted: u32) -> bool {
    return (atomicLoad(&page_flags[e]) & wanted) != 0u;
}

fn blocks_read(e: u32, page: vec2<i32>, texels: vec4<f32>, masked: bool) -> bool {
    if (!masked) {
        return true;
    }
    let covered = block_bits(page, vec2<i32>(floor(texels.xy)), vec2<i32>(floor(texels.zw)));
    let read = vec2<u32>(atomicLoad(&receiver_masks[2u * e]), atomicLoad(&receiver_masks[2u * e + 1u]));
    return any((covered & read) != vec2<u32>(0u));
}

@compute @workgroup_size(64)
fn cull_pages(@builtin(global_invocation_id) id: vec3<u32>) {
    let instance = id.x;
    let level = id.y;
    if (instance >= frame.views.y || level >= level_count()) {
        return;
    }
    let b = bounds[instance];
    let range = ranges[instance];
    if ((b.flags & FLAG_CASTER) == 0u || (range.w & 1u) != 0u || atomicLoad(&counters.level_rendered[level]) == 0u) {
        return;
    }
    let movable = (range.w & 2u) != 0u;
    let wanted = select(PAGE_RENDERED, PAGE_RENDERED | PAGE_REFRESHED, movable);
    let layer = select(0u, DYNAMIC_ONLY, movable && static_apart());
    // The mask culls within the layer that is drawn again anyway: every caster's, or the
    // movable casters' where static ones are apart (their layer is not kept whole), or every
    // caster's in a frame where every page is invalid (the cache off, the light moving).
    let masked = receiver_mask_on() && (movable || !static_apart() || params.counts.w != 0u);
    // A page partial in its movable layer alone has that layer drawn again next frame; else
    // the page is released.
    let partial = select(PAGE_PARTIAL | PAGE_INVALID, PAGE_PARTIAL, movable && static_apart());
    let drawn = vec4<i32>(
        LEVEL_PAGES - i32(atomicLoad(&counters.rects[level][0])),
        LEVEL_PAGES - i32(atomicLoad(&counters.rects[level][1])),
        i32(atomicLoad(&counters.rects[level][2])) - 1,
        i32(atomicLoad(&counters.rects[level][3])) - 1,
    );
    let texels = box_texels(level, b.min, b.max);
    let box = texel_pages(level, texels);
    let first = max(box.xy, drawn.xy);
    let last = min(box.zw, drawn.zw);
    var count = 0u;
    for (var y = first.y; y <= last.y; y++) {
        for (var x = first.x; x <= last.x; x++) {
            let e = entry_of(level, vec2<i32>(x, y));
            if (!page_wanted(e, wanted)) {
                continue;
            }
            if (blocks_read(e, vec2<i32>(x, y), texels, masked)) {
                count++;
            } else {
                atomicOr(&page_flags[e], partial);
                atomicAdd(&counters.mask_culled, 1u);
            }
        }
    }
    if (count == 0u) {
        return;
    }
    let base = atomicAdd(&counters.pairs, count);
    let draw = atomicAdd(&counters.draws, 1u);
    if (draw >= arrayLength(&draws)) {
        atomicAdd(&counters.overflow, count);
        return;
    }
    if (base + count > arrayLength(&pairs)) {
        atomicAdd(&counters.overflow, count);
        draws[draw] = DrawIndexedArgs(0u, 0u, 0u, 0, 0u);
        return;
    }
    var next = base;
    for (var y = first.y; y <= last.y; y++) {
        for (var x = first.x; x <= last.x; x++) {
            let e = entry_of(level, vec2<i32>(x, y));
            if (page_wanted(e, wanted) && blocks_read(e, vec2<i32>(x, y), texels, masked)) {
                pairs[next] = vec2<u32>(instance, e | layer);
                next++;
            }
        }
    }
    draws[draw] = DrawIndexedArgs(range.y, count, range.x, bitcast<i32>(range.z), base);
    atomicAdd(&counters.level_pairs[level], count);
}
