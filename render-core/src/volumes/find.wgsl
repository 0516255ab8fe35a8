// Stencil shadow volumes, first step (volumes/mod.rs): per caster, the edges whose
// quad is extruded (the silhouette, from the edge adjacency of volumes/edges.rs) and the
// triangles that cap the volume, appended as records (volumes/records.wgsl) that the draw
// passes (volumes/draw.wgsl) turn into triangles.
#import volumes/common.wgsl
#import volumes/point_light.wgsl
#import volumes/footprint.wgsl
#import volumes/shadowing.wgsl
#import volumes/grid.wgsl
#import volumes/big_casters.wgsl
#import volumes/records.wgsl
#import culling/codes.wgsl

@group(2) @binding(0) var<storage, read_write> quads: array<vec2<u32>>;
@group(2) @binding(1) var<storage, read_write> caps: array<vec2<u32>>;
// z-fail quads, caps at the casters, moved caps and fan caps, then z-pass
// (volumes/pipelines.rs DRAWS).
@group(2) @binding(2) var<storage, read_write> draws: array<DrawArgs, 8>;
// Fan caps (volumes/records.wgsl `append_fans`), z-fail from the start, z-pass from the end;
// and per caster its fan's corner, a vertex index inverted (0: none yet), cleared each frame
// before the silhouettes (volumes/find_passes.rs).
@group(2) @binding(15) var<storage, read_write> fans: array<vec2<u32>>;
@group(2) @binding(16) var<storage, read_write> anchors: array<atomic<u32>>;
// Per caster, how many intervals of its volume are drawn (0: none), with Z_PASS set where
// the stencil counts it z-pass; and the intervals, MAX_INTERVALS per caster (common.wgsl).
// Z-fail records fill `quads` and each part of `caps` from the start, z-pass records from
// the end (common.wgsl `cap_slot`).
@group(2) @binding(3) var<storage, read_write> kept: array<u32>;
@group(2) @binding(4) var<storage, read_write> intervals: array<vec2<f32>>;
// Per interval, the strips of the picture its volume is drawn across (`strips_word`).
@group(2) @binding(14) var<storage, read_write> strips: array<u32>;
// The visible receivers in the light's view, per slice of the view and grid cell
// (volumes/grid.wgsl).
@group(2) @binding(5) var<storage, read_write> grid: array<atomic<u32>>;
// 0: casters counted z-pass, 1: casters kept, 2, 3: fill (volumes/fill.rs), 4: intervals
// drawn, 5, 6: edges and triangles of the intervals past each caster's first
// (`within_room`), 7: receiver points listed (volumes/grid.wgsl), 8: casters handed to
// workgroups, 9: casters kept whole past the budget (volumes/big_casters.wgsl), 10: fan
// caps (`keep_caster`).
// Keep COUNTERS in sync with volumes/scene.rs.
const COUNTERS: u32 = 11u;
@group(2) @binding(6) var<storage, read_write> counters: array<atomic<u32>, COUNTERS>;
// Per instance, the outcome code (the `casters` overlay).
@group(2) @binding(7) var<storage, read_write> outcomes: array<u32>;
// The camera's visible surface: object id + 1 (0: sky) and world position (view/targets.rs).
@group(2) @binding(8) var surface_ids: texture_2d<u32>;
@group(2) @binding(9) var surface_positions: texture_2d<f32>;

// A point in the light's frame: across (x, y) and depth past the scene's nearest (z).
fn in_light(p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        dot(p, volume.right.xyz) - volume.right.w,
        dot(p, volume.up.xyz) - volume.up.w,
        dot(p, volume.travel.xyz) - volume.travel.w,
    );
}

