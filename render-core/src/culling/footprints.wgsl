// The footprint test (Bittner's occlusion queries, driven by the GPU): the boxes of the casters
// the cheap tests kept (culling/cull.wgsl's `candidates`) rasterised in one view's light space.
// In the second phase the view's map as it stands is the depth buffer (LESS, no writes, the
// test forced before the shader), so only unoccluded texels run the shader; in the first phase
// nothing is drawn yet and every texel runs. A texel passes where the box is nearer than what
// the mask needs there: any receiver depth FRAG marked, or a texel the raster masks marked
// (widened by the filter's reach for GEOM). Any passing texel marks the caster
// (STATE_FOOTPRINT_HIT); `cs_resolve_footprints` draws the marked ones. After the maps are
// finished the drawn casters' boxes are tested once more against them: those still marked
// are the front-most somewhere the mask needs, the light-visible set the next frame's first
// phase draws.
// A caster's triangles lie inside its box, so every texel centre they cover is covered by a
// box face no farther from the light: the test never culls a caster that a texel needs.
#import view/common.wgsl
#import culling/cull_common.wgsl

@group(1) @binding(0) var<uniform> cull: CullFrame;
@group(1) @binding(1) var<storage, read> cull_views: array<CullView>;
@group(1) @binding(2) var<storage, read> bounds: array<InstanceBounds>;
@group(1) @binding(3) var<storage, read> candidates: array<u32>;
@group(1) @binding(4) var<storage, read_write> state: array<atomic<u32>>;
// Per view, FRAG's depths and the widened raster mask (GEOM), a block of mask side squared.
@group(1) @binding(5) var<storage, read> mask_bits: array<u32>;
@group(1) @binding(6) var<storage, read> widened: array<f32>;
@group(1) @binding(7) var mask_raster: texture_2d_array<f32>;
// The view this pass renders.
@group(2) @binding(0) var<uniform> pass_view: ShadowView;

// Normalised depth the boxes are moved towards the light, as the cheap tests' margin.
const DEPTH_MARGIN: f32 = 1e-6;

// The box's 12 triangles, counter-clockwise seen from outside (corner k: x from bit 0, y from
// bit 1, z from bit 2), so back faces can be culled.
const BOX_CORNERS = array<u32, 36>(
    1u, 3u, 7u, 1u, 7u, 5u, 0u, 4u, 6u, 0u, 6u, 2u,
    2u, 6u, 7u, 2u, 7u, 3u, 0u, 1u, 5u, 0u, 5u, 4u,
    4u, 5u, 7u, 4u, 7u, 6u, 0u, 2u, 3u, 0u, 3u, 1u,
);

struct FootprintOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) instance: u32,
}

@vertex
fn vs_footprint(@builtin(vertex_index) vertex: u32, @builtin(instance_index) k: u32) -> FootprintOut {
    let view = pass_view.index.x;
    let instance = candidates[view * cull.counts.x + k];
    let b = bounds[instance];
    let corner = BOX_CORNERS[vertex % 36u];
    let p = vec3<f32>(
        select(b.min.x, b.max.x, (corner & 1u) != 0u),
        select(b.min.y, b.max.y, (corner & 2u) != 0u),
        select(b.min.z, b.max.z, (corner & 4u) != 0u),
    );
    var out: FootprintOut;
    out.clip = pass_view.light_clip_from_world * vec4<f32>(p, 1.0);
    out.clip.z -= DEPTH_MARGIN * out.clip.w;
    out.instance = instance;
    return out;
}

// The depth a caster must be nearer than at mask texel `m` of the view, 0 where nothing needs it.
fn needed_depth(view: u32, params: vec4<u32>, m: vec2<u32>) -> f32 {
    let size = params.w;
    let index = view * size * size + m.y * size + m.x;
    var needed = bitcast<f32>(mask_bits[index]);
    if ((params.x & METHOD_GEOM) != 0u) {
        needed = max(needed, widened[index]);
    } else {
        needed = max(needed, textureLoad(mask_raster, m, view, 0).x);
    }
    return needed;
}

@early_depth_test(force)
@fragment
fn fs_footprint(in: FootprintOut) {
    let view = pass_view.index.x;
    let params = cull_views[view].params;
    if ((params.x & METHOD_MASK) != 0u) {
        let local = vec2<u32>(max(floor(in.clip.xy) - vec2<f32>(pass_view.square.yz), vec2<f32>(0.0)));
        let m = min(local / max(params.z, 1u), vec2<u32>(params.w - 1u));
        if (in.clip.z >= needed_depth(view, params, m)) {
            return;
        }
    }
    atomicOr(&state[view * cull.counts.x + in.instance], STATE_FOOTPRINT_HIT);
}
