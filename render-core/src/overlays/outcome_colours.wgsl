// What happened to a caster in the shadow pass, as a colour: the camera's `casters` tint
// (frame/camera.wgsl) and the stripes of the light's view inset (overlays/light_inset.wgsl).
// Green rendered, purple excluded, orange culled by the light frustum (or left out of the
// oracle's set), yellow by light occlusion, magenta by the mask, changed region or shadow
// volume. Alpha is how strongly the camera tint covers the object (0: not a caster).
#import culling/codes.wgsl

fn outcome_colour(code: u32) -> vec4<f32> {
    switch code {
        case OUTCOME_NOT_CASTER: { return vec4<f32>(0.0); }
        case OUTCOME_RENDERED: { return vec4<f32>(0.15, 0.85, 0.25, 0.55); }
        case OUTCOME_EXCLUDED: { return vec4<f32>(0.6, 0.2, 0.9, 0.6); }
        case OUTCOME_CULLED_LIGHT_FRUSTUM, OUTCOME_CULLED_ORACLE: {
            return vec4<f32>(1.0, 0.55, 0.05, 0.6);
        }
        case OUTCOME_CULLED_LIGHT_OCCLUSION: { return vec4<f32>(0.95, 0.85, 0.1, 0.6); }
        default: { return vec4<f32>(0.95, 0.1, 0.75, 0.6); }
    }
}
