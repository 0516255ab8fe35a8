// Caster tests on the GPU, stage by stage and view by view (workgroup y is the view): light
// frustum, occlusion in the light's view against a max-depth pyramid of what is already in the
// view's shadow map, and the receiver mask's pyramid or (DigitalRune) the caster's shadow
// volume against the camera's frustum and depth. Writes each instance's draw in the view's
// block (instance count 0 or 1), its outcome and the view's counters.
#import culling/cull_common.wgsl

struct DrawArgs {
    index_count: u32,
    instance_count: u32,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
}

@group(0) @binding(0) var<uniform> cull: CullFrame;
@group(0) @binding(1) var<storage, read> cull_views: array<CullView>;
@group(0) @binding(2) var<storage, read> views: array<ShadowView>;
@group(0) @binding(3) var<storage, read> bounds: array<InstanceBounds>;
@group(0) @binding(4) var<storage, read> visible: array<u32>;
@group(0) @binding(5) var<storage, read_write> draws: array<DrawArgs>;
@group(0) @binding(6) var<storage, read_write> state: array<u32>;
// Per view, COUNTER_SLOTS counters (culling/codes.wgsl): what remains after each stage, and
// what was drawn.
@group(0) @binding(7) var<storage, read_write> counters: array<atomic<u32>>;
// Per view and instance: SELECTION_ORACLE when the oracle method wants it
// (culling/receivers.wgsl), SELECTION_EXCLUDED when left out on request.
@group(0) @binding(8) var<storage, read> selection: array<u32>;
// Max pyramids (culling/pyramid.wgsl), a block per view: of the shadow map's depth, and of
// the mask.
@group(0) @binding(9) var<storage, read> occlusion: array<f32>;
@group(0) @binding(10) var<storage, read> mask: array<f32>;
// Receivers whose geometry goes into the mask (GEOM, GEOM+BVOL), a block per view.
@group(0) @binding(11) var<storage, read_write> receiver_draws: array<DrawArgs>;
// Max pyramid of the camera's negated (reversed) depth: the farthest surface over a block.
@group(0) @binding(12) var<storage, read> camera_depth: array<f32>;
// The footprint test (culling/footprints.wgsl): per view, the casters the cheap tests kept
// (instance ids, a block per view) and the indirect draw of their boxes.
@group(0) @binding(13) var<storage, read_write> candidates: array<u32>;
@group(0) @binding(14) var<storage, read_write> footprint_draws: array<FootprintDraw>;
// With METHOD_GEOMETRY_FOOTPRINT the footprint is the caster's own geometry: one indexed draw
// per instance and view (like `draws`), the candidates' instance count 1 until the verdict.
@group(0) @binding(15) var<storage, read_write> footprint_geometry: array<DrawArgs>;

struct FootprintDraw {
    vertex_count: u32,
    instance_count: atomic<u32>,
    first_vertex: u32,
    first_instance: u32,
}

// Normalised depth tolerance for rasterisation against box corners.
const DEPTH_MARGIN: f32 = 1e-6;

// One caster in one view.
struct Item {
    view: u32,
    instance: u32,
    // Index of the instance's entry in the view's blocks.
    slot: u32,
    method: u32,
}

fn item(id: vec3<u32>) -> Item {
    let n = cull.counts.x;
    return Item(id.y, id.x, id.y * n + id.x, cull_views[id.y].params.x);
}

fn valid(id: vec3<u32>) -> bool {
    return id.x < cull.counts.x && id.y < cull.counts.y;
}

fn count(it: Item, counter: u32) {
    atomicAdd(&counters[it.view * COUNTER_SLOTS + counter], 1u);
}

fn view_box(it: Item) -> LightBox {
    return light_box(bounds[it.instance], views[it.view]);
}

