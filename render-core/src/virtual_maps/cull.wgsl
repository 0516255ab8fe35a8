// Per-page caster culling (virtual_maps/frame.rs): each caster against the pages drawn this
// frame at each level, through the level's square of drawn pages, the hierarchy of page
// flags (`page_hierarchy`: for a caster over more than a few pages, the cells of the coarsest
// mip at most 2 x 2 under its pages, then blocks of 4 x 4 pages) and then page by page, and
// with the receiver mask on, against the blocks of the page that pixels read (Unreal 5.6's
// receiver mask), and with static occlusion a movable caster against the static depths a
// refreshed page keeps; a caster over any of them gets one indirect draw with an instance
// per page, its (caster, entry) pairs listed for the page shader (virtual_maps/draw.wgsl).
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

// The page flags and hierarchy cells this invocation read, for the counters.
var<private> flag_reads: u32;

// Whether a cell of mip `mip` under pages `first..=last` holds a page with one of `bits`.
fn cells_hold(level: u32, mip: u32, first: vec2<i32>, last: vec2<i32>, bits: u32) -> bool {
    let lo = first >> vec2<u32>(mip);
    let hi = last >> vec2<u32>(mip);
    for (var y = lo.y; y <= hi.y; y++) {
        for (var x = lo.x; x <= hi.x; x++) {
            flag_reads++;
            if ((atomicLoad(&page_hierarchy[hierarchy_cell(level, mip, vec2<i32>(x, y))]) & bits) != 0u) {
                return true;
            }
        }
    }
    return false;
}

// The finest mip whose cells under pages `first..=last` are at most 2 x 2.
fn covering_mip(first: vec2<i32>, last: vec2<i32>) -> u32 {
    var mip = 1u;
    while (mip < HIERARCHY_MIPS && any((last >> vec2<u32>(mip)) - (first >> vec2<u32>(mip)) > vec2<i32>(1))) {
        mip++;
    }
    return mip;
}

// What one caster asks of one level's pages.
struct CasterPages {
    instance: u32,
    level: u32,
    // Its pages within the drawn ones, first and last.
    first: vec2<i32>,
    last: vec2<i32>,
    texels: vec4<f32>,
    // The page flags and hierarchy bits it is drawn into, the layer bit of its pairs, whether
    // the mask culls it and the flags a page it leaves out takes.
    wanted: u32,
    hierarchy_bits: u32,
    layer: u32,
    masked: bool,
    partial: u32,
    // Static occlusion: whether it applies (a movable caster, static casters apart), and the
    // caster's nearest depth in the level's view.
    occludable: bool,
    nearest: f32,
}

// Whether this pipeline tests movable casters against refreshed pages' static depths: the
// pipeline frame.rs picks where static occlusion applies, so the cull without it carries
// none of its code.
override STATIC_OCCLUSION: bool = false;

// Casters over at most this many pages walk them one by one: the hierarchy would read more.
const SMALL_SPAN: i32 = 8;

// The caster's pages `first..=last` one by one: counted (the mask's left-out pages flagged)
// when `base` is 0xffffffff, else listed as pairs from `base + done`. Returns the pages it is
// drawn into.
fn visit_range(c: CasterPages, first: vec2<i32>, last: vec2<i32>, base: u32, done: u32) -> u32 {
    var count = 0u;
    for (var y = first.y; y <= last.y; y++) {
        for (var x = first.x; x <= last.x; x++) {
            let page = vec2<i32>(x, y);
            let e = entry_of(c.level, page);
            flag_reads++;
            if (!page_wanted(e, c.wanted)) {
                continue;
            }
            // A refreshed page keeps its static layer: a movable caster wholly behind it
            // changes none of the page's nearer depths (tables.wgsl `behind_static`).
            if (c.occludable && (atomicLoad(&page_flags[e]) & PAGE_RENDERED) == 0u
                && behind_static(e, page, c.texels, c.nearest)) {
                if (base == 0xffffffffu) {
                    atomicAdd(&counters.occlusion_culled, 1u);
                }
                continue;
            }
            let read = blocks_read(e, page, c.texels, c.masked);
            if (base == 0xffffffffu) {
                if (read) {
                    count++;
                } else {
                    atomicOr(&page_flags[e], c.partial);
                    atomicAdd(&counters.mask_culled, 1u);
                }
            } else if (read) {
                pairs[base + done + count] = vec2<u32>(c.instance, e | c.layer);
                count++;
            }
        }
    }
    return count;
}

