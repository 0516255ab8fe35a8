// The many-lights technique's "light reaching this point": every light of the scene that
// reaches the point, each through its shadow map (PCF), summed (layered/mod.rs), and, when
// the sun shines too, the sun through its cascades, the first views. A spot light
// reads its one view; a point light the cube face its direction to the point falls in.
// Without the sun, `method` is the share of the lights' irradiance that arrives unshadowed,
// so error counts treat it as they treat one light's visibility; with it, the sun's
// visibility, as the map technique's is. `added` is the lights' light, coloured. Where the
// maps were culled on the GPU (`lights.count.z`), a measuring frame also reads the reference
// maps of every caster (`reference`) and marks the oracle, as the map technique does.
// Bound as group 1 of the shading pass.
#import shadow_view/lookup.wgsl
#import metrics/measure.wgsl

// Keep in sync with layered/lights.rs (LightRecord).
struct LightRecord {
    // xyz: position; w: range in metres (0: none).
    position_range: vec4<f32>,
    // rgb: colour times intensity over the sun's illuminance; w: cosine of the inner cone.
    color_inner: vec4<f32>,
    // xyz: the spot's direction; w: cosine of the outer cone, -2 for a point light.
    spot: vec4<f32>,
    // x: the first view; y: views (1 spot, 6 point, 0 unshadowed).
    views: vec4<u32>,
}

struct Lights {
    // x: how many records are this frame's; y: the sun's views (cascades), the first views,
    // 0 when the sun does not shine; z: 1 when the reference maps are bound (else the
    // method's maps are, and every caster in a view's frustum was drawn: the reference is
    // the method).
    count: vec4<u32>,
    records: array<LightRecord>,
}

@group(1) @binding(0) var light_maps: texture_depth_2d_array;
@group(1) @binding(1) var<storage, read> lights: Lights;
@group(1) @binding(2) var reference_maps: texture_depth_2d_array;
@group(1) @binding(3) var reference_ids: texture_2d_array<u32>;

struct LightReaching {
    method: f32,
    reference: f32,
    view: u32,
    shaded: bool,
    added: vec3<f32>,
}

// Irradiance from light `r` at `p` with normal `n`, on the sun's scale, before shadows: the
// inverse square, glTF's range window, the spot's cone, and the cosine.
fn irradiance(r: LightRecord, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let d = r.position_range.xyz - p;
    let squared = max(dot(d, d), 1e-8);
    let l = d * inverseSqrt(squared);
    var e = max(dot(n, l), 0.0) / squared;
    let range = r.position_range.w;
    if (range > 0.0) {
        let x = squared / (range * range);
        let window = clamp(1.0 - x * x, 0.0, 1.0);
        e *= window * window;
    }
    e *= spot_cone(-l, r.spot.xyz, r.spot.w, r.color_inner.w);
    return e;
}

// The view of light `r` that holds `p`: its one view, or the cube face (geom/punctual.rs
// CUBE_FACES: +X, -X, +Y, -Y, +Z, -Z) of the major axis from the light to `p`.
fn view_of(r: LightRecord, p: vec3<f32>) -> u32 {
    if (r.views.y < 6u) {
        return r.views.x;
    }
    return r.views.x + cube_face(p - r.position_range.xyz);
}

// Fraction of the kernel's taps that see the light: x in the method's maps, y in the
// reference's when `measuring` and it is bound (marking the oracle), else x again.
fn map_light(l: ShadowLookup, measuring: bool) -> vec2<f32> {
    if (!l.inside) {
        return vec2<f32>(1.0);
    }
    let reference = measuring && lights.count.z != 0u;
    var lit = vec2<f32>(0.0);
    for (var j = 0; j < l.kernel; j++) {
        for (var i = 0; i < l.kernel; i++) {
            let t = l.first + vec2<i32>(i, j);
            if (!tap_in_map(l, t)) {
                lit += vec2<f32>(1.0);
                continue;
            }
            let texel = map_texel(l, t);
            let threshold = tap_threshold(l, t);
            let tap = select(0.0, 1.0, threshold <= textureLoad(light_maps, texel, l.layer, 0));
            var tap_reference = tap;
            if (reference) {
                tap_reference = select(0.0, 1.0, threshold <= textureLoad(reference_maps, texel, l.layer, 0));
                if (tap_reference == 0.0) {
                    mark_oracle(l.view, textureLoad(reference_ids, texel, l.layer, 0).x);
                }
            }
            lit += vec2<f32>(tap, tap_reference);
        }
    }
    return lit / f32(l.kernel * l.kernel);
}

