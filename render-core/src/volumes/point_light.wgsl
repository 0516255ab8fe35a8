// Stencil shadow volumes of a point light (volumes/mod.rs), part of volumes/find.wgsl: the
// cube of receiver cells around the light, and the casters culled and clamped by it.

// A point light's receiver grid: the six faces of a cube around the light, each a tile of
// `face_cells()` cells a side in the grid, tiled three across and two down; a point's place
// across the light is its cell coordinate (the grid's cell size is 1) and its depth its
// distance from the light.
fn face_cells() -> f32 {
    return f32(volume.grid.w);
}

// Face `f` of the cube: the axis it faces along (x, y, z: 0, 1, 2) and its sign.
fn face_axis(f: u32) -> u32 {
    return f / 2u;
}

fn face_sign_of(f: u32) -> f32 {
    return select(1.0, -1.0, (f & 1u) != 0u);
}

// `d` (from the light) on face `f`: the two other axes over its distance along the face's
// own (xy, from -1 to 1 inside the face), and that distance (z).
fn on_face(d: vec3<f32>, f: u32) -> vec3<f32> {
    let k = face_axis(f);
    let m = d[k] * face_sign_of(f);
    let a = select(0u, 1u, k == 0u);
    let b = select(2u, 1u, k == 2u);
    return vec3<f32>(d[a] / m, d[b] / m, m);
}

// Where face `f`'s tile starts in the grid, in cells.
fn face_origin(f: u32) -> vec2<f32> {
    return vec2<f32>(f32(f % 3u), f32(f / 3u)) * face_cells();
}

// A point in a point light's frame (as `in_light` places points for the sun).
fn in_point_light(p: vec3<f32>) -> vec3<f32> {
    let d = p - volume.point.xyz;
    let s = abs(d);
    var k = 2u;
    if (s.x >= s.y && s.x >= s.z) {
        k = 0u;
    } else if (s.y >= s.z) {
        k = 1u;
    }
    let f = 2u * k + select(0u, 1u, d[k] < 0.0);
    let uv = clamp(on_face(d, f).xy, vec2<f32>(-1.0), vec2<f32>(1.0));
    let cell = face_origin(f) + min((uv * 0.5 + 0.5) * face_cells(), vec2<f32>(face_cells() - 0.5));
    return vec3<f32>(cell, length(d));
}

// `cull_casters` for a point light: the caster's box seen from the light covers, on each
// cube face it reaches, the box of its corners' places there (all of the face where the box
// crosses the face's plane); per slice of the view (planes through the eye that the light's
// rays cross in turn, as the sun's), the visible receiver points in those cells, as far from
// the light as the box's nearest point or further, give an occupied interval of distances,
// merged as the sun's are (`merged_intervals`). A volume goes to infinity unless clamped;
// clamped, its end caps, flat between points at an interval's end, are moved out by the
// cosine of the box's angular radius so that they sag no nearer than the interval's end,
// and a box too close to the light for that (over 45 degrees) keeps its whole volume. The
// workgroup's first lane finishes the caster here from what its lanes gathered
// (`gather_from_point`, merged in `merged`).
fn cull_from_point(ci: u32) {
    let p = point_caster(ci);
    var found: array<vec2<f32>, MAX_SLICES>;
    var bins: array<u32, MAX_SLICES>;
    var n = 0u;
    if (given() && !p.whole) {
        n = given_intervals(ci, p.nearest, &found);
    }
    if (gathers_for(p.whole)) {
        if (read_merged(&found, &bins)) {
            n = compact_found(p.nearest, p.pad, &found, &bins);
        } else if (defer_caster(ci)) {
            return;
        } else {
            n = TOO_MANY_CELLS;
        }
    }
    finish_point_caster(ci, p, n, &found);
}

// A caster's world box seen from a point light: its nearest and farthest distance from the
// light, its padding, whether it keeps its whole volume whatever lies under it, and per cube
// face the cells the box covers, first and last.
struct PointCaster {
    nearest: f32,
    farthest: f32,
    pad: f32,
    whole: bool,
    first: array<vec2<i32>, 6>,
    last: array<vec2<i32>, 6>,
}

fn point_caster(ci: u32) -> PointCaster {
    let b = bounds[casters[ci].instance];
    let light = volume.point.xyz;
    var p: PointCaster;
    p.nearest = length(clamp(light, b.min, b.max) - light);
    for (var k = 0u; k < 8u; k++) {
        p.farthest = max(p.farthest, length(box_corner(b, k) - light));
    }
    let centre = 0.5 * (b.min + b.max);
    let sine = 0.5 * length(b.max - b.min) / max(length(centre - light), 1e-6);
    p.pad = 1e-3 + p.farthest * 1e-5;
    p.whole = p.nearest <= p.pad || sine > 0.7071 || (!culling() && !clamping());
    for (var f = 0u; f < 6u && !p.whole; f++) {
        p.first[f] = vec2<i32>(1);
        p.last[f] = vec2<i32>(0);
        var lo = vec2<f32>(1e30);
        var hi = vec2<f32>(-1e30);
        var behind = 0u;
        for (var k = 0u; k < 8u; k++) {
            let q = on_face(box_corner(b, k) - light, f);
            if (q.z <= 1e-4) {
                behind++;
            } else {
                lo = min(lo, q.xy);
                hi = max(hi, q.xy);
            }
        }
        if (behind == 8u || outside_face(b, f)) {
            continue;
        }
        if (behind > 0u) {
            lo = vec2<f32>(-1.0);
            hi = vec2<f32>(1.0);
        }
        if (any(lo > vec2<f32>(1.0)) || any(hi < vec2<f32>(-1.0))) {
            continue;
        }
        let origin = face_origin(f);
        let top = vec2<i32>(origin) + vec2<i32>(i32(face_cells()) - 1);
        p.first[f] = clamp(cell_of(origin + (lo * 0.5 + 0.5) * face_cells() - 1e-3), vec2<i32>(origin), top);
        p.last[f] = clamp(cell_of(origin + (hi * 0.5 + 0.5) * face_cells() + 1e-3), vec2<i32>(origin), top);
    }
    return p;
}

