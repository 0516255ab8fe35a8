// Frame uniforms and scene bindings shared by the camera and shadow passes: group 0 of every
// scene pass. Keep in sync with view/gpu_data.rs (FrameUniforms).
#import scene_gpu/instance.wgsl
#import shadow_view/views.wgsl

struct FrameUniforms {
    clip_from_world: mat4x4<f32>,
    // xyz: camera position; w: unused.
    eye_world: vec4<f32>,
    // xyz: unit view direction; w: a pixel's width one metre from the eye, metres.
    camera_forward: vec4<f32>,
    // xyz: unit vector towards the sun; w: sun illuminance scale.
    direction_to_sun: vec4<f32>,
    // x: constant depth bias (m); y: slope bias (texels); z: normal offset (texels); w: unused.
    shadow: vec4<f32>,
    // x: PCF kernel width in texels; y: 1 when shadows are on; z: 1 when the frame measures
    // error and oracle; w: overlay bits.
    params: vec4<u32>,
    // x: shadow views this frame; y: instances, the stride of per-view blocks of
    // per-instance data; z: how cascades are selected (0 by depth, 1 by map); w: constant
    // bias in texels of each view (f32 bits).
    views: vec4<u32>,
    // xyz: the point light that lights the frame in place of the sun; w: its intensity over
    // the sun's illuminance, candela per lux (0: the sun does; view/gpu_data.rs).
    point_light: vec4<f32>,
    // xyz: that light's direction where it is a spot (unit); w: the cosine of its outer
    // cone, -2 where it shines every way (view/gpu_data.rs NO_CONE).
    spot: vec4<f32>,
    // x: the cosine of the spot's inner cone.
    spot_inner: vec4<f32>,
}

// How much of a spot light's light leaves it along unit direction `l` (from the light):
// all within the inner cone (cosine `cos_inner`), fading to none at the outer
// (`cos_outer`); all of it where `cos_outer` is -2 (no cone).
fn spot_cone(l: vec3<f32>, direction: vec3<f32>, cos_outer: f32, cos_inner: f32) -> f32 {
    if (cos_outer < -1.5) {
        return 1.0;
    }
    return smoothstep(cos_outer, max(cos_inner, cos_outer + 1e-4), dot(l, direction));
}

// Whether the frame's light reaches `p` at all: everywhere but outside a spot's outer cone.
fn light_reaches(p: vec3<f32>) -> bool {
    if (frame.point_light.w <= 0.0) {
        return true;
    }
    let l = normalize(p - frame.point_light.xyz);
    return spot_cone(l, frame.spot.xyz, frame.spot.w, frame.spot_inner.x) > 0.0;
}

// From `p` towards the frame's light (xyz, unit) and the illuminance it gets there facing it
// (w, on the sun's scale; a spot's cone included).
fn towards_light(p: vec3<f32>) -> vec4<f32> {
    if (frame.point_light.w > 0.0) {
        let d = frame.point_light.xyz - p;
        let squared = max(dot(d, d), 1e-8);
        let l = d * inverseSqrt(squared);
        let cone = spot_cone(-l, frame.spot.xyz, frame.spot.w, frame.spot_inner.x);
        return vec4<f32>(l, frame.point_light.w * cone / squared);
    }
    return frame.direction_to_sun;
}

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> instances: array<InstanceData>;
// This frame's shadow views (shadow_view/views.wgsl).
@group(0) @binding(2) var<storage, read> shadow_views: array<ShadowView>;

fn world_position(instance: u32, local: vec3<f32>) -> vec3<f32> {
    return (instances[instance].world_from_local * vec4<f32>(local, 1.0)).xyz;
}

// Where a shadow view rasterises an instance's vertex. The shadow pass and the footprint test
// (culling/footprints.wgsl) both call this, so they cover the same texels at the same depths.
fn shadow_clip_position(view: ShadowView, instance: u32, local: vec3<f32>) -> vec4<f32> {
    return light_clip(view, world_position(instance, local));
}

fn world_normal(instance: u32, local: vec3<f32>) -> vec3<f32> {
    let m = instances[instance].normal_from_local;
    let n = m[0].xyz * local.x + m[1].xyz * local.y + m[2].xyz * local.z;
    let len = length(n);
    return select(vec3<f32>(0.0, 1.0, 0.0), n / len, len > 0.0);
}

// The point's camera depth as view `v` measures the depths it shades (shadow_view/mod.rs
// `DepthMeasure`): along the view direction, or from the eye.
fn shading_depth(v: u32, world_pos: vec3<f32>) -> f32 {
    let from_eye = world_pos - frame.eye_world.xyz;
    if (shadow_views[v].shades_depth_m.z > 0.5) {
        return length(from_eye);
    }
    return dot(from_eye, frame.camera_forward.xyz);
}

// Whether the point at `world_pos` is shaded from view `v`: within the depths it covers.
fn view_shades(v: u32, world_pos: vec3<f32>) -> bool {
    let depth_m = shading_depth(v, world_pos);
    let range = shadow_views[v].shades_depth_m;
    return depth_m >= range.x && depth_m < range.y;
}
