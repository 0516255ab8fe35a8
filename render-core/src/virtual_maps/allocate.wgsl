// The page table's frame (virtual_maps/frame.rs), in this order: entries touched by a moved
// box invalid; each entry kept, released when its page left its level's square, or kept
// invalid where it was invalidated or everything was; (marking); invalid pages drawn again
// in place where marked, released where not; free physical pages listed; marked entries given
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
    // A page the receiver mask left partial was made invalid (drawn again below), or where
    // its movable layer alone is partial, that layer is stale.
    let partial = (flags & PAGE_PARTIAL) != 0u;
    if (!same_page) {
        release(e);
        atomicAdd(&counters.invalidated, 1u);
        return;
    }
    // Invalid, or every page is: kept where it is, still invalid, until marking says whether
    // it is drawn again there (`redraw_in_place`).
    if (params.counts.w != 0u || (flags & PAGE_INVALID) != 0u) {
        clear_stale_blocks(e);
        atomicStore(&page_flags[e], PAGE_RESIDENT | PAGE_INVALID);
        atomicAdd(&counters.invalidated, 1u);
        return;
    }
    atomicStore(&page_flags[e], PAGE_RESIDENT | (flags & PAGE_DYNAMIC_STALE));
    if (partial) {
        make_stale(e, vec2<u32>(0xffffffffu));
    }
}

// An invalid page (`begin_pages`) that pixels marked is drawn again whole in the physical page
// it holds; one that none marked is released. A page keeps its place in the atlas: the
// rasteriser's depths depend, in their last bit, on where in the atlas a page is drawn (the
// same triangle elsewhere rounds otherwise), so a page drawn again where it was holds the very
// depths a page drawn there before holds, and a frame that draws every page again is the
// exact reference of a cached one.
fn redraw_in_place(slot: u32) {
    if (owners[slot] == 0u) {
        return;
    }
    let e = owners[slot] - 1u;
    let flags = atomicLoad(&page_flags[e]);
    if ((flags & PAGE_INVALID) == 0u) {
        return;
    }
    if ((flags & PAGE_MARKED) != 0u) {
        atomicAnd(&page_flags[e], ~PAGE_INVALID);
        atomicOr(&page_flags[e], PAGE_RENDERED);
    } else {
        release(e);
    }
}

// Allocation is ordered, so the same frame gives every page the same physical page on every
// run (and so the same depths, bit for bit: `redraw_in_place`): the free list holds the free
// physical pages in ascending order, and the entries asking for a page take them in ascending
// order of entry (finest level first). One workgroup does each: each of its threads a run of
// consecutive items, ranked by a prefix sum over the threads.
const RANK_THREADS: u32 = 256u;
const NO_ENTRY: u32 = 0xffffffffu;
var<workgroup> prefix: array<u32, 256>;

// The items of threads before `t` that `count` counts, each thread giving its own; the total
// is then `prefix[RANK_THREADS - 1u]`. Every thread of the workgroup calls it.
fn exclusive_prefix(t: u32, count: u32) -> u32 {
    prefix[t] = count;
    workgroupBarrier();
    for (var d = 1u; d < RANK_THREADS; d <<= 1u) {
        var before = 0u;
        if (t >= d) {
            before = prefix[t - d];
        }
        workgroupBarrier();
        prefix[t] += before;
        workgroupBarrier();
    }
    return prefix[t] - count;
}

// Thread `t`'s run of `items` items: first and one past the last.
fn thread_run(t: u32, items: u32) -> vec2<u32> {
    let run = (items + RANK_THREADS - 1u) / RANK_THREADS;
    return vec2<u32>(min(t * run, items), min((t + 1u) * run, items));
}

// The free physical pages into the free list, in order; `redrawing` first draws invalid
// pages again in place or releases them (the first round). The second round runs only where
// the first allocation refused pages, after the eviction.
fn list_free(t: u32, running: bool, redrawing: bool) {
    let run = thread_run(t, params.counts.y);
    var count = 0u;
    for (var slot = run.x; slot < run.y && running; slot++) {
        if (redrawing) {
            redraw_in_place(slot);
        }
        count += select(0u, 1u, owners[slot] == 0u);
    }
    var at = exclusive_prefix(t, count);
    for (var slot = run.x; slot < run.y && running; slot++) {
        if (owners[slot] == 0u) {
            free_list[at] = slot;
            at++;
        }
    }
    if (running && t == 0u) {
        atomicStore(&counters.free_count, prefix[RANK_THREADS - 1u]);
    }
}

