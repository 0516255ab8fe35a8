// Visible objects from the camera's object ids: one flag per object, a count of visible
// receivers and their world-space bounds, and the reversed depths their pixels span (for
// cascades split over visible depths only, Lauritzen's SDSM), reduced per workgroup first.
#import scene_gpu/instance.wgsl

// Keep in sync with view/visibility.rs (`take_latest`).
struct Counters {
    visible_objects: atomic<u32>,
    visible_receivers: atomic<u32>,
    // The visible receivers' world box as order-preserving keys (`order_key`); the minimum
    // is kept as the maximum of the inverted key, so zeroed counters start both empty.
    receivers_min_inverted: array<atomic<u32>, 3>,
    receivers_max: array<atomic<u32>, 3>,
    // The receiver pixels' reversed depths (positive floats order as their bits): the
    // nearest as the largest depth, the furthest as the largest inverted.
    depth_near: atomic<u32>,
    depth_far_inverted: atomic<u32>,
}

@group(0) @binding(0) var object_ids: texture_2d<u32>;
@group(0) @binding(1) var<storage, read> instances: array<InstanceData>;
@group(0) @binding(2) var<storage, read_write> visible: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read_write> counters: Counters;
@group(0) @binding(4) var<storage, read> boxes: array<InstanceBounds>;
@group(0) @binding(5) var camera_depth: texture_depth_2d;

var<workgroup> group_near: atomic<u32>;
var<workgroup> group_far_inverted: atomic<u32>;

// A u32 that orders as the float does.
fn order_key(x: f32) -> u32 {
    let b = bitcast<u32>(x);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

@compute @workgroup_size(8, 8)
fn cs_mark_visible(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    if (local == 0u) {
        atomicStore(&group_near, 0u);
        atomicStore(&group_far_inverted, 0u);
    }
    workgroupBarrier();
    let size = textureDimensions(object_ids);
    if (all(id.xy < size)) {
        mark(vec2<i32>(id.xy));
    }
    workgroupBarrier();
    if (local == 0u) {
        let near = atomicLoad(&group_near);
        if (near != 0u) {
            atomicMax(&counters.depth_near, near);
            atomicMax(&counters.depth_far_inverted, atomicLoad(&group_far_inverted));
        }
    }
}

fn mark(pixel: vec2<i32>) {
    let object = textureLoad(object_ids, pixel, 0).x;
    if (object == 0u) {
        return;
    }
    let index = object - 1u;
    let receives = (instances[index].flags.x & FLAG_RECEIVER) != 0u;
    if (receives) {
        let depth = textureLoad(camera_depth, pixel, 0);
        atomicMax(&group_near, bitcast<u32>(depth));
        atomicMax(&group_far_inverted, ~bitcast<u32>(depth));
    }
    if (atomicOr(&visible[index], 1u) == 0u) {
        atomicAdd(&counters.visible_objects, 1u);
        if (receives) {
            atomicAdd(&counters.visible_receivers, 1u);
            let b = boxes[index];
            for (var k = 0u; k < 3u; k++) {
                atomicMax(&counters.receivers_min_inverted[k], ~order_key(b.min[k]));
                atomicMax(&counters.receivers_max[k], order_key(b.max[k]));
            }
        }
    }
}
