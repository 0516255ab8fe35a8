// Stencil shadow volumes of the sun, second step (volumes/mod.rs): two indirect draws build
// each record of volumes/find.wgsl into triangles from the scene's vertices, wound outwards.
// Drawn z-fail into the stencil: back faces behind the visible surface count +1, front
// faces -1 (two-sided), so the stencil holds how many volumes hold the visible point.
#import volumes/common.wgsl

@group(2) @binding(0) var<storage, read> quad_records: array<vec2<u32>>;
@group(2) @binding(1) var<storage, read> cap_records: array<vec2<u32>>;

fn extruded(p: vec3<f32>) -> vec3<f32> {
    return p - volume.to_light.xyz * volume.to_light.w;
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
    let corners = array<vec3<f32>, 4>(b, a, extruded(a), extruded(b));
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
    return on_screen(extruded(p[far[v - 3u]]));
}
