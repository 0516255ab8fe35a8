// The page tables and the pool as the compute passes write them (group 1; virtual_maps/
// frame.rs): per entry its flags, physical page and absolute page; per physical page its
// entry; the frame's free pages, drawn pages and counters; the boxes that moved; the
// hierarchy of page flags.
#import virtual_maps/pages.wgsl

// Keep in sync with virtual_maps/counts.rs (the word offsets).
struct Counters {
    marked: atomic<u32>,
    resident: atomic<u32>,
    rendered: atomic<u32>,
    refused: atomic<u32>,
    free_count: atomic<u32>,
    taken: atomic<u32>,
    pairs: atomic<u32>,
    draws: atomic<u32>,
    // (caster, page) pairs that found no room: their pages are drawn again next frame.
    overflow: atomic<u32>,
    evicted: atomic<u32>,
    // Pages refused by the first allocation, before cached pages were evicted.
    first_refused: atomic<u32>,
    invalidated: atomic<u32>,
    // Draw arguments of the clears: 6 vertices, an instance per drawn page.
    clear_args: array<atomic<u32>, 4>,
    level_marked: array<atomic<u32>, 156>,
    level_rendered: array<atomic<u32>, 156>,
    level_pairs: array<atomic<u32>, 156>,
    // Per level, the drawn pages' square: 32 less the first column and row, and one past
    // the last column and row (all 0: none drawn), so that zeroed counters start empty.
    rects: array<array<atomic<u32>, 4>, 156>,
    // When measuring: the texels of physical pages that visible pixels' taps read.
    texels_sampled: atomic<u32>,
    // Cached pages whose movable casters' layer alone is drawn this frame.
    refreshed: atomic<u32>,
    // Items in the list of drawn pages (drawn and refreshed).
    listed: atomic<u32>,
    // (caster, page) pairs the receiver mask left out.
    mask_culled: atomic<u32>,
    // The cull: the flags of the pages under casters' boxes (within the drawn pages' square),
    // which a walk page by page would read, and the page flags and hierarchy cells it read.
    cull_spanned: atomic<u32>,
    cull_reads: atomic<u32>,
    // Static occlusion: (moved box, page) pairs that left the page's movable layer fresh,
    // the box wholly behind its static depths, and (caster, refreshed page) pairs left out
    // so.
    occlusion_spared: atomic<u32>,
    occlusion_culled: atomic<u32>,
    // When measuring: per level, the pairs in the per-page oracle (copied in after the
    // oracle's draw, draw.wgsl).
    level_oracle: array<u32, 156>,
}

@group(1) @binding(1) var<storage, read_write> page_flags: array<atomic<u32>>;
@group(1) @binding(2) var<storage, read_write> counters: Counters;
@group(1) @binding(3) var<storage, read_write> page_slots: array<u32>;
@group(1) @binding(4) var<storage, read_write> page_tags: array<vec2<i32>>;
// Per physical page: its entry + 1, 0 when free.
@group(1) @binding(5) var<storage, read_write> owners: array<u32>;
@group(1) @binding(6) var<storage, read_write> free_list: array<u32>;
@group(1) @binding(7) var<storage, read_write> rendered_list: array<u32>;
// Boxes that moved this frame, world min and max (xyz) in pairs.
@group(1) @binding(8) var<storage, read> moved: array<vec4<f32>>;
// Per entry, two words: a bit per block of the page (row by row, 8 x 8) that a visible
// pixel's taps read this frame (the receiver mask; kept only when it is on).
@group(1) @binding(9) var<storage, read_write> receiver_masks: array<atomic<u32>>;
// The hierarchy of page flags (Unreal's HPB): per level, mips 1 to 5 of its 32 x 32 pages
// (16 x 16 cells of 2 x 2 pages, 8 x 8 of 4 x 4, ..., one cell of all), each cell whether a
// page under it is drawn whole this frame (HIERARCHY_DRAWN) or refreshed (HIERARCHY_REFRESHED),
// by the page's place in its level's square. Cleared each frame, written by `tally_pages`,
// read by the cull.
@group(1) @binding(10) var<storage, read_write> page_hierarchy: array<atomic<u32>>;
// Where static casters occlude movable ones: per physical page, row by row, the farthest
// static depth of each of its 8 x 8 blocks (layer 0), written by `reduce_static`
// (occlusion.wgsl) the frame after the page was drawn whole and read only while it stays
// resident.
@group(1) @binding(11) var<storage, read_write> static_depths: array<f32>;
// Where static casters are apart: per entry, two words, the blocks of its page whose movable
// layer a moved box made stale (`block_bits`' layout; meaningful while PAGE_DYNAMIC_STALE is
// set). A read page is refreshed only where pixels read one of them (`tally_pages`), and the
// light term reads none of them (light.wgsl).
@group(1) @binding(12) var<storage, read_write> stale_blocks: array<atomic<u32>>;

const HIERARCHY_MIPS: u32 = 5u;
// Cells per level: 256 + 64 + 16 + 4 + 1.
const HIERARCHY_CELLS: u32 = 341u;
const HIERARCHY_DRAWN: u32 = 1u;
const HIERARCHY_REFRESHED: u32 = 2u;

// The word of cell `cell` (pages >> mip) of mip `mip` (1 to 5) of level `level`'s hierarchy:
// after the cells of the finer mips, 1024 / 4 + ... + 1024 / 4^(mip - 1) of them.
fn hierarchy_cell(level: u32, mip: u32, cell: vec2<i32>) -> u32 {
    let side = u32(LEVEL_PAGES) >> mip;
    let before = (1024u - (1024u >> (2u * (mip - 1u)))) / 3u;
    return level * HIERARCHY_CELLS + before + u32(cell.y) * side + u32(cell.x);
}

