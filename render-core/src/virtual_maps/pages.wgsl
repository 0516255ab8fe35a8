// Virtual shadow maps' page grid (virtual_maps/mod.rs): every level is a shadow view of the
// frame (shadow_views[level]), cut into pages of 128 texels. The sun's levels are a clipmap:
// each a 4096-texel square of 32 x 32 pages on a fixed texel grid, and a page's entry in its
// level's table is wrapped by its absolute page position, so a page keeps its entry (and its
// physical page) while the square moves with the camera. A point light's levels are its
// cube's six faces, each a chain of mips (16,384 texels square, 8192, ...; a perspective view
// from the light; the mips finer than a level's 4096 texels are tiles of 4096, a level each),
// whose pages never move; a spot light's, one such chain along its cone. A chain is the
// levels that may shade a point, finest first: the sun's whole clipmap, one face's mips, or
// the spot's. Every user binds `params` here; the tables it binds as it needs them.
#import shadow_view/lookup.wgsl

const PAGE_TEXELS: i32 = 128;
const LEVEL_PAGES: i32 = 32;
const LEVEL_ENTRIES: u32 = 1024u;
// The near plane of a point light's faces, metres (geom/punctual.rs NEAR_M).
const POINT_NEAR_M: f32 = 0.05;

// An entry's flags: marked by a visible pixel this frame; holding a physical page; drawn this
// frame (every layer); marked but given no physical page; touched by a moving box (drawn
// again in the physical page it holds where marked, allocate.wgsl `redraw_in_place`). Where
// static casters are kept apart, a moving box leaves the page resident but its movable
// casters' layer stale, and a marked stale page has that layer alone drawn (refreshed).
const PAGE_MARKED: u32 = 1u;
const PAGE_RESIDENT: u32 = 2u;
const PAGE_RENDERED: u32 = 4u;
const PAGE_REFUSED: u32 = 8u;
const PAGE_INVALID: u32 = 16u;
const PAGE_DYNAMIC_STALE: u32 = 32u;
const PAGE_REFRESHED: u32 = 64u;
// The receiver mask left a caster out of the page: it holds the depths of the blocks pixels
// read this frame only, so the next frame draws it again: whole (the cull also made it
// invalid), or its movable layer where only movable casters were left out.
const PAGE_PARTIAL: u32 = 128u;
// The receiver mask's blocks: 8 x 8 per page, 16 texels square.
const BLOCK_TEXELS: i32 = 16;
// A drawn page's item in the list of drawn pages (and a pair's entry): its entry, and this
// bit for the movable casters' layer alone.
const DYNAMIC_ONLY: u32 = 0x40000000u;
const ENTRY_BITS: u32 = 0x3fffffffu;

// Keep in sync with virtual_maps/gpu_data.rs (VirtualParams).
struct VirtualParams {
    // x: levels; y: physical pages; z: the atlas's columns of pages; w: 1 when every page is
    // invalid this frame (the light, the scene or the settings changed, or the cache is off).
    counts: vec4<u32>,
    // x: the finest level's texel, metres; y: the level bias, octaves; z: moved boxes this
    // frame; w: the atlas's rows of pages.
    tuning: vec4<f32>,
    // x: physical pages kept back from the first allocations for the fallback pages of
    // pixels whose own pages were refused; y: 1 when static casters are kept apart (a second
    // layer of pages, below the first in the atlas, holds the movable ones); z: bit 0 when the
    // receiver mask culls casters per block of a page, bit 1 when static casters occlude
    // movable ones per page (static casters apart); w: mips per face of a point light's cube (0: the sun's clipmap).
    limits: vec4<u32>,
    // Per level, xy: the absolute position of its square's first page (column, row).
    first_page: array<vec4<i32>, 156>,
}

@group(1) @binding(0) var<uniform> params: VirtualParams;

fn level_count() -> u32 {
    return params.counts.x;
}

// Mips per face of a point light's cube, 0 for the sun.
fn face_mips() -> u32 {
    return params.limits.w;
}

// Texels along a level's side.
const LEVEL_TEXELS: i32 = 4096;
// Texels of its mip each tile reaches past its share of the face (geom/punctual.rs
// TILE_OVERLAP_TEXELS).
const TILE_OVERLAP: f32 = 8.0;

// Mips of a chain: the sun's levels, or a face's (a spot's) mips.
fn chain_mips() -> u32 {
    return select(level_count(), face_mips(), face_mips() != 0u);
}

