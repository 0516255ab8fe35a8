// The error heat map: tints pixels whose shadow differs from the reference. Red: shadow missing
// (the reference is darker), blue: extra shadow. Reads the shading pass's shadow target
// (red channel: method, green: reference).
#import palette.wgsl

@group(0) @binding(0) var shadow_factors: texture_2d<f32>;

@vertex
fn vs_fullscreen(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
}

@fragment
fn fs_heat_map(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let f = textureLoad(shadow_factors, vec2<i32>(position.xy), 0);
    let difference = f.g - f.r;
    if (abs(difference) < 0.5 / 255.0) {
        discard;
    }
    let strength = 0.45 + 0.5 * min(abs(difference), 1.0);
    return vec4<f32>(select(PALETTE_EXTRA_SHADOW, PALETTE_MISSING_SHADOW, difference < 0.0), strength);
}
