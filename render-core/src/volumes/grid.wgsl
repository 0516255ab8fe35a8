// The receiver grid (Lloyd's potential shadow receivers, at pixel precision): the visible
// receiver points in the light's view, per slice of the picture and cell across the light.
// Each cell holds a word of the slices that hold points there, and each (slice, cell) three
// words: the shallowest and the deepest point's depth along the light (past the scene's
// nearest, or from a point light; plus 1, as bits, the shallowest inverted so both grow with
// atomicMax; 0: none), and which of DEPTH_BINS equal bins of depth hold a point. A cell over
// a truss and the floor far below it keeps the two apart: the air between is in no bin, and
// a volume over the cell is not drawn through it. The points themselves are listed per cell
// too (`cells`, `points`), for casters to test one by one (`gather_receivers`).
// Part of volumes/find.wgsl.

// Bins of a (slice, cell)'s depths, one bit each (`VolumeFrame::cell.z` their size).
const DEPTH_BINS: u32 = 32u;

fn cell_of(p: vec2<f32>) -> vec2<i32> {
    return vec2<i32>(floor(p / volume.cell.x));
}

// The strip of the view (Lloyd's slice between two planes through the eye) that pixel
// `pixel` lies in (`strip_coordinate`): planes through the eye that hold the axis across both
// the light and the view direction cut the picture into parallel strips of equal width.
fn slice_of(pixel: vec2<u32>) -> u32 {
    let k = volume.grid.x;
    let u = strip_coordinate(vec2<f32>(pixel) + 0.5);
    return min(u32(max((u * 0.5 + 0.5) * f32(k), 0.0)), k - 1u);
}

// The words of a (slice, cell): 0 the shallowest, 1 the deepest, 2 the occupied bins.
const SHALLOWEST: u32 = 0u;
const DEEPEST: u32 = 1u;
const BINS: u32 = 2u;

// The grid starts with one word per cell: which slices hold points there.
fn slices_word(cell: vec2<i32>) -> u32 {
    return u32(cell.y) * volume.grid.y + u32(cell.x);
}

fn grid_word(slice: u32, cell: vec2<i32>, word: u32) -> u32 {
    let cells = volume.grid.y * volume.grid.z;
    return cells + (slice * cells + slices_word(cell)) * 3u + word;
}

// The grid's last cell.
fn grid_last() -> vec2<i32> {
    return vec2<i32>(volume.grid.yz) - 1;
}

// The bin of depth `depth`; depths past the last bin's end fall in it.
fn depth_bin(depth: f32) -> u32 {
    return min(u32(max(depth / volume.cell.z, 0.0)), DEPTH_BINS - 1u);
}

// Per grid cell (row by row, no slices): its visible receiver points' count and where they
// start in `points`.
@group(2) @binding(10) var<storage, read_write> cells: array<atomic<u32>>;
// The visible receiver points listed by cell: world position as bits (xyz); slice
// (POINT_SLICE_BITS), whether it faces the light (FACING_LIGHT) and its instance above (w).
@group(2) @binding(11) var<storage, read_write> points: array<vec4<u32>>;
@group(2) @binding(12) var surface_normals: texture_2d<f32>;

const POINT_SLICE_BITS: u32 = 0x1fu;
const FACING_LIGHT: u32 = 0x20u;
const POINT_INSTANCE_SHIFT: u32 = 6u;

// A visible pixel's receiver point as the grid takes it (`found`: it is one).
struct ReceiverPixel {
    found: bool,
    cell: vec2<i32>,
    slice: u32,
    depth: f32,
    instance: u32,
    at: vec3<f32>,
    // Whether its geometric normal faces the light.
    facing: bool,
}

