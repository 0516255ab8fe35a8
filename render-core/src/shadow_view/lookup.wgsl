// Where a camera fragment reads a shadow view: the PCF taps and the receiver's plane across
// them. Shading (shadow_map/light.wgsl) and the receiver passes that must agree with it bit
// for bit (culling/receivers.wgsl) share these functions. Texel coordinates are the view's
// own (0 at its square's first texel); `map_texel` places them in the depth array.
#import view/common.wgsl

struct ShadowLookup {
    // Lookup position in the view's texels.
    p: vec2<f32>,
    // Normalised light depth of the (normal-offset) receiver point.
    depth: f32,
    // Depth change per texel along the receiver's plane.
    ddepth_per_texel: vec2<f32>,
    bias: f32,
    // The first tap and the kernel width.
    first: vec2<i32>,
    kernel: i32,
    // False outside the light frustum, where everything is lit.
    inside: bool,
    // The view, its side in texels, its layer and first texel in the depth array.
    view: u32,
    size: i32,
    layer: i32,
    origin: vec2<i32>,
}

fn shadow_lookup(world_pos: vec3<f32>, geometric: vec3<f32>, v: u32) -> ShadowLookup {
    var l: ShadowLookup;
    let view = shadow_views[v];
    // A warped (LiSPSM) view's texel grows with the point's clip w across the map and with
    // w squared along it, and its depth range with w; w is 1 in an orthographic view.
    // A perspective view from a point: texels grow with w, a metre of depth with w squared.
    let w = (view.light_clip_from_world * vec4<f32>(world_pos, 1.0)).w;
    let perspective = view.index.y == 1u;
    let texel_m = vec2<f32>(view.light_right.w * w, view.light_up.w * w * select(w, 1.0, perspective));
    let range_m = max(view.light_dir.w * w * select(1.0, w, perspective), 1e-6);
    let size = f32(view.square.w);
    let offset_pos = world_pos + geometric * (frame.shadow.z * max(texel_m.x, texel_m.y));
    let clip = light_clip(view, offset_pos);
    let ndc = clip.xyz / clip.w;
    l.inside = clip.w > 0.0 && !(abs(ndc.x) > 1.0 || abs(ndc.y) > 1.0 || ndc.z > 1.0);
    l.p = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * size;
    l.depth = ndc.z;

    let a = dot(geometric, view.light_right.xyz);
    let b = dot(geometric, view.light_up.xyz);
    let c = dot(geometric, view.light_dir.xyz);
    let c_safe = select(min(c, -1e-3), max(c, 1e-3), c > 0.0);
    l.ddepth_per_texel = vec2<f32>(-a / c_safe * texel_m.x, b / c_safe * texel_m.y) / range_m;
    let m = view.light_clip_from_world;
    let m_w = vec3<f32>(m[0].w, m[1].w, m[2].w);
    if (any(m_w != vec3<f32>(0.0))) {
        // A warped view: the receiver's plane through the projection itself, as its depth
        // also changes with w along the map.
        l.ddepth_per_texel = warped_plane_gradient(m, ndc, clip.w, geometric, size, l.ddepth_per_texel);
    }
    let slope = min(abs(l.ddepth_per_texel.x) + abs(l.ddepth_per_texel.y), 10.0 * max(texel_m.x, texel_m.y) / range_m);
    // The constant bias: metres, plus texels of this view (frame.views.w, a float).
    let texel_bias_m = bitcast<f32>(frame.views.w) * max(texel_m.x, texel_m.y);
    l.bias = (frame.shadow.x + texel_bias_m) / range_m + frame.shadow.y * slope;
    l.kernel = i32(frame.params.x);
    l.first = vec2<i32>(floor(l.p - 0.5 * f32(l.kernel - 1)));
    l.view = v;
    l.size = i32(view.square.w);
    l.layer = i32(view.square.x);
    l.origin = vec2<i32>(view.square.yz);
    return l;
}

// The depth change per texel along the plane through the point with normal `n`, from the
// projection's Jacobian at the point (clip `m`, its normalised position `ndc` and clip w):
// each tangent's change of texel position and depth, solved for the depth per texel. Near a
// plane seen edge-on from the light, `fallback` (the orthographic estimate).
fn warped_plane_gradient(
    m: mat4x4<f32>,
    ndc: vec3<f32>,
    w: f32,
    n: vec3<f32>,
    size: f32,
    fallback: vec2<f32>,
) -> vec2<f32> {
    let row_x = vec3<f32>(m[0].x, m[1].x, m[2].x);
    let row_y = vec3<f32>(m[0].y, m[1].y, m[2].y);
    let row_z = vec3<f32>(m[0].z, m[1].z, m[2].z);
    let row_w = vec3<f32>(m[0].w, m[1].w, m[2].w);
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(n.x) > 0.9);
    let t1 = normalize(cross(n, helper));
    let t2 = cross(n, t1);
    // Texel position and depth per metre along a tangent.
    let along = per_metre_along(row_x, row_y, row_z, row_w, ndc, w, size, t1);
    let across = per_metre_along(row_x, row_y, row_z, row_w, ndc, w, size, t2);
    let det = along.x * across.y - along.y * across.x;
    if (abs(det) < 1e-12) {
        return fallback;
    }
    return vec2<f32>(
        (along.z * across.y - along.y * across.z) / det,
        (along.x * across.z - along.z * across.x) / det,
    );
}

