// Per-page caster culling (virtual_maps/frame.rs): each caster against the pages drawn this
// frame at each level, through the level's square of drawn pages, the hierarchy of page flags
// (`page_hierarchy`: the cells of the coarsest mip at most 2 x 2 under the caster's pages,
// then blocks of 4 x 4 pages) and then page by page, and with the receiver mask on, against
// the blocks of the page that pixels read (Unreal 5.6's receiver mask); a caster over any of
// them gets one indirect draw with an instance per page, its (caster, entry) pairs listed for
// the page shader (virtual_maps/draw.wgsl). x: instance, y: level.
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
}

// The caster's pages, block by block of 4 x 4 pages where the hierarchy holds a wanted one:
// counted (the mask's left-out pages flagged) when `base` is 0xffffffff, else listed as pairs
// from `base`. Returns the pages it is drawn into.
fn visit_pages(c: CasterPages, base: u32) -> u32 {
    var count = 0u;
    let lo = c.first >> vec2<u32>(2u);
    let hi = c.last >> vec2<u32>(2u);
    for (var by = lo.y; by <= hi.y; by++) {
        for (var bx = lo.x; bx <= hi.x; bx++) {
            let block = vec2<i32>(bx, by);
            if ((atomicLoad(&page_hierarchy[hierarchy_cell(c.level, 2u, block)]) & c.hierarchy_bits) == 0u) {
                continue;
            }
            let first = max(c.first, block * 4);
            let last = min(c.last, block * 4 + 3);
            for (var y = first.y; y <= last.y; y++) {
                for (var x = first.x; x <= last.x; x++) {
                    let page = vec2<i32>(x, y);
                    let e = entry_of(c.level, page);
                    if (!page_wanted(e, c.wanted)) {
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
                        pairs[base + count] = vec2<u32>(c.instance, e | c.layer);
                        count++;
                    }
                }
            }
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
    c.texels = box_texels(level, b.min, b.max);
    let box = texel_pages(level, c.texels);
    c.first = max(box.xy, drawn.xy);
    c.last = min(box.zw, drawn.zw);
    if (any(c.first > c.last)
        || !cells_hold(level, covering_mip(c.first, c.last), c.first, c.last, c.hierarchy_bits)) {
        return;
    }
    let count = visit_pages(c, 0xffffffffu);
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
