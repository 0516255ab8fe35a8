// One instance of the scene. Keep in sync with frame/gpu_data.rs (InstanceData).

struct InstanceData {
    world_from_local: mat4x4<f32>,
    normal_from_local: array<vec4<f32>, 3>,
    base_color: vec4<f32>,
    flags: vec4<u32>,
}

const FLAG_CASTER: u32 = 1u;
const FLAG_RECEIVER: u32 = 2u;
