// Receiver masks rasterised in the light's view (Bittner 4.1, 4.2): the bounding boxes (BVOL)
// or the geometry (GEOM) of visible receivers mark the mask target, at the mask's resolution.
// Casters are widened by the PCF footprint when tested against these masks (culling/cull.wgsl).
// One view per pass: the view's mask layer, or its square of the shadow map.
// Marked texels hold a depth beyond every caster (MASK_MARKED_*, culling/codes.wgsl): only
// coverage counts. Boxes and geometry mark different values so the light's view inset can
// colour them (overlays/light_inset.wgsl).
#import view/common.wgsl
#import culling/cull_common.wgsl

@group(1) @binding(0) var<uniform> cull: CullFrame;
@group(1) @binding(1) var<storage, read> cull_views: array<CullView>;
@group(1) @binding(2) var<storage, read> bounds: array<InstanceBounds>;
@group(1) @binding(3) var<storage, read> visible: array<u32>;
@group(1) @binding(4) var<storage, read> state: array<u32>;
// Last frame's boxes, for incremental updates (Bittner 5.1).
@group(1) @binding(5) var<storage, read> previous_bounds: array<InstanceBounds>;
// The view this pass renders.
@group(2) @binding(0) var<uniform> pass_view: ShadowView;

fn pass_params() -> vec4<u32> {
    return cull_views[pass_view.index.x].params;
}

fn pass_state(instance: u32) -> u32 {
    return state[pass_view.index.x * cull.counts.x + instance];
}

struct MaskOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) marked: f32,
}

// The receiver box's outline in the light's view: the convex hull of its 8 corners in NDC
// (Andrew's monotone chain), counter-clockwise, and how many corners it has (one more slot:
// the chain ends on its first corner again). Its widened fan takes BOX_OUTLINE_VERTICES.
struct Hull {
    points: array<vec2<f32>, 9>,
    count: u32,
}

