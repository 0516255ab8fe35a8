// The shadow-volume fill heat map (volumes/fill.rs): every pixel that volume faces cover,
// from blue (one fragment) to yellow (PALETTE_FILL_HIGH_COUNT and more), on a log scale.
#import palette.wgsl

// [0] fragments, [1] behind the surface, then one count per pixel (volumes/draw.wgsl).
@group(0) @binding(0) var<storage, read> fill: array<u32>;
// x: the view's width in pixels.
@group(0) @binding(1) var<uniform> fill_size: vec4<u32>;

@vertex
fn vs_fullscreen(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
}

@fragment
fn fs_fill_heat(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<u32>(position.xy);
    let count = fill[2u + pixel.y * fill_size.x + pixel.x];
    if (count == 0u) {
        discard;
    }
    let t = clamp(log2(f32(count)) / log2(f32(PALETTE_FILL_HIGH_COUNT)), 0.0, 1.0);
    return vec4<f32>(mix(PALETTE_FILL_LOW, PALETTE_FILL_HIGH, t), 0.35 + 0.4 * t);
}
