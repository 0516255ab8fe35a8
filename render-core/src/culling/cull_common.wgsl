// Culling parameters and per-instance light boxes, shared by the caster tests (culling/cull.wgsl)
// and the masks (culling/masks.wgsl). Keep in sync with culling/gpu/gpu_data.rs. Per-view
// data (state, draws, counters, pyramids, masks) lies in one block per shadow view.
#import culling/codes.wgsl
#import scene_gpu/instance.wgsl
#import shadow_view/views.wgsl

// Shared by every view.
struct CullFrame {
    camera_clip_from_world: mat4x4<f32>,
    // x: instance count (the stride of per-view blocks); y: view count; z: the camera
    // pyramid's base size; w: 1 when `state` holds last frame's light-visible casters.
    counts: vec4<u32>,
    // x, y: the camera's view in pixels; z, w: unused.
    camera: vec4<u32>,
}

// One view's culling parameters.
struct CullView {
    // x: method bits (METHOD_*) for this view this frame; y: texels a mask built from whole
    // receivers is widened by (PCF radius, normal offset, rasterisation); z: shadow texels per
    // mask texel; w: the mask's side in texels.
    params: vec4<u32>,
    // x: how far a shadow volume starts before its caster (normalised light depth: the normal
    // offset and a texel); y, z, w: unused.
    volume: vec4<f32>,
    // Words per view of x: the occlusion pyramid, y: the mask pyramid; z, w: unused.
    pyramids: vec4<u32>,
    // x: the filter's reach in shadow texels, how far a receiver point's PCF taps (moved by
    // the normal offset) can lie from the texel the point falls in; y, z, w: unused.
    reach: vec4<u32>,
}

// Whether the method draws a raster mask (BVOL's boxes, GEOM's geometry, `incr`'s changed
// region); FRAG's mask is its depths alone, and nothing clears or reads the raster for it.
fn has_raster_mask(method: u32) -> bool {
    return (method & METHODS_RASTER_MASK) != 0u;
}

// The filter's reach in mask texels, rounded up.
fn reach_in_mask_texels(cv: CullView) -> u32 {
    let scale = max(cv.params.z, 1u);
    return (cv.reach.x + scale - 1u) / scale;
}

// The instance's box in light clip space: x, y in NDC, z in normalised depth.
struct LightBox {
    lo: vec3<f32>,
    hi: vec3<f32>,
}

// Corner `k` (0 to 7) of the instance's box: bit 0 picks x, bit 1 y, bit 2 z.
fn bounds_corner(b: InstanceBounds, k: u32) -> vec3<f32> {
    return vec3<f32>(
        select(b.min.x, b.max.x, (k & 1u) != 0u),
        select(b.min.y, b.max.y, (k & 2u) != 0u),
        select(b.min.z, b.max.z, (k & 4u) != 0u),
    );
}

fn light_box(b: InstanceBounds, view: ShadowView) -> LightBox {
    var out: LightBox;
    out.lo = vec3<f32>(1e30);
    out.hi = vec3<f32>(-1e30);
    for (var k = 0u; k < 8u; k++) {
        let clip = light_clip(view, bounds_corner(b, k));
        if (clip.w <= 0.0) {
            // Behind a warped view's centre (LiSPSM): the box may reach anywhere in the map,
            // from the light's near plane on.
            out.lo = min(out.lo, vec3<f32>(-1.0, -1.0, 0.0));
            out.hi = max(out.hi, vec3<f32>(1.0));
            continue;
        }
        let ndc = clip.xyz / clip.w;
        out.lo = min(out.lo, ndc);
        out.hi = max(out.hi, ndc);
    }
    return out;
}

fn in_light_frustum(box: LightBox) -> bool {
    return all(box.hi >= vec3<f32>(-1.0, -1.0, 0.0)) && all(box.lo <= vec3<f32>(1.0));
}

// A box's 12 triangles, counter-clockwise seen from outside (corner k: x from bit 0, y from
// bit 1, z from bit 2), so back faces can be culled.
const BOX_CORNERS = array<u32, 36>(
    1u, 3u, 7u, 1u, 7u, 5u, 0u, 4u, 6u, 0u, 6u, 2u,
    2u, 6u, 7u, 2u, 7u, 3u, 0u, 1u, 5u, 0u, 5u, 4u,
    4u, 5u, 7u, 4u, 7u, 6u, 0u, 2u, 3u, 0u, 3u, 1u,
);

// Normalised depth the rasterised boxes are moved towards the light, as the cheap tests'
// margin.
const BOX_DEPTH_MARGIN: f32 = 1e-6;

// Vertex `vertex` (0 to 35) of box `b` in light clip space, a little towards the light.
fn box_vertex(b: InstanceBounds, vertex: u32, view: ShadowView) -> vec4<f32> {
    var clip = light_clip(view, bounds_corner(b, BOX_CORNERS[vertex % 36u]));
    clip.z -= BOX_DEPTH_MARGIN * clip.w;
    return clip;
}