fn receiver_pixel(pixel: vec2<u32>) -> ReceiverPixel {
    var r: ReceiverPixel;
    let size = textureDimensions(surface_ids);
    if (any(pixel >= size)) {
        return r;
    }
    let object = textureLoad(surface_ids, vec2<i32>(pixel), 0).x;
    if (object == 0u || (bounds[object - 1u].flags & FLAG_RECEIVER) == 0u) {
        return r;
    }
    r.at = textureLoad(surface_positions, vec2<i32>(pixel), 0).xyz;
    // A point whose normals both face away from the light is dark whatever shadows it, and
    // the exact shadow does not count it: no volume need reach it. The geometric normal
    // comes from the picture's derivatives, so one that grazes the light (within 3 degrees,
    // where the exact surface may face it) still counts.
    let normal = textureLoad(surface_normals, vec2<i32>(pixel), 0);
    let towards = dot(normal.xyz, to_volume_light(r.at));
    r.facing = towards > 0.0;
    if (towards < -0.05 && normal.w == 0.0) {
        return r;
    }
    var p = in_light(r.at);
    if (from_point()) {
        p = in_point_light(r.at);
    }
    r.found = true;
    r.cell = clamp(cell_of(p.xy), vec2<i32>(0), grid_last());
    r.slice = slice_of(pixel);
    r.depth = max(p.z, 0.0);
    r.instance = object - 1u;
    return r;
}

// Lloyd's potential shadow receivers, exactly: every visible receiver pixel that shadow
// can change marks the grid cell under it, in its slice, with its depth along the light.
@compute @workgroup_size(8, 8)
fn mark_receivers(@builtin(global_invocation_id) id: vec3<u32>) {
    let r = receiver_pixel(id.xy);
    if (!r.found) {
        return;
    }
    let bits = bitcast<u32>(r.depth + 1.0);
    atomicMax(&grid[grid_word(r.slice, r.cell, SHALLOWEST)], ~bits);
    atomicMax(&grid[grid_word(r.slice, r.cell, DEEPEST)], bits);
    atomicOr(&grid[grid_word(r.slice, r.cell, BINS)], 1u << depth_bin(r.depth));
    atomicOr(&grid[slices_word(r.cell)], 1u << r.slice);
    atomicAdd(&cells[2u * slices_word(r.cell)], 1u);
}

// Each cell's room in `points` (counters[7]: taken so far), its count back to 0 for
// `list_receivers` to count again.
@compute @workgroup_size(64)
fn place_cells(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= volume.grid.y * volume.grid.z) {
        return;
    }
    let count = atomicLoad(&cells[2u * id.x]);
    if (count > 0u) {
        atomicStore(&cells[2u * id.x + 1u], atomicAdd(&counters[7], count));
        atomicStore(&cells[2u * id.x], 0u);
    }
}

// Every visible receiver point into its cell's room in `points`.
@compute @workgroup_size(8, 8)
fn list_receivers(@builtin(global_invocation_id) id: vec3<u32>) {
    let r = receiver_pixel(id.xy);
    if (!r.found) {
        return;
    }
    let word = 2u * slices_word(r.cell);
    let slot = atomicLoad(&cells[word + 1u]) + atomicAdd(&cells[word], 1u);
    let tag = r.slice | select(0u, FACING_LIGHT, r.facing) | (r.instance << POINT_INSTANCE_SHIFT);
    points[slot] = vec4<u32>(bitcast<vec3<u32>>(r.at), tag);
}

// The unit vector from `p` towards the light.
fn to_volume_light(p: vec3<f32>) -> vec3<f32> {
    if (from_point()) {
        return normalize(volume.point.xyz - p);
    }
    return volume.to_light.xyz;
}

// A point's depth as the grid measures it: along the sun past the scene's nearest, or its
// distance from a point light.
fn light_depth(p: vec3<f32>) -> f32 {
    if (from_point()) {
        return distance(p, volume.point.xyz);
    }
    return max(in_light(p).z, 0.0);
}