// A caster's volume lies in its box's column across the light, from the box's nearest depth
// on, and within that column under its footprint (its mesh's box turned with it,
// volumes/footprint.wgsl). Per slice, the visible receiver points under the footprint that
// are no nearer than the box give
// an occupied depth interval (culling, options.y bit 0: no interval, no volume); with
// clamping (bit 1) the volume is drawn only across the union of those intervals, merged to
// at most MAX_INTERVALS, else from the caster to past the scene. Bit 2: only the cells whose
// centres the footprint covers (discrete clamping's image-precision test, each cell's
// depths whole), else every cell it touches, whose points are tested one by one against the
// caster's box (volumes/grid.wgsl `gather_receivers`). An interval [a, b] becomes extrusions
// from a past the box's far side to b past its near side, so every vertex's volume covers
// it. A caster whose cells would take more loop iterations than the frame allows a lane is
// left to workgroups of its own (volumes/big_casters.wgsl).
// One workgroup culls each caster: `cull_lanes()` of its lanes share the caster's cells and
// their points (`gather_footprint`), merge what they gather in the workgroup, and the first
// finishes the caster.
@compute @workgroup_size(CULL_LANES)
fn cull_casters(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let ci = group.x + group.y * 65535u;
    let real = ci < volume.counts.z;
    clear_merged(lane, CULL_LANES);
    workgroupBarrier();
    if (real && lane < cull_lanes() && gathers(ci)) {
        gather_lane(ci, vec2<u32>(lane, cull_lanes()));
    }
    workgroupBarrier();
    if (!real || lane != 0u) {
        return;
    }
    if (from_point()) {
        cull_from_point(ci);
        return;
    }
    let s = sun_caster(ci);
    var found: array<vec2<f32>, MAX_SLICES>;
    var bins: array<u32, MAX_SLICES>;
    var n = 0u;
    if (given()) {
        n = given_intervals(ci, s.lo.z, &found);
    } else if (gathers(ci)) {
        if (read_merged(&found, &bins)) {
            n = compact_found(s.lo.z, s.pad, &found, &bins);
        } else if (defer_caster(ci)) {
            return;
        } else {
            n = TOO_MANY_CELLS;
        }
    }
    finish_sun_caster(ci, s, n, &found);
}

// Lanes of a `cull_casters` workgroup.
const CULL_LANES: u32 = 32u;

// How many of them share a caster's cells this frame (`VolumeFrame::options.z`).
fn cull_lanes() -> u32 {
    return clamp(volume.options.z, 1u, CULL_LANES);
}

// Whether the cull gathers caster `ci`'s receivers (`gathers_for`).
fn gathers(ci: u32) -> bool {
    return gathers_for(from_point() && point_caster(ci).whole);
}

// Whether the cull gathers a caster's receivers: to cull or clamp it, where the CPU has not
// given its intervals and its volume is not `whole` anyway (a box too close to a point light).
fn gathers_for(whole: bool) -> bool {
    return !given() && (culling() || clamping()) && !whole;
}

fn culling() -> bool {
    return (volume.options.y & 1u) != 0u;
}

fn clamping() -> bool {
    return (volume.options.y & 2u) != 0u;
}

fn centres() -> bool {
    return (volume.options.y & 4u) != 0u;
}

// A caster's world box in the sun's frame (lo, hi, rounded outwards by `pad`) and the grid
// cells under it, first and last (with `centres`, those whose centre it holds).
struct SunCaster {
    lo: vec3<f32>,
    hi: vec3<f32>,
    pad: f32,
    first: vec2<i32>,
    last: vec2<i32>,
}

fn sun_caster(ci: u32) -> SunCaster {
    let b = bounds[casters[ci].instance];
    var s: SunCaster;
    s.lo = vec3<f32>(1e30);
    s.hi = vec3<f32>(-1e30);
    for (var k = 0u; k < 8u; k++) {
        let p = in_light(box_corner(b, k));
        s.lo = min(s.lo, p);
        s.hi = max(s.hi, p);
    }
    // Rounded outwards by a millimetre and a bit of the box.
    s.pad = 1e-3 + length(s.hi - s.lo) * 1e-5;
    let top = grid_last();
    s.first = clamp(cell_of(s.lo.xy - s.pad), vec2<i32>(0), top);
    s.last = clamp(cell_of(s.hi.xy + s.pad), vec2<i32>(0), top);
    if (centres()) {
        // Cells whose centre lies in the box.
        s.first = clamp(vec2<i32>(ceil(s.lo.xy / volume.cell.x - 0.5)), vec2<i32>(0), top + 1);
        s.last = clamp(vec2<i32>(floor(s.hi.xy / volume.cell.x - 0.5)), vec2<i32>(-1), top);
    }
    return s;
}

