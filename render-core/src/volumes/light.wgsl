// The shadow-volume technique's "light reaching this point": lit where the stencil the volume
// passes left at the point's pixel is 0, none where any volume holds it (volumes/mod.rs). The
// point is found in the camera's picture, so the truth's points (truth/at_points.wgsl) read
// the pixel they were cast through. Hard shadows: no reference and no views to shade by.
// Bound as group 1 of the shading pass.
#import view/common.wgsl

@group(1) @binding(0) var volume_stencil: texture_2d<u32>;

struct LightReaching {
    method: f32,
    reference: f32,
    view: u32,
    shaded: bool,
    // Light of the technique's own lights (many lights), added to the sun's; none here.
    added: vec3<f32>,
}

// The technique's own lights without shadows (where the frame does not shadow the point).
fn light_unshadowed(world_pos: vec3<f32>, geometric: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}

fn light_reaching(world_pos: vec3<f32>, geometric: vec3<f32>, measuring: bool) -> LightReaching {
    let clip = frame.clip_from_world * vec4<f32>(world_pos, 1.0);
    let size = vec2<f32>(textureDimensions(volume_stencil));
    let ndc = clip.xy / clip.w;
    let pixel = vec2<i32>(floor(vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * size));
    let inside = clip.w > 0.0 && all(pixel >= vec2<i32>(0)) && all(vec2<f32>(pixel) < size);
    var light = 1.0;
    if (inside && textureLoad(volume_stencil, pixel, 0).r != 0u) {
        light = 0.0;
    }
    return LightReaching(light, light, 0u, false, vec3<f32>(0.0));
}
