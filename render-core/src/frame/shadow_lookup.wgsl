// The camera's vertex stage and where a camera fragment reads the shadow map. Shading
// (frame/camera.wgsl) and the receiver passes that must agree with it bit for bit
// (culling/receivers.wgsl) share these functions.
// Prepended with frame/instance.wgsl and frame/common.wgsl.

struct VsOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) instance: u32,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @builtin(instance_index) instance: u32,
) -> VsOut {
    var out: VsOut;
    out.world_pos = world_position(instance, position);
    out.clip = frame.clip_from_world * vec4<f32>(out.world_pos, 1.0);
    out.normal = world_normal(instance, normal);
    out.instance = instance;
    return out;
}

// The face normal from screen-space derivatives, facing the eye. Call in uniform control flow.
fn geometric_normal(world_pos: vec3<f32>, shading_normal: vec3<f32>) -> vec3<f32> {
    let to_eye = frame.eye_world.xyz - world_pos;
    var g = cross(dpdx(world_pos), dpdy(world_pos));
    g = select(shading_normal, normalize(g), length(g) > 0.0);
    return select(g, -g, dot(g, to_eye) < 0.0);
}

// One fragment's shadow lookup: the PCF taps and the receiver's plane across them.
struct ShadowLookup {
    // Lookup position in texels.
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
}

fn shadow_lookup(world_pos: vec3<f32>, geometric: vec3<f32>) -> ShadowLookup {
    var l: ShadowLookup;
    let texel_m = vec2<f32>(frame.light_right.w, frame.light_up.w);
    let range_m = max(frame.light_dir.w, 1e-6);
    let size = frame.shadow.w;
    let offset_pos = world_pos + geometric * (frame.shadow.z * max(texel_m.x, texel_m.y));
    let clip = frame.light_clip_from_world * vec4<f32>(offset_pos, 1.0);
    let ndc = clip.xyz / clip.w;
    l.inside = !(abs(ndc.x) > 1.0 || abs(ndc.y) > 1.0 || ndc.z > 1.0);
    l.p = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * size;
    l.depth = ndc.z;

    let a = dot(geometric, frame.light_right.xyz);
    let b = dot(geometric, frame.light_up.xyz);
    let c = dot(geometric, frame.light_dir.xyz);
    let c_safe = select(min(c, -1e-3), max(c, 1e-3), c > 0.0);
    l.ddepth_per_texel = vec2<f32>(-a / c_safe * texel_m.x, b / c_safe * texel_m.y) / range_m;
    let slope = min(abs(l.ddepth_per_texel.x) + abs(l.ddepth_per_texel.y), 10.0 * max(texel_m.x, texel_m.y) / range_m);
    l.bias = frame.shadow.x / range_m + frame.shadow.y * slope;
    l.kernel = i32(frame.params.x);
    l.first = vec2<i32>(floor(l.p - 0.5 * f32(l.kernel - 1)));
    return l;
}

// Whether tap `t` lies in the map; taps outside it count as lit.
fn tap_in_map(t: vec2<i32>) -> bool {
    let max_texel = i32(frame.shadow.w) - 1;
    return all(t >= vec2<i32>(0)) && all(t <= vec2<i32>(max_texel));
}

// Tap `t` is lit when the stored depth is at least this: the receiver's plane extended to the
// tap's texel centre, minus the bias. A caster shadows the tap only if it is nearer.
fn tap_threshold(l: ShadowLookup, t: vec2<i32>) -> f32 {
    let delta = vec2<f32>(t) + 0.5 - l.p;
    let receiver = l.depth + dot(l.ddepth_per_texel, delta);
    return receiver - l.bias;
}