// Caster `ci`'s volume from its `n` occupied depth intervals in `found` (TOO_MANY_CELLS:
// unknown, the whole volume): culled, clamped to them, or whole, as the options ask.
fn finish_sun_caster(
    ci: u32,
    s: SunCaster,
    occupied: u32,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
) {
    var n = occupied;
    if (n == TOO_MANY_CELLS) {
        atomicAdd(&counters[9], 1u);
    }
    if (n == TOO_MANY_CELLS || (!culling() && !clamping())) {
        // The whole volume, across every strip of the picture: a partial gather may have left
        // its pieces' slices behind (the shadow of a roof with the camera under it, lost
        // where the gather ran past its budget).
        (*found)[0] = vec2<f32>(s.lo.z, 1e30);
        piece_slices[0] = ALL_SLICES;
        n = 1u;
    }
    let keep = !culling() || n > 0u;
    var count = 0u;
    if (keep && clamping() && n > 0u) {
        count = merged_intervals(ci, found, n, array<vec3<f32>, 3>(s.lo, s.hi, vec3<f32>(s.pad)));
        count = within_room(ci, count);
    } else if (keep) {
        count = whole_or_a_centimetre(ci, clamping());
    }
    var reach = 0.0;
    for (var r = 0u; r < count; r++) {
        reach = max(reach, intervals[ci * MAX_INTERVALS + r].y);
    }
    let z_pass = counts_z_pass(s.lo - s.pad, s.hi + s.pad, reach);
    keep_caster(ci, count, z_pass);
}

// Gathers into `found` and `bins` the depths of the visible receiver points under caster
// `ci`'s footprint (volumes/footprint.wgsl) in its cells (`s`), no nearer than the caster
// (with its padding to spare): the cells the footprint meets, or with `centres` those whose
// centre it holds; shared among `lanes.y` lanes as `gather_footprint` shares them, this
// one `lanes.x`. False once past the budget of loop iterations.
fn gather_under(
    ci: u32,
    s: SunCaster,
    lanes: vec2<u32>,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    bins: ptr<function, array<u32, MAX_SLICES>>,
) -> bool {
    let c = casters[ci];
    var q: array<vec2<f32>, 8>;
    for (var k = 0u; k < 8u; k++) {
        q[k] = in_light(oriented_corner(c, k)).xy;
    }
    let half = select(0.5 * volume.cell.x, 0.0, centres());
    var steps = 0;
    // Discrete clamping keeps Lloyd's image precision: cells only.
    var box = caster_box(ci, !centres(), &steps);
    return gather_footprint(
        &q,
        &box,
        true,
        array<vec4<i32>, 3>(
            vec4<i32>(s.first, s.last),
            vec4<i32>(vec2<i32>(0), grid_last()),
            vec4<i32>(vec2<i32>(lanes), lane_budget(lanes), 0),
        ),
        vec3<f32>(volume.cell.x, half, s.pad),
        vec2<f32>(s.lo.z, s.pad),
        found,
        bins,
        &steps,
    );
}

// Exact clamping (options.y bit 3, volumes/exact.rs): the CPU has written each caster's
// occupied depths into its interval slots, ended by one whose end is negative.
fn given() -> bool {
    return (volume.options.y & 8u) != 0u;
}

// Caster `ci`'s occupied depths as exact clamping gives them, into `found`, each starting no
// nearer than `nearest` (the caster's). Returns how many.
fn given_intervals(ci: u32, nearest: f32, found: ptr<function, array<vec2<f32>, MAX_SLICES>>) -> u32 {
    var n = 0u;
    for (var r = 0u; r < MAX_INTERVALS; r++) {
        let depths = intervals[ci * MAX_INTERVALS + r];
        if (depths.y < 0.0) {
            break;
        }
        (*found)[n] = vec2<f32>(max(depths.x, nearest), depths.y);
        piece_slices[n] = ALL_SLICES;
        n++;
    }
    return n;
}