fn cross2(o: vec2<f32>, a: vec2<f32>, b: vec2<f32>) -> f32 {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

fn convex_hull(corners: array<vec2<f32>, 8>) -> Hull {
    var sorted = corners;
    for (var i = 1u; i < 8u; i++) {
        let p = sorted[i];
        var j = i;
        while (j > 0u && (sorted[j - 1u].x > p.x || (sorted[j - 1u].x == p.x && sorted[j - 1u].y > p.y))) {
            sorted[j] = sorted[j - 1u];
            j--;
        }
        sorted[j] = p;
    }
    // Lower hull left to right, then upper hull right to left; points that do not turn left
    // are dropped (collinear and repeated corners too).
    var hull: Hull;
    var k = 0u;
    for (var i = 0u; i < 8u; i++) {
        while (k >= 2u && cross2(hull.points[k - 2u], hull.points[k - 1u], sorted[i]) <= 0.0) {
            k--;
        }
        hull.points[k] = sorted[i];
        k++;
    }
    let lower = k + 1u;
    for (var i = 7u; i > 0u; i--) {
        let p = sorted[i - 1u];
        while (k >= lower && cross2(hull.points[k - 2u], hull.points[k - 1u], p) <= 0.0) {
            k--;
        }
        hull.points[min(k, 8u)] = p;
        k++;
    }
    // The last point repeats the first; a box seen as a point is one corner.
    hull.count = max(k, 2u) - 1u;
    if (hull.count == 2u && all(hull.points[0] == hull.points[1])) {
        hull.count = 1u;
    }
    return hull;
}

// Which corner of a square a convex outline's edge with outward normal `n` moves by, when
// the square is added to the outline (a Minkowski sum): 0 (+x, +y), 1 (-x, +y), 2 (-x, -y),
// 3 (+x, -y), counter-clockwise by the normal's angle.
fn square_corner_of(n: vec2<f32>) -> u32 {
    if (n.x > 0.0 && n.y >= 0.0) {
        return 0u;
    }
    if (n.x <= 0.0 && n.y > 0.0) {
        return 1u;
    }
    if (n.x < 0.0 && n.y <= 0.0) {
        return 2u;
    }
    return 3u;
}

fn square_corner(k: u32, half: f32) -> vec2<f32> {
    return vec2<f32>(select(half, -half, k == 1u || k == 2u), select(half, -half, k >= 2u));
}

// Corner `index` of the hull widened by a square of half side `half` (the hull plus the
// square, exactly: at each hull corner, the square's corners from the one its incoming
// edge moves by to the one its outgoing edge moves by), and how many corners it has.
fn widened_corner(hull: Hull, half: f32, index: u32) -> vec3<f32> {
    if (hull.count == 1u) {
        return vec3<f32>(hull.points[0] + square_corner(index % 4u, half), 4.0);
    }
    let m = hull.count;
    var found = hull.points[0];
    var emitted = 0u;
    for (var j = 0u; j < m; j++) {
        let here = hull.points[j];
        let before = hull.points[(j + m - 1u) % m];
        let after = hull.points[(j + 1u) % m];
        let edge_in = here - before;
        let edge_out = after - here;
        let first = square_corner_of(vec2<f32>(edge_in.y, -edge_in.x));
        let last = square_corner_of(vec2<f32>(edge_out.y, -edge_out.x));
        let steps = (last + 4u - first) % 4u;
        for (var s = 0u; s <= steps; s++) {
            if (emitted == index) {
                found = here + square_corner((first + s) % 4u, half);
            }
            emitted++;
        }
    }
    return vec3<f32>(found, f32(emitted));
}

// The outline of visible receiver `instance`'s box in the light's view (Bittner 4.1: the
// bounding volumes are rasterised): the convex hull of its corners, widened by one mask texel
// so every texel it touches has its centre inside, as a fan of triangles. Nothing for other
// instances (a degenerate triangle). A box reaching behind a perspective view's centre may
// reach anywhere in the map: its light-space rectangle, the whole map, stands in. GEOM+BVOL
// takes boxes only for receivers that were not visible in the light's view last frame.
@vertex
fn vs_box(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> MaskOut {
    var out: MaskOut;
    out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    out.marked = MASK_MARKED_BOX;
    let flags = bounds[instance].flags;
    var wanted = visible[instance] != 0u && (flags & FLAG_RECEIVER) != 0u;
    if ((pass_params().x & METHOD_GEOM) != 0u) {
        wanted = wanted && (pass_state(instance) & STATE_LIGHT_VISIBLE) == 0u;
    }
    if (!wanted) {
        return out;
    }
    let b = bounds[instance];
    let box = light_box(b, pass_view);
    if (!in_light_frustum(box)) {
        return out;
    }
    // One mask texel so every texel the box touches has its centre inside; for BVOL alone also
    // the filter's reach (GEOM+BVOL widens the whole mask after, culling/widen.wgsl).
    let params = pass_params();
    var texels = 1u;
    if ((params.x & METHOD_GEOM) == 0u) {
        texels += reach_in_mask_texels(cull_views[pass_view.index.x]);
    }
    let pad = 2.0 * f32(texels) / f32(params.w);
    var corners: array<vec2<f32>, 8>;
    var in_front = true;
    for (var k = 0u; k < 8u; k++) {
        let clip = light_clip(pass_view, bounds_corner(b, k));
        in_front = in_front && clip.w > 0.0;
        corners[k] = clip.xy / max(clip.w, 1e-30);
    }
    if (!in_front) {
        if (vertex < 6u) {
            out.clip = rectangle_corner(vertex, box.lo.xy - pad, box.hi.xy + pad);
        }
        return out;
    }
    // A fan over the widened hull's corners; triangles past its last corner collapse.
    if (vertex >= BOX_OUTLINE_VERTICES) {
        return out;
    }
    let hull = convex_hull(corners);
    let triangle = vertex / 3u;
    var index = 0u;
    if (vertex % 3u != 0u) {
        index = triangle + vertex % 3u;
    }
    let corner = widened_corner(hull, pad, index);
    if (index >= u32(corner.z)) {
        out.clip = vec4<f32>(widened_corner(hull, pad, 0u).xy, 0.5, 1.0);
    } else {
        out.clip = vec4<f32>(corner.xy, 0.5, 1.0);
    }
    return out;
}

// One corner of the two triangles covering a light-space rectangle.
fn rectangle_corner(vertex: u32, lo: vec2<f32>, hi: vec2<f32>) -> vec4<f32> {
    // Corners (lo, lo), (hi, lo), (lo, hi) and (lo, hi), (hi, lo), (hi, hi).
    let v = vertex % 6u;
    let high_x = v == 1u || v == 4u || v == 5u;
    let high_y = v == 2u || v == 3u || v == 5u;
    return vec4<f32>(select(lo.x, hi.x, high_x), select(lo.y, hi.y, high_y), 0.5, 1.0);
}

// Incremental updates: a moving object's box where it was last frame (vertices 0-5) and
// where it is now (6-11), widened by `pad` in NDC; nothing for objects that did not move.
fn moved_box_corner(vertex: u32, instance: u32, pad: f32) -> vec4<f32> {
    let now = bounds[instance];
    let before = previous_bounds[instance];
    let moved = any(now.min != before.min) || any(now.max != before.max);
    if ((now.flags & FLAG_DYNAMIC) == 0u || !moved) {
        return vec4<f32>(2.0, 2.0, 2.0, 1.0);
    }
    var which = now;
    if (vertex < 6u) {
        which = before;
    }
    let box = light_box(which, pass_view);
    if (!in_light_frustum(box)) {
        return vec4<f32>(2.0, 2.0, 2.0, 1.0);
    }
    return rectangle_corner(vertex, box.lo.xy - pad, box.hi.xy + pad);
}

// The changed region into the mask, a mask texel wider on each side (as `vs_box`).
@vertex
fn vs_moved_box(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> MaskOut {
    var out: MaskOut;
    out.clip = moved_box_corner(vertex, instance, 2.0 / f32(pass_params().w));
    out.marked = MASK_MARKED_BOX;
    return out;
}

// Incremental updates at full mask resolution: a moving object's box faces where it was last
// frame (vertices 0-35) and where it is now (36-71), depth tested against the map as it
// stands (LESS_EQUAL, no writes). Only where the box is not behind what the map holds can
// the object have been, or become, the front-most caster: those texels are marked, then
// cleared (culling/footprints.wgsl, `fs_clear_marked`) and redrawn; where a nearer caster
// covers the box (a car in a building's shadow) the map keeps that caster's depth.
@vertex
fn vs_moved_faces(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> MaskOut {
    var out: MaskOut;
    out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
    out.marked = MASK_MARKED_BOX;
    let now = bounds[instance];
    let before = previous_bounds[instance];
    let moved = any(now.min != before.min) || any(now.max != before.max);
    if ((now.flags & FLAG_DYNAMIC) == 0u || !moved) {
        return out;
    }
    var which = now;
    if (vertex < 36u) {
        which = before;
    }
    out.clip = box_vertex(which, vertex, pass_view);
    return out;
}

// The changed region in the shadow map, exactly: cleared to the far plane before redrawing.
@vertex
fn vs_clear_moved(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    return moved_box_corner(vertex, instance, 0.0);
}

struct ClearOut {
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_clear() -> ClearOut {
    return ClearOut(1.0);
}

// Receiver geometry in the light's view; which receivers is decided by the indirect draws.
@vertex
fn vs_geometry(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> MaskOut {
    var out: MaskOut;
    out.clip = light_clip(pass_view, world_position(instance, position));
    // Depth is not tested: keep every fragment inside the clip volume's depth range.
    out.clip.z = 0.5 * out.clip.w;
    out.marked = MASK_MARKED_GEOMETRY;
    return out;
}

@fragment
fn fs_mark(in: MaskOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.marked, 0.0, 0.0, 0.0);
}