// The caster's pages: a few one by one; more only where the cells of the coarsest mip at
// most 2 x 2 under them hold a wanted page, then block by block of 4 x 4 pages where the
// hierarchy holds one (`visit_range`'s counting or listing).
fn visit_pages(c: CasterPages, base: u32) -> u32 {
    let span = c.last - c.first + 1;
    if (span.x * span.y <= SMALL_SPAN) {
        return visit_range(c, c.first, c.last, base, 0u);
    }
    if (!cells_hold(c.level, covering_mip(c.first, c.last), c.first, c.last, c.hierarchy_bits)) {
        return 0u;
    }
    var count = 0u;
    let lo = c.first >> vec2<u32>(2u);
    let hi = c.last >> vec2<u32>(2u);
    for (var by = lo.y; by <= hi.y; by++) {
        for (var bx = lo.x; bx <= hi.x; bx++) {
            let block = vec2<i32>(bx, by);
            flag_reads++;
            if ((atomicLoad(&page_hierarchy[hierarchy_cell(c.level, 2u, block)]) & c.hierarchy_bits) == 0u) {
                continue;
            }
            let first = max(c.first, block * 4);
            let last = min(c.last, block * 4 + 3);
            count += visit_range(c, first, last, base, count);
        }
    }
    return count;
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
    var c: CasterPages;
    c.instance = instance;
    c.level = level;
    let movable = (range.w & 2u) != 0u;
    c.wanted = select(PAGE_RENDERED, PAGE_RENDERED | PAGE_REFRESHED, movable);
    c.hierarchy_bits = select(HIERARCHY_DRAWN, HIERARCHY_DRAWN | HIERARCHY_REFRESHED, movable);
    c.layer = select(0u, DYNAMIC_ONLY, movable && static_apart());
    // The mask culls within the layer that is drawn again anyway: every caster's, or the
    // movable casters' where static ones are apart (their layer is not kept whole), or every
    // caster's in a frame where every page is invalid (the cache off, the light moving).
    c.masked = receiver_mask_on() && (movable || !static_apart() || params.counts.w != 0u);
    // A page partial in its movable layer alone has that layer drawn again next frame; else
    // the page is released.
    c.partial = select(PAGE_PARTIAL | PAGE_INVALID, PAGE_PARTIAL, movable && static_apart());
    let drawn = vec4<i32>(
        LEVEL_PAGES - i32(atomicLoad(&counters.rects[level][0])),
        LEVEL_PAGES - i32(atomicLoad(&counters.rects[level][1])),
        i32(atomicLoad(&counters.rects[level][2])) - 1,
        i32(atomicLoad(&counters.rects[level][3])) - 1,
    );
    c.occludable = STATIC_OCCLUSION && movable;
    // (Computed only where used: a call in `select` runs for every caster and level.)
    if (c.occludable) {
        c.nearest = box_nearest_depth(level, b.min, b.max);
    }
    c.texels = box_texels(level, b.min, b.max);
    let box = texel_pages(level, c.texels);
    c.first = max(box.xy, drawn.xy);
    c.last = min(box.zw, drawn.zw);
    if (any(c.first > c.last)) {
        return;
    }
    // What walking the pages one by one would read, and what the hierarchy's walk reads.
    let span = c.last - c.first + 1;
    atomicAdd(&counters.cull_spanned, u32(span.x * span.y));
    let count = visit_pages(c, 0xffffffffu);
    atomicAdd(&counters.cull_reads, flag_reads);
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
    visit_pages(c, base);
    draws[draw] = DrawIndexedArgs(range.y, count, range.x, bitcast<i32>(range.z), base);
    atomicAdd(&counters.level_pairs[level], count);
}