// Not clamped, or clamped without culling where no receiver lies under the box: the whole
// volume, or a centimetre of it. Returns the interval count, 1.
fn whole_or_a_centimetre(ci: u32, clamping: bool) -> u32 {
    let whole = vec2<f32>(0.0, volume.to_light.w);
    intervals[ci * MAX_INTERVALS] = select(whole, vec2<f32>(0.0, 1e-2), clamping);
    strips[ci * MAX_INTERVALS] = strips_word(ALL_SLICES);
    return 1u;
}

// Records caster `ci`'s outcome: `count` intervals drawn (0: culled), counted z-pass or not.
fn keep_caster(ci: u32, count: u32, z_pass: bool) {
    let c = casters[ci];
    kept[ci] = count | select(0u, Z_PASS, z_pass && count > 0u)
        | select(0u, PAST_FAR, past_far(bounds[c.instance]));
    outcomes[c.instance] = select(volume.counts.w, OUTCOME_RENDERED, count > 0u);
    if (count > 0u) {
        atomicAdd(&counters[1], 1u);
        atomicAdd(&counters[4], count);
        if (z_pass) {
            atomicAdd(&counters[0], 1u);
        }
    }
    if (fan_capped(c)) {
        atomicAdd(&counters[10], fan_caps(ci, count));
    }
}

// The fan caps of caster `ci`'s `count` intervals (volumes/records.wgsl `append_fans`), each
// two triangles fewer than its records: the two edges at its corner draw nothing.
fn fan_caps(ci: u32, count: u32) -> u32 {
    var caps = 0u;
    for (var r = 0u; r < count; r++) {
        let span = intervals[ci * MAX_INTERVALS + r];
        caps += select(0u, 1u, span.x != 0.0) + select(0u, 1u, needs_end_cap(ci, span.y));
    }
    return caps;
}

// The record buffers hold one interval of every caster and as many again: a caster's
// intervals past its first take their room from that budget (counters 5 and 6: edges and
// triangles taken). Where the room has run out, its intervals become one across them all.
fn within_room(ci: u32, count: u32) -> u32 {
    if (count <= 1u) {
        return count;
    }
    let c = casters[ci];
    let next = ci + 1u < volume.counts.z;
    let edges = select(volume.counts.x, casters[ci + 1u].edge_start, next) - c.edge_start;
    let triangles = select(volume.counts.y, casters[ci + 1u].triangle_start, next)
        - c.triangle_start;
    let extra = count - 1u;
    let edges_before = atomicAdd(&counters[5], extra * edges);
    let triangles_before = atomicAdd(&counters[6], extra * triangles);
    if (edges_before + extra * edges <= volume.counts.x
        && triangles_before + extra * triangles <= volume.counts.y) {
        return count;
    }
    let first = ci * MAX_INTERVALS;
    intervals[first] = vec2<f32>(intervals[first].x, intervals[first + extra].y);
    strips[first] = strips_word(ALL_SLICES);
    return 1u;
}

// A point of the light's frame (as `in_light` gives it) in world space.
fn from_light(p: vec3<f32>) -> vec3<f32> {
    return volume.right.xyz * (p.x + volume.right.w) + volume.up.xyz * (p.y + volume.up.w)
        + volume.travel.xyz * (p.z + volume.travel.w);
}

// The pixels of the picture's box around the caster's box column (`lo`, `hi` across the
// light) between depths `near` and `far` along it; a column that reaches behind the eye
// counts as the whole picture.
fn column_pixels(lo: vec2<f32>, hi: vec2<f32>, near: f32, far: f32) -> f32 {
    var bounds = vec4<f32>(1e30, 1e30, -1e30, -1e30);
    for (var k = 0u; k < 8u; k++) {
        let p = corner(vec3<f32>(lo, near), vec3<f32>(hi, far), k);
        if (!grow_picture_box(from_light(p), &bounds)) {
            return whole_picture_pixels();
        }
    }
    return picture_box_pixels(bounds);
}

