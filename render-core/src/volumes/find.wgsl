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
@group(2) @binding(2) var<storage, read_write> draws: array<DrawArgs, 2>;
// Per caster, 1 when its volume is drawn.
@group(2) @binding(3) var<storage, read_write> kept: array<u32>;
// The visible receivers' boxes in light space (`LightBox`), and how many.
@group(2) @binding(4) var<storage, read_write> receivers: array<LightBox>;
// 0: visible receivers, 1: casters kept.
@group(2) @binding(5) var<storage, read_write> counters: array<atomic<u32>, 4>;
// Per instance, the outcome code (the `casters` overlay).
@group(2) @binding(6) var<storage, read_write> outcomes: array<u32>;
// Per instance, non-zero where a pixel shows it (view/visibility.wgsl).
@group(2) @binding(7) var<storage, read> visible: array<u32>;

// A box in the light's space: across the light (x, y) and along it (z, the depth the light
// travels); `lo.w`, `hi.w` unused.
struct LightBox {
    lo: vec4<f32>,
    hi: vec4<f32>,
}

// The light's frame: two directions across it and the one it travels.
fn light_axes() -> array<vec3<f32>, 3> {
    let travel = -volume.to_light.xyz;
    let helper = select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), abs(travel.y) > 0.9);
    let right = normalize(cross(helper, travel));
    let up = cross(travel, right);
    return array<vec3<f32>, 3>(right, up, travel);
}

fn light_box(b: InstanceBounds) -> LightBox {
    let axes = light_axes();
    var out = LightBox(vec4<f32>(1e30), vec4<f32>(-1e30));
    for (var k = 0u; k < 8u; k++) {
        let corner = vec3<f32>(
            select(b.min.x, b.max.x, (k & 1u) != 0u),
            select(b.min.y, b.max.y, (k & 2u) != 0u),
            select(b.min.z, b.max.z, (k & 4u) != 0u),
        );
        let p = vec4<f32>(dot(corner, axes[0]), dot(corner, axes[1]), dot(corner, axes[2]), 0.0);
        out.lo = min(out.lo, p);
        out.hi = max(out.hi, p);
    }
    return out;
}

// Lloyd's potential shadow receivers: every visible receiver's box in light space.
@compute @workgroup_size(64)
fn collect_receivers(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * 65535u * 64u;
    if (i >= volume.options.x) {
        return;
    }
    let b = bounds[i];
    if (visible[i] == 0u || (b.flags & FLAG_RECEIVER) == 0u) {
        return;
    }
    let slot = atomicAdd(&counters[0], 1u);
    receivers[slot] = light_box(b);
}

// A caster's volume (its box across the light, from its nearest depth on) can hold a visible
// point only where it overlaps a visible receiver's box: else it is not drawn. Conservative:
// the boxes hold what they bound, and the volume lies inside its box's extrusion.
@compute @workgroup_size(64)
fn cull_casters(@builtin(global_invocation_id) id: vec3<u32>) {
    let ci = id.x + id.y * 65535u * 64u;
    if (ci >= volume.counts.z) {
        return;
    }
    let c = casters[ci];
    var keep = volume.options.y == 0u;
    if (!keep) {
        let own = light_box(bounds[c.instance]);
        // The boxes are rounded outwards by a millimetre and a bit of their size.
        let pad = vec3<f32>(1e-3) + (own.hi.xyz - own.lo.xyz) * 1e-5;
        let count = atomicLoad(&counters[0]);
        for (var r = 0u; r < count && !keep; r++) {
            let other = receivers[r];
            keep = all(other.hi.xy + pad.xy >= own.lo.xy)
                && all(other.lo.xy - pad.xy <= own.hi.xy)
                && other.hi.z + pad.z >= own.lo.z;
        }
    }
    kept[ci] = select(0u, 1u, keep);
    outcomes[c.instance] = select(volume.counts.w, OUTCOME_RENDERED, keep);
    if (keep) {
        atomicAdd(&counters[1], 1u);
    }
}


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
    for (var k = 0u; k < 4u; k++) {
        atomicStore(&counters[k], 0u);
    }
}

