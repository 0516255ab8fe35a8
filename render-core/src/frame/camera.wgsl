// The camera passes: a depth + object-id prepass, then shading with the shadow map.
// Prepended with frame/instance.wgsl, frame/common.wgsl and frame/shadow_lookup.wgsl.

@group(1) @binding(0) var shadow_map: texture_depth_2d;
// Measurement (metrics/mod.rs): the reference map of every caster, its caster ids, the oracle
// flags and the counters. Used only when frame.params.z != 0.
@group(1) @binding(1) var reference_map: texture_depth_2d;
@group(1) @binding(2) var reference_ids: texture_2d<u32>;
@group(1) @binding(3) var<storage, read_write> oracle: array<atomic<u32>>;
@group(1) @binding(4) var<storage, read_write> measured: Measured;

// Per object: 0 not a caster, 1 rendered, 2 excluded, 3 + k culled by stage k
// (frame/gpu_data.rs, outcome_code). Read for the `casters` overlay.
@group(2) @binding(0) var<storage, read> outcomes: array<u32>;

const OVERLAY_CASTERS: u32 = 1u;

fn outcome_tint(code: u32) -> vec4<f32> {
    switch code {
        case 0u: { return vec4<f32>(0.0); }
        case 1u: { return vec4<f32>(0.15, 0.85, 0.25, 0.55); }
        case 2u: { return vec4<f32>(0.6, 0.2, 0.9, 0.6); }
        case 3u, 4u: { return vec4<f32>(1.0, 0.55, 0.05, 0.6); }
        case 5u: { return vec4<f32>(0.95, 0.85, 0.1, 0.6); }
        default: { return vec4<f32>(0.95, 0.1, 0.75, 0.6); }
    }
}

// Keep in sync with metrics/mod.rs (`counters: GpuCounters<4>` and `take_latest`).
struct Measured {
    visible_px: atomic<u32>,
    missing_px: atomic<u32>,
    extra_px: atomic<u32>,
    oracle_casters: atomic<u32>,
}

// Object id per pixel: instance index + 1, 0 is sky.
@fragment
fn fs_prepass(in: VsOut) -> @location(0) u32 {
    return in.instance + 1u;
}

struct ShadeOut {
    @location(0) color: vec4<f32>,
    @location(1) shadow: vec4<f32>,
}

// Fraction of kernel taps that see the light (frame/shadow_lookup.wgsl). With `mark_oracle`,
// every shadowed tap marks the reference caster that won its texel.
fn shadow_factor(map: texture_depth_2d, l: ShadowLookup, mark_oracle: bool) -> f32 {
    if (!l.inside) {
        return 1.0;
    }
    var lit = 0.0;
    for (var j = 0; j < l.kernel; j++) {
        for (var i = 0; i < l.kernel; i++) {
            let t = l.first + vec2<i32>(i, j);
            if (!tap_in_map(t)) {
                lit += 1.0;
                continue;
            }
            let stored = textureLoad(map, t, 0);
            let tap_lit = tap_threshold(l, t) <= stored;
            lit += select(0.0, 1.0, tap_lit);
            if (mark_oracle && !tap_lit) {
                let caster = textureLoad(reference_ids, t, 0).x;
                if (caster != 0u && atomicOr(&oracle[caster - 1u], 1u) == 0u) {
                    atomicAdd(&measured.oracle_casters, 1u);
                }
            }
        }
    }
    return lit / f32(l.kernel * l.kernel);
}

// The depth test must run before this shader: its counters and oracle marks are side effects
// that hidden fragments must not have. FrameRenderer removes the attribute (and measurement)
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
    var visibility = 1.0;
    var reference = 1.0;
    if (frame.params.y != 0u && receives) {
        let lookup = shadow_lookup(in.world_pos, geometric);
        visibility = shadow_factor(shadow_map, lookup, false);
        reference = visibility;
        if (frame.params.z != 0u) {
            reference = shadow_factor(reference_map, lookup, true);
            atomicAdd(&measured.visible_px, 1u);
            if (reference < visibility) {
                atomicAdd(&measured.missing_px, 1u);
            } else if (reference > visibility) {
                atomicAdd(&measured.extra_px, 1u);
            }
        }
    }
    let l = frame.direction_to_sun.xyz;
    let diffuse = max(dot(n, l), 0.0) * frame.direction_to_sun.w * visibility;
    let sky = mix(vec3<f32>(0.30, 0.28, 0.25), vec3<f32>(0.45, 0.55, 0.70), n.y * 0.5 + 0.5);
    let ambient = sky * 0.35;
    let sun = vec3<f32>(1.0, 0.95, 0.85);
    var out: ShadeOut;
    var color = data.base_color.rgb * (ambient + sun * diffuse);
    if ((frame.params.w & OVERLAY_CASTERS) != 0u) {
        let tint = outcome_tint(outcomes[in.instance] & 0xffu);
        color = mix(color, tint.rgb * (0.35 + 0.65 * max(dot(n, l), 0.0)), tint.a);
    }
    out.color = vec4<f32>(color, 1.0);
    out.shadow = vec4<f32>(visibility, reference, 0.0, 1.0);
    return out;
}
