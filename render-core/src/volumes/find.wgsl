// Stencil shadow volumes of the sun, first step (volumes/mod.rs): per caster, the edges whose
// quad is extruded (the silhouette, from the edge adjacency of volumes/edges.rs) and the
// triangles that cap the volume, appended as records that the draw passes
// (volumes/draw.wgsl) turn into triangles.
#import volumes/common.wgsl

// vertex_count, instance_count, first_vertex, first_instance; quads then caps.
struct DrawArgs {
    vertex_count: u32,
    instance_count: atomic<u32>,
    first_vertex: u32,
    first_instance: u32,
}

@group(2) @binding(0) var<storage, read_write> quads: array<vec2<u32>>;
@group(2) @binding(1) var<storage, read_write> caps: array<vec2<u32>>;
@group(2) @binding(2) var<storage, read_write> draws: array<DrawArgs, 2>;

fn append_quad(caster: u32, edge: u32, reversed: bool) {
    let slot = atomicAdd(&draws[0].instance_count, 1u);
    quads[slot] = vec2<u32>(caster, edge | select(0u, REVERSED, reversed));
}

// One edge of one caster: its quad, as many times as its multiplicity.
@compute @workgroup_size(64)
fn find_silhouettes(@builtin(global_invocation_id) id: vec3<u32>) {
    let item = id.x + id.y * 65535u * 64u;
    if (item >= volume.counts.x) {
        return;
    }
    let ci = caster_of(item, false);
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
    let c = casters[ci];
    let t = item - c.triangle_start;
    let s = face_sign(c, t);
    if (s == 0) {
        return;
    }
    let slot = atomicAdd(&draws[1].instance_count, 1u);
    caps[slot] = vec2<u32>(ci, t | select(0u, REVERSED, s < 0));
}

// Before the passes above: no records.
@compute @workgroup_size(1)
fn reset_draws() {
    draws[0].vertex_count = 6u;
    atomicStore(&draws[0].instance_count, 0u);
    draws[0].first_vertex = 0u;
    draws[0].first_instance = 0u;
    draws[1].vertex_count = 6u;
    atomicStore(&draws[1].instance_count, 0u);
    draws[1].first_vertex = 0u;
    draws[1].first_instance = 0u;
}

