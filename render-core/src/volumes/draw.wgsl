// Stencil shadow volumes of the sun, second step (volumes/mod.rs): four indirect draws build
// each record of volumes/find.wgsl into triangles from the scene's vertices, wound outwards.
// Z-fail volumes: back faces behind the visible surface count +1, front faces -1; z-pass
// volumes: front faces in front of it +1, back faces -1 (two-sided either way), so the
// stencil holds how many volumes hold the visible point.
#import volumes/common.wgsl
#import volumes/strips.wgsl
#import palette.wgsl

@group(2) @binding(0) var<storage, read> quad_records: array<vec2<u32>>;
@group(2) @binding(1) var<storage, read> cap_records: array<vec2<u32>>;
// Per caster, MAX_INTERVALS intervals of its volume: extrusion distances along the light
// where it starts and ends (volumes/find.wgsl `cull_casters`).
@group(2) @binding(2) var<storage, read> intervals: array<vec2<f32>>;
// Per caster, its interval count and flags (volumes/find.wgsl `kept`).
@group(2) @binding(3) var<storage, read> kept: array<u32>;
// Per interval, the strips of the picture it is drawn across (volumes/strips.wgsl).
@group(2) @binding(4) var<storage, read> strips: array<u32>;

// A record's interval: the record's caster word holds the caster and the interval's index.
fn interval_of(caster_word: u32) -> vec2<f32> {
    let caster = caster_word & CASTER_BITS;
    return intervals[caster * MAX_INTERVALS + (caster_word >> INTERVAL_SHIFT)];
}

// `p` moved `distance` away from the light, on screen. A point light's volumes that reach
// past the scene go to infinity (w = 0: a flat cap between far points would sag back into
// the scene; depth clamping keeps them), the sun's to past the scene.
fn extruded(p: vec3<f32>, distance: f32) -> VolumeOut {
    if (from_point() && distance >= volume.to_light.w) {
        return at_clip(frame.clip_from_world * vec4<f32>(away_from_light(p), 0.0));
    }
    return on_screen(p + away_from_light(p) * distance);
}

// Z-pass records fill the record buffers from their end.
fn from_end(r: u32, length: u32) -> u32 {
    return length - 1u - r;
}

fn on_screen(p: vec3<f32>) -> VolumeOut {
    return at_clip(frame.clip_from_world * vec4<f32>(p, 1.0));
}

// A silhouette quad across one interval, wound outwards: the edge as its lit triangle winds
// it, (b, a, a', b'), from the interval's start to its end.
fn quad(v: u32, record: vec2<u32>) -> VolumeOut {
    let c = casters[record.x & CASTER_BITS];
    let span = interval_of(record.x);
    let e = edges[record.y & ~REVERSED];
    var a = world_vertex(c, e.a);
    var b = world_vertex(c, e.b);
    if ((record.y & REVERSED) != 0u) {
        let t = a;
        a = b;
        b = t;
    }
    let corners = array<VolumeOut, 4>(
        extruded(b, span.x),
        extruded(a, span.x),
        extruded(a, span.y),
        extruded(b, span.y),
    );
    let order = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u);
    return in_strips(corners[order[v]], record.x);
}

@vertex
fn vs_quad(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return quad(v, quad_records[r]);
}

@vertex
fn vs_quad_pass(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return quad(v, quad_records[from_end(r, arrayLength(&quad_records))]);
}

// Which caps a pipeline draws (volumes/pipelines.rs `Faces`).
const NEAR_CAPS: u32 = 0u;
const PAST_FAR_CAPS: u32 = 1u;
const MOVED_CAPS: u32 = 2u;

// A casting triangle's caps across one interval, drawn by three pipelines
// (volumes/pipelines.rs). Vertices 0 to 2: where the interval starts at the caster, the near
// cap, the triangle itself as it faces the sun (clipped at the near plane like the camera's
// passes, unless the caster reaches past the far plane, then depth clamped; both pushed
// back); where it starts further on, the triangle moved there. Vertices 3 to 5: the triangle
// moved to where the interval ends, wound the other way. Each pipeline collapses the
// vertices it does not draw.
fn cap(v: u32, record: vec2<u32>, faces: u32) -> VolumeOut {
    let span = interval_of(record.x);
    var drawn = MOVED_CAPS;
    if (v < 3u && span.x == 0.0) {
        drawn = select(NEAR_CAPS, PAST_FAR_CAPS, (kept[record.x & CASTER_BITS] & PAST_FAR) != 0u);
    }
    if (drawn != faces) {
        return nothing();
    }
    let c = casters[record.x & CASTER_BITS];
    var p = triangle(c, record.y & ~REVERSED);
    if ((record.y & REVERSED) != 0u) {
        let t = p[1];
        p[1] = p[2];
        p[2] = t;
    }
    if (v < 3u) {
        return in_strips(extruded(p[v], span.x), record.x);
    }
    let far = array<u32, 3>(0u, 2u, 1u);
    return in_strips(extruded(p[far[v - 3u]], span.y), record.x);
}

