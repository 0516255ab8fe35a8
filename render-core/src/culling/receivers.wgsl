// Receiver passes in the camera's view, before the shadow maps are drawn. They run with the
// camera's depth test EQUAL, so exactly the visible fragments arrive, and they compute every
// PCF tap exactly as shading will (shadow_view/lookup.wgsl), in every view that shades the
// fragment (`view_selected`, as shading chooses).
// - FRAG's mask (Bittner 4.4): each visible receiver fragment marks the texels that the taps
//   of its pixel's footprint read (`mark_receiver_pixel`), with the depth a caster must be
//   nearer than to shadow them. This is the reverse shadow test turned around: the camera's
//   fragments mark the light's texels, so the mask needs no bias. The footprint, not only the
//   pixel's centre, keeps the shadow of a point the next frame's pixel centres land on after
//   a small move or turn (frame/flicker.rs).
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
    // A light's perspective view (many lights) shades every point in its map.
    let selected = shadow_views[v].index.y == 1u || view_selected(v, in.world_pos, chosen, frame.views.x);
    l.inside = l.inside && receives && frame.params.y != 0u && selected;
    return l;
}

// Marks every tap that a point of the pixel's footprint within `reach` texels of the lookup
// position reads, each with the depth the receiver's plane needs there (`tap_threshold`).
fn mark_fragment_mask(l: ShadowLookup, reach: vec2<f32>) {
    let params = cull_views[l.view].params;
    let scale = params.z;
    let mask_size = params.w;
    let block = l.view * mask_size * mask_size;
    let taps = footprint_taps(l, reach);
    let lo = max(taps[0], vec2<i32>(0));
    let hi = min(taps[1], vec2<i32>(l.size - 1));
    for (var y = lo.y; y <= hi.y; y++) {
        for (var x = lo.x; x <= hi.x; x++) {
            let t = vec2<i32>(x, y);
            let needed = tap_threshold(l, t);
            if (needed <= 0.0) {
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

// The pixel's footprint on the receiver's plane: the disc of the pixel's half diagonal across
// the view, carried along the camera ray onto the plane. A point of the footprint lies at
// `e - (n.e / n.u) u` from the pixel's point for an offset `e` across the view (|e| <= radius,
// e at right angles to the view direction), so its extent along any `axis` has a closed form.
struct PixelFootprint {
    // From the eye to the point, unit.
    ray: vec3<f32>,
    normal: vec3<f32>,
    // n.u, kept away from 0 so that a plane seen edge-on reaches at most 1 / MIN_FACING pixels.
    facing: f32,
    radius_m: f32,
}

// How obliquely a footprint may be seen before it stops growing (1 / 0.02: 50 pixel widths
// along the view). A receiver seen more edge-on than this from the camera keeps its centre's
// taps and the 50 widths around them.
const MIN_FACING: f32 = 0.02;
// At most this many texels each way around the lookup position, to bound the work per pixel.
const MAX_REACH_TEXELS: f32 = 8.0;

fn pixel_footprint(world_pos: vec3<f32>, geometric: vec3<f32>) -> PixelFootprint {
    var f: PixelFootprint;
    let from_eye = world_pos - frame.eye_world.xyz;
    f.ray = from_eye * inverseSqrt(max(dot(from_eye, from_eye), 1e-12));
    f.normal = geometric;
    let facing = dot(geometric, f.ray);
    f.facing = select(min(facing, -MIN_FACING), max(facing, MIN_FACING), facing > 0.0);
    let view_depth = max(dot(from_eye, frame.camera_forward.xyz), 0.0);
    f.radius_m = frame.camera_forward.w * view_depth * 0.70710678;
    return f;
}

// How far the footprint reaches from its centre along `axis`, metres.
fn footprint_extent(f: PixelFootprint, axis: vec3<f32>) -> f32 {
    let g = axis - dot(axis, f.ray) / f.facing * f.normal;
    let forward = frame.camera_forward.xyz;
    return f.radius_m * length(g - dot(g, forward) * forward);
}

// How far the footprint reaches from the lookup position in view `v`, texels.
// A warped (LiSPSM) view's texel sizes are those at the point (`shadow_lookup`).
fn footprint_reach(f: PixelFootprint, v: u32, world_pos: vec3<f32>) -> vec2<f32> {
    let view = shadow_views[v];
    let w = (view.light_clip_from_world * vec4<f32>(world_pos, 1.0)).w;
    let texel_m = vec2<f32>(view.light_right.w * w, view.light_up.w * w * w);
    let reach = vec2<f32>(
        footprint_extent(f, view.light_right.xyz),
        footprint_extent(f, view.light_up.xyz),
    ) / max(texel_m, vec2<f32>(1e-12));
    return min(reach, vec2<f32>(MAX_REACH_TEXELS));
}

// How far the footprint's camera depth, as view `v` measures it, reaches from the centre's.
fn footprint_depth_reach(f: PixelFootprint, v: u32) -> f32 {
    if (shadow_views[v].shades_depth_m.z > 0.5) {
        return footprint_extent(f, f.ray);
    }
    return footprint_extent(f, frame.camera_forward.xyz);
}

// Whether view `v` shades a point of camera depth within `reach` of the point's: within its
// depths, or the band at the end of the view before it that blends into it.
fn view_may_shade(v: u32, world_pos: vec3<f32>, reach: f32) -> bool {
    let depth_m = shading_depth(v, world_pos);
    let own = shadow_views[v].shades_depth_m;
    var near = own.x;
    let band = frame.shadow.w;
    if (band > 0.0 && v > 0u && next_adjacent(v - 1u, frame.views.x)) {
        let before = shadow_views[v - 1u].shades_depth_m;
        near = before.y - band_width(before.xy, band);
    }
    return depth_m + reach >= near && depth_m - reach < own.y;
}

// FRAG's mask for one visible receiver pixel: every tap that a point of its footprint reads,
// in every view that may shade such a point, so that a point between this frame's pixel
// centres (the next frame's, after a small move) finds its casters too. Selecting by map, a
// point takes the first view holding all its taps: the views up to the first that holds the
// whole footprint's. A light's perspective views (many lights) each shade the point too.
fn mark_receiver_pixel(world_pos: vec3<f32>, geometric: vec3<f32>) {
    let f = pixel_footprint(world_pos, geometric);
    let by_map = frame.views.z != 0u;
    // A view of the sun holds the whole footprint: the sun's later views do not shade it.
    var held = false;
    for (var v = 0u; v < frame.views.x; v++) {
        let perspective = shadow_views[v].index.y == 1u;
        if (held && !perspective) {
            continue;
        }
        if (!by_map && !view_may_shade(v, world_pos, footprint_depth_reach(f, v))) {
            continue;
        }
        let l = shadow_lookup(world_pos, geometric, v);
        if (l.depth > 1.0) {
            continue;
        }
        let reach = footprint_reach(f, v, world_pos);
        mark_fragment_mask(l, reach);
        let taps = footprint_taps(l, reach);
        if (by_map && !perspective && all(taps[0] >= vec2<i32>(0)) && all(taps[1] <= vec2<i32>(l.size - 1))) {
            // Every tap of every point of the footprint lies in this view's map.
            held = true;
        }
    }
}

// The first and the last tap that a point within `reach` texels of the lookup position reads.
fn footprint_taps(l: ShadowLookup, reach: vec2<f32>) -> array<vec2<i32>, 2> {
    let half_kernel = 0.5 * f32(l.kernel - 1);
    return array<vec2<i32>, 2>(
        vec2<i32>(floor(l.p - reach - half_kernel)),
        vec2<i32>(floor(l.p + reach - half_kernel)) + vec2<i32>(l.kernel - 1),
    );
}

@early_depth_test(force)
@fragment
fn fs_fragment_mask(in: VsOut) {
    let receives = (instances[in.instance].flags.x & FLAG_RECEIVER) != 0u;
    if (receives && frame.params.y != 0u) {
        mark_receiver_pixel(in.world_pos, geometric_normal(in.world_pos, in.normal));
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
    mark_receiver_pixel(world_pos, geometric);
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
    let chosen = chosen_view(in.world_pos, geometric, frame.views.x);
    for (var v = 0u; v < frame.views.x; v++) {
        let l = receiver_lookup(in, geometric, v, chosen);
        if (l.inside) {
            mark_oracle_casters(l);
        }
    }
}