// Tiles along a side of mip `m` of a chain: the mips of a point or spot light finer than a
// level's 4096 texels are cut into tiles of 4096, a level each (punctual.rs `mip_tiles`; the
// coarsest mip is one page).
fn mip_tiles(m: u32) -> u32 {
    if (face_mips() == 0u) {
        return 1u;
    }
    let side_pages = 1u << (face_mips() - 1u - m);
    return max(side_pages / u32(LEVEL_PAGES), 1u);
}

// The first level of mip `m` within its chain (the mip's tiles follow row by row).
fn mip_offset(m: u32) -> u32 {
    var levels = 0u;
    for (var k = 0u; k < m; k++) {
        levels += mip_tiles(k) * mip_tiles(k);
    }
    return levels;
}

// Levels of a chain (punctual.rs `face_levels`).
fn chain_length() -> u32 {
    return mip_offset(chain_mips());
}

// Chains of levels: one for the sun's clipmap, a face each for a point light, one for a spot.
fn chain_count() -> u32 {
    return level_count() / chain_length();
}

// The chain that shades world point `p`: the sun's or the spot's one, or the face of its
// major axis from a point light.
fn chain_of(p: vec3<f32>) -> u32 {
    return select(0u, cube_face(p - frame.point_light.xyz), chain_count() == 6u);
}

// The levels of chain `c`: its finest and one past its coarsest.
fn chain_levels(c: u32) -> vec2<u32> {
    return vec2<u32>(c * chain_length(), (c + 1u) * chain_length());
}

// Pages along level `level`'s side (a point light's coarser mips have fewer).
fn level_pages(level: u32) -> i32 {
    return i32(shadow_views[level].square.w) / PAGE_TEXELS;
}

fn wrap_pages(p: vec2<i32>) -> vec2<i32> {
    return ((p % LEVEL_PAGES) + LEVEL_PAGES) % LEVEL_PAGES;
}

// The absolute position of page `page` of level `level`'s square.
fn absolute_page(level: u32, page: vec2<i32>) -> vec2<i32> {
    return params.first_page[level].xy + page;
}

// The table entry of page `page` (0..32 each way) of level `level`'s square.
fn entry_of(level: u32, page: vec2<i32>) -> u32 {
    let wrapped = wrap_pages(absolute_page(level, page));
    return level * LEVEL_ENTRIES + u32(wrapped.y * LEVEL_PAGES + wrapped.x);
}

// The page of its level's square that entry `e` stands for this frame.
fn window_page(e: u32) -> vec2<i32> {
    let local = i32(e % LEVEL_ENTRIES);
    let wrapped = vec2<i32>(local % LEVEL_PAGES, local / LEVEL_PAGES);
    return wrap_pages(wrapped - params.first_page[e / LEVEL_ENTRIES].xy);
}

// The first texel of physical page `slot` in the atlas (layer 0: static casters, or every
// caster where they are not kept apart; layer 1: movable casters).
fn slot_origin(slot: u32) -> vec2<i32> {
    let columns = params.counts.z;
    return vec2<i32>(i32(slot % columns), i32(slot / columns)) * PAGE_TEXELS;
}

fn layer_origin(slot: u32, layer: u32) -> vec2<i32> {
    let rows = i32(params.tuning.w);
    return slot_origin(slot) + vec2<i32>(0, i32(layer) * rows * PAGE_TEXELS);
}

// Texel `t` of a level's square (within page `t / PAGE_TEXELS`, held by physical page
// `slot`) in the atlas's layer `layer`.
fn slot_texel(slot: u32, layer: u32, t: vec2<i32>) -> vec2<i32> {
    return layer_origin(slot, layer) + t % PAGE_TEXELS;
}

// Texel `t`'s bit in its page (of 512 words, row by row): the word and the bit in it.
fn texel_bit(t: vec2<i32>) -> vec2<u32> {
    let local = t % PAGE_TEXELS;
    let bit = u32(local.y * PAGE_TEXELS + local.x);
    return vec2<u32>(bit / 32u, 1u << (bit % 32u));
}

fn static_apart() -> bool {
    return params.limits.y != 0u;
}

fn receiver_mask_on() -> bool {
    return (params.limits.z & 1u) != 0u;
}

// Static occlusion, set only where static casters are apart: a movable caster wholly behind
// a page's cached static depths neither makes its movable layer stale nor is drawn into it
// (tables.wgsl `behind_static`).
fn static_occlusion_on() -> bool {
    return (params.limits.z & 2u) != 0u;
}

