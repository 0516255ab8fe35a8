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

// Where the footprint of the projected corners `q` (corner k as in `corner`) crosses the
// band of rows `band` (lowest and highest y): its lowest and highest x there (lowest above
// highest where it misses the band). The hull's outline is made of projected box edges, and
// its extremes in the band lie on them, clipped to the band.
fn footprint_row(q: ptr<function, array<vec2<f32>, 8>>, band: vec2<f32>) -> vec2<f32> {
    var span = vec2<f32>(1e30, -1e30);
    for (var e = 0u; e < 12u; e++) {
        // Edge e joins corner k to k with bit `b` set: the four corners without that bit.
        let b = e / 4u;
        let j = e % 4u;
        let k = ((j >> b) << (b + 1u)) | (j & ((1u << b) - 1u));
        let p0 = (*q)[k];
        let p1 = (*q)[k | (1u << b)];
        if (max(p0.y, p1.y) < band.x || min(p0.y, p1.y) > band.y) {
            continue;
        }
        let dy = p1.y - p0.y;
        var x = vec2<f32>(p0.x, p1.x);
        if (abs(dy) > 1e-12) {
            let t = clamp((band - p0.y) / dy, vec2<f32>(0.0), vec2<f32>(1.0));
            x = mix(vec2<f32>(p0.x), vec2<f32>(p1.x), t);
        }
        span = vec2<f32>(min(span.x, min(x.x, x.y)), max(span.y, max(x.x, x.y)));
    }
    return span;
}

// Loop iterations `footprint_row` takes.
const FOOTPRINT_STEPS: u32 = 12u;

// The cells of a grid of cells `size` wide whose square of half-size `half` around its
// centre comes within `pad` of the span `span` of one axis: first and last.
fn cells_meeting(span: vec2<f32>, size: f32, half: f32, pad: f32) -> vec2<i32> {
    return vec2<i32>(
        i32(ceil((span.x - half - pad) / size - 0.5)),
        i32(floor((span.y + half + pad) / size - 0.5)),
    );
}