// Grows `bounds` (NDC: min xy, max xy) by world point `p` in the picture, clamped to it;
// false for a point behind the eye.
fn grow_picture_box(p: vec3<f32>, bounds: ptr<function, vec4<f32>>) -> bool {
    let clip = frame.clip_from_world * vec4<f32>(p, 1.0);
    if (clip.w <= 0.0) {
        return false;
    }
    let ndc = clamp(clip.xy / clip.w, vec2<f32>(-1.0), vec2<f32>(1.0));
    *bounds = vec4<f32>(min((*bounds).xy, ndc), max((*bounds).zw, ndc));
    return true;
}

fn whole_picture_pixels() -> f32 {
    let size = vec2<f32>(textureDimensions(surface_ids));
    return size.x * size.y;
}

// The pixels of a picture box grown by `grow_picture_box`.
fn picture_box_pixels(bounds: vec4<f32>) -> f32 {
    let extent = (bounds.zw - bounds.xy) * 0.5 * vec2<f32>(textureDimensions(surface_ids));
    return extent.x * extent.y;
}

// Lloyd's V for caster `ci`: the vertices a new interval adds, 2C + 2S, with S the
// silhouette's quads (about twice the square root of the triangles, a closed mesh's
// silhouette loop) and C a cap's: the lit half of its triangles, or a fan's triangle per
// silhouette edge (`fan_capped`).
fn new_interval_vertices(ci: u32) -> f32 {
    let end = select(volume.counts.y, casters[ci + 1u].triangle_start, ci + 1u < volume.counts.z);
    let triangles = f32(end - casters[ci].triangle_start);
    let edges = 2.0 * sqrt(triangles);
    let cap = select(1.5 * triangles, 3.0 * edges, fan_capped(casters[ci]));
    return 2.0 * cap + 2.0 * 4.0 * edges;
}

// Sorts the `n` occupied depth intervals in `found` by their start and merges those that
// overlap or touch, then those whose gap costs fewer pixels than a new interval would: the
// two caps that would bound it and its vertices at the calibrated pixels per vertex (Lloyd's
// V > R rule; areas are picture boxes), then the ones with the smallest gaps until at most
// MAX_INTERVALS are left, and writes them as extrusion distances for caster `ci` (`box`: for
// the sun, the caster's box in the light's frame, lo and hi, and its padding; for a point
// light, its box in the world and its padding, nearest and farthest distance from the light,
// xyz). Returns how many.
fn merged_intervals(
    ci: u32,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    n: u32,
    box: array<vec3<f32>, 3>,
) -> u32 {
    let pad = box[2].x;
    for (var i = 1u; i < n; i++) {
        let item = (*found)[i];
        let slices = piece_slices[i];
        var j = i;
        while (j > 0u && (*found)[j - 1u].x > item.x) {
            (*found)[j] = (*found)[j - 1u];
            piece_slices[j] = piece_slices[j - 1u];
            j--;
        }
        (*found)[j] = item;
        piece_slices[j] = slices;
    }
    var m = 0u;
    for (var i = 0u; i < n; i++) {
        let next = (*found)[i];
        var merge = m > 0u && next.x <= (*found)[m - 1u].y + 2.0 * pad;
        if (m > 0u && !merge) {
            let end = (*found)[m - 1u].y;
            let gap = interval_pixels(box, end, next.x);
            let caps = interval_pixels(box, end, end) + interval_pixels(box, next.x, next.x);
            merge = gap <= caps + new_interval_vertices(ci) * volume.cell.y;
        }
        if (merge) {
            (*found)[m - 1u].y = max((*found)[m - 1u].y, next.y);
            piece_slices[m - 1u] |= piece_slices[i];
        } else {
            (*found)[m] = next;
            piece_slices[m] = piece_slices[i];
            m++;
        }
    }
    while (m > MAX_INTERVALS) {
        var smallest = 0u;
        for (var i = 1u; i + 1u < m; i++) {
            if ((*found)[i + 1u].x - (*found)[i].y < (*found)[smallest + 1u].x - (*found)[smallest].y) {
                smallest = i;
            }
        }
        (*found)[smallest].y = (*found)[smallest + 1u].y;
        piece_slices[smallest] |= piece_slices[smallest + 1u];
        for (var i = smallest + 1u; i + 1u < m; i++) {
            (*found)[i] = (*found)[i + 1u];
            piece_slices[i] = piece_slices[i + 1u];
        }
        m--;
    }
    for (var i = 0u; i < m; i++) {
        intervals[ci * MAX_INTERVALS + i] = extrusions((*found)[i], box);
        strips[ci * MAX_INTERVALS + i] = strips_word(piece_slices[i]);
    }
    return m;
}