// Resolution matching: the finest mip of the point's chain whose texel is no larger than the
// point's pixel, as areas on the surface (the measure's own terms, metrics/measure.wgsl), plus
// the bias. The sun's finest texel is a setting; a face's grows with the distance along its
// axis.
fn matched_mip(world_pos: vec3<f32>, n: vec3<f32>) -> u32 {
    let to_eye = frame.eye_world.xyz - world_pos;
    let distance = length(to_eye);
    let pixel_m = distance * frame.camera_forward.w;
    let cos_view = max(abs(dot(n, to_eye / max(distance, 1e-6))), 0.02);
    let finest = shadow_views[chain_levels(chain_of(world_pos)).x];
    var to_light = finest.light_dir.xyz;
    var finest_m = params.tuning.x;
    if (face_mips() != 0u) {
        let d = world_pos - frame.point_light.xyz;
        to_light = d / max(length(d), 1e-12);
        finest_m = finest.light_right.w * max(dot(d, finest.light_dir.xyz), 1e-6);
    }
    let cos_light = max(abs(dot(n, to_light)), 0.02);
    let texel_m = pixel_m * sqrt(cos_light / cos_view);
    let octaves = log2(max(texel_m, 1e-30) / finest_m) + params.tuning.y;
    // NaN (a broken surface) takes the finest mip, which the lookup then rejects.
    let mip = select(0.0, floor(octaves), octaves == octaves);
    return u32(clamp(mip, 0.0, f32(chain_mips() - 1u)));
}

// The level of mip `m` of chain `chain` that holds world point `p`: the mip's one level, or
// the tile whose share of the face holds it (the taps of its kernel then lie within the
// tile's overlap).
fn mip_level(p: vec3<f32>, chain: u32, m: u32) -> u32 {
    let first = chain_levels(chain).x + mip_offset(m);
    let tiles = mip_tiles(m);
    if (tiles == 1u) {
        return first;
    }
    // Texels of the first tile's grid, which runs on across the others.
    let clip = light_clip(shadow_views[first], p);
    if (!(clip.w > 0.0)) {
        return first;
    }
    let side = f32(LEVEL_TEXELS);
    let t = vec2<f32>(clip.x / clip.w * 0.5 + 0.5, 0.5 - clip.y / clip.w * 0.5) * side;
    let scale = side / (side + 2.0 * TILE_OVERLAP);
    let tile = clamp(
        floor((t - TILE_OVERLAP * scale) / (side * scale)),
        vec2<f32>(0.0),
        vec2<f32>(f32(tiles - 1u)),
    );
    return first + u32(tile.y) * tiles + u32(tile.x);
}

// The level a point is shaded from when its pages are there: the matched mip's, or that of
// the first coarser mip of its chain whose square holds every tap (`level_count()` when
// none does).
fn holding_level(world_pos: vec3<f32>, n: vec3<f32>) -> u32 {
    let chain = chain_of(world_pos);
    for (var m = matched_mip(world_pos, n); m < chain_mips(); m++) {
        let level = mip_level(world_pos, chain, m);
        if (lookup_contained(shadow_lookup(world_pos, n, level))) {
            return level;
        }
    }
    return level_count();
}

// The pages (of its level's square) that lookup `l`'s taps read: first and last.
fn tap_pages(l: ShadowLookup) -> array<vec2<i32>, 2> {
    return array<vec2<i32>, 2>(l.first / PAGE_TEXELS, (l.first + l.kernel - 1) / PAGE_TEXELS);
}

// The blocks of page `page` that texels `first..=last` (relative to the level's square,
// any range) cover, as the receiver mask's two words.
fn block_bits(page: vec2<i32>, first: vec2<i32>, last: vec2<i32>) -> vec2<u32> {
    let origin = page * PAGE_TEXELS;
    let lo = clamp((first - origin) / BLOCK_TEXELS, vec2<i32>(0), vec2<i32>(7));
    let hi = clamp((last - origin) / BLOCK_TEXELS, vec2<i32>(0), vec2<i32>(7));
    var words = vec2<u32>(0u);
    if (any(last < origin) || any(first >= origin + PAGE_TEXELS)) {
        return words;
    }
    let row = ((1u << u32(hi.x - lo.x + 1)) - 1u) << u32(lo.x);
    for (var y = lo.y; y <= hi.y; y++) {
        if (y < 4) {
            words.x |= row << u32(8 * y);
        } else {
            words.y |= row << u32(8 * (y - 4));
        }
    }
    return words;
}