// Every slice of `found` without receiver depths yet, and no bins, for `gather_cell`.
fn clear_found(
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    bins: ptr<function, array<u32, MAX_SLICES>>,
) {
    for (var slice = 0u; slice < volume.grid.x; slice++) {
        (*found)[slice] = vec2<f32>(1e30, -1.0);
        (*bins)[slice] = 0u;
    }
}

// Widens each slice's depths in `found` by the receiver points of `cell` in that slice no
// nearer than `nearest` (with `pad` to spare), and adds their bins to `bins`. Returns the
// loop iterations it took: one per slice that holds points there.
fn gather_cell(
    cell: vec2<i32>,
    nearest: f32,
    pad: f32,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    bins: ptr<function, array<u32, MAX_SLICES>>,
) -> i32 {
    var held = atomicLoad(&grid[slices_word(cell)]);
    let steps = i32(countOneBits(held));
    for (; held != 0u; held &= held - 1u) {
        let slice = firstTrailingBit(held);
        let deepest = atomicLoad(&grid[grid_word(slice, cell, DEEPEST)]);
        if (deepest == 0u || bitcast<f32>(deepest) - 1.0 + pad < nearest) {
            continue;
        }
        let shallowest = ~atomicLoad(&grid[grid_word(slice, cell, SHALLOWEST)]);
        let was = (*found)[slice];
        (*found)[slice] = vec2<f32>(
            min(was.x, bitcast<f32>(shallowest) - 1.0),
            max(was.y, bitcast<f32>(deepest) - 1.0),
        );
        (*bins)[slice] |= atomicLoad(&grid[grid_word(slice, cell, BINS)]);
    }
    return steps;
}

// The occupied depths of `found`'s slices, each from no nearer than `nearest`, cut where
// `bins` has empty bins between them (with `pad` to spare at each cut), moved to `found`'s
// front. Past MAX_SLICES pieces the last one grows over the rest. Returns how many.
fn compact_found(
    nearest: f32,
    pad: f32,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    bins: ptr<function, array<u32, MAX_SLICES>>,
) -> u32 {
    var slices: array<vec2<f32>, MAX_SLICES>;
    for (var slice = 0u; slice < volume.grid.x; slice++) {
        slices[slice] = (*found)[slice];
    }
    let size = volume.cell.z;
    var n = 0u;
    for (var slice = 0u; slice < volume.grid.x; slice++) {
        let depths = slices[slice];
        if (depths.y < 0.0) {
            continue;
        }
        let start = max(depths.x, nearest);
        if (start > depths.y) {
            // The caster's padding reaches past the deepest point.
            n = add_found(found, n, vec2<f32>(start, depths.y), 1u << slice);
            continue;
        }
        let last = depth_bin(depths.y + pad);
        let before = n;
        var open = false;
        var opened = start;
        for (var b = depth_bin(start - pad); b <= last + 1u; b++) {
            let occupied = b <= last && ((*bins)[slice] & (1u << b)) != 0u;
            if (occupied && !open) {
                open = true;
                opened = max(start, f32(b) * size - pad);
            } else if (!occupied && open) {
                open = false;
                let end = select(min(depths.y, f32(b) * size + pad), depths.y, b > last);
                n = add_found(found, n, vec2<f32>(opened, end), 1u << slice);
            }
        }
        if (n == before) {
            n = add_found(found, n, vec2<f32>(start, depths.y), 1u << slice);
        }
    }
    return n;
}

// `depths` as `found`'s piece `n`, from the slices `slices` (one bit each), or grown into
// its last. Returns the pieces now.
fn add_found(
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    n: u32,
    depths: vec2<f32>,
    slices: u32,
) -> u32 {
    if (n < MAX_SLICES) {
        (*found)[n] = depths;
        piece_slices[n] = slices;
        return n + 1u;
    }
    let was = (*found)[n - 1u];
    (*found)[n - 1u] = vec2<f32>(min(was.x, depths.x), max(was.y, depths.y));
    piece_slices[n - 1u] |= slices;
    return n;
}