// Where level `level`'s square places a world point, texels (x right, y down the map); z:
// the point's clip w (1 for the sun's levels; a face's distance along its axis).
fn level_texel(level: u32, p: vec3<f32>) -> vec3<f32> {
    let view = shadow_views[level];
    let c = light_clip(view, p);
    let size = f32(view.square.w);
    let ndc = c.xy / c.w;
    return vec3<f32>(vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * size, c.w);
}

// The texels of level `level`'s square that the world box `lo..hi` covers, widened by a
// texel: first (xy) and last (zw), unclamped. A box wholly behind a face's near plane covers
// none; one across it, the whole square.
fn box_texels(level: u32, lo: vec3<f32>, hi: vec3<f32>) -> vec4<f32> {
    var t_lo = vec2<f32>(1e30);
    var t_hi = vec2<f32>(-1e30);
    var behind = 0u;
    for (var i = 0u; i < 8u; i++) {
        let corner = select(lo, hi, vec3<bool>((i & 1u) != 0u, (i & 2u) != 0u, (i & 4u) != 0u));
        let t = level_texel(level, corner);
        if (t.z < POINT_NEAR_M) {
            behind++;
            continue;
        }
        t_lo = min(t_lo, t.xy);
        t_hi = max(t_hi, t.xy);
    }
    if (behind == 8u) {
        return vec4<f32>(1.0, 1.0, -1.0, -1.0);
    }
    if (behind > 0u) {
        let size = f32(shadow_views[level].square.w);
        return vec4<f32>(-1.0, -1.0, size + 1.0, size + 1.0);
    }
    return vec4<f32>(t_lo - 1.0, t_hi + 1.0);
}

// The pages of `texels` (`box_texels`) in level `level`'s square, first and last (x > z:
// none).
fn texel_pages(level: u32, texels: vec4<f32>) -> vec4<i32> {
    let side = level_pages(level);
    let first = clamp(vec2<i32>(floor(texels.xy / f32(PAGE_TEXELS))), vec2<i32>(0), vec2<i32>(side));
    let last = clamp(vec2<i32>(floor(texels.zw / f32(PAGE_TEXELS))), vec2<i32>(-1), vec2<i32>(side - 1));
    return vec4<i32>(first, last);
}

// The pages of level `level`'s square that the world box `lo..hi` covers, widened by a
// texel, as first and last page (x > z: none).
fn box_pages(level: u32, lo: vec3<f32>, hi: vec3<f32>) -> vec4<i32> {
    return texel_pages(level, box_texels(level, lo, hi));
}


// What the light's depths may differ by between the cull's corners and the rasteriser's
// interpolation: a box counts as behind only by more than this.
const DEPTH_MARGIN: f32 = 1e-6;

// The nearest depth of the world box `lo..hi` in level `level`'s view (a stored depth's
// scale); 0 where a corner lies behind a face's near plane.
fn box_nearest_depth(level: u32, lo: vec3<f32>, hi: vec3<f32>) -> f32 {
    var nearest = 1.0;
    for (var i = 0u; i < 8u; i++) {
        let corner = select(lo, hi, vec3<bool>((i & 1u) != 0u, (i & 2u) != 0u, (i & 4u) != 0u));
        let c = light_clip(shadow_views[level], corner);
        if (c.w < POINT_NEAR_M) {
            return 0.0;
        }
        nearest = min(nearest, c.z / c.w);
    }
    return nearest;
}

// The blocks of `covered` (`block_bits`' words) in the page of entry `e` (resident, its
// static layer drawn before this frame) behind whose static depths, all of them nearer, lies
// a movable caster nearest at depth `nearest`. Drawn there or not, moved there or not, such a
// caster leaves each texel's nearer depth of both layers as it is, which is all the light
// term reads (light.wgsl `stored_depth`).
fn blocks_behind_static(e: u32, covered: vec2<u32>, nearest: f32) -> vec2<u32> {
    let base = page_slots[e] * 64u;
    var behind = vec2<u32>(0u);
    for (var w = 0u; w < 2u; w++) {
        // The covered blocks of word w, lowest first.
        var left = select(covered.x, covered.y, w == 1u);
        var found = 0u;
        while (left != 0u) {
            let bit = countTrailingZeros(left);
            left &= left - 1u;
            if (static_depths[base + 32u * w + bit] < nearest - DEPTH_MARGIN) {
                found |= 1u << bit;
            }
        }
        behind = select(vec2<u32>(found, behind.y), vec2<u32>(behind.x, found), w == 1u);
    }
    return behind;
}

// The blocks of page `page` that a box's texels `texels` (`box_texels`) cover.
fn box_blocks(page: vec2<i32>, texels: vec4<f32>) -> vec2<u32> {
    return block_bits(page, vec2<i32>(floor(texels.xy)), vec2<i32>(floor(texels.zw)));
}

// Whether a movable caster nearest at depth `nearest` over texels `texels` lies wholly behind
// the static casters of page `page` (entry `e`): behind every block of it that it covers.
fn behind_static(e: u32, page: vec2<i32>, texels: vec4<f32>, nearest: f32) -> bool {
    let covered = box_blocks(page, texels);
    return any(covered != vec2<u32>(0u))
        && all(blocks_behind_static(e, covered, nearest) == covered);
}
