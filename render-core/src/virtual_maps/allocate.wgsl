// The page table's frame (virtual_maps/frame.rs), in this order: entries touched by a moved
// box invalid; each entry kept, or released when its page left its level's square, was
// invalidated or everything was; (marking); free physical pages listed; marked entries given
// pages, all but a few kept back; where the pool ran out, cached pages no pixel marked evicted
// and the refused entries given pages again; (the refused pixels' fallback marks); the
// fallback pages given the pages kept back; the frame's counts, the drawn pages' list,
// squares and hierarchy, and the clears' draw arguments. No readback: the CPU learns the
// counts a frame or more later.
#import virtual_maps/tables.wgsl

// x: box, y: level. Every entry whose page the box covers is invalid this frame, or, where
// static casters are kept apart, the blocks of its movable layer the box covers are stale,
// less those where static occlusion finds the box behind the page's cached static depths
// (the box's old and new places come as boxes of their own).
@compute @workgroup_size(64)
fn invalidate_moved(@builtin(global_invocation_id) id: vec3<u32>) {
    let boxes = u32(params.tuning.z);
    if (id.x >= boxes || id.y >= level_count()) {
        return;
    }
    let lo = moved[2u * id.x].xyz;
    let hi = moved[2u * id.x + 1u].xyz;
    let texels = box_texels(id.y, lo, hi);
    let pages = texel_pages(id.y, texels);
    let occluding = static_occlusion_on();
    var nearest = 0.0;
    if (occluding) {
        nearest = box_nearest_depth(id.y, lo, hi);
    }
    for (var y = pages.y; y <= pages.w; y++) {
        for (var x = pages.x; x <= pages.z; x++) {
            let page = vec2<i32>(x, y);
            let e = entry_of(id.y, page);
            if (!static_apart()) {
                atomicOr(&page_flags[e], PAGE_INVALID);
                continue;
            }
            var blocks = box_blocks(page, texels);
            if (occluding && static_layer_cached(e, page)) {
                blocks &= ~blocks_behind_static(e, blocks, nearest);
                if (all(blocks == vec2<u32>(0u))) {
                    atomicAdd(&counters.occlusion_spared, 1u);
                    continue;
                }
            }
            make_stale(e, blocks);
        }
    }
}

// Blocks `blocks` of entry `e`'s movable layer stale.
fn make_stale(e: u32, blocks: vec2<u32>) {
    atomicOr(&stale_blocks[2u * e], blocks.x);
    atomicOr(&stale_blocks[2u * e + 1u], blocks.y);
    atomicOr(&page_flags[e], PAGE_DYNAMIC_STALE);
}

// Entry `e`'s movable layer whole again (drawn): no block stale.
fn clear_stale(e: u32) {
    clear_stale_blocks(e);
    atomicAnd(&page_flags[e], ~PAGE_DYNAMIC_STALE);
}

// Where static casters are apart, entry `e`'s stale blocks forgotten (its flags are cleared
// apart, or its page drawn).
fn clear_stale_blocks(e: u32) {
    if (static_apart()) {
        atomicStore(&stale_blocks[2u * e], 0u);
        atomicStore(&stale_blocks[2u * e + 1u], 0u);
    }
}

// Whether entry `e` holds page `page` of its level's square with a static layer drawn in an
// earlier frame (so `static_depths` holds its blocks): resident, this page's, not released.
fn static_layer_cached(e: u32, page: vec2<i32>) -> bool {
    let flags = atomicLoad(&page_flags[e]);
    return (flags & (PAGE_RESIDENT | PAGE_INVALID)) == PAGE_RESIDENT
        && all(page_tags[e] == absolute_page(e / LEVEL_ENTRIES, page));
}

fn entry_count() -> u32 {
    return level_count() * LEVEL_ENTRIES;
}

fn release(e: u32) {
    owners[page_slots[e]] = 0u;
    clear_stale_blocks(e);
    atomicStore(&page_flags[e], 0u);
}

