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
// Where the mask leaves few candidates (FRAG, `incr`: METHOD_GEOMETRY_FOOTPRINT) the footprint
// is the caster's own geometry (`vs_footprint_geometry`), drawn exactly as the shadow pass
// draws it (shadow_map/shadow_depth.wgsl): its fragments are the texels and depths it would
// write, so it passes exactly where it can shadow a tap the mask needs (and, against the map,
// where nothing drawn is nearer). Elsewhere the candidates are many and their boxes stand in
// for them, as Bittner's occlusion queries do: a caster's triangles lie inside its box, so
// every texel centre they cover is covered by a box face no farther from the light. Either
// way the test never culls a caster that a texel needs.
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

struct FootprintOut {
    @invariant @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) instance: u32,
}

@vertex
fn vs_footprint(@builtin(vertex_index) vertex: u32, @builtin(instance_index) k: u32) -> FootprintOut {
    let view = pass_view.index.x;
    let instance = candidates[view * cull.counts.x + k];
    var out: FootprintOut;
    out.clip = box_vertex(bounds[instance], vertex, pass_view);
    out.instance = instance;
    return out;
}

// The candidate's triangles, one indexed draw per instance (culling/cull.wgsl's
// `footprint_geometry`), transformed as `vs_shadow` transforms them.
@vertex
fn vs_footprint_geometry(@location(0) position: vec3<f32>, @builtin(instance_index) instance: u32) -> FootprintOut {
    var out: FootprintOut;
    out.clip = shadow_clip_position(pass_view, instance, position);
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
    } else if (has_raster_mask(params.x)) {
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

// Incremental updates: the view's square, a triangle over it.
@vertex
fn vs_square(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
}

struct ClearOut {
    @builtin(frag_depth) depth: f32,
}

// Incremental updates: the texels the moved boxes marked (culling/masks.wgsl,
// `vs_moved_faces`) cleared to the far plane before the casters there are drawn again.
@fragment
fn fs_clear_marked(@builtin(position) position: vec4<f32>) -> ClearOut {
    let view = pass_view.index.x;
    let local = vec2<u32>(max(floor(position.xy) - vec2<f32>(pass_view.square.yz), vec2<f32>(0.0)));
    if (textureLoad(mask_raster, local, view, 0).x < MASK_MARKED_BOX) {
        discard;
    }
    return ClearOut(1.0);
}