// Per piece of `found` (`compact_found`), the slices of the view its receivers lie in, one
// bit each: its volume is drawn only across their strips of the picture
// (volumes/strips_clipped.wgsl).
// Every bit where the pieces come from the CPU (`given_intervals`).
var<private> piece_slices: array<u32, MAX_SLICES>;

// What stands for a caster's intervals where its cells ran past the budget of loop steps.
const TOO_MANY_CELLS: u32 = 0xffffffffu;

// Gathers into `found` and `bins` (`gather_receivers`, for the caster's `box`) the cells
// from `cells[0].xy` to `cells[0].zw` that the footprint of `q` meets (where `tested`; else
// all of them), row by row (`footprint_row`), and always the rows and columns at `cells[1]`
// (lowest xy, highest zw: the border cells, which also hold points beyond). `cells[2]`:
// this lane, the lanes sharing the cells (the cull's workgroup's, or a big caster's
// workgroups') and the budget of loop iterations. The lanes take every n-th row, n the lanes or the
// rows if fewer; the lanes left over for each row share its cells, so a wall seen edge-on
// (few rows, long ones) spreads as well as a floor; and those left over for each cell share
// its points, so a strut over a few dense cells spreads too. `units`: the cells' size in
// `q`'s units, their half-size there (0: their centres only) and the padding; `depth`: the
// caster's nearest depth and its padding. Counts loop iterations in `steps`; false once past
// the budget.
fn gather_footprint(
    q: ptr<function, array<vec2<f32>, 8>>,
    box: ptr<function, CasterBox>,
    tested: bool,
    cells: array<vec4<i32>, 3>,
    units: vec3<f32>,
    depth: vec2<f32>,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    bins: ptr<function, array<u32, MAX_SLICES>>,
    steps: ptr<function, i32>,
) -> bool {
    let range = cells[0];
    let border = cells[1];
    let budget = cells[2].z;
    let lanes = max(cells[2].y, 1);
    let row_lanes = clamp(range.w - range.y + 1, 1, lanes);
    let row_lane = cells[2].x % row_lanes;
    let column_lanes = clamp(range.z - range.x + 1, 1, lanes / row_lanes);
    let column_lane = (cells[2].x / row_lanes) % column_lanes;
    let point_lanes = lanes / (row_lanes * column_lanes);
    let point_lane = cells[2].x / (row_lanes * column_lanes);
    if (point_lane >= point_lanes) {
        return true;
    }
    let share = vec2<u32>(u32(point_lane), u32(point_lanes));
    // Where its rows' cells could take a lane past its budget, it counts them first, and
    // stops before it gathers once the count's own steps and the least its walk would take
    // (its rows' steps and one per cell it meets) are past the budget: a floor or a wall
    // seen by 32 lanes spends a short count, not its whole budget, before its workgroups
    // take it (`cull_casters`).
    let range_cells = (range.z - range.x + 1) * (range.w - range.y + 1);
    if (range_cells > (budget - *steps) * row_lanes * column_lanes) {
        var counted = 0;
        var least = *steps;
        for (var y = range.y + row_lane; y <= range.w; y += row_lanes) {
            let xs = footprint_cells(q, tested, y, range, border, units);
            let rows = row_steps(tested, y, border);
            let after_first = xs.y - (xs.x + column_lane);
            counted += rows;
            least += 2 * rows + select(0, after_first / column_lanes + 1, after_first >= 0);
            if (least > budget) {
                return false;
            }
        }
        *steps += counted;
    }
    for (var y = range.y + row_lane; y <= range.w; y += row_lanes) {
        let xs = footprint_cells(q, tested, y, range, border, units);
        *steps += row_steps(tested, y, border);
        for (var x = xs.x + column_lane; x <= xs.y; x += column_lanes) {
            let room = budget - *steps;
            *steps += 1 + gather_receivers(vec2<i32>(x, y), depth, box, share, found, bins, room);
            if (*steps > budget) {
                return false;
            }
        }
        // The border columns, where the footprint's cells leave them out (one lane a row).
        for (var side = 0u; side < 2u && column_lane == 0; side++) {
            let x = select(border.x, border.z, side == 1u);
            if (x >= range.x && x <= range.z && (x < xs.x || x > xs.y)) {
                let room = budget - *steps;
                *steps += gather_receivers(vec2<i32>(x, y), depth, box, share, found, bins, room);
            }
        }
    }
    return *steps <= budget;
}

