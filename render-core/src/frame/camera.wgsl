// The camera passes: a depth + object-id prepass, then shading with the shadow technique's
// "light reaching this point" (technique/light.wgsl: the technique's own file, for the
// method and, when measuring, the reference).
#import view/camera_vertex.wgsl
#import metrics/measure.wgsl
#import overlays/outcome_colours.wgsl
#import technique/light.wgsl

const OVERLAY_CASTERS: u32 = 1u;
const OVERLAY_VIEWS: u32 = 2u;

struct PrepassOut {
    // Instance index + 1, 0 is sky.
    @location(0) id: u32,
    // The surface every shadow lookup starts from (view/targets.rs, SURFACE_FORMAT).
    @location(1) position: vec4<f32>,
    @location(2) normal: vec4<f32>,
}

// Object id and surface per pixel. The geometric normal is the shading pass's, from the same
// derivatives of the same interpolated position; w is 1 where the shading normal (turned to
// the eye, as `fs_shade` turns it) faces the light and a spot's cone holds the point, so that
// shadow changes the pixel.
@fragment
fn fs_prepass(in: VsOut) -> PrepassOut {
    var out: PrepassOut;
    out.id = in.instance + 1u;
    out.position = vec4<f32>(in.world_pos, 1.0);
    let n = select(in.normal, -in.normal, dot(in.normal, frame.eye_world.xyz - in.world_pos) < 0.0);
    let lit_side = dot(n, towards_light(in.world_pos).xyz) > 0.0 && light_reaches(in.world_pos);
    out.normal = vec4<f32>(geometric_normal(in.world_pos, in.normal), select(0.0, 1.0, lit_side));
    return out;
}

struct ShadeOut {
    @location(0) color: vec4<f32>,
    @location(1) shadow: vec4<f32>,
}

// The depth test must run before this shader: its counters and oracle marks are side effects
// that hidden fragments must not have. The frame removes the attribute (and measurement)
// on devices without SHADER_EARLY_DEPTH_TEST.
@early_depth_test(force)
@fragment
fn fs_shade(in: VsOut) -> ShadeOut {
    let to_eye = frame.eye_world.xyz - in.world_pos;
    let geometric = geometric_normal(in.world_pos, in.normal);
    var n = in.normal;
    n = select(n, -n, dot(n, to_eye) < 0.0);

    let data = instances[in.instance];
    let receives = (data.flags.x & FLAG_RECEIVER) != 0u;
    var light = LightReaching(1.0, 1.0, 0u, false, vec3<f32>(0.0));
    if (frame.params.y != 0u && receives) {
        let measuring = frame.params.z != 0u;
        light = light_reaching(in.world_pos, geometric, measuring);
        if (measuring) {
            count_error(light.method, light.reference);
            if (light.shaded) {
                count_undersampling(light.view, in.world_pos, geometric);
            }
        }
    } else {
        light.added = light_unshadowed(in.world_pos, geometric);
    }
    let visibility = light.method;
    let light_here = towards_light(in.world_pos);
    let l = light_here.xyz;
    let diffuse = max(dot(n, l), 0.0) * light_here.w * visibility;
    let sky = mix(vec3<f32>(0.30, 0.28, 0.25), vec3<f32>(0.45, 0.55, 0.70), n.y * 0.5 + 0.5);
    // Without the sun (a technique lit by the scene's own lights) the sky is dimmer.
    let ambient = sky * select(0.12, 0.35, frame.direction_to_sun.w > 0.0);
    let sun = vec3<f32>(1.0, 0.95, 0.85);
    var out: ShadeOut;
    var color = data.base_color.rgb * (ambient + sun * diffuse + light.added);
    if ((frame.params.w & OVERLAY_CASTERS) != 0u) {
        let code = outcomes[light.view * frame.views.y + in.instance] & STATE_OUTCOME_BITS;
        let tint = outcome_colour(code);
        color = mix(color, tint.rgb * (0.35 + 0.65 * max(dot(n, l), 0.0)), tint.a);
    }
    if ((frame.params.w & OVERLAY_VIEWS) != 0u && light.shaded) {
        color = mix(color, palette_view(light.view), 0.35);
    }
    out.color = vec4<f32>(color, 1.0);
    out.shadow = vec4<f32>(visibility, light.reference, 0.0, 1.0);
    return out;
}
