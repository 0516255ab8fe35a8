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

// A screen-aligned rectangle around the light-space box of visible receiver `instance`,
// one mask texel wider on each side so every texel it touches has its centre inside.
// Nothing for other instances (a degenerate triangle). GEOM+BVOL takes boxes only for
// receivers that were not visible in the light's view last frame.
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
    let box = light_box(bounds[instance], pass_view);
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
    let lo = box.lo.xy - pad;
    let hi = box.hi.xy + pad;
    // Two triangles: corners (lo, lo), (hi, lo), (lo, hi) and (lo, hi), (hi, lo), (hi, hi).
    let v = vertex % 6u;
    let high_x = v == 1u || v == 4u || v == 5u;
    let high_y = v == 2u || v == 3u || v == 5u;
    let c = vec2<f32>(select(lo.x, hi.x, high_x), select(lo.y, hi.y, high_y));
    out.clip = vec4<f32>(c, 0.5, 1.0);
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
