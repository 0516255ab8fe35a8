// Stencil shadow volumes, first step's last passes (volumes/find.wgsl, which binds the
// buffers): each caster's silhouette edges and casting triangles, per interval of its volume,
// appended as records of the indirect draws that volumes/draw.wgsl turns into triangles.

// vertex_count, instance_count, first_vertex, first_instance (common.wgsl `QUADS`...).
struct DrawArgs {
    vertex_count: atomic<u32>,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
}

fn z_pass(caster: u32) -> bool {
    return (kept[caster] & Z_PASS) != 0u;
}

// How many records draw `k` had before this new one, whose vertices it adds.
fn new_record(k: u32) -> u32 {
    return atomicAdd(&draws[k].vertex_count, record_vertices(k)) / record_vertices(k);
}

fn draw_of(kind: u32, caster: u32) -> u32 {
    return kind + select(0u, Z_PASS_DRAWS, z_pass(caster));
}

fn append_quad(caster: u32, interval: u32, edge: u32, reversed: bool) {
    let record = vec2<u32>(caster | (interval << INTERVAL_SHIFT), edge | select(0u, REVERSED, reversed));
    let k = draw_of(QUADS, caster);
    let n = new_record(k);
    quads[select(n, arrayLength(&quads) - 1u - n, k >= Z_PASS_DRAWS)] = record;
}

// The fan caps of a caster's silhouette edge `edge` over interval `interval`, where moved
// caps close it (`fan_capped`): a triangle from the caster's fan corner (`anchors`) to the
// edge, where the interval starts further on and where it ends. The corner is one of the
// silhouette's: the least vertex index of its edges, which every silhouette edge offers
// here and `vs_fan_cap` (volumes/draw.wgsl) reads once all have.
fn append_fans(caster: u32, interval: u32, edge: u32, reversed: bool) {
    let e = edges[edge];
    atomicMax(&anchors[caster], ~min(e.a, e.b));
    let span = intervals[caster * MAX_INTERVALS + interval];
    let record = vec2<u32>(caster | (interval << INTERVAL_SHIFT), edge | select(0u, REVERSED, reversed));
    if (span.x != 0.0) {
        append_fan(caster, vec2<u32>(record.x, record.y | AT_START));
    }
    if (needs_end_cap(caster, span.y)) {
        append_fan(caster, record);
    }
}

fn append_fan(caster: u32, record: vec2<u32>) {
    let k = draw_of(FAN_CAPS, caster);
    let n = new_record(k);
    fans[select(n, arrayLength(&fans) - 1u - n, k >= Z_PASS_DRAWS)] = record;
}

// Whether a volume that ends `end` from its caster needs a cap there: z-pass needs none at
// infinity, where a point light's cap lies at the far plane's depth, in front of no surface.
fn needs_end_cap(caster: u32, end: f32) -> bool {
    return !z_pass(caster) || !at_infinity(end);
}

// One edge of one caster: its quad per interval, as many times as its multiplicity, and its
// fan caps (`append_fans`).
@compute @workgroup_size(64)
fn find_silhouettes(@builtin(global_invocation_id) id: vec3<u32>) {
    let item = id.x + id.y * 65535u * 64u;
    if (item >= volume.counts.x) {
        return;
    }
    let ci = caster_of(item, false);
    let count = kept[ci] & COUNT_BITS;
    if (count == 0u) {
        return;
    }
    let c = casters[ci];
    let edge = c.first_edge + item - c.edge_start;
    let e = edges[edge];
    var m = face_sign(c, e.face);
    if (e.opposite != NO_FACE) {
        m -= face_sign(c, e.opposite);
    }
    for (var r = 0u; r < count; r++) {
        for (var k = 0; k < abs(m); k++) {
            append_quad(ci, r, edge, m < 0);
        }
        if (m != 0 && fan_capped(c)) {
            append_fans(ci, r, edge, m < 0);
        }
    }
}

fn append_cap(kind: u32, caster: u32, record: vec2<u32>) {
    let k = draw_of(kind, caster);
    caps[cap_slot(k, new_record(k))] = record;
}

// One triangle of one caster: its caps per interval when it casts. Where an interval starts
// at the caster, the triangle itself is its near cap (the past-far one where the caster
// reaches past the far plane), which z-pass needs only of a mesh that is not closed: a
// closed caster's own lit surface can end a camera ray outside its volume only where the
// volume ends (volumes/draw.wgsl). Where it starts further on, the triangle moved there;
// where it ends, the triangle moved there (`needs_end_cap`); a fan-capped caster's
// silhouette edges close it there instead (`append_fans`).
@compute @workgroup_size(64)
fn find_caps(@builtin(global_invocation_id) id: vec3<u32>) {
    let item = id.x + id.y * 65535u * 64u;
    if (item >= volume.counts.y) {
        return;
    }
    let ci = caster_of(item, true);
    let count = kept[ci] & COUNT_BITS;
    if (count == 0u) {
        return;
    }
    let c = casters[ci];
    let t = item - c.triangle_start;
    let s = face_sign(c, t);
    if (s == 0) {
        return;
    }
    for (var r = 0u; r < count; r++) {
        let record = vec2<u32>(ci | (r << INTERVAL_SHIFT), t | select(0u, REVERSED, s < 0));
        let span = intervals[ci * MAX_INTERVALS + r];
        let moved = !fan_capped(c);
        if (span.x != 0.0) {
            if (moved) {
                append_cap(MOVED_CAPS, ci, vec2<u32>(record.x, record.y | AT_START));
            }
        } else if (!z_pass(ci) || c.closed == 0u) {
            append_cap(CAPS_AT_CASTERS, ci, record);
        }
        if (moved && needs_end_cap(ci, span.y)) {
            append_cap(MOVED_CAPS, ci, record);
        }
    }
}

// Before the passes above: no records.
@compute @workgroup_size(1)
fn reset_draws() {
    for (var k = 0u; k < 2u * Z_PASS_DRAWS; k++) {
        atomicStore(&draws[k].vertex_count, 0u);
        draws[k].instance_count = 1u;
        draws[k].first_vertex = 0u;
        draws[k].first_instance = 0u;
    }
    for (var k = 0u; k < COUNTERS; k++) {
        atomicStore(&counters[k], 0u);
    }
    atomicStore(&big[0], 0u);
}
