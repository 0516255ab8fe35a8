// The light's view for the inset: shadow-map depth as grey, near (towards the sun) bright.

@group(0) @binding(0) var shadow_map: texture_depth_2d;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

@vertex
fn vs_fullscreen(@builtin(vertex_index) index: u32) -> VsOut {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    var out: VsOut;
    out.clip = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
    out.uv = uv;
    return out;
}

@fragment
fn fs_light_view(in: VsOut) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(shadow_map));
    let texel = vec2<i32>(clamp(in.uv * size, vec2<f32>(0.0), size - 1.0));
    let depth = textureLoad(shadow_map, texel, 0);
    let near = pow(clamp(1.0 - depth, 0.0, 1.0), 2.0);
    let cleared = depth >= 1.0;
    let grey = select(vec3<f32>(0.05 + 0.95 * near), vec3<f32>(0.02, 0.02, 0.08), cleared);
    return vec4<f32>(grey, 1.0);
}
