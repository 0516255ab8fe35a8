// Static occlusion (virtual_maps/frame.rs `encode_pages`): with static casters apart, each
// physical page drawn whole in the last frame has the farthest static depth of each of its
// 8 x 8 blocks of 16 x 16 texels written to `static_depths`, before this frame's moved boxes
// are tested against them (allocate.wgsl `invalidate_moved`) and the cull leaves out the
// movable casters behind them (cull.wgsl). Its own pass at the frame's start, so the flags
// still say which pages the last frame drew whole. Workgroup: a physical page; invocation:
// a block.
#import virtual_maps/tables.wgsl

@group(2) @binding(0) var page_atlas: texture_depth_2d;

@compute @workgroup_size(8, 8)
fn reduce_static(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_id) block: vec3<u32>,
) {
    let slot = group.x;
    if (slot >= params.counts.y || owners[slot] == 0u) {
        return;
    }
    let e = owners[slot] - 1u;
    if ((atomicLoad(&page_flags[e]) & PAGE_RENDERED) == 0u) {
        return;
    }
    let origin = layer_origin(slot, 0u) + vec2<i32>(block.xy) * BLOCK_TEXELS;
    var farthest = 0.0;
    for (var y = 0; y < BLOCK_TEXELS; y++) {
        for (var x = 0; x < BLOCK_TEXELS; x++) {
            farthest = max(farthest, textureLoad(page_atlas, origin + vec2<i32>(x, y), 0));
        }
    }
    static_depths[slot * 64u + block.y * 8u + block.x] = farthest;
}
