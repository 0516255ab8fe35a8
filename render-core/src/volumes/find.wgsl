// Stencil shadow volumes of the sun, first step (volumes/mod.rs): per caster, the edges whose
// quad is extruded (the silhouette, from the edge adjacency of volumes/edges.rs) and the
// triangles that cap the volume, appended as records that the draw passes
// (volumes/draw.wgsl) turn into triangles.
#import volumes/common.wgsl
#import culling/codes.wgsl

// vertex_count, instance_count, first_vertex, first_instance; quads then caps.
struct DrawArgs {
    vertex_count: u32,
    instance_count: atomic<u32>,
    first_vertex: u32,
    first_instance: u32,
}

@group(2) @binding(0) var<storage, read_write> quads: array<vec2<u32>>;
@group(2) @binding(1) var<storage, read_write> caps: array<vec2<u32>>;
// z-fail quads and caps, z-pass quads and caps (volumes/pipelines.rs DRAWS).
@group(2) @binding(2) var<storage, read_write> draws: array<DrawArgs, 4>;
// Per caster, how far its volume reaches along the light (metres, as bits; 0: not drawn),
// with Z_PASS set where the stencil counts it z-pass.
// Z-fail records fill `quads` and `caps` from the start, z-pass records from the end.
@group(2) @binding(3) var<storage, read_write> kept: array<u32>;
// The visible receivers in the light's view: per grid cell, the deepest visible receiver
// point (its depth past the scene's nearest, plus 1, as bits; 0: none).
@group(2) @binding(4) var<storage, read_write> grid: array<atomic<u32>>;
// 0: casters counted z-pass, 1: casters kept, 2, 3: fill (volumes/fill.rs).
@group(2) @binding(5) var<storage, read_write> counters: array<atomic<u32>, 4>;
// Per instance, the outcome code (the `casters` overlay).
@group(2) @binding(6) var<storage, read_write> outcomes: array<u32>;
// The camera's visible surface: object id + 1 (0: sky) and world position (view/targets.rs).
@group(2) @binding(7) var surface_ids: texture_2d<u32>;
@group(2) @binding(8) var surface_positions: texture_2d<f32>;

// A point in the light's frame: across (x, y) and depth past the scene's nearest (z).
fn in_light(p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        dot(p, volume.right.xyz) - volume.right.w,
        dot(p, volume.up.xyz) - volume.up.w,
        dot(p, volume.travel.xyz) - volume.travel.w,
    );
}

fn cell_of(p: vec2<f32>) -> vec2<i32> {
    return vec2<i32>(floor(p / volume.cell.x));
}

// Lloyd's potential shadow receivers, exactly: every visible receiver pixel marks the grid
// cell under it with its depth along the light.
@compute @workgroup_size(8, 8)
fn mark_receivers(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(surface_ids);
    if (any(id.xy >= size)) {
        return;
    }
    let object = textureLoad(surface_ids, vec2<i32>(id.xy), 0).x;
    if (object == 0u || (bounds[object - 1u].flags & FLAG_RECEIVER) == 0u) {
        return;
    }
    let p = in_light(textureLoad(surface_positions, vec2<i32>(id.xy), 0).xyz);
    let side = i32(volume.options.z);
    let cell = clamp(cell_of(p.xy), vec2<i32>(0), vec2<i32>(side - 1));
    atomicMax(&grid[u32(cell.y * side + cell.x)], bitcast<u32>(max(p.z, 0.0) + 1.0));
}

// The cells a caster's box covers in the light's view, at most this many before its volume
// is kept whole.
const MAX_CELLS: i32 = 4096;

