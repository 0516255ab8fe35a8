// The virtual maps' page view (virtual_maps/overlay.rs), the `light-view` overlay of this
// technique: every level's square side by side, finest first, left to right and down (a
// point light's: a row per face, +X, -X, +Y, -Y, +Z, -Z, its mips finest first, the tiles of
// its finest mips each in its share of the mip's cell; a spot's mips as the sun's levels),
// each page in the colour of what it did this frame (palette.rs PAGE_*), dark where it is
// empty.
#import virtual_maps/pages.wgsl
#import palette.wgsl

@group(1) @binding(1) var<storage, read> page_flags: array<u32>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

@vertex
fn vs_pages(@builtin(vertex_index) index: u32) -> VsOut {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    var out: VsOut;
    out.clip = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
    out.uv = uv;
    return out;
}

// Mips per row of the view: for a point light, a face per row (+X, -X, +Y, -Y, +Z, -Z);
// else the smallest square that holds the chain's mips (the sun's levels, a spot's mips).
fn columns() -> u32 {
    if (chain_count() == 6u) {
        return max(chain_mips(), 6u);
    }
    return u32(ceil(sqrt(f32(chain_mips())) - 1e-4));
}

// The chain and the mip of the view's cell `cell` (the mip `chain_mips()` where none is).
fn cell_mip(cell: vec2<u32>) -> vec2<u32> {
    if (chain_count() == 6u) {
        let shown = cell.x < chain_mips() && cell.y < 6u;
        return vec2<u32>(cell.y, select(chain_mips(), cell.x, shown));
    }
    return vec2<u32>(0u, min(cell.y * columns() + cell.x, chain_mips()));
}

@fragment
fn fs_pages(in: VsOut) -> @location(0) vec4<f32> {
    let n = f32(columns());
    let cell = vec2<u32>(min(in.uv * n, vec2<f32>(n - 1.0)));
    let mip = cell_mip(cell);
    let in_cell = fract(in.uv * n);
    if (mip.y >= chain_mips() || any(in_cell < vec2<f32>(0.015)) || any(in_cell > vec2<f32>(0.985))) {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    // A tiled mip shows each tile's square in its share of the cell.
    let tiles = mip_tiles(mip.y);
    let within = in_cell * f32(tiles);
    let tile = min(vec2<u32>(within), vec2<u32>(tiles - 1u));
    let level = chain_levels(mip.x).x + mip_offset(mip.y) + tile.y * tiles + tile.x;
    let local = within - vec2<f32>(tile);
    let side = f32(level_pages(level));
    let page = vec2<i32>(local * side);
    let flags = page_flags[entry_of(level, page)];
    var colour = PALETTE_MAP_EMPTY;
    if ((flags & PAGE_REFUSED) != 0u) {
        colour = PALETTE_PAGE_REFUSED;
    } else if ((flags & PAGE_RENDERED) != 0u) {
        colour = PALETTE_PAGE_DRAWN;
    } else if ((flags & PAGE_REFRESHED) != 0u) {
        colour = PALETTE_PAGE_REFRESHED;
    } else if ((flags & PAGE_RESIDENT) != 0u && (flags & PAGE_MARKED) != 0u) {
        colour = PALETTE_PAGE_CACHED;
    } else if ((flags & PAGE_RESIDENT) != 0u) {
        colour = PALETTE_PAGE_IDLE;
    }
    // Page borders, faint, where pages are not tiny.
    let in_page = fract(local * side);
    if (any(in_page < vec2<f32>(0.06))) {
        colour *= 0.7;
    }
    return vec4<f32>(colour, 1.0);
}
