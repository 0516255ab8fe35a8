// Stencil shadow volumes of the sun, second step (volumes/mod.rs): four indirect draws build
// each record of volumes/find.wgsl into triangles from the scene's vertices, wound outwards.
// Z-fail volumes: back faces behind the visible surface count +1, front faces -1; z-pass
// volumes: front faces in front of it +1, back faces -1 (two-sided either way), so the
// stencil holds how many volumes hold the visible point.
#import volumes/common.wgsl

@group(2) @binding(0) var<storage, read> quad_records: array<vec2<u32>>;
@group(2) @binding(1) var<storage, read> cap_records: array<vec2<u32>>;
// Per caster, how far its volume reaches along the light, negative where counted z-pass
// (volumes/find.wgsl `cull_casters`).
@group(2) @binding(2) var<storage, read> reach: array<f32>;

fn extruded(p: vec3<f32>, caster: u32) -> vec3<f32> {
    return p - volume.to_light.xyz * abs(reach[caster]);
}

// Z-pass records fill the record buffers from their end.
fn from_end(r: u32, length: u32) -> u32 {
    return length - 1u - r;
}

// Invariant as the camera's vertex stage (view/camera_vertex.wgsl): a near cap, a caster's
// own lit triangle, lands at exactly the visible surface's depth there, so the depth test
// counts it behind the surface (z-fail: the point on a lit face is outside the volume).
struct VolumeOut {
    @builtin(position) @invariant clip: vec4<f32>,
}

fn on_screen(p: vec3<f32>) -> VolumeOut {
    return VolumeOut(frame.clip_from_world * vec4<f32>(p, 1.0));
}

// A silhouette quad, wound outwards: the edge as its lit triangle winds it, (b, a, a', b').
fn quad(v: u32, record: vec2<u32>) -> VolumeOut {
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

@vertex
fn vs_quad(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return quad(v, quad_records[r]);
}

@vertex
fn vs_quad_pass(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return quad(v, quad_records[from_end(r, arrayLength(&quad_records))]);
}

// A casting triangle's caps, drawn by two pipelines (volumes/pipelines.rs): the near cap as
// the triangle faces the sun (vertices 0 to 2, clipped at the near plane like the camera's
// passes), and the far one moved along the light and wound the other way (3 to 5, depth
// clamped). Each pipeline collapses the other's three vertices to nothing.
fn cap(v: u32, record: vec2<u32>, near: bool) -> VolumeOut {
    if ((v < 3u) != near) {
        return nothing();
    }
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

fn nothing() -> VolumeOut {
    return VolumeOut(vec4<f32>(0.0, 0.0, 0.0, 1.0));
}

@vertex
fn vs_near_cap(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return cap(v, cap_records[r], true);
}

@vertex
fn vs_far_cap(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return cap(v, cap_records[r], false);
}

fn cap_from_end(r: u32) -> vec2<u32> {
    return cap_records[from_end(r, arrayLength(&cap_records))];
}

// Z-pass: a closed caster's near cap is its own lit surface, which a camera ray outside the
// volume can cross only where it ends, so only the far cap is drawn. An open mesh's triangle
// can be seen through from its back, so it keeps both.
@vertex
fn vs_near_cap_pass(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    let record = cap_from_end(r);
    if (casters[record.x].closed != 0u) {
        return nothing();
    }
    return cap(v, record, true);
}

@vertex
fn vs_far_cap_pass(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return cap(v, cap_from_end(r), false);
}

// The fill pass (when measuring or showing the fill heat map): the same faces with the depth
// test off, each fragment counted, in total, where it writes the stencil (behind the visible
// surface for z-fail, in front of it for z-pass) and per pixel. Fill: [0] fragments, [1]
// stencil writes, then one word per pixel.
@group(3) @binding(0) var<storage, read_write> fill: array<atomic<u32>>;
// The camera's depth (the prepass's), to tell fragments behind the surface.
@group(3) @binding(1) var scene_depth: texture_depth_2d;

fn count_fill(position: vec4<f32>, z_pass: bool) {
    let pixel = vec2<u32>(position.xy);
    let size = textureDimensions(scene_depth);
    if (any(pixel >= size)) {
        return;
    }
    atomicAdd(&fill[0], 1u);
    // Reversed depth: in front of the surface is greater (the stencil pass's depth test).
    if ((position.z > textureLoad(scene_depth, vec2<i32>(pixel), 0)) == z_pass) {
        atomicAdd(&fill[1], 1u);
    }
    atomicAdd(&fill[2u + pixel.y * size.x + pixel.x], 1u);
}

@fragment
fn fs_fill(@builtin(position) position: vec4<f32>) {
    count_fill(position, false);
}

@fragment
fn fs_fill_pass(@builtin(position) position: vec4<f32>) {
    count_fill(position, true);
}