// Every slice of the view.
const ALL_SLICES: u32 = 0xffffffffu;

// The strips of the picture an interval is drawn across, from its slices' bits: the first
// (bits 0 to 7) and the last (bits 8 to 15) of them (volumes/strips_clipped.wgsl); all of
// them with the strips off (options.y bit 4).
fn strips_word(slices: u32) -> u32 {
    let some = select(slices, ALL_SLICES, slices == 0u || (volume.options.y & 16u) != 0u);
    return firstTrailingBit(some) | (firstLeadingBit(some) << 8u);
}

// The extrusion distances that cover the depths `depths` (along the sun, or from the point
// light) from every vertex of a caster's `box` (as `merged_intervals` takes it): from the
// farthest vertex's start to past the nearest vertex's end; for a point light, the end moved
// out by the cosine of the box's angular radius, as its flat caps sag towards the light.
fn extrusions(depths: vec2<f32>, box: array<vec3<f32>, 3>) -> vec2<f32> {
    var start: f32;
    var end: f32;
    if (from_point()) {
        let pad = box[2].x;
        let nearest = box[2].y;
        let farthest = box[2].z;
        let centre = 0.5 * (box[0] + box[1]);
        let sine = 0.5 * length(box[1] - box[0]) / max(length(centre - volume.point.xyz), 1e-6);
        let cosine = sqrt(max(1.0 - sine * sine, 0.5));
        start = max(depths.x - farthest - pad, 0.0);
        end = (depths.y + 2.0 * pad + 1e-2) / cosine - nearest;
    } else {
        let pad = box[2].x;
        start = max(depths.x - box[1].z - pad, 0.0);
        end = depths.y - box[0].z + 2.0 * pad + 1e-2;
    }
    return vec2<f32>(select(start, 0.0, start < 1e-2), min(end, volume.to_light.w));
}

// The pixels of the picture's box around where a caster's volume lies between depths `near`
// and `far`: the sun's column (`column_pixels`), or for a point light the caster's box
// (`box`: its world corners and reach, as `merged_intervals` takes it) pushed out from the
// light to those distances.
fn interval_pixels(box: array<vec3<f32>, 3>, near: f32, far: f32) -> f32 {
    if (!from_point()) {
        return column_pixels(box[0].xy, box[1].xy, near, far);
    }
    let light = volume.point.xyz;
    var bounds = vec4<f32>(1e30, 1e30, -1e30, -1e30);
    for (var k = 0u; k < 16u; k++) {
        let d = normalize(corner(box[0], box[1], k % 8u) - light);
        if (!grow_picture_box(light + d * select(near, far, k >= 8u), &bounds)) {
            return whole_picture_pixels();
        }
    }
    return picture_box_pixels(bounds);
}

// Whether a box reaches past the camera's far plane.
fn past_far(b: InstanceBounds) -> bool {
    var far = -1e30;
    for (var k = 0u; k < 8u; k++) {
        far = max(far, (frame.clip_from_world * vec4<f32>(box_corner(b, k), 1.0)).w);
    }
    return far >= volume.slicing.w * 0.999;
}

// Whether the stencil may count the volume of a caster whose box spans `lo` to `hi` in the
// light's frame z-pass: DOOM 3's test, as boxes. The volume lies in the box's column across
// the light, from its near side to `reach` past its far side; z-pass counts from the near
// plane, so it is right wherever the camera's near rectangle cannot lie in that column.
fn counts_z_pass(lo: vec3<f32>, hi: vec3<f32>, reach: f32) -> bool {
    if (volume.options.w != 0u) {
        return volume.options.w == 1u;
    }
    let near_lo = volume.near_lo.xyz;
    let near_hi = volume.near_hi.xyz;
    return any(near_hi.xy < lo.xy) || any(near_lo.xy > hi.xy) || near_hi.z < lo.z
        || near_lo.z > hi.z + reach;
}
