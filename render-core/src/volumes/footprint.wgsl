// A caster's footprint across the light, tighter than its world box's: its mesh's own box
// carried into the world by the instance's transform (an oriented box, as Lloyd's CCe fits
// them), projected onto a plane across the light. A strut turned across the axes fills a
// thin band of its world box's rectangle; the grid tests (volumes/find.wgsl) skip the cells
// the band misses. The projection of a box is the convex hull of its eight corners, whose
// outline is made of projected box edges, so the cell's two axes and the normals of the
// twelve projected edges separate every cell it misses (the separating axis theorem).
// Part of volumes/find.wgsl.

// Corner `k` (bit 0 x, bit 1 y, bit 2 z) of caster `c`'s mesh box in world space.
fn oriented_corner(c: Caster, k: u32) -> vec3<f32> {
    return world_position(c.instance, corner(c.local_min.xyz, c.local_max.xyz, k));
}

// Whether the rectangle with centre `centre` and half-size `half` (0 for a point) overlaps
// the hull of `q` (a box's corners projected across the light, corner k as in `corner`), or
// comes within `pad` of it.
fn footprint_meets(
    q: ptr<function, array<vec2<f32>, 8>>,
    centre: vec2<f32>,
    half: vec2<f32>,
    pad: f32,
) -> bool {
    var lo = vec2<f32>(1e30);
    var hi = vec2<f32>(-1e30);
    for (var k = 0u; k < 8u; k++) {
        lo = min(lo, (*q)[k]);
        hi = max(hi, (*q)[k]);
    }
    if (any(centre + half + pad < lo) || any(centre - half - pad > hi)) {
        return false;
    }
    for (var e = 0u; e < 12u; e++) {
        // Edge e joins corner k to k with bit `b` set: the four corners without that bit.
        let b = e / 4u;
        let j = e % 4u;
        let k = ((j >> b) << (b + 1u)) | (j & ((1u << b) - 1u));
        let d = (*q)[k | (1u << b)] - (*q)[k];
        let length_d = length(d);
        // An edge along the light projects to a point, and its normal separates nothing.
        if (length_d < 1e-6) {
            continue;
        }
        let axis = vec2<f32>(-d.y, d.x) / length_d;
        var low = 1e30;
        var high = -1e30;
        for (var i = 0u; i < 8u; i++) {
            let s = dot(axis, (*q)[i]);
            low = min(low, s);
            high = max(high, s);
        }
        let mid = dot(axis, centre);
        let reach = dot(abs(axis), half) + pad;
        if (mid + reach < low || mid - reach > high) {
            return false;
        }
    }
    return true;
}
