// Receiver passes in the camera's view, before the shadow map is drawn. They run with the
// camera's depth test EQUAL, so exactly the visible fragments arrive, and they compute every
// PCF tap exactly as shading will (frame/shadow_lookup.wgsl).
// - FRAG's mask (Bittner 4.4): each visible receiver fragment marks the texels its taps read
//   with the depth a caster must be nearer than to shadow it. This is the reverse shadow test
//   turned around: the camera's fragments mark the light's texels, so the mask is exact and
//   needs no bias.
// - The oracle method: each shadowed tap marks the reference caster that wins its texel.
// Prepended with frame/instance.wgsl, frame/common.wgsl and frame/shadow_lookup.wgsl.

// x: mask size in texels; y: shadow texels per mask texel.
@group(1) @binding(0) var<uniform> mask_size: vec4<u32>;
@group(1) @binding(1) var<storage, read_write> mask_bits: array<atomic<u32>>;
@group(1) @binding(2) var reference_map: texture_depth_2d;
@group(1) @binding(3) var reference_ids: texture_2d<u32>;
@group(1) @binding(4) var<storage, read_write> oracle: array<atomic<u32>>;

// Added to the depth a tap needs, in normalised depth, so that the mask never falls short of
// the shading pass's own arithmetic.
const MASK_MARGIN: f32 = 1e-5;

fn receiver_lookup(in: VsOut, geometric: vec3<f32>) -> ShadowLookup {
    var l = shadow_lookup(in.world_pos, geometric);
    let receives = (instances[in.instance].flags.x & FLAG_RECEIVER) != 0u;
    l.inside = l.inside && receives && frame.params.y != 0u;
    return l;
}

@early_depth_test(force)
@fragment
fn fs_fragment_mask(in: VsOut) {
    let l = receiver_lookup(in, geometric_normal(in.world_pos, in.normal));
    if (!l.inside) {
        return;
    }
    let scale = mask_size.y;
    for (var j = 0; j < l.kernel; j++) {
        for (var i = 0; i < l.kernel; i++) {
            let t = l.first + vec2<i32>(i, j);
            let needed = tap_threshold(l, t);
            if (!tap_in_map(t) || needed <= 0.0) {
                continue;
            }
            let m = vec2<u32>(t) / scale;
            let index = m.y * mask_size.x + m.x;
            // Positive floats order as their bits. Neighbouring pixels mostly mark the same
            // texels with about the same depth: a plain load skips most read-modify-writes.
            let bits = bitcast<u32>(needed + MASK_MARGIN);
            if (bits > atomicLoad(&mask_bits[index])) {
                atomicMax(&mask_bits[index], bits);
            }
        }
    }
}

@early_depth_test(force)
@fragment
fn fs_oracle(in: VsOut) {
    let l = receiver_lookup(in, geometric_normal(in.world_pos, in.normal));
    if (!l.inside) {
        return;
    }
    for (var j = 0; j < l.kernel; j++) {
        for (var i = 0; i < l.kernel; i++) {
            let t = l.first + vec2<i32>(i, j);
            if (!tap_in_map(t) || tap_threshold(l, t) <= textureLoad(reference_map, t, 0)) {
                continue;
            }
            let caster = textureLoad(reference_ids, t, 0).x;
            if (caster != 0u) {
                atomicOr(&oracle[caster - 1u], 1u);
            }
        }
    }
}
