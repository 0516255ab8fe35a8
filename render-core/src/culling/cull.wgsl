// Caster tests on the GPU, stage by stage: light frustum, occlusion in the light's view
// against a max-depth pyramid of what is already in the shadow map, and the receiver mask's
// pyramid. Writes each instance's draw (instance count 0 or 1), outcome and counters.
// Prepended with culling/cull_common.wgsl.

struct DrawArgs {
    index_count: u32,
    instance_count: u32,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
}

// Keep in sync with culling/gpu.rs (`Counter`).
struct Counters {
    in_frustum: atomic<u32>,
    not_occluded: atomic<u32>,
    in_mask: atomic<u32>,
    rendered: atomic<u32>,
    triangles: atomic<u32>,
    first_phase: atomic<u32>,
}

@group(0) @binding(0) var<uniform> cull: CullParams;
@group(0) @binding(1) var<storage, read> bounds: array<Bounds>;
@group(0) @binding(2) var<storage, read> visible: array<u32>;
@group(0) @binding(3) var<storage, read_write> draws: array<DrawArgs>;
@group(0) @binding(4) var<storage, read_write> state: array<u32>;
@group(0) @binding(5) var<storage, read_write> counters: Counters;
// Per instance: bit 0 the oracle method wants it (culling/receivers.wgsl), bit 1 excluded.
@group(0) @binding(6) var<storage, read> selection: array<u32>;
// Max pyramids (culling/pyramid.wgsl): of the shadow map's depth, and of the mask.
@group(0) @binding(7) var<storage, read> occlusion: array<f32>;
@group(0) @binding(8) var<storage, read> mask: array<f32>;
// Receivers whose geometry goes into the mask (GEOM, GEOM+BVOL).
@group(0) @binding(9) var<storage, read_write> receiver_draws: array<DrawArgs>;

const SELECTION_ORACLE: u32 = 1u;
const SELECTION_EXCLUDED: u32 = 2u;

const OUTCOME_NOT_CASTER: u32 = 0u;
const OUTCOME_RENDERED: u32 = 1u;
const OUTCOME_EXCLUDED: u32 = 2u;
// 3 + stage index: stage 1 light frustum, 2 light occlusion, 3 receiver mask (or oracle).
const OUTCOME_CULLED_FRUSTUM: u32 = 4u;
const OUTCOME_CULLED_OCCLUSION: u32 = 5u;
const OUTCOME_CULLED_MASK: u32 = 6u;

// Normalised depth tolerance for rasterisation against box corners.
const DEPTH_MARGIN: f32 = 1e-6;

fn flags_of(i: u32) -> u32 {
    return bounds[i].flags;
}

const OCCLUSION_PYRAMID: u32 = 0u;
const MASK_PYRAMID: u32 = 1u;

fn pyramid_load(which: u32, index: u32) -> f32 {
    if (which == OCCLUSION_PYRAMID) {
        return occlusion[index];
    }
    return mask[index];
}

// The largest value of a max pyramid over the base texels [lo, hi]. The base is `base_size`
// texels square; level m is max((base_size / 2) >> m, 1) square and holds blocks of 2^(m+1)
// base texels (the last block of a level takes in the odd texel left over).
fn pyramid_max(which: u32, base_size: u32, lo: vec2<i32>, hi: vec2<i32>) -> f32 {
    let extent = u32(max(hi.x - lo.x, hi.y - lo.y) + 1);
    // Smallest block size 2^(m+1) >= extent, so the rectangle spans at most 2x2 blocks.
    var width = max(base_size / 2u, 1u);
    var offset = 0u;
    var m = 0u;
    while ((2u << m) < extent && width > 1u) {
        offset += width * width;
        width = max(width / 2u, 1u);
        m++;
    }
    let shift = vec2<u32>(m + 1u);
    let last = vec2<u32>(width - 1u);
    let a = min(vec2<u32>(lo) >> shift, last);
    let b = min(vec2<u32>(hi) >> shift, last);
    var value = 0.0;
    for (var y = a.y; y <= b.y; y++) {
        for (var x = a.x; x <= b.x; x++) {
            value = max(value, pyramid_load(which, offset + y * width + x));
        }
    }
    return value;
}

// The texels of the shadow map a light box covers, widened by `pad`, clamped to the map.
fn texel_rect(box: LightBox, size: u32, pad: i32) -> array<vec2<i32>, 2> {
    let s = f32(size);
    let u = vec2<f32>(box.lo.x, box.hi.x) * 0.5 + 0.5;
    let v = 0.5 - vec2<f32>(box.hi.y, box.lo.y) * 0.5;
    let lo = vec2<i32>(floor(vec2<f32>(u.x, v.x) * s)) - pad;
    let hi = vec2<i32>(floor(vec2<f32>(u.y, v.y) * s)) + pad;
    let last = vec2<i32>(i32(size) - 1);
    return array<vec2<i32>, 2>(clamp(lo, vec2<i32>(0), last), clamp(hi, vec2<i32>(0), last));
}

fn occluded(box: LightBox) -> bool {
    if ((cull.params.x & METHOD_OCCLUSION) == 0u) {
        return false;
    }
    let r = texel_rect(box, cull.sizes.x, 1);
    return box.lo.z - DEPTH_MARGIN >= pyramid_max(OCCLUSION_PYRAMID, cull.sizes.x, r[0], r[1]);
}