@compute @workgroup_size(64)
fn begin_pages(@builtin(global_invocation_id) id: vec3<u32>) {
    let e = id.x;
    if (e >= entry_count()) {
        return;
    }
    if (receiver_mask_on() || static_apart()) {
        atomicStore(&receiver_masks[2u * e], 0u);
        atomicStore(&receiver_masks[2u * e + 1u], 0u);
    }
    let flags = atomicLoad(&page_flags[e]);
    if ((flags & PAGE_RESIDENT) == 0u) {
        clear_stale_blocks(e);
        atomicStore(&page_flags[e], 0u);
        return;
    }
    let level = e / LEVEL_ENTRIES;
    let same_page = all(page_tags[e] == absolute_page(level, window_page(e)));
    // A page the receiver mask left partial was made invalid (released here), or where its
    // movable layer alone is partial, that layer is stale.
    let partial = (flags & PAGE_PARTIAL) != 0u;
    if (params.counts.w != 0u || (flags & PAGE_INVALID) != 0u || !same_page) {
        release(e);
        atomicAdd(&counters.invalidated, 1u);
        return;
    }
    atomicStore(&page_flags[e], PAGE_RESIDENT | (flags & PAGE_DYNAMIC_STALE));
    if (partial) {
        make_stale(e, vec2<u32>(0xffffffffu));
    }
}

// Every free physical page into the free list. The second round runs only where the first
// allocation refused pages, after the eviction.
fn list_free(slot: u32) {
    if (slot < params.counts.y && owners[slot] == 0u) {
        free_list[atomicAdd(&counters.free_count, 1u)] = slot;
    }
}

@compute @workgroup_size(64)
fn list_free_pages(@builtin(global_invocation_id) id: vec3<u32>) {
    list_free(id.x);
}

@compute @workgroup_size(64)
fn list_free_again(@builtin(global_invocation_id) id: vec3<u32>) {
    if (atomicLoad(&counters.first_refused) > 0u) {
        list_free(id.x);
    }
}

// A physical page for entry `e` from the free list, leaving `kept_back` pages in it, or the
// entry refused.
fn take_page(e: u32, kept_back: u32) -> bool {
    let taken = atomicAdd(&counters.taken, 1u);
    let free = atomicLoad(&counters.free_count);
    if (taken + kept_back >= free) {
        // Given back, so the count ends at the pages taken: every value below the limit is
        // handed out once, and the counter never falls below it again.
        atomicSub(&counters.taken, 1u);
        atomicOr(&page_flags[e], PAGE_REFUSED);
        return false;
    }
    let slot = free_list[taken];
    owners[slot] = e + 1u;
    page_slots[e] = slot;
    page_tags[e] = absolute_page(e / LEVEL_ENTRIES, window_page(e));
    atomicAnd(&page_flags[e], ~PAGE_REFUSED);
    atomicOr(&page_flags[e], PAGE_RESIDENT | PAGE_RENDERED);
    return true;
}

fn wants_page(e: u32) -> bool {
    let flags = atomicLoad(&page_flags[e]);
    return (flags & PAGE_MARKED) != 0u && (flags & PAGE_RESIDENT) == 0u;
}

// Marked pages, each level's, from the pool less the pages kept back for fallbacks.
@compute @workgroup_size(64)
fn allocate_pages(@builtin(global_invocation_id) id: vec3<u32>) {
    let e = id.x;
    if (e < entry_count() && wants_page(e) && !take_page(e, params.limits.x)) {
        atomicAdd(&counters.first_refused, 1u);
    }
}

// Where the pool ran out: cached pages that no pixel marked give their physical pages back.
@compute @workgroup_size(64)
fn evict_unmarked(@builtin(global_invocation_id) id: vec3<u32>) {
    let e = id.x;
    if (e >= entry_count() || atomicLoad(&counters.first_refused) == 0u) {
        return;
    }
    let flags = atomicLoad(&page_flags[e]);
    if ((flags & PAGE_RESIDENT) != 0u && (flags & PAGE_MARKED) == 0u) {
        release(e);
        atomicAdd(&counters.evicted, 1u);
    }
}

// Between the rounds: the free list starts again (one thread).
@compute @workgroup_size(1)
fn restart_free_list() {
    if (atomicLoad(&counters.first_refused) > 0u) {
        atomicStore(&counters.free_count, 0u);
        atomicStore(&counters.taken, 0u);
    }
}

