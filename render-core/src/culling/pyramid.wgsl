// Max pyramids for the caster tests, all levels in one buffer with a block per shadow view
// (workgroup z is the view): level m is max(w0 >> m, 1) texels square (w0 half the base) and
// holds the largest value over blocks of 2^(m+1) base texels, the last block of a row or
// column taking in the odd texel left over. The base is a view's square of the shadow map
// (occlusion), its receiver mask (the rasterised mask and FRAG's per-texel depths, whichever
// is larger), or the camera's depth negated (reversed depth: the largest value is the
// farthest surface), square over the view's larger side.
#import shadow_view/views.wgsl
#import culling/cull_common.wgsl

// Keep in sync with culling/gpu/pyramid.rs (`LevelParams`).
struct Level {
    // x: destination offset, y: destination width, z: source offset, w: source width (texels).
    level: vec4<u32>,
    // x: words per view of the pyramid; y: words per view of the mask bits; z, w: unused.
    blocks: vec4<u32>,
}

@group(0) @binding(0) var<storage, read_write> pyramid: array<f32>;
@group(0) @binding(1) var<uniform> params: Level;
@group(0) @binding(2) var camera_depth: texture_depth_2d;
@group(0) @binding(3) var mask_source: texture_2d_array<f32>;
@group(0) @binding(4) var<storage, read> mask_bits: array<u32>;
@group(0) @binding(5) var map_depth: texture_depth_2d_array;
@group(0) @binding(6) var<storage, read> views: array<ShadowView>;
// The mask's base: whether view z has a raster mask (FRAG's has only its depths).
@group(0) @binding(7) var<storage, read> cull_views: array<CullView>;

// The source texels that block `d` of the destination covers: 2x2, or 3 wide at an odd edge.
fn block(d: vec2<u32>, source_size: u32, dest_size: u32) -> array<vec2<u32>, 2> {
    let lo = d * 2u;
    var hi = min(lo + 1u, vec2<u32>(source_size - 1u));
    hi = select(hi, vec2<u32>(source_size - 1u), d == vec2<u32>(dest_size - 1u));
    return array<vec2<u32>, 2>(lo, hi);
}

fn dest_index(id: vec3<u32>) -> u32 {
    return id.z * params.blocks.x + params.level.x + id.y * params.level.y + id.x;
}

@compute @workgroup_size(8, 8)
fn cs_reduce(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= vec2<u32>(params.level.y))) {
        return;
    }
    let b = block(id.xy, params.level.w, params.level.y);
    let source = id.z * params.blocks.x + params.level.z;
    var value = -3.4e38;
    for (var y = b[0].y; y <= b[1].y; y++) {
        for (var x = b[0].x; x <= b[1].x; x++) {
            value = max(value, pyramid[source + y * params.level.w + x]);
        }
    }
    pyramid[dest_index(id)] = value;
}

// The first level from view z's square of the shadow maps.
@compute @workgroup_size(8, 8)
fn cs_reduce_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= vec2<u32>(params.level.y))) {
        return;
    }
    let square = views[id.z].square;
    let b = block(id.xy, params.level.w, params.level.y);
    var value = -3.4e38;
    for (var y = b[0].y; y <= b[1].y; y++) {
        for (var x = b[0].x; x <= b[1].x; x++) {
            let texel = square.yz + vec2<u32>(x, y);
            value = max(value, textureLoad(map_depth, texel, square.x, 0));
        }
    }
    pyramid[dest_index(id)] = value;
}

@compute @workgroup_size(8, 8)
fn cs_reduce_mask(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= vec2<u32>(params.level.y))) {
        return;
    }
    let b = block(id.xy, params.level.w, params.level.y);
    let bits_block = id.z * params.blocks.y;
    let raster = has_raster_mask(cull_views[id.z].params.x);
    var value = 0.0;
    for (var y = b[0].y; y <= b[1].y; y++) {
        for (var x = b[0].x; x <= b[1].x; x++) {
            let bits = mask_bits[bits_block + y * params.level.w + x];
            var marked = 0.0;
            if (raster) {
                marked = textureLoad(mask_source, vec2<u32>(x, y), id.z, 0).x;
            }
            value = max(value, max(marked, bitcast<f32>(bits)));
        }
    }
    pyramid[dest_index(id)] = value;
}

// The camera's reversed depth, negated, so the max pyramid holds the farthest surface; texels
// beyond the texture (the base is square over its larger side) count as 0, the far plane.
@compute @workgroup_size(8, 8)
fn cs_reduce_camera_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= vec2<u32>(params.level.y))) {
        return;
    }
    let size = textureDimensions(camera_depth);
    let b = block(id.xy, params.level.w, params.level.y);
    var value = -3.4e38;
    for (var y = b[0].y; y <= b[1].y; y++) {
        for (var x = b[0].x; x <= b[1].x; x++) {
            var depth = 0.0;
            if (x < size.x && y < size.y) {
                depth = textureLoad(camera_depth, vec2<u32>(x, y), 0);
            }
            value = max(value, -depth);
        }
    }
    pyramid[dest_index(id)] = value;
}
