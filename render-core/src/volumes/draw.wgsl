// Stencil shadow volumes of the sun, second step (volumes/mod.rs): two indirect draws build
// each record of volumes/find.wgsl into triangles from the scene's vertices, wound outwards.
// Drawn z-fail into the stencil: back faces behind the visible surface count +1, front
// faces -1 (two-sided), so the stencil holds how many volumes hold the visible point.
#import volumes/common.wgsl

@group(2) @binding(0) var<storage, read> quad_records: array<vec2<u32>>;
@group(2) @binding(1) var<storage, read> cap_records: array<vec2<u32>>;
// Per caster, how far its volume reaches along the light (volumes/find.wgsl `cull_casters`).
@group(2) @binding(2) var<storage, read> reach: array<f32>;

fn extruded(p: vec3<f32>, caster: u32) -> vec3<f32> {
    return p - volume.to_light.xyz * reach[caster];
}

struct VolumeOut {
    @builtin(position) clip: vec4<f32>,
}

fn on_screen(p: vec3<f32>) -> VolumeOut {
    return VolumeOut(frame.clip_from_world * vec4<f32>(p, 1.0));
}

// A silhouette quad, wound outwards: the edge as its lit triangle winds it, (b, a, a', b').
@vertex
fn vs_quad(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    let record = quad_records[r];
    let c = casters[record.x];
    let e = edges[record.y & ~REVERSED];
    var a = world_vertex(c, e.a);
    var b = world_vertex(c, e.b);
    if ((record.y & REVERSED) != 0u) {
        let t = a;
        a = b;
        b = t;
    }
    let corners = array<vec3<f32>, 4>(b, a, extruded(a, record.x), extruded(b, record.x));
    let order = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u);
    return on_screen(corners[order[v]]);
}

// A casting triangle's caps: the near one as the triangle faces the sun, then the far one
// moved along the light and wound the other way.
@vertex
fn vs_cap(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    let record = cap_records[r];
    let c = casters[record.x];
    var p = triangle(c, record.y & ~REVERSED);
    if ((record.y & REVERSED) != 0u) {
        let t = p[1];
        p[1] = p[2];
        p[2] = t;
    }
    if (v < 3u) {
        return on_screen(p[v]);
    }
    let far = array<u32, 3>(0u, 2u, 1u);
    return on_screen(extruded(p[far[v - 3u]], record.x));
}

// The fill pass (when measuring or showing the fill heat map): the same faces with the depth
// test off, each fragment counted, in total, behind the visible surface (where z-fail writes
// the stencil) and per pixel. Fill: [0] fragments, [1] behind, then one word per pixel.
@group(3) @binding(0) var<storage, read_write> fill: array<atomic<u32>>;
// The camera's depth (the prepass's), to tell fragments behind the surface.
@group(3) @binding(1) var scene_depth: texture_depth_2d;

@fragment
fn fs_fill(@builtin(position) position: vec4<f32>) {
    let pixel = vec2<u32>(position.xy);
    let size = textureDimensions(scene_depth);
    if (any(pixel >= size)) {
        return;
    }
    atomicAdd(&fill[0], 1u);
    // Reversed depth: behind the surface is smaller.
    if (position.z <= textureLoad(scene_depth, vec2<i32>(pixel), 0)) {
        atomicAdd(&fill[1], 1u);
    }
    atomicAdd(&fill[2u + pixel.y * size.x + pixel.x], 1u);
}