// False when no visible receiver can be shadowed by this box: it covers no marked texel, or
// (FRAG) lies behind every receiver depth the mask holds there.
fn touches_mask(box: LightBox) -> bool {
    if ((cull.params.x & METHOD_MASK) == 0u) {
        return true;
    }
    // Whole-receiver masks miss the taps near their edges: widen the caster instead.
    let pad = select(i32(cull.params.y), 1, (cull.params.x & (METHOD_GEOM | METHOD_BVOL)) == 0u);
    let r = texel_rect(box, cull.sizes.x, pad);
    let scale = vec2<i32>(i32(cull.sizes.z));
    let needed = pyramid_max(MASK_PYRAMID, cull.sizes.y, r[0] / scale, r[1] / scale);
    return box.lo.z - DEPTH_MARGIN < needed;
}

// Receivers that fill the mask with their geometry, for GEOM and GEOM+BVOL (which takes
// geometry for receivers that were visible in the light's view last frame, else boxes).
@compute @workgroup_size(64)
fn cs_receivers(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= cull.sizes.w) {
        return;
    }
    let flags = flags_of(i);
    var geometry = visible[i] != 0u && (flags & CULL_RECEIVER) != 0u;
    if ((cull.params.x & METHOD_BVOL) != 0u) {
        geometry = geometry && (state[i] & STATE_LIGHT_VISIBLE) != 0u;
    }
    receiver_draws[i].instance_count = select(0u, 1u, geometry && (cull.params.x & METHOD_GEOM) != 0u);
}

fn render(i: u32, phase_bit: u32) {
    draws[i].instance_count = 1u;
    atomicAdd(&counters.rendered, 1u);
    atomicAdd(&counters.triangles, draws[i].index_count / 3u);
    state[i] = (state[i] & ~0xffu) | OUTCOME_RENDERED | phase_bit;
}

// First phase: the casters drawn before any test reads the shadow map. The visible receivers
// for methods that draw them with the mask (GEOM, FRAG), and the casters visible in the
// light's view last frame (occlusion culling's temporal coherence), or the oracle's set.
@compute @workgroup_size(64)
fn cs_first_phase(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= cull.sizes.w) {
        return;
    }
    let flags = flags_of(i);
    let light_visible = state[i] & STATE_LIGHT_VISIBLE;
    draws[i].instance_count = 0u;
    if ((flags & CULL_CASTER) == 0u) {
        state[i] = OUTCOME_NOT_CASTER;
        return;
    }
    if ((selection[i] & SELECTION_EXCLUDED) != 0u) {
        state[i] = OUTCOME_EXCLUDED;
        return;
    }
    let method = cull.params.x;
    if ((method & METHOD_ORACLE) != 0u) {
        if ((selection[i] & SELECTION_ORACLE) != 0u) {
            state[i] = 0u;
            render(i, STATE_FIRST_PHASE);
        } else {
            state[i] = OUTCOME_CULLED_FRUSTUM;
        }
        return;
    }
    state[i] = light_visible;
    let box = light_box(bounds[i], cull.light_clip_from_world);
    if (!in_light_frustum(box)) {
        return;
    }
    var first = false;
    if ((method & METHOD_DRAW_RECEIVERS) != 0u && visible[i] != 0u && (flags & CULL_RECEIVER) != 0u) {
        first = (method & METHOD_BVOL) == 0u || light_visible != 0u;
    }
    if ((method & METHOD_TEMPORAL) != 0u && light_visible != 0u && touches_mask(box)) {
        first = true;
    }
    if (first) {
        atomicAdd(&counters.first_phase, 1u);
        render(i, STATE_FIRST_PHASE);
    }
}

// Second phase, after the first phase's casters are in the shadow map and its pyramid is
// built: every caster through the stages; the survivors not drawn yet are drawn now. Whether
// a caster is visible in the light's view is kept for the next frame.
@compute @workgroup_size(64)
fn cs_second_phase(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= cull.sizes.w) {
        return;
    }
    let s = state[i];
    let flags = flags_of(i);
    let first = (s & STATE_FIRST_PHASE) != 0u;
    draws[i].instance_count = 0u;
    if ((flags & CULL_CASTER) == 0u || (selection[i] & SELECTION_EXCLUDED) != 0u || (cull.params.x & METHOD_ORACLE) != 0u) {
        return;
    }
    let box = light_box(bounds[i], cull.light_clip_from_world);
    if (!in_light_frustum(box)) {
        state[i] = OUTCOME_CULLED_FRUSTUM;
        return;
    }
    atomicAdd(&counters.in_frustum, 1u);
    let hidden = occluded(box);
    let light_visible = select(STATE_LIGHT_VISIBLE, 0u, hidden);
    if (first) {
        atomicAdd(&counters.not_occluded, 1u);
        atomicAdd(&counters.in_mask, 1u);
        state[i] = OUTCOME_RENDERED | light_visible;
        return;
    }
    if (hidden) {
        state[i] = OUTCOME_CULLED_OCCLUSION;
        return;
    }
    atomicAdd(&counters.not_occluded, 1u);
    if (!touches_mask(box)) {
        state[i] = OUTCOME_CULLED_MASK | light_visible;
        return;
    }
    atomicAdd(&counters.in_mask, 1u);
    state[i] = light_visible;
    render(i, 0u);
}
