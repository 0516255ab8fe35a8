// Visible objects from the camera's object ids: one flag per object, and a count of visible
// receivers. Prepended with frame/instance.wgsl.


struct Counters {
    visible_objects: atomic<u32>,
    visible_receivers: atomic<u32>,
}

@group(0) @binding(0) var object_ids: texture_2d<u32>;
@group(0) @binding(1) var<storage, read> instances: array<InstanceData>;
@group(0) @binding(2) var<storage, read_write> visible: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read_write> counters: Counters;

@compute @workgroup_size(8, 8)
fn cs_mark_visible(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(object_ids);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let object = textureLoad(object_ids, vec2<i32>(id.xy), 0).x;
    if (object == 0u) {
        return;
    }
    let index = object - 1u;
    if (atomicOr(&visible[index], 1u) == 0u) {
        atomicAdd(&counters.visible_objects, 1u);
        if ((instances[index].flags.x & FLAG_RECEIVER) != 0u) {
            atomicAdd(&counters.visible_receivers, 1u);
        }
    }
}
