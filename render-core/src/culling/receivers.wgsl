// Receiver passes in the camera's view, before the shadow maps are drawn. They run with the
// camera's depth test EQUAL, so exactly the visible fragments arrive, and they compute every
// PCF tap exactly as shading will (shadow_view/lookup.wgsl), in every view that shades the
// fragment (`view_selected`, as shading chooses).
// - FRAG's mask (Bittner 4.4): each visible receiver fragment marks the texels its taps read
//   with the depth a caster must be nearer than to shadow it. This is the reverse shadow test
//   turned around: the camera's fragments mark the light's texels, so the mask is exact and
//   needs no bias.
// - The oracle method: each shadowed tap marks the reference caster that wins its texel.
// FRAG's mask also comes from the prepass's surface targets in a compute pass
// (`cs_fragment_mask`), one thread per pixel: the same lookup from the same position and
// normal, without drawing the visible geometry again.
#import view/camera_vertex.wgsl
#import shadow_view/lookup.wgsl
#import culling/cull_common.wgsl

@group(1) @binding(0) var<storage, read> cull_views: array<CullView>;
// Per view, a block of mask side squared texels.
@group(1) @binding(1) var<storage, read_write> mask_bits: array<atomic<u32>>;
@group(1) @binding(2) var reference_maps: texture_depth_2d_array;
@group(1) @binding(3) var reference_ids: texture_2d_array<u32>;
// Per view and instance (culling/cull.wgsl's `selection`).
@group(1) @binding(4) var<storage, read_write> selection: array<atomic<u32>>;
// The prepass's object ids and visible surface (view/targets.rs), for `cs_fragment_mask`.
@group(1) @binding(5) var surface_ids: texture_2d<u32>;
@group(1) @binding(6) var surface_positions: texture_2d<f32>;
@group(1) @binding(7) var surface_normals: texture_2d<f32>;

// Added to the depth a tap needs, in normalised depth, so that the mask never falls short of
// the shading pass's own arithmetic.
const MASK_MARGIN: f32 = 1e-5;

fn receiver_lookup(in: VsOut, geometric: vec3<f32>, v: u32, chosen: u32) -> ShadowLookup {
    var l = shadow_lookup(in.world_pos, geometric, v);
    let receives = (instances[in.instance].flags.x & FLAG_RECEIVER) != 0u;
    l.inside = l.inside && receives && frame.params.y != 0u && view_selected(v, in.world_pos, chosen);
    return l;
}

fn mark_fragment_mask(l: ShadowLookup) {
    let params = cull_views[l.view].params;
    let scale = params.z;
    let mask_size = params.w;
    let block = l.view * mask_size * mask_size;
    for (var j = 0; j < l.kernel; j++) {
        for (var i = 0; i < l.kernel; i++) {
            let t = l.first + vec2<i32>(i, j);
            let needed = tap_threshold(l, t);
            if (!tap_in_map(l, t) || needed <= 0.0) {
                continue;
            }
            let m = vec2<u32>(t) / scale;
            let index = block + m.y * mask_size + m.x;
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
fn fs_fragment_mask(in: VsOut) {
    let geometric = geometric_normal(in.world_pos, in.normal);
    let chosen = chosen_view(in.world_pos, geometric);
    for (var v = 0u; v < frame.views.x; v++) {
        let l = receiver_lookup(in, geometric, v, chosen);
        if (l.inside) {
            mark_fragment_mask(l);
        }
    }
}

// FRAG's mask from the prepass's targets: each visible receiver pixel, as `fs_fragment_mask`.
@compute @workgroup_size(8, 8)
fn cs_fragment_mask(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= textureDimensions(surface_ids))) {
        return;
    }
    let object = textureLoad(surface_ids, id.xy, 0).x;
    if (object == 0u || frame.params.y == 0u) {
        return;
    }
    if ((instances[object - 1u].flags.x & FLAG_RECEIVER) == 0u) {
        return;
    }
    let world_pos = textureLoad(surface_positions, id.xy, 0).xyz;
    let geometric = textureLoad(surface_normals, id.xy, 0).xyz;
    let chosen = chosen_view(world_pos, geometric);
    for (var v = 0u; v < frame.views.x; v++) {
        if (view_selected(v, world_pos, chosen)) {
            let l = shadow_lookup(world_pos, geometric, v);
            if (l.inside) {
                mark_fragment_mask(l);
            }
        }
    }
}

fn mark_oracle_casters(l: ShadowLookup) {
    for (var j = 0; j < l.kernel; j++) {
        for (var i = 0; i < l.kernel; i++) {
            let t = l.first + vec2<i32>(i, j);
            if (!tap_in_map(l, t)) {
                continue;
            }
            let texel = map_texel(l, t);
            if (tap_threshold(l, t) <= textureLoad(reference_maps, texel, l.layer, 0)) {
                continue;
            }
            let caster = textureLoad(reference_ids, texel, l.layer, 0).x;
            if (caster != 0u) {
                atomicOr(&selection[l.view * frame.views.y + caster - 1u], SELECTION_ORACLE);
            }
        }
    }
}

@early_depth_test(force)
@fragment
fn fs_oracle(in: VsOut) {
    let geometric = geometric_normal(in.world_pos, in.normal);
    let chosen = chosen_view(in.world_pos, geometric);
    for (var v = 0u; v < frame.views.x; v++) {
        let l = receiver_lookup(in, geometric, v, chosen);
        if (l.inside) {
            mark_oracle_casters(l);
        }
    }
}