// A caster's volume (its box across the light, from its nearest depth on) can hold a visible
// receiver point only where the grid marks one under it, no nearer than the box: else it is
// not drawn (culling, options.y bit 0). With clamping (bit 1) it reaches only to the deepest
// such point. Conservative: the box holds the caster, the volume lies inside its box's
// extrusion, every vertex lies at least as deep as the box's near side, and each cell keeps
// the deepest point in it. Writes the volume's reach along the light (metres, as bits).
@compute @workgroup_size(64)
fn cull_casters(@builtin(global_invocation_id) id: vec3<u32>) {
    let ci = id.x + id.y * 65535u * 64u;
    if (ci >= volume.counts.z) {
        return;
    }
    let c = casters[ci];
    let culling = (volume.options.y & 1u) != 0u;
    let clamping = (volume.options.y & 2u) != 0u;
    let b = bounds[c.instance];
    var lo = vec3<f32>(1e30);
    var hi = vec3<f32>(-1e30);
    for (var k = 0u; k < 8u; k++) {
        let corner = vec3<f32>(
            select(b.min.x, b.max.x, (k & 1u) != 0u),
            select(b.min.y, b.max.y, (k & 2u) != 0u),
            select(b.min.z, b.max.z, (k & 4u) != 0u),
        );
        let p = in_light(corner);
        lo = min(lo, p);
        hi = max(hi, p);
    }
    // Rounded outwards by a millimetre and a bit of the box.
    let pad = 1e-3 + length(hi - lo) * 1e-5;
    let side = i32(volume.options.z);
    let first = clamp(cell_of(lo.xy - pad), vec2<i32>(0), vec2<i32>(side - 1));
    let last = clamp(cell_of(hi.xy + pad), vec2<i32>(0), vec2<i32>(side - 1));
    let span = last - first + 1;
    var deepest = -1.0;
    if (span.x * span.y > MAX_CELLS) {
        deepest = 1e30;
    } else if (culling || clamping) {
        for (var y = first.y; y <= last.y; y++) {
            for (var x = first.x; x <= last.x; x++) {
                let bits = atomicLoad(&grid[u32(y * side + x)]);
                if (bits != 0u) {
                    deepest = max(deepest, bitcast<f32>(bits) - 1.0);
                }
            }
        }
    }
    let keep = !culling || deepest + pad >= max(lo.z, 0.0);
    var reach = volume.to_light.w;
    if (clamping && deepest < 1e29) {
        reach = min(reach, max(deepest - lo.z, 0.0) + 2.0 * pad + 1e-2);
    }
    let z_pass = counts_z_pass(lo - pad, hi + pad, reach);
    kept[ci] = select(0u, bitcast<u32>(reach) | select(0u, Z_PASS, z_pass), keep);
    outcomes[c.instance] = select(volume.counts.w, OUTCOME_RENDERED, keep);
    if (keep) {
        atomicAdd(&counters[1], 1u);
        if (z_pass) {
            atomicAdd(&counters[0], 1u);
        }
    }
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
    let apart = any(near_hi.xy < lo.xy) || any(near_lo.xy > hi.xy)
        || near_hi.z < lo.z || near_lo.z > hi.z + reach;
    return apart;
}

fn z_pass(caster: u32) -> bool {
    return (kept[caster] & Z_PASS) != 0u;
}

fn append_quad(caster: u32, edge: u32, reversed: bool) {
    let record = vec2<u32>(caster, edge | select(0u, REVERSED, reversed));
    if (z_pass(caster)) {
        quads[arrayLength(&quads) - 1u - atomicAdd(&draws[2].instance_count, 1u)] = record;
    } else {
        quads[atomicAdd(&draws[0].instance_count, 1u)] = record;
    }
}

// One edge of one caster: its quad, as many times as its multiplicity.
@compute @workgroup_size(64)
fn find_silhouettes(@builtin(global_invocation_id) id: vec3<u32>) {
    let item = id.x + id.y * 65535u * 64u;
    if (item >= volume.counts.x) {
        return;
    }
    let ci = caster_of(item, false);
    if (kept[ci] == 0u) {
        return;
    }
    let c = casters[ci];
    let edge = c.first_edge + item - c.edge_start;
    let e = edges[edge];
    var m = face_sign(c, e.face);
    if (e.opposite != NO_FACE) {
        m -= face_sign(c, e.opposite);
    }
    for (var k = 0; k < abs(m); k++) {
        append_quad(ci, edge, m < 0);
    }
}

// One triangle of one caster: its caps when it casts.
@compute @workgroup_size(64)
fn find_caps(@builtin(global_invocation_id) id: vec3<u32>) {
    let item = id.x + id.y * 65535u * 64u;
    if (item >= volume.counts.y) {
        return;
    }
    let ci = caster_of(item, true);
    if (kept[ci] == 0u) {
        return;
    }
    let c = casters[ci];
    let t = item - c.triangle_start;
    let s = face_sign(c, t);
    if (s == 0) {
        return;
    }
    let record = vec2<u32>(ci, t | select(0u, REVERSED, s < 0));
    if (z_pass(ci)) {
        caps[arrayLength(&caps) - 1u - atomicAdd(&draws[3].instance_count, 1u)] = record;
    } else {
        caps[atomicAdd(&draws[1].instance_count, 1u)] = record;
    }
}

// Before the passes above: no records.
@compute @workgroup_size(1)
fn reset_draws() {
    for (var k = 0u; k < 4u; k++) {
        draws[k].vertex_count = 6u;
        atomicStore(&draws[k].instance_count, 0u);
        draws[k].first_vertex = 0u;
        draws[k].first_instance = 0u;
    }
    for (var k = 0u; k < 4u; k++) {
        atomicStore(&counters[k], 0u);
    }
}

