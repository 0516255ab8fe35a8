// Max pyramids for the caster tests, all levels in one buffer: level m is max(w0 >> m, 1)
// texels square (w0 half the base) and holds the largest value over blocks of 2^(m+1) base
// texels, the last block of a row or column taking in the odd texel left over. The base is
// the shadow map's depth (occlusion), the receiver mask (the rasterised mask and FRAG's
// per-texel depths, whichever is larger), or the camera's depth negated (reversed depth: the
// largest value is the farthest surface), square over the view's larger side.

@group(0) @binding(0) var<storage, read_write> pyramid: array<f32>;
// x: destination offset, y: destination width, z: source offset, w: source width (texels).
@group(0) @binding(1) var<uniform> level: vec4<u32>;
@group(0) @binding(2) var depth_source: texture_depth_2d;
@group(0) @binding(3) var mask_source: texture_2d<f32>;
@group(0) @binding(4) var<storage, read> mask_bits: array<u32>;

// The source texels that block `d` of the destination covers: 2x2, or 3 wide at an odd edge.
fn block(d: vec2<u32>, source_size: u32, dest_size: u32) -> array<vec2<u32>, 2> {
    let lo = d * 2u;
    var hi = min(lo + 1u, vec2<u32>(source_size - 1u));
    hi = select(hi, vec2<u32>(source_size - 1u), d == vec2<u32>(dest_size - 1u));
    return array<vec2<u32>, 2>(lo, hi);
}

@compute @workgroup_size(8, 8)
fn cs_reduce(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= vec2<u32>(level.y))) {
        return;
    }
    let b = block(id.xy, level.w, level.y);
    var value = -3.4e38;
    for (var y = b[0].y; y <= b[1].y; y++) {
        for (var x = b[0].x; x <= b[1].x; x++) {
            value = max(value, pyramid[level.z + y * level.w + x]);
        }
    }
    pyramid[level.x + id.y * level.y + id.x] = value;
}

// The first level from a depth texture, its values times `sign`; texels beyond the texture
// (the camera's base is square over its larger side) count as 0, the camera's far plane.
fn reduce_depth(id: vec3<u32>, sign: f32) {
    if (any(id.xy >= vec2<u32>(level.y))) {
        return;
    }
    let size = textureDimensions(depth_source);
    let b = block(id.xy, level.w, level.y);
    var value = -3.4e38;
    for (var y = b[0].y; y <= b[1].y; y++) {
        for (var x = b[0].x; x <= b[1].x; x++) {
            var depth = 0.0;
            if (x < size.x && y < size.y) {
                depth = textureLoad(depth_source, vec2<u32>(x, y), 0);
            }
            value = max(value, sign * depth);
        }
    }
    pyramid[level.x + id.y * level.y + id.x] = value;
}

@compute @workgroup_size(8, 8)
fn cs_reduce_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    reduce_depth(id, 1.0);
}

@compute @workgroup_size(8, 8)
fn cs_reduce_mask(@builtin(global_invocation_id) id: vec3<u32>) {
    if (any(id.xy >= vec2<u32>(level.y))) {
        return;
    }
    let b = block(id.xy, level.w, level.y);
    var value = 0.0;
    for (var y = b[0].y; y <= b[1].y; y++) {
        for (var x = b[0].x; x <= b[1].x; x++) {
            let bits = mask_bits[y * level.w + x];
            value = max(value, max(textureLoad(mask_source, vec2<u32>(x, y), 0).x, bitcast<f32>(bits)));
        }
    }
    pyramid[level.x + id.y * level.y + id.x] = value;
}

// The camera's reversed depth, negated, so the max pyramid holds the farthest surface.
@compute @workgroup_size(8, 8)
fn cs_reduce_camera_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    reduce_depth(id, -1.0);
}
