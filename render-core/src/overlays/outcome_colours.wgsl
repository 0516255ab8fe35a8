// What happened to a caster in the shadow pass, as a colour: the camera's `casters` tint
// (frame/camera.wgsl) and the stripes of the light's view inset (overlays/light_inset.wgsl).
// Green rendered, purple excluded, orange culled by the light frustum (or left out of the
// oracle's set), yellow by light occlusion, magenta by the mask, changed region or shadow
// volume (the colours: palette.rs, which the legends share). Alpha is how strongly the camera tint covers the object (0: not a caster).
#import culling/codes.wgsl
#import palette.wgsl

fn outcome_colour(code: u32) -> vec4<f32> {
    switch code {
        case OUTCOME_NOT_CASTER: { return vec4<f32>(0.0); }
        case OUTCOME_RENDERED: { return vec4<f32>(PALETTE_RENDERED, 0.55); }
        case OUTCOME_EXCLUDED: { return vec4<f32>(PALETTE_EXCLUDED, 0.6); }
        case OUTCOME_CULLED_LIGHT_FRUSTUM, OUTCOME_CULLED_ORACLE: {
            return vec4<f32>(PALETTE_CULLED_LIGHT_FRUSTUM, 0.6);
        }
        case OUTCOME_CULLED_LIGHT_OCCLUSION: { return vec4<f32>(PALETTE_CULLED_LIGHT_OCCLUSION, 0.6); }
        default: { return vec4<f32>(PALETTE_CULLED_MASK, 0.6); }
    }
}
