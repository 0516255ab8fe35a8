// Depth-only rendering of casters into the shadow map. Prepended with frame/instance.wgsl and frame/common.wgsl.

@vertex
fn vs_shadow(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    return frame.light_clip_from_world * vec4<f32>(world_position(instance, position), 1.0);
}
