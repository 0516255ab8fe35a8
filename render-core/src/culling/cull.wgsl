// Caster tests on the GPU, stage by stage: light frustum, occlusion in the light's view
// against a max-depth pyramid of what is already in the shadow map, and the receiver mask's
// pyramid or (DigitalRune) the caster's shadow volume against the camera's frustum and depth. Writes each instance's draw (instance count 0 or 1), outcome and counters.
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
    in_camera_frustum: atomic<u32>,
    not_camera_occluded: atomic<u32>,
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
// Max pyramid of the camera's negated (reversed) depth: the farthest surface over a block.
@group(0) @binding(10) var<storage, read> camera_depth: array<f32>;

const SELECTION_ORACLE: u32 = 1u;
const SELECTION_EXCLUDED: u32 = 2u;

const OUTCOME_NOT_CASTER: u32 = 0u;
const OUTCOME_RENDERED: u32 = 1u;
const OUTCOME_EXCLUDED: u32 = 2u;
// 3 + stage index: stage 1 light frustum, 2 light occlusion, 3 receiver mask (or oracle), or
// for DigitalRune's methods 3 the shadow volume outside the camera frustum, 4 hidden from it.
const OUTCOME_CULLED_FRUSTUM: u32 = 4u;
const OUTCOME_CULLED_OCCLUSION: u32 = 5u;
const OUTCOME_CULLED_MASK: u32 = 6u;
const OUTCOME_CULLED_CAMERA_FRUSTUM: u32 = 6u;
const OUTCOME_CULLED_CAMERA_OCCLUSION: u32 = 7u;

// Normalised depth tolerance for rasterisation against box corners.
const DEPTH_MARGIN: f32 = 1e-6;

fn flags_of(i: u32) -> u32 {
    return bounds[i].flags;
}

const OCCLUSION_PYRAMID: u32 = 0u;
const MASK_PYRAMID: u32 = 1u;
const CAMERA_PYRAMID: u32 = 2u;

fn pyramid_load(which: u32, index: u32) -> f32 {
    if (which == OCCLUSION_PYRAMID) {
        return occlusion[index];
    }
    if (which == CAMERA_PYRAMID) {
        return camera_depth[index];
    }
    return mask[index];
}

