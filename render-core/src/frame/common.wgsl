// Frame uniforms and scene bindings shared by the camera and shadow passes.
// Prepended with frame/instance.wgsl. Keep in sync with frame/gpu_data.rs (FrameUniforms).

struct FrameUniforms {
    clip_from_world: mat4x4<f32>,
    light_clip_from_world: mat4x4<f32>,
    eye_world: vec4<f32>,
    direction_to_sun: vec4<f32>,
    light_right: vec4<f32>,
    light_up: vec4<f32>,
    light_dir: vec4<f32>,
    shadow: vec4<f32>,
    params: vec4<u32>,
}


@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> instances: array<InstanceData>;

fn world_position(instance: u32, local: vec3<f32>) -> vec3<f32> {
    return (instances[instance].world_from_local * vec4<f32>(local, 1.0)).xyz;
}

fn world_normal(instance: u32, local: vec3<f32>) -> vec3<f32> {
    let m = instances[instance].normal_from_local;
    let n = m[0].xyz * local.x + m[1].xyz * local.y + m[2].xyz * local.z;
    let len = length(n);
    return select(vec3<f32>(0.0, 1.0, 0.0), n / len, len > 0.0);
}
