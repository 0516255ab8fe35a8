// Per-layer triangle culling (Rákos 19.5, 19.6) before the maps are drawn: each caster's
// triangles against each view of its slot (a view, or a multiview group), kept where any of
// them may see it: not wholly outside one plane of the view's frustum, and, for a closed
// mesh, facing the light (a closed mesh's back faces are never the nearest surface). Kept
// triangles are listed per slot as records that the culled draws read (layered/culled.wgsl).
// Keep in sync with layered/cull.rs.
#import view/common.wgsl

struct Job {
    first_index: u32,
    triangles: u32,
    base_vertex: i32,
    instance: u32,
    slot: u32,
    // Triangles of the jobs before this one.
    offset: u32,
    // Bit 0: the mesh is closed (back faces may go).
    flags: u32,
    pad: u32,
}

struct Slot {
    first_view: u32,
    views: u32,
    // Where its records start.
    base: u32,
    pad: u32,
}

struct Params {
    // x: jobs; y: triangles over all jobs; z: bit 0 frustum culling, bit 1 back faces; w:
    // workgroups along x.
    counts: vec4<u32>,
}

@group(1) @binding(0) var<storage, read> jobs: array<Job>;
@group(1) @binding(1) var<storage, read> slots: array<Slot>;
@group(1) @binding(2) var<storage, read> indices: array<u32>;
@group(1) @binding(3) var<storage, read> vertices: array<f32>;
@group(1) @binding(4) var<storage, read_write> records: array<vec4<u32>>;
// Per slot an indirect draw: vertex count (3 per kept triangle), instances, first vertex,
// first instance.
@group(1) @binding(5) var<storage, read_write> draws: array<atomic<u32>>;
@group(1) @binding(6) var<uniform> params: Params;

const CULL_FRUSTUM: u32 = 1u;
const CULL_BACK_FACES: u32 = 2u;
const JOB_CLOSED: u32 = 1u;

fn vertex(i: u32) -> vec3<f32> {
    return vec3<f32>(vertices[i * 6u], vertices[i * 6u + 1u], vertices[i * 6u + 2u]);
}

// The job whose triangles hold triangle `t` of all jobs.
fn job_of(t: u32) -> u32 {
    var lo = 0u;
    var hi = params.counts.x;
    while (hi - lo > 1u) {
        let mid = (lo + hi) / 2u;
        if (jobs[mid].offset <= t) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// Whether view `v` may see the triangle at world `a`, `b`, `c`.
fn seen(v: u32, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, closed: bool) -> bool {
    let view = shadow_views[v];
    let p = array<vec4<f32>, 3>(light_clip(view, a), light_clip(view, b), light_clip(view, c));
    if ((params.counts.z & CULL_FRUSTUM) != 0u) {
        // Wholly outside one plane: left, right, bottom, top, near, far.
        var out = vec4<u32>(0u);
        var out_z = vec2<u32>(0u);
        for (var k = 0u; k < 3u; k++) {
            let q = p[k];
            out += vec4<u32>(
                select(0u, 1u, q.x < -q.w),
                select(0u, 1u, q.x > q.w),
                select(0u, 1u, q.y < -q.w),
                select(0u, 1u, q.y > q.w),
            );
            out_z += vec2<u32>(select(0u, 1u, q.z < 0.0), select(0u, 1u, q.z > q.w));
        }
        if (any(out == vec4<u32>(3u)) || any(out_z == vec2<u32>(3u))) {
            return false;
        }
    }
    if ((params.counts.z & CULL_BACK_FACES) != 0u && closed && p[0].w > 0.0 && p[1].w > 0.0 && p[2].w > 0.0) {
        // Counter-clockwise in the view's picture faces the light; none and clockwise do not.
        let s0 = p[0].xy / p[0].w;
        let s1 = p[1].xy / p[1].w;
        let s2 = p[2].xy / p[2].w;
        let e1 = s1 - s0;
        let e2 = s2 - s0;
        if (e1.x * e2.y - e1.y * e2.x <= 0.0) {
            return false;
        }
    }
    return true;
}

@compute @workgroup_size(64)
fn cull_triangles(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let t = (group.y * params.counts.w + group.x) * 64u + lane;
    if (t >= params.counts.y) {
        return;
    }
    let job = jobs[job_of(t)];
    let first = job.first_index + 3u * (t - job.offset);
    let i = vec3<u32>(
        u32(i32(indices[first]) + job.base_vertex),
        u32(i32(indices[first + 1u]) + job.base_vertex),
        u32(i32(indices[first + 2u]) + job.base_vertex),
    );
    let a = world_position(job.instance, vertex(i.x));
    let b = world_position(job.instance, vertex(i.y));
    let c = world_position(job.instance, vertex(i.z));
    let slot = slots[job.slot];
    let closed = (job.flags & JOB_CLOSED) != 0u;
    var keep = false;
    for (var v = 0u; v < slot.views && !keep; v++) {
        keep = seen(slot.first_view + v, a, b, c, closed);
    }
    if (!keep) {
        return;
    }
    let at = atomicAdd(&draws[job.slot * 4u], 3u) / 3u;
    records[slot.base + at] = vec4<u32>(i, job.instance | (slot.first_view << 24u));
}
