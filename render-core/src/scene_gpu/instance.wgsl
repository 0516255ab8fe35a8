// One instance of the scene and its world-space bounds. Keep in sync with
// scene_gpu/gpu_data.rs (InstanceData, InstanceBounds, FLAG_*); the validation test compares
// the flags.

struct InstanceData {
    world_from_local: mat4x4<f32>,
    normal_from_local: array<vec4<f32>, 3>,
    base_color: vec4<f32>,
    flags: vec4<u32>,
}

struct InstanceBounds {
    // The world-space box and the FLAG_* bits.
    min: vec3<f32>,
    flags: u32,
    max: vec3<f32>,
    padding: u32,
}

const FLAG_CASTER: u32 = 1u;
const FLAG_RECEIVER: u32 = 2u;
const FLAG_DYNAMIC: u32 = 4u;