// Every light at the point, shadowed where `shadowed`.
fn lights_at(world_pos: vec3<f32>, geometric: vec3<f32>, shadowed: bool, measuring: bool) -> LightReaching {
    var out = LightReaching(1.0, 1.0, 0u, false, vec3<f32>(0.0));
    var total = 0.0;
    var lit = vec2<f32>(0.0);
    var first = true;
    for (var i = 0u; i < lights.count.x; i++) {
        let r = lights.records[i];
        let e = irradiance(r, world_pos, geometric);
        if (e <= 0.0) {
            continue;
        }
        var v = vec2<f32>(1.0);
        if (shadowed && r.views.y > 0u) {
            let view = view_of(r, world_pos);
            let lookup = shadow_lookup(world_pos, geometric, view);
            if (first) {
                out.view = view;
                out.shaded = lookup.inside;
                first = false;
            }
            v = map_light(lookup, measuring);
        }
        total += e;
        lit += e * v;
        out.added += e * v.x * r.color_inner.rgb;
    }
    if (total > 0.0) {
        out.method = lit.x / total;
        out.reference = lit.y / total;
    }
    return out;
}

// The sun's visibility through its cascades, as the map technique shades it
// (shadow_map/light.wgsl): the views `view_selected` picks, the least of them, or with a blend
// band each weighted by `blend_weight`, faded out over the last one's band.
fn sun_light(world_pos: vec3<f32>, geometric: vec3<f32>, measuring: bool) -> LightReaching {
    let count = lights.count.y;
    var out = LightReaching(1.0, 1.0, 0u, false, vec3<f32>(0.0));
    let blended = frame.shadow.w > 0.0 && frame.views.z == 0u;
    let chosen = chosen_view(world_pos, geometric, count);
    var weighted = vec2<f32>(0.0);
    var weight = 0.0;
    var first = true;
    for (var v = 0u; v < count; v++) {
        var w = 1.0;
        if (blended) {
            w = blend_weight(v, world_pos, count);
        } else if (!view_selected(v, world_pos, chosen, count)) {
            w = 0.0;
        }
        if (w <= 0.0) {
            continue;
        }
        let lookup = shadow_lookup(world_pos, geometric, v);
        if (first) {
            out.view = v;
            out.shaded = lookup.inside;
            first = false;
        }
        if (blended && !lookup.inside) {
            continue;
        }
        let lit = map_light(lookup, measuring);
        out.method = min(out.method, lit.x);
        out.reference = min(out.reference, lit.y);
        weighted += w * lit;
        weight += w;
    }
    if (blended && weight > 0.0) {
        let fade = fade_out(world_pos, count);
        out.method = mix(weighted.x / weight, 1.0, fade);
        out.reference = mix(weighted.y / weight, 1.0, fade);
    }
    return out;
}

fn light_reaching(world_pos: vec3<f32>, geometric: vec3<f32>, measuring: bool) -> LightReaching {
    let lamps = lights_at(world_pos, geometric, true, measuring);
    if (lights.count.y == 0u) {
        return lamps;
    }
    var out = sun_light(world_pos, geometric, measuring);
    out.added = lamps.added;
    return out;
}

fn light_unshadowed(world_pos: vec3<f32>, geometric: vec3<f32>) -> vec3<f32> {
    return lights_at(world_pos, geometric, false, false).added;
}
