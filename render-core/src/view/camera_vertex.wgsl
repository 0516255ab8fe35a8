// The camera's vertex stage. Shading (frame/camera.wgsl) and the receiver passes that must
// agree with it bit for bit (culling/receivers.wgsl) share it.
#import view/common.wgsl

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