// The refused entries again, after the eviction.
@compute @workgroup_size(64)
fn allocate_refused(@builtin(global_invocation_id) id: vec3<u32>) {
    let e = id.x;
    if (e < entry_count() && atomicLoad(&counters.first_refused) > 0u
        && (atomicLoad(&page_flags[e]) & PAGE_REFUSED) != 0u) {
        take_page(e, params.limits.x);
    }
}

// The coarsest level's pages that refused pixels marked (mark.wgsl `mark_fallback`), from
// the pages kept back. x: entry of the level, y: chain.
@compute @workgroup_size(64)
fn allocate_fallback(@builtin(global_invocation_id) id: vec3<u32>) {
    let e = (chain_levels(id.y).y - 1u) * LEVEL_ENTRIES + id.x;
    if (id.x < LEVEL_ENTRIES && id.y < chain_count()
        && atomicLoad(&counters.first_refused) > 0u && wants_page(e)) {
        take_page(e, 0u);
    }
}

// Whether this frame's pixels read a stale block of entry `e`'s movable layer (marking's
// blocks, `receiver_masks`, kept where static casters are apart).
fn reads_stale(e: u32) -> bool {
    let stale = vec2<u32>(atomicLoad(&stale_blocks[2u * e]), atomicLoad(&stale_blocks[2u * e + 1u]));
    let read = vec2<u32>(atomicLoad(&receiver_masks[2u * e]), atomicLoad(&receiver_masks[2u * e + 1u]));
    return any((stale & read) != vec2<u32>(0u));
}

@compute @workgroup_size(64)
fn tally_pages(@builtin(global_invocation_id) id: vec3<u32>) {
    let e = id.x;
    if (e >= entry_count()) {
        return;
    }
    let flags = atomicLoad(&page_flags[e]);
    if ((flags & PAGE_RESIDENT) != 0u) {
        atomicAdd(&counters.resident, 1u);
    }
    if ((flags & PAGE_REFUSED) != 0u) {
        atomicAdd(&counters.refused, 1u);
    }
    // A page drawn whole needs no refresh; a marked page whose pixels read a block of its
    // movable layer that went stale, cached otherwise, has that layer drawn. Else it stays
    // stale where it is (and those blocks unread: light.wgsl).
    let stale_and_read = PAGE_RESIDENT | PAGE_MARKED | PAGE_DYNAMIC_STALE;
    var item = e;
    if ((flags & PAGE_RENDERED) != 0u) {
        clear_stale(e);
        atomicAdd(&counters.rendered, 1u);
    } else if ((flags & stale_and_read) == stale_and_read && reads_stale(e)) {
        clear_stale(e);
        atomicOr(&page_flags[e], PAGE_REFRESHED);
        atomicAdd(&counters.refreshed, 1u);
        item = e | DYNAMIC_ONLY;
    } else {
        return;
    }
    let level = e / LEVEL_ENTRIES;
    rendered_list[atomicAdd(&counters.listed, 1u)] = item;
    atomicAdd(&counters.level_rendered[level], 1u);
    let page = window_page(e);
    let bit = select(HIERARCHY_DRAWN, HIERARCHY_REFRESHED, (item & DYNAMIC_ONLY) != 0u);
    for (var mip = 1u; mip <= HIERARCHY_MIPS; mip++) {
        atomicOr(&page_hierarchy[hierarchy_cell(level, mip, page >> vec2<u32>(mip))], bit);
    }
    atomicMax(&counters.rects[level][0], u32(LEVEL_PAGES - page.x));
    atomicMax(&counters.rects[level][1], u32(LEVEL_PAGES - page.y));
    atomicMax(&counters.rects[level][2], u32(page.x + 1));
    atomicMax(&counters.rects[level][3], u32(page.y + 1));
}

@compute @workgroup_size(1)
fn finish_pages() {
    // A quad per layer of each listed page (draw.wgsl `vs_clear`).
    atomicStore(&counters.clear_args[0], 6u + 6u * params.limits.y);
    atomicStore(&counters.clear_args[1], atomicLoad(&counters.listed));
}