fn map_size(it: Item) -> u32 {
    return views[it.view].square.w;
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
// base texels (the last block of a level takes in the odd texel left over). `block` is the
// first word of the view's pyramid.
fn pyramid_max(which: u32, block: u32, base_size: u32, lo: vec2<i32>, hi: vec2<i32>) -> f32 {
    let extent = u32(max(hi.x - lo.x, hi.y - lo.y) + 1);
    // Smallest block size 2^(m+1) >= extent / 8, so the rectangle spans at most 9x9 blocks:
    // a finer level than 2x2 blocks hugs the rectangle closer for a few more loads.
    var width = max(base_size / 2u, 1u);
    var offset = block;
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

// The texels of a view's shadow map a light box covers, widened by `pad`, clamped to the map.
fn texel_rect(box: LightBox, size: u32, pad: i32) -> array<vec2<i32>, 2> {
    let s = f32(size);
    let u = vec2<f32>(box.lo.x, box.hi.x) * 0.5 + 0.5;
    let v = 0.5 - vec2<f32>(box.hi.y, box.lo.y) * 0.5;
    let lo = vec2<i32>(floor(vec2<f32>(u.x, v.x) * s)) - pad;
    let hi = vec2<i32>(floor(vec2<f32>(u.y, v.y) * s)) + pad;
    let last = vec2<i32>(i32(size) - 1);
    return array<vec2<i32>, 2>(clamp(lo, vec2<i32>(0), last), clamp(hi, vec2<i32>(0), last));
}

fn occlusion_max(it: Item, box: LightBox) -> f32 {
    let size = map_size(it);
    let r = texel_rect(box, size, 1);
    return pyramid_max(OCCLUSION_PYRAMID, it.view * cull_views[it.view].pyramids.x, size, r[0], r[1]);
}

fn occluded(it: Item, box: LightBox) -> bool {
    if ((it.method & METHOD_OCCLUSION) == 0u) {
        return false;
    }
    return box.lo.z - DEPTH_MARGIN >= occlusion_max(it, box);
}

// The stage a method's mask is: the receiver mask, or for incremental updates the changed
// region.
fn mask_stage(it: Item) -> u32 {
    return select(SLOT_RECEIVER_MASK, SLOT_CHANGED_REGION, (it.method & METHOD_INCREMENTAL) != 0u);
}

// False when no visible receiver can be shadowed by this box: it covers no marked texel, or
// (FRAG) lies behind every receiver depth the mask holds there.
fn touches_mask(it: Item, box: LightBox) -> bool {
    if ((it.method & METHOD_MASK) == 0u) {
        return true;
    }
    let params = cull_views[it.view].params;
    // GEOM's mask misses the taps near its edges: widen the caster instead (BVOL's boxes are
    // widened where they are drawn, culling/masks.wgsl).
    let pad = select(1, i32(params.y), (it.method & METHOD_GEOM) != 0u);
    let r = texel_rect(box, map_size(it), pad);
    let scale = vec2<i32>(i32(params.z));
    let mask_size = params.w;
    let block = it.view * cull_views[it.view].pyramids.y;
    let needed = pyramid_max(MASK_PYRAMID, block, mask_size, r[0] / scale, r[1] / scale);
    return box.lo.z - DEPTH_MARGIN < needed;
}

// DigitalRune's shadow volume of a caster: its light box widened by the filter's reach
// (PCF radius, normal offset, a texel), from just before the caster to `far_end` (normalised
// light depth), tested against the camera. 0 when the camera may see it, else the outcome.
// `counted`: add to the stage counters (the second phase's verdict).
fn volume_outcome(it: Item, box: LightBox, far_end: f32, counted: bool) -> u32 {
    let cv = cull_views[it.view];
    let pad = 2.0 * f32(cv.params.y) / f32(map_size(it));
    let lo = vec3<f32>(box.lo.xy - pad, box.lo.z - cv.volume.x);
    let hi = vec3<f32>(box.hi.xy + pad, max(far_end, box.hi.z) + DEPTH_MARGIN);
    let world_from_light_clip = views[it.view].world_from_light_clip;
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
        let world = world_from_light_clip * vec4<f32>(corner, 1.0);
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
    if (counted) {
        count(it, SLOT_CAMERA_FRUSTUM);
    }
    if (in_front) {
        let last = vec2<i32>(cull.camera.xy) - 1;
        let a = clamp(vec2<i32>(floor(p_lo)) - 1, vec2<i32>(0), last);
        let b = clamp(vec2<i32>(floor(p_hi)) + 1, vec2<i32>(0), last);
        // The farthest visible surface over the rectangle, as reversed depth.
        let farthest = -pyramid_max(CAMERA_PYRAMID, 0u, cull.counts.z, a, b);
        if (nearest + DEPTH_MARGIN < farthest) {
            return OUTCOME_CULLED_CAMERA_OCCLUSION;
        }
    }
    if (counted) {
        count(it, SLOT_CAMERA_OCCLUSION);
    }
    return 0u;
}

// The progressive volume's far end from last frame's shadow map (state bits from
// STATE_EXTENT_SHIFT), or the far plane when conservative or nothing is stored yet.
fn stored_far_end(it: Item, s: u32) -> f32 {
    if ((it.method & METHOD_PROGRESSIVE) == 0u) {
        return 1.0;
    }
    let stored = s >> STATE_EXTENT_SHIFT;
    // Nothing stored yet (a new scene): the far plane.
    return select(f32(stored) / 65535.0, 1.0, stored == 0u);
}

// After the frame's shadow maps are complete (progressive only): each caster's far end for
// the next frame, the farthest depth in the view's map over its box. As in DigitalRune's
// occlusion buffer, the caster is among the occluders it is tested against, so where it hides
// all that lies behind it (or others do) the volume ends too soon, and its shadow can be lost.
@compute @workgroup_size(64)
fn cs_far_ends(@builtin(global_invocation_id) id: vec3<u32>) {
    if (!valid(id)) {
        return;
    }
    let it = item(id);
    if ((bounds[it.instance].flags & FLAG_CASTER) == 0u || (it.method & METHOD_PROGRESSIVE) == 0u) {
        return;
    }
    let far_end = clamp(occlusion_max(it, view_box(it)), 0.0, 1.0);
    let bits = u32(ceil(far_end * 65535.0)) << STATE_EXTENT_SHIFT;
    state[it.slot] = (state[it.slot] & ((1u << STATE_EXTENT_SHIFT) - 1u)) | bits;
}

// Receivers that fill the mask with their geometry, for GEOM and GEOM+BVOL (which takes
// geometry for receivers that were visible in the light's view last frame, else boxes).
@compute @workgroup_size(64)
fn cs_receivers(@builtin(global_invocation_id) id: vec3<u32>) {
    if (!valid(id)) {
        return;
    }
    let it = item(id);
    let flags = bounds[it.instance].flags;
    var geometry = visible[it.instance] != 0u && (flags & FLAG_RECEIVER) != 0u;
    if ((it.method & METHOD_BVOL) != 0u) {
        geometry = geometry && (state[it.slot] & STATE_LIGHT_VISIBLE) != 0u;
    }
    receiver_draws[it.slot].instance_count = select(0u, 1u, geometry && (it.method & METHOD_GEOM) != 0u);
}

fn render(it: Item, phase_bit: u32) {
    draws[it.slot].instance_count = 1u;
    count(it, SLOT_RENDERED);
    atomicAdd(&counters[it.view * COUNTER_SLOTS + SLOT_TRIANGLES], draws[it.slot].index_count / 3u);
    state[it.slot] = (state[it.slot] & ~STATE_OUTCOME_BITS) | OUTCOME_RENDERED | phase_bit;
}

// One more caster for the view's footprint pass: its box, or its geometry.
fn push_candidate(it: Item) {
    if ((it.method & METHOD_GEOMETRY_FOOTPRINT) != 0u) {
        footprint_geometry[it.slot].instance_count = 1u;
        return;
    }
    let k = atomicAdd(&footprint_draws[it.view].instance_count, 1u);
    // Every candidate writes the same box vertex count (12 triangles).
    footprint_draws[it.view].vertex_count = 36u;
    candidates[it.view * cull.counts.x + k] = it.instance;
}

// The cheap tests kept the caster: drawn now, or with the footprint test, drawn after it if a
// texel of its box passes (`cs_resolve_footprints`).
fn keep(it: Item, phase_bit: u32) {
    // In the first phase nothing is drawn yet: without a mask every texel would pass.
    let first_without_mask = phase_bit != 0u && (it.method & METHOD_MASK) == 0u;
    if ((it.method & METHOD_FOOTPRINT) == 0u || first_without_mask) {
        render(it, phase_bit);
        return;
    }
    push_candidate(it);
    state[it.slot] = (state[it.slot] & ~(STATE_OUTCOME_BITS | STATE_FOOTPRINT_HIT)) | OUTCOME_PENDING | phase_bit;
}

// After a footprint pass: candidates with a passing texel are drawn, the others culled. A
// first-phase candidate that failed goes through every test again in the second phase.
@compute @workgroup_size(64)
fn cs_resolve_footprints(@builtin(global_invocation_id) id: vec3<u32>) {
    if (!valid(id)) {
        return;
    }
    let it = item(id);
    footprint_geometry[it.slot].instance_count = 0u;
    let s = state[it.slot];
    if ((s & STATE_OUTCOME_BITS) != OUTCOME_PENDING) {
        return;
    }
    let phase_bit = s & STATE_FIRST_PHASE;
    if ((s & STATE_FOOTPRINT_HIT) != 0u) {
        if (phase_bit == 0u) {
            count(it, SLOT_FOOTPRINT);
        }
        render(it, phase_bit);
    } else {
        state[it.slot] = (s & ~(STATE_OUTCOME_BITS | STATE_FIRST_PHASE)) | OUTCOME_CULLED_FOOTPRINT;
    }
}

// After the maps are finished: the drawn casters become candidates of a last footprint pass
// against the finished maps, which says which of them are front-most where the mask needs
// them: the light-visible set of the next frame's first phase. The first phase tests against
// a map with nothing in it yet, and in the second a drawn caster is not hidden by itself, so
// neither can tell a caster that others hide wherever it is needed.
@compute @workgroup_size(64)
fn cs_collect_drawn(@builtin(global_invocation_id) id: vec3<u32>) {
    if (!valid(id)) {
        return;
    }
    let it = item(id);
    let s = state[it.slot];
    if ((s & STATE_OUTCOME_BITS) != OUTCOME_RENDERED) {
        return;
    }
    push_candidate(it);
    state[it.slot] = s & ~STATE_FOOTPRINT_HIT;
}

// A drawn caster is visible in the light's view next frame where its box passed.
@compute @workgroup_size(64)
fn cs_resolve_light_visible(@builtin(global_invocation_id) id: vec3<u32>) {
    if (!valid(id)) {
        return;
    }
    let it = item(id);
    footprint_geometry[it.slot].instance_count = 0u;
    let s = state[it.slot];
    if ((s & STATE_OUTCOME_BITS) != OUTCOME_RENDERED) {
        return;
    }
    let visible = select(0u, STATE_LIGHT_VISIBLE, (s & STATE_FOOTPRINT_HIT) != 0u);
    state[it.slot] = (s & ~STATE_LIGHT_VISIBLE) | visible;
}

// First phase: the casters drawn before any test reads the shadow map. The visible receivers
// for methods that draw them with the mask (GEOM, FRAG), and the casters visible in the
// light's view last frame (occlusion culling's temporal coherence), or the oracle's set.
@compute @workgroup_size(64)
fn cs_first_phase(@builtin(global_invocation_id) id: vec3<u32>) {
    if (!valid(id)) {
        return;
    }
    let it = item(id);
    let flags = bounds[it.instance].flags;
    let light_visible = state[it.slot] & STATE_LIGHT_VISIBLE;
    draws[it.slot].instance_count = 0u;
    if ((flags & FLAG_CASTER) == 0u) {
        state[it.slot] = OUTCOME_NOT_CASTER;
        return;
    }
    if ((selection[it.slot] & SELECTION_EXCLUDED) != 0u) {
        state[it.slot] = OUTCOME_EXCLUDED;
        return;
    }
    let method = it.method;
    if ((method & METHOD_ORACLE) != 0u) {
        if ((selection[it.slot] & SELECTION_ORACLE) != 0u) {
            state[it.slot] = 0u;
            count(it, SLOT_ORACLE);
            render(it, STATE_FIRST_PHASE);
        } else {
            state[it.slot] = OUTCOME_CULLED_ORACLE;
        }
        return;
    }
    let extent = state[it.slot] & ~((1u << STATE_EXTENT_SHIFT) - 1u);
    state[it.slot] = light_visible | extent;
    let box = view_box(it);
    if (!in_light_frustum(box)) {
        return;
    }
    var first = false;
    if ((method & METHOD_DRAW_RECEIVERS) != 0u && visible[it.instance] != 0u && (flags & FLAG_RECEIVER) != 0u) {
        // GEOM+BVOL takes only the receivers the light saw last frame (Bittner 4.3); so does
        // FRAG once there is a last frame: its mask holds depths, so a receiver hidden from
        // the light wherever it would shadow is culled by the second phase's test.
        let estimate = (method & METHOD_BVOL) != 0u || ((method & METHOD_FRAG) != 0u && cull.counts.w != 0u);
        first = !estimate || light_visible != 0u;
    }
    if ((method & METHOD_TEMPORAL) != 0u && light_visible != 0u) {
        first = true;
    }
    // Receivers drawn with their mask are occluders too, but only those that can shadow
    // a visible receiver are worth drawing (FRAG's mask is ready before this phase).
    first = first && touches_mask(it, box);
    if (first && (method & METHOD_VOLUME) != 0u) {
        first = volume_outcome(it, box, stored_far_end(it, extent), false) == 0u;
    }
    if (first) {
        count(it, SLOT_FIRST_PHASE);
        keep(it, STATE_FIRST_PHASE);
    }
}

// Second phase, after the first phase's casters are in the shadow map and its pyramid is
// built: every caster through the stages; the survivors not drawn yet are drawn now. Whether
// a caster is visible in the light's view is kept for the next frame.
@compute @workgroup_size(64)
fn cs_second_phase(@builtin(global_invocation_id) id: vec3<u32>) {
    if (!valid(id)) {
        return;
    }
    let it = item(id);
    let s = state[it.slot];
    let flags = bounds[it.instance].flags;
    let first = (s & STATE_FIRST_PHASE) != 0u;
    let method = it.method;
    draws[it.slot].instance_count = 0u;
    if ((flags & FLAG_CASTER) == 0u || (selection[it.slot] & SELECTION_EXCLUDED) != 0u || (method & METHOD_ORACLE) != 0u) {
        return;
    }
    let box = view_box(it);
    if (!in_light_frustum(box)) {
        state[it.slot] = OUTCOME_CULLED_LIGHT_FRUSTUM;
        return;
    }
    count(it, SLOT_LIGHT_FRUSTUM);
    let hidden = occluded(it, box);
    let extent = s & ~((1u << STATE_EXTENT_SHIFT) - 1u);
    // Light-visible for the next frame's first phase: not hidden now, and what the footprint
    // test after the maps said when the caster was last drawn (`cs_resolve_light_visible`): a
    // box the pyramid cannot hide is not a caster the map needs.
    let light_visible = select(s & STATE_LIGHT_VISIBLE, 0u, hidden) | extent;
    if (first) {
        count(it, SLOT_LIGHT_OCCLUSION);
        count(it, mask_stage(it));
        if ((method & METHOD_VOLUME) != 0u) {
            count(it, SLOT_CAMERA_FRUSTUM);
            count(it, SLOT_CAMERA_OCCLUSION);
        }
        count(it, SLOT_FOOTPRINT);
        state[it.slot] = OUTCOME_RENDERED | light_visible;
        return;
    }
    if (hidden) {
        state[it.slot] = OUTCOME_CULLED_LIGHT_OCCLUSION | light_visible;
        return;
    }
    count(it, SLOT_LIGHT_OCCLUSION);
    if ((method & METHOD_VOLUME) != 0u) {
        let outcome = volume_outcome(it, box, stored_far_end(it, light_visible), true);
        if (outcome != 0u) {
            state[it.slot] = outcome | light_visible;
            return;
        }
    } else {
        if (!touches_mask(it, box)) {
            let culled = select(OUTCOME_CULLED_RECEIVER_MASK, OUTCOME_CULLED_CHANGED_REGION, (method & METHOD_INCREMENTAL) != 0u);
            state[it.slot] = culled | light_visible;
            return;
        }
        count(it, mask_stage(it));
    }
    state[it.slot] = light_visible;
    keep(it, 0u);
}