// Caster `ci`'s volume from its `n` occupied intervals of distance in `found`
// (TOO_MANY_CELLS: unknown, the whole volume), as `finish_sun_caster` (volumes/find.wgsl).
fn finish_point_caster(
    ci: u32,
    p: PointCaster,
    n: u32,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
) {
    let b = bounds[casters[ci].instance];
    let whole = p.whole || n == TOO_MANY_CELLS;
    if (n == TOO_MANY_CELLS) {
        atomicAdd(&counters[9], 1u);
    }
    var count = 0u;
    if (whole) {
        count = whole_or_a_centimetre(ci, false);
    } else if (n > 0u && clamping()) {
        let reach = vec3<f32>(p.pad, p.nearest, p.farthest);
        count = merged_intervals(ci, found, n, array<vec3<f32>, 3>(b.min, b.max, reach));
        count = within_room(ci, count);
    } else if (n > 0u || !culling()) {
        count = whole_or_a_centimetre(ci, clamping() && n == 0u);
    }
    keep_caster(ci, count, counts_z_pass_from_point(b));
}

// Whether every direction from the light into box `b` lies outside face `f`'s pyramid (the
// directions whose largest component is the face's): all eight corners beyond one of its
// four planes. A box straddling the face's plane beside the light (a strut right under a
// lamp) sends nothing to that face, though its corners' places there reach over all of it.
fn outside_face(b: InstanceBounds, f: u32) -> bool {
    let k = face_axis(f);
    let a = select(0u, 1u, k == 0u);
    let c = select(2u, 1u, k == 2u);
    var beyond = vec4<bool>(true);
    for (var i = 0u; i < 8u; i++) {
        let d = box_corner(b, i) - volume.point.xyz;
        let m = d[k] * face_sign_of(f);
        beyond = beyond & (vec4<f32>(m - d[a], m + d[a], m - d[c], m + d[c]) < vec4<f32>(0.0));
    }
    return any(beyond);
}

// `gather_under` (volumes/find.wgsl) for a point light: the depths of the visible receiver
// points in the cells of each cube face (`p`) that the caster's footprint there meets (its
// mesh's box turned with it, projected from the light; where a corner lies behind the
// face's plane, every cell), no nearer than the caster; shared among `lanes.y` lanes as
// `gather_footprint` shares them, this one `lanes.x`. False once past the budget of loop
// iterations.
fn gather_from_point(
    ci: u32,
    p: PointCaster,
    lanes: vec2<u32>,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    bins: ptr<function, array<u32, MAX_SLICES>>,
) -> bool {
    let c = casters[ci];
    var steps = 0;
    var box = caster_box(ci, true, &steps);
    var within = true;
    for (var f = 0u; f < 6u && within; f++) {
        let origin = face_origin(f);
        var q: array<vec2<f32>, 8>;
        var in_front = true;
        for (var k = 0u; k < 8u; k++) {
            let on = on_face(oriented_corner(c, k) - volume.point.xyz, f);
            in_front = in_front && on.z > 1e-4;
            q[k] = origin + (on.xy * 0.5 + 0.5) * face_cells();
        }
        let top = vec2<i32>(origin) + vec2<i32>(i32(face_cells()) - 1);
        // A face's border cells also hold the points clamped onto it (`in_point_light`).
        within = gather_footprint(
            &q,
            &box,
            in_front,
            array<vec4<i32>, 3>(
                vec4<i32>(p.first[f], p.last[f]),
                vec4<i32>(vec2<i32>(origin), top),
                vec4<i32>(vec2<i32>(lanes), lane_budget(lanes), 0),
            ),
            vec3<f32>(1.0, 0.5, 1e-3),
            vec2<f32>(p.nearest, p.pad),
            found,
            bins,
            &steps,
        );
    }
    return within;
}

// DOOM 3's test for a point light: a volume can hold a point of the camera's near rectangle
// only where the segment from the light to that point crosses the caster, inside the pyramid
// from the light to the rectangle; a box wholly outside one of the pyramid's planes cannot.
fn counts_z_pass_from_point(b: InstanceBounds) -> bool {
    if (volume.options.w != 0u) {
        return volume.options.w == 1u;
    }
    for (var i = 0u; i < 5u; i++) {
        let plane = volume.near_planes[i];
        var outside = true;
        for (var k = 0u; k < 8u; k++) {
            outside = outside && dot(plane.xyz, box_corner(b, k)) + plane.w < 0.0;
        }
        if (outside) {
            return true;
        }
    }
    return false;
}
