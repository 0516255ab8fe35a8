// The shadow-map technique's "light reaching this point": the fraction of PCF taps that see
// the light in each view that shades the point (`view_selected`), the least of them, from the
// method's maps and, when measuring, from the reference maps (marking the oracle). Bound as
// group 1 of the shading pass (shadow_map/mod.rs).
#import shadow_view/lookup.wgsl
#import metrics/measure.wgsl

@group(1) @binding(0) var shadow_maps: texture_depth_2d_array;
@group(1) @binding(1) var reference_maps: texture_depth_2d_array;
@group(1) @binding(2) var reference_ids: texture_2d_array<u32>;

// The light reaching a point, from the method's shadow and from the reference.
struct LightReaching {
    method: f32,
    reference: f32,
    // The first view that shades the point (the `casters` overlay reads its outcomes, the
    // `cascades` overlay tints by it), and whether the point lies in its map.
    view: u32,
    shaded: bool,
    // Light of the technique's own lights (many lights), added to the sun's; none here.
    added: vec3<f32>,
}

// The technique's own lights without shadows (where the frame does not shadow the point).
fn light_unshadowed(world_pos: vec3<f32>, geometric: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}

// Fraction of kernel taps that see the light. With `mark`, every shadowed tap marks the
// reference caster that won its texel (the oracle).
fn shadow_factor(reference: bool, l: ShadowLookup, mark: bool) -> f32 {
    if (!l.inside) {
        return 1.0;
    }
    var lit = 0.0;
    for (var j = 0; j < l.kernel; j++) {
        for (var i = 0; i < l.kernel; i++) {
            let t = l.first + vec2<i32>(i, j);
            if (!tap_in_map(l, t)) {
                lit += 1.0;
                continue;
            }
            let texel = map_texel(l, t);
            var stored: f32;
            if (reference) {
                stored = textureLoad(reference_maps, texel, l.layer, 0);
            } else {
                stored = textureLoad(shadow_maps, texel, l.layer, 0);
            }
            let tap_lit = tap_threshold(l, t) <= stored;
            lit += select(0.0, 1.0, tap_lit);
            if (mark && !tap_lit) {
                mark_oracle(l.view, textureLoad(reference_ids, texel, l.layer, 0).x);
            }
        }
    }
    return lit / f32(l.kernel * l.kernel);
}

// One view's light at a lookup: the method's, and the reference's when `measuring` (marking
// the oracle), else the method's again.
fn view_light(lookup: ShadowLookup, measuring: bool) -> vec2<f32> {
    let visibility = shadow_factor(false, lookup, false);
    var reference = visibility;
    if (measuring) {
        reference = shadow_factor(true, lookup, true);
    }
    return vec2<f32>(visibility, reference);
}

// `measuring`: also the reference's factor (else equal to the method's) and the oracle.
fn light_reaching(world_pos: vec3<f32>, geometric: vec3<f32>, measuring: bool) -> LightReaching {
    if (frame.shadow.w > 0.0 && frame.views.z == 0u) {
        return light_blended(world_pos, geometric, measuring);
    }
    var out = LightReaching(1.0, 1.0, 0u, false, vec3<f32>(0.0));
    var first = true;
    let chosen = chosen_view(world_pos, geometric, frame.views.x);
    for (var v = 0u; v < frame.views.x; v++) {
        if (!view_selected(v, world_pos, chosen, frame.views.x)) {
            continue;
        }
        let lookup = shadow_lookup(world_pos, geometric, v);
        if (first) {
            out.view = v;
            // Shaded by a map only where the point lies in it.
            out.shaded = lookup.inside;
            first = false;
        }
        let light = view_light(lookup, measuring);
        out.method = min(out.method, light.x);
        out.reference = min(out.reference, light.y);
    }
    return out;
}

// With a blend band between cascades: each view's light weighted by `blend_weight` among the
// views whose map holds the point, then faded towards no shadow over the last view's band.
fn light_blended(world_pos: vec3<f32>, geometric: vec3<f32>, measuring: bool) -> LightReaching {
    var out = LightReaching(1.0, 1.0, 0u, false, vec3<f32>(0.0));
    var method = 0.0;
    var reference = 0.0;
    var weight = 0.0;
    var first = true;
    for (var v = 0u; v < frame.views.x; v++) {
        let w = blend_weight(v, world_pos, frame.views.x);
        if (w <= 0.0) {
            continue;
        }
        let lookup = shadow_lookup(world_pos, geometric, v);
        if (first) {
            out.view = v;
            out.shaded = lookup.inside;
            first = false;
        }
        // A neighbour's map need not hold the band: then the other view alone shades it.
        if (!lookup.inside) {
            continue;
        }
        let light = view_light(lookup, measuring);
        method += w * light.x;
        reference += w * light.y;
        weight += w;
    }
    if (weight > 0.0) {
        let fade = fade_out(world_pos, frame.views.x);
        out.method = mix(method / weight, 1.0, fade);
        out.reference = mix(reference / weight, 1.0, fade);
    }
    return out;
}