@compute @workgroup_size(256)
fn list_free_pages(@builtin(local_invocation_index) t: u32) {
    list_free(t, true, true);
}

@compute @workgroup_size(256)
fn list_free_again(@builtin(local_invocation_index) t: u32) {
    list_free(t, atomicLoad(&counters.first_refused) > 0u, false);
}

// Physical page `rank` of the free list for entry `e`, leaving `kept_back` pages in it, or
// the entry refused.
fn take_page(e: u32, rank: u32, kept_back: u32) -> bool {
    if (rank + kept_back >= atomicLoad(&counters.free_count)) {
        atomicOr(&page_flags[e], PAGE_REFUSED);
        return false;
    }
    let slot = free_list[rank];
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

// The rounds of allocation: marked entries; the refused ones again after the eviction; the
// coarsest level's pages that refused pixels marked (mark.wgsl `mark_fallback`), an item per
// entry of each chain's coarsest level.
const ROUND_MARKED: u32 = 0u;
const ROUND_REFUSED: u32 = 1u;
const ROUND_FALLBACK: u32 = 2u;

fn round_items(round: u32) -> u32 {
    return select(entry_count(), chain_count() * LEVEL_ENTRIES, round == ROUND_FALLBACK);
}

// The entry of item `k` of round `round` where it asks for a page, else NO_ENTRY.
fn asking(round: u32, k: u32) -> u32 {
    var e = k;
    var asks = false;
    if (round == ROUND_MARKED) {
        asks = wants_page(k);
    } else if (round == ROUND_REFUSED) {
        asks = (atomicLoad(&page_flags[k]) & PAGE_REFUSED) != 0u;
    } else {
        e = (chain_levels(k / LEVEL_ENTRIES).y - 1u) * LEVEL_ENTRIES + k % LEVEL_ENTRIES;
        asks = wants_page(e);
    }
    return select(NO_ENTRY, e, asks);
}

// One round: the entries asking take the free list's pages in order, from the pages the
// rounds before took, leaving `kept_back`; returns the entries refused.
fn allocate_round(t: u32, round: u32, running: bool, kept_back: u32) -> u32 {
    let run = thread_run(t, round_items(round));
    var count = 0u;
    for (var k = run.x; k < run.y && running; k++) {
        count += select(0u, 1u, asking(round, k) != NO_ENTRY);
    }
    let first = atomicLoad(&counters.taken);
    var rank = first + exclusive_prefix(t, count);
    let asked = prefix[RANK_THREADS - 1u];
    var refused = 0u;
    for (var k = run.x; k < run.y && running; k++) {
        let e = asking(round, k);
        if (e != NO_ENTRY) {
            refused += select(1u, 0u, take_page(e, rank, kept_back));
            rank++;
        }
    }
    storageBarrier();
    workgroupBarrier();
    if (running && t == 0u) {
        let free = atomicLoad(&counters.free_count);
        let room = select(0u, free - kept_back, free > kept_back);
        atomicStore(&counters.taken, max(first, min(first + asked, room)));
    }
    return refused;
}

// Marked pages, each level's, from the pool less the pages kept back for fallbacks.
@compute @workgroup_size(256)
fn allocate_pages(@builtin(local_invocation_index) t: u32) {
    let refused = allocate_round(t, ROUND_MARKED, true, params.limits.x);
    if (refused > 0u) {
        atomicAdd(&counters.first_refused, refused);
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
@compute @workgroup_size(256)
fn allocate_refused(@builtin(local_invocation_index) t: u32) {
    allocate_round(t, ROUND_REFUSED, atomicLoad(&counters.first_refused) > 0u, params.limits.x);
}

// The coarsest level's pages that refused pixels marked, from the pages kept back.
@compute @workgroup_size(256)
fn allocate_fallback(@builtin(local_invocation_index) t: u32) {
    allocate_round(t, ROUND_FALLBACK, atomicLoad(&counters.first_refused) > 0u, 0u);
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