fn nothing() -> VolumeOut {
    return at_clip(vec4<f32>(0.0, 0.0, 0.0, 1.0));
}

@vertex
fn vs_near_cap(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return cap(v, cap_records[r], NEAR_CAPS);
}

@vertex
fn vs_past_far_cap(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return cap(v, cap_records[r], PAST_FAR_CAPS);
}

@vertex
fn vs_moved_cap(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return cap(v, cap_records[r], MOVED_CAPS);
}

fn cap_from_end(r: u32) -> vec2<u32> {
    return cap_records[from_end(r, arrayLength(&cap_records))];
}

// Z-pass: a closed caster's near cap is its own lit surface, which a camera ray outside the
// volume can cross only where it ends, so only the far cap is drawn. An open mesh's triangle
// can be seen through from its back, so it keeps both.
fn near_cap_pass(v: u32, r: u32, faces: u32) -> VolumeOut {
    let record = cap_from_end(r);
    if (casters[record.x & CASTER_BITS].closed != 0u) {
        return nothing();
    }
    return cap(v, record, faces);
}

@vertex
fn vs_near_cap_pass(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return near_cap_pass(v, r, NEAR_CAPS);
}

@vertex
fn vs_past_far_cap_pass(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return near_cap_pass(v, r, PAST_FAR_CAPS);
}

@vertex
fn vs_moved_cap_pass(@builtin(vertex_index) v: u32, @builtin(instance_index) r: u32) -> VolumeOut {
    return cap(v, cap_from_end(r), MOVED_CAPS);
}

// The fill pass (when measuring or showing the fill heat map): the same faces with the depth
// test off, each fragment counted, in total, where it writes the stencil (behind the visible
// surface for z-fail, in front of it for z-pass) and per pixel. Fill: [0] fragments, [1]
// stencil writes, then one word per pixel.
@group(3) @binding(0) var<storage, read_write> fill: array<atomic<u32>>;
// The camera's depth (the prepass's), to tell fragments behind the surface.
@group(3) @binding(1) var scene_depth: texture_depth_2d;

// Every fragment rasterised counts as fill; a stencil write only where the stencil pass
// keeps it (`fs_stencil`).
fn count_fill(f: FragmentIn, z_pass: bool) {
    let position = f.position;
    let pixel = vec2<u32>(position.xy);
    let size = textureDimensions(scene_depth);
    if (any(pixel >= size)) {
        return;
    }
    atomicAdd(&fill[0], 1u);
    // Reversed depth: in front of the surface is greater (the stencil pass's depth test).
    if ((position.z > textureLoad(scene_depth, vec2<i32>(pixel), 0)) == z_pass && whole_at(f)) {
        atomicAdd(&fill[1], 1u);
    }
    atomicAdd(&fill[2u + pixel.y * size.x + pixel.x], 1u);
}

@fragment
fn fs_fill(f: FragmentIn) {
    count_fill(f, false);
}

@fragment
fn fs_fill_pass(f: FragmentIn) {
    count_fill(f, true);
}

// The stencil pass where pieces are cut to their strips: a fragment counts only where its
// piece is whole (volumes/strips_clipped.wgsl `whole_at`).
@fragment
fn fs_stencil(f: FragmentIn) {
    if (!whole_at(f)) {
        discard;
    }
}

// The `volumes` overlay: each volume face in front of the visible surface, translucent
// yellow (Lloyd et al.'s Figure 1), so overlapping layers grow brighter.
@fragment
fn fs_volume(f: FragmentIn) -> @location(0) vec4<f32> {
    if (!whole_at(f)) {
        discard;
    }
    return vec4<f32>(PALETTE_VOLUME, 0.12);
}