// How the texel position (x, y) and normalised depth (z) change per metre along `t`.
fn per_metre_along(
    row_x: vec3<f32>,
    row_y: vec3<f32>,
    row_z: vec3<f32>,
    row_w: vec3<f32>,
    ndc: vec3<f32>,
    w: f32,
    size: f32,
    t: vec3<f32>,
) -> vec3<f32> {
    let dw = dot(row_w, t);
    let d_ndc = vec3<f32>(
        dot(row_x, t) - ndc.x * dw,
        dot(row_y, t) - ndc.y * dw,
        dot(row_z, t) - ndc.z * dw,
    ) / w;
    return vec3<f32>(0.5 * size * d_ndc.x, -0.5 * size * d_ndc.y, d_ndc.z);
}

// Whether tap `t` lies in the view's square; taps outside it count as lit.
fn tap_in_map(l: ShadowLookup, t: vec2<i32>) -> bool {
    return all(t >= vec2<i32>(0)) && all(t <= vec2<i32>(l.size - 1));
}

// Tap `t` in the depth array.
fn map_texel(l: ShadowLookup, t: vec2<i32>) -> vec2<i32> {
    return l.origin + t;
}

// Tap `t` is lit when the stored depth is at least this: the receiver's plane extended to the
// tap's texel centre, minus the bias. A caster shadows the tap only if it is nearer.
fn tap_threshold(l: ShadowLookup, t: vec2<i32>) -> f32 {
    let delta = vec2<f32>(t) + 0.5 - l.p;
    let receiver = l.depth + dot(l.ddepth_per_texel, delta);
    return receiver - l.bias;
}

// Whether every tap of `l` lies in its view's map.
fn lookup_contained(l: ShadowLookup) -> bool {
    return l.inside && all(l.first >= vec2<i32>(0)) && all(l.first + vec2<i32>(l.kernel - 1) <= vec2<i32>(l.size - 1));
}

// No view: what `chosen_view` returns when selecting by depth, or when no map holds the point.
const NO_VIEW: u32 = 0xffffffffu;

// When the frame selects by map (frame.views.z == 1, cascades/mod.rs `CascadeSelection`): the
// first of the sun's views `0..count` whose map holds every tap of the point. Selecting by
// depth needs no lookup here. A point's callers compute it once and hand it to
// `view_selected` for every view. `count`: the views that shade the sun, frame.views.x for the
// map technique, the cascades before the lights' views for many lights (layered/light.wgsl).
fn chosen_view(world_pos: vec3<f32>, geometric: vec3<f32>, count: u32) -> u32 {
    if (frame.views.z == 0u) {
        return NO_VIEW;
    }
    for (var v = 0u; v < count; v++) {
        if (lookup_contained(shadow_lookup(world_pos, geometric, v))) {
            return v;
        }
    }
    return NO_VIEW;
}

// Whether view `v` of the sun's `count` shades the point: by view depth (`blend_weight`,
// `view_shades` without a band), or by map, when `v` is `chosen` (`chosen_view`). Shading
// and the receiver passes both choose through this.
fn view_selected(v: u32, world_pos: vec3<f32>, chosen: u32, count: u32) -> bool {
    if (frame.views.z == 0u) {
        return blend_weight(v, world_pos, count) > 0.0;
    }
    return v == chosen;
}

// Whether view `v + 1` of the sun's `count` shades the depths right after `v`'s, so `v` can
// blend into it.
fn next_adjacent(v: u32, count: u32) -> bool {
    return v + 1u < count
        && shadow_views[v + 1u].shades_depth_m.x == shadow_views[v].shades_depth_m.y;
}

// How much view `v` contributes at the point, by view depth: 1 inside its depths, falling to 0
// over the blend band at their far end (frame.shadow.w of the depths, cascades/mod.rs) where
// the next view takes over, and what the previous view gives up in its band. Without a band,
// 1 exactly where `view_shades`.
fn blend_weight(v: u32, world_pos: vec3<f32>, count: u32) -> f32 {
    let band = frame.shadow.w;
    if (band <= 0.0) {
        return select(0.0, 1.0, view_shades(v, world_pos));
    }
    let depth_m = shading_depth(v, world_pos);
    let own = shadow_views[v].shades_depth_m;
    if (depth_m >= own.x && depth_m < own.y) {
        if (!next_adjacent(v, count)) {
            return 1.0;
        }
        return band_left(own.xy, depth_m, band);
    }
    if (v > 0u && next_adjacent(v - 1u, count)) {
        let before = shadow_views[v - 1u].shades_depth_m;
        let depth_before = shading_depth(v - 1u, world_pos);
        if (depth_before >= before.x && depth_before < before.y) {
            return 1.0 - band_left(before.xy, depth_before, band);
        }
    }
    return 0.0;
}

// Over the last share `band` of the depths `range`, from 1 down to 0 at their far end.
fn band_left(range: vec2<f32>, depth_m: f32, band: f32) -> f32 {
    return clamp((range.y - depth_m) / band_width(range, band), 0.0, 1.0);
}

// How deep the blend band `band` at the far end of the depths `range` is, metres.
fn band_width(range: vec2<f32>, band: f32) -> f32 {
    return max(band * (range.y - max(range.x, 0.0)), 1e-6);
}

// How far the shadow has faded out at the point: over the blend band at the far end of the
// last of the sun's `count` views, from 0 to 1.
fn fade_out(world_pos: vec3<f32>, count: u32) -> f32 {
    let band = frame.shadow.w;
    if (band <= 0.0 || count == 0u) {
        return 0.0;
    }
    let last = shadow_views[count - 1u].shades_depth_m;
    let depth_m = shading_depth(count - 1u, world_pos);
    if (depth_m < last.x || depth_m >= last.y) {
        return 0.0;
    }
    return 1.0 - band_left(last.xy, depth_m, band);
}