// The cells of row `y` from `range.x` to `range.z` that the footprint of `q` meets (where
// `tested` and the row is not one of `border`'s; else all of them): first and last.
fn footprint_cells(
    q: ptr<function, array<vec2<f32>, 8>>,
    tested: bool,
    y: i32,
    range: vec4<i32>,
    border: vec4<i32>,
    units: vec3<f32>,
) -> vec2<i32> {
    if (!tested || y == border.y || y == border.w) {
        return range.xz;
    }
    let centre = (f32(y) + 0.5) * units.x;
    let band = vec2<f32>(centre - units.y - units.z, centre + units.y + units.z);
    let span = footprint_row(q, band);
    if (span.x > span.y) {
        return vec2<i32>(1, 0);
    }
    let meets = cells_meeting(span, units.x, units.y, units.z);
    return vec2<i32>(max(meets.x, range.x), min(meets.y, range.z));
}

// Loop iterations of a row of `gather_footprint`, besides its cells'.
fn row_steps(tested: bool, y: i32, border: vec4<i32>) -> i32 {
    return select(3, 3 + i32(FOOTPRINT_STEPS), tested && y != border.y && y != border.w);
}

// The budget of loop iterations of one of `lanes.y` lanes sharing a caster's cells: the
// cull's, or a big caster's (volumes/frame.rs `StepBudget`).
fn lane_budget(lanes: vec2<u32>) -> i32 {
    return i32(select(volume.steps.y, volume.steps.x, lanes.y <= CULL_LANES));
}

// `gather_cell` for a caster's `box`: while `room` loop iterations are left for this lane's
// share of the cell's listed points (every `share.y`-th from the `share.x`-th), only those
// the caster can shadow (`ray_meets_box`; its own points facing the light left out where its
// mesh is convex). A cell whose share is past the frame's cell points (`cell.w`) is taken
// whole by the first of the lanes sharing it; one past this lane's room by this lane.
// Returns the iterations taken.
fn gather_receivers(
    cell: vec2<i32>,
    depth: vec2<f32>,
    box: ptr<function, CasterBox>,
    share: vec2<u32>,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    bins: ptr<function, array<u32, MAX_SLICES>>,
    room: i32,
) -> i32 {
    let word = 2u * slices_word(cell);
    let count = atomicLoad(&cells[word]);
    let mine = (count + share.y - 1u - share.x) / share.y;
    let whole = !(*box).points || f32((count + share.y - 1u) / share.y) > volume.cell.w;
    if (whole || i32(mine) >= room) {
        if (whole && share.x != 0u) {
            return 0;
        }
        return gather_cell(cell, depth.x, depth.y, found, bins);
    }
    let start = atomicLoad(&cells[word + 1u]);
    for (var k = start + share.x; k < start + count; k += share.y) {
        let point = points[k];
        let p = bitcast<vec3<f32>>(point.xyz);
        let own = (point.w >> POINT_INSTANCE_SHIFT) == (*box).instance;
        if ((own && (*box).convex && (point.w & FACING_LIGHT) != 0u) || !ray_meets_box(p, box, point_pad(p))) {
            continue;
        }
        let slice = point.w & POINT_SLICE_BITS;
        let d = light_depth(p);
        let was = (*found)[slice];
        (*found)[slice] = vec2<f32>(min(was.x, d), max(was.y, d));
        (*bins)[slice] |= 1u << depth_bin(d);
    }
    return i32(mine);
}
