// Drawing the pages (virtual_maps/frame.rs): one pass over the physical atlas that keeps
// what it holds. First each page drawn this frame is cleared (a quad at the far depth per
// layer; a refreshed page's movable layer alone), then every (caster, page) pair the cull
// listed is drawn: the caster in its level's view (the sun's orthographic, a point light's
// face in perspective), moved from its page of the level's square
// to the page's place in the atlas (in the movable layer for a movable caster where static
// ones are apart), clip distances at the page's edges keeping it there. Composed with
// `enable clip_distances;` first.
#import virtual_maps/pages.wgsl

@group(1) @binding(1) var<storage, read> page_slots: array<u32>;
@group(1) @binding(2) var<storage, read> pairs: array<vec2<u32>>;
@group(1) @binding(3) var<storage, read> rendered_list: array<u32>;

struct PageOut {
    @invariant @builtin(position) clip: vec4<f32>,
    @builtin(clip_distances) edges: array<f32, 4>,
}

// The atlas's clip position of `local` (texels from the first of entry `e`'s page, times
// `w`) in the page's layer `layer`, at clip depth `z` and clip w `w`: the level's clip
// position moved to the page's place, still homogeneous, so that a face of a point light
// rasterises with its perspective and is clipped at its near plane (w is 1 for the sun's).
fn in_atlas(e: u32, layer: u32, local: vec2<f32>, z: f32, w: f32) -> PageOut {
    var out: PageOut;
    let side = f32(PAGE_TEXELS) * w;
    out.edges = array<f32, 4>(local.x, side - local.x, local.y, side - local.y);
    let layers = f32(1u + params.limits.y);
    let atlas = vec2<f32>(f32(params.counts.z), params.tuning.w * layers) * f32(PAGE_TEXELS);
    let t = vec2<f32>(layer_origin(page_slots[e], layer)) * w + local;
    out.clip = vec4<f32>(2.0 * t.x / atlas.x - w, w - 2.0 * t.y / atlas.y, z, w);
    return out;
}

// The caster of pair `pair_index` at `position`, in its page's place.
fn page_vertex(position: vec3<f32>, pair_index: u32) -> PageOut {
    let pair = pairs[pair_index];
    let e = pair.y & ENTRY_BITS;
    let layer = select(0u, 1u, (pair.y & DYNAMIC_ONLY) != 0u);
    let view = shadow_views[e / LEVEL_ENTRIES];
    let c = shadow_clip_position(view, pair.x, position);
    let size = f32(view.square.w);
    let texel = vec2<f32>(c.x * 0.5 + 0.5 * c.w, 0.5 * c.w - c.y * 0.5) * size;
    let origin = vec2<f32>(window_page(e) * PAGE_TEXELS);
    return in_atlas(e, layer, texel - origin * c.w, c.z, c.w);
}

@vertex
fn vs_page(@location(0) position: vec3<f32>, @builtin(instance_index) pair_index: u32) -> PageOut {
    return page_vertex(position, pair_index);
}

@vertex
fn vs_clear(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> PageOut {
    let corner = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0), vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0),
        vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 1.0),
    );
    // Quad 0 clears layer 0, quad 1 (where static casters are apart) the movable layer; a
    // refreshed page keeps its layer 0 (its quad clipped away).
    let item = rendered_list[i];
    let layer = v / 6u;
    var out = in_atlas(item & ENTRY_BITS, layer, corner[v % 6u] * f32(PAGE_TEXELS), 1.0, 1.0);
    let kept = layer == 0u && (item & DYNAMIC_ONLY) != 0u;
    let edge = select(1.0, -1.0, kept);
    out.edges = array<f32, 4>(edge, edge, edge, edge);
    return out;
}

// When measuring (the per-page oracle, virtual_maps/oracle.rs `encode_oracle`): the pairs
// drawn again over the atlas, read-only with an EQUAL depth test, so a fragment runs only
// where its caster holds the texel's depth; a pair holding a texel that `mark_shadowed`
// (mark.wgsl) found shadowed for a visible pixel's tap is in the oracle.
// Per physical page and layer, a bit per texel.
@group(2) @binding(0) var<storage, read> oracle_texels: array<u32>;
// Per level, its pairs in the oracle (LEVEL_SLOTS words), then a bit per pair.
@group(2) @binding(1) var<storage, read_write> oracle: array<atomic<u32>>;

const ORACLE_LEVELS: u32 = 156u;

struct OracleOut {
    @invariant @builtin(position) clip: vec4<f32>,
    @builtin(clip_distances) edges: array<f32, 4>,
    @location(0) @interpolate(flat) pair: u32,
}

@vertex
fn vs_oracle(@location(0) position: vec3<f32>, @builtin(instance_index) pair_index: u32) -> OracleOut {
    let out = page_vertex(position, pair_index);
    return OracleOut(out.clip, out.edges, pair_index);
}

@fragment
@early_depth_test(force)
fn fs_oracle(@builtin(position) frag: vec4<f32>, @location(0) @interpolate(flat) pair_index: u32) {
    let pair = pairs[pair_index];
    let e = pair.y & ENTRY_BITS;
    let layer = select(0u, 1u, (pair.y & DYNAMIC_ONLY) != 0u);
    let slot = page_slots[e];
    let bit = texel_bit(vec2<i32>(frag.xy) - layer_origin(slot, layer));
    let layers = 1u + params.limits.y;
    if ((oracle_texels[(slot * layers + layer) * 512u + bit.x] & bit.y) == 0u) {
        return;
    }
    let flag = 1u << (pair_index % 32u);
    if ((atomicOr(&oracle[ORACLE_LEVELS + pair_index / 32u], flag) & flag) == 0u) {
        atomicAdd(&oracle[e / LEVEL_ENTRIES], 1u);
    }
}