// The largest value of a max pyramid over the base texels [lo, hi]. The base is `base_size`
// texels square; level m is max((base_size / 2) >> m, 1) square and holds blocks of 2^(m+1)
// base texels (the last block of a level takes in the odd texel left over).
fn pyramid_max(which: u32, base_size: u32, lo: vec2<i32>, hi: vec2<i32>) -> f32 {
    let extent = u32(max(hi.x - lo.x, hi.y - lo.y) + 1);
    // Smallest block size 2^(m+1) >= extent / 8, so the rectangle spans at most 9x9 blocks:
    // a finer level than 2x2 blocks hugs the rectangle closer for a few more loads.
    var width = max(base_size / 2u, 1u);
    var offset = 0u;
    var m = 0u;
    while ((16u << m) < extent && width > 1u) {
        offset += width * width;
        width = max(width / 2u, 1u);
        m++;
    }
    let shift = vec2<u32>(m + 1u);
    let last = vec2<u32>(width - 1u);
    let a = min(vec2<u32>(lo) >> shift, last);
    let b = min(vec2<u32>(hi) >> shift, last);
    var value = -3.4e38;
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

// DigitalRune's shadow volume of a caster: its light box widened by the filter's reach
// (PCF radius, normal offset, a texel), from just before the caster to `far_end` (normalised
// light depth), tested against the camera. 0 when the camera may see it, else the outcome.
// `count`: add to the stage counters (the second phase's verdict).
fn volume_outcome(box: LightBox, far_end: f32, count: bool) -> u32 {
    let pad = 2.0 * f32(cull.params.y) / f32(cull.sizes.x);
    let lo = vec3<f32>(box.lo.xy - pad, box.lo.z - cull.volume.x);
    let hi = vec3<f32>(box.hi.xy + pad, max(far_end, box.hi.z) + DEPTH_MARGIN);
    // Outside one plane of the camera's clip volume with every corner: the shadow is not in
    // view. Planes: -w <= x <= w, -w <= y <= w, 0 <= z <= w (reversed depth).
    var outside = vec3<bool>(true);
    var outside_far = vec3<bool>(true);
    var in_front = true;
    var nearest = 0.0;
    var p_lo = vec2<f32>(1e30);
    var p_hi = vec2<f32>(-1e30);
    for (var k = 0u; k < 8u; k++) {
        let corner = vec3<f32>(
            select(lo.x, hi.x, (k & 1u) != 0u),
            select(lo.y, hi.y, (k & 2u) != 0u),
            select(lo.z, hi.z, (k & 4u) != 0u),
        );
        let world = cull.world_from_light_clip * vec4<f32>(corner, 1.0);
        let clip = cull.camera_clip_from_world * vec4<f32>(world.xyz / world.w, 1.0);
        outside = outside & (clip.xyz < vec3<f32>(-clip.w, -clip.w, 0.0));
        outside_far = outside_far & (clip.xyz > vec3<f32>(clip.w));
        // Occlusion needs every corner in front of the near plane.
        in_front = in_front && clip.w > 0.0 && clip.z <= clip.w;
        if (clip.w > 0.0) {
            let ndc = clip.xyz / clip.w;
            nearest = max(nearest, ndc.z);
            let pixel = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * vec2<f32>(cull.camera.xy);
            p_lo = min(p_lo, pixel);
            p_hi = max(p_hi, pixel);
        }
    }
    if (any(outside) || any(outside_far)) {
        return OUTCOME_CULLED_CAMERA_FRUSTUM;
    }
    if (count) {
        atomicAdd(&counters.in_camera_frustum, 1u);
    }
    if (in_front) {
        let last = vec2<i32>(cull.camera.xy) - 1;
        let a = clamp(vec2<i32>(floor(p_lo)) - 1, vec2<i32>(0), last);
        let b = clamp(vec2<i32>(floor(p_hi)) + 1, vec2<i32>(0), last);
        // The farthest visible surface over the rectangle, as reversed depth.
        let farthest = -pyramid_max(CAMERA_PYRAMID, cull.camera.z, a, b);
        if (nearest + DEPTH_MARGIN < farthest) {
            return OUTCOME_CULLED_CAMERA_OCCLUSION;
        }
    }
    if (count) {
        atomicAdd(&counters.not_camera_occluded, 1u);
    }
    return 0u;
}

// The progressive volume's far end from last frame's shadow map (state bits 16-31), or the
// far plane when conservative or nothing is stored yet.
fn stored_far_end(s: u32) -> f32 {
    if ((cull.params.x & METHOD_PROGRESSIVE) == 0u) {
        return 1.0;
    }
    let stored = s >> STATE_EXTENT_SHIFT;
    // Nothing stored yet (a new scene): the far plane.
    return select(f32(stored) / 65535.0, 1.0, stored == 0u);
}

// After the frame's shadow map is complete (progressive only): each caster's far end for
// the next frame, the farthest depth in the map over its box. As in DigitalRune's occlusion
// buffer, the caster is among the occluders it is tested against, so where it hides all
// that lies behind it (or others do) the volume ends too soon, and its shadow can be lost.
@compute @workgroup_size(64)
fn cs_far_ends(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= cull.sizes.w || (flags_of(i) & CULL_CASTER) == 0u) {
        return;
    }
    let box = light_box(bounds[i], cull.light_clip_from_world);
    let r = texel_rect(box, cull.sizes.x, 1);
    let far_end = clamp(pyramid_max(OCCLUSION_PYRAMID, cull.sizes.x, r[0], r[1]), 0.0, 1.0);
    let bits = u32(ceil(far_end * 65535.0)) << STATE_EXTENT_SHIFT;
    state[i] = (state[i] & ((1u << STATE_EXTENT_SHIFT) - 1u)) | bits;
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
    let extent = state[i] & ~((1u << STATE_EXTENT_SHIFT) - 1u);
    state[i] = light_visible | extent;
    let box = light_box(bounds[i], cull.light_clip_from_world);
    if (!in_light_frustum(box)) {
        return;
    }
    var first = false;
    if ((method & METHOD_DRAW_RECEIVERS) != 0u && visible[i] != 0u && (flags & CULL_RECEIVER) != 0u) {
        first = (method & METHOD_BVOL) == 0u || light_visible != 0u;
    }
    if ((method & METHOD_TEMPORAL) != 0u && light_visible != 0u) {
        first = true;
    }
    // Receivers drawn with their mask are occluders too, but only those that can shadow
    // a visible receiver are worth drawing (FRAG's mask is ready before this phase).
    first = first && touches_mask(box);
    if (first && (method & METHOD_VOLUME) != 0u) {
        first = volume_outcome(box, stored_far_end(extent), false) == 0u;
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
    let method = cull.params.x;
    let extent = s & ~((1u << STATE_EXTENT_SHIFT) - 1u);
    let light_visible = select(STATE_LIGHT_VISIBLE, 0u, hidden) | extent;
    if (first) {
        atomicAdd(&counters.not_occluded, 1u);
        atomicAdd(&counters.in_mask, 1u);
        if ((method & METHOD_VOLUME) != 0u) {
            atomicAdd(&counters.in_camera_frustum, 1u);
            atomicAdd(&counters.not_camera_occluded, 1u);
        }
        state[i] = OUTCOME_RENDERED | light_visible;
        return;
    }
    if (hidden) {
        state[i] = OUTCOME_CULLED_OCCLUSION | light_visible;
        return;
    }
    atomicAdd(&counters.not_occluded, 1u);
    if ((method & METHOD_VOLUME) != 0u) {
        let outcome = volume_outcome(box, stored_far_end(light_visible), true);
        if (outcome != 0u) {
            state[i] = outcome | light_visible;
            return;
        }
    } else {
        if (!touches_mask(box)) {
            state[i] = OUTCOME_CULLED_MASK | light_visible;
            return;
        }
        atomicAdd(&counters.in_mask, 1u);
    }
    state[i] = light_visible;
    render(i, 0u);
}
