// Stencil shadow volumes, second step (volumes/mod.rs): eight pipelines over six indirect
// draws build each record of volumes/records.wgsl into triangles from the scene's vertices,
// wound outwards.
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
// Fan caps (volumes/records.wgsl `append_fans`) and per caster its fan's corner, inverted.
@group(2) @binding(5) var<storage, read> fan_records: array<vec2<u32>>;
@group(2) @binding(6) var<storage, read> anchors: array<u32>;

// A record's interval: the record's caster word holds the caster and the interval's index.
fn interval_of(caster_word: u32) -> vec2<f32> {
    let caster = caster_word & CASTER_BITS;
    return intervals[caster * MAX_INTERVALS + (caster_word >> INTERVAL_SHIFT)];
}

// `p` moved `distance` away from the light, on screen. A point light's volumes that reach
// past the scene go to infinity (w = 0: a flat cap between far points would sag back into
// the scene; depth clamping keeps them), the sun's to past the scene.
fn extruded(p: vec3<f32>, distance: f32) -> VolumeOut {
    if (at_infinity(distance)) {
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
// it, (b, a, a', b'), from the interval's start to its end, as two triangles. Each vertex
// moves only its own corner.
fn quad(v: u32, record: vec2<u32>) -> VolumeOut {
    let c = casters[record.x & CASTER_BITS];
    let span = interval_of(record.x);
    let e = edges[record.y & ~REVERSED];
    let order = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u);
    let corner = order[v];
    let on_b = (corner == 0u || corner == 3u) != ((record.y & REVERSED) != 0u);
    let p = world_vertex(c, select(e.a, e.b, on_b));
    return in_strips(extruded(p, select(span.y, span.x, corner < 2u)), record.x);
}

// Vertex `i` of a draw is vertex `i % record_vertices(k)` of record `i / record_vertices(k)`
// (common.wgsl).
@vertex
fn vs_quad(@builtin(vertex_index) i: u32) -> VolumeOut {
    return quad(i % QUAD_VERTICES, quad_records[i / QUAD_VERTICES]);
}

@vertex
fn vs_quad_pass(@builtin(vertex_index) i: u32) -> VolumeOut {
    let r = from_end(i / QUAD_VERTICES, arrayLength(&quad_records));
    return quad(i % QUAD_VERTICES, quad_records[r]);
}

// Corner `k` of a cap record's triangle as it casts: wound the other way where its back
// faces the light (REVERSED), so that every cap is wound outwards.
fn cap_corner(record: vec2<u32>, k: u32) -> vec3<f32> {
    let swapped = array<u32, 3>(0u, 2u, 1u);
    let corner = select(k, swapped[k], (record.y & REVERSED) != 0u);
    return triangle_corner(casters[record.x & CASTER_BITS], record.y & TRIANGLE_BITS, corner);
}

// The cap record of draw `k`'s vertex `i` (common.wgsl `cap_slot`).
fn cap_record(k: u32, i: u32) -> vec2<u32> {
    return cap_records[cap_slot(k, i / CAP_VERTICES)];
}

// A cap where its interval starts at the caster (volumes/records.wgsl `find_caps`): the
// casting triangle itself, clipped at the near plane like the camera's passes (near caps), or
// depth clamped where the caster reaches past the far plane (past-far caps), pushed back
// either way (volumes/pipelines.rs `Faces`). A pipeline draws the one it is for and
// collapses the other.
fn cap_at_caster(i: u32, record: vec2<u32>, past_far: bool) -> VolumeOut {
    if (((kept[record.x & CASTER_BITS] & PAST_FAR) != 0u) != past_far) {
        return nothing();
    }
    let span = interval_of(record.x);
    return in_strips(extruded(cap_corner(record, i % CAP_VERTICES), span.x), record.x);
}

// A cap moved along the light: the triangle where its interval starts further on, as it
// faces the light, or where it ends, wound the other way.
fn moved_cap(i: u32, record: vec2<u32>) -> VolumeOut {
    let span = interval_of(record.x);
    if ((record.y & AT_START) != 0u) {
        return in_strips(extruded(cap_corner(record, i % CAP_VERTICES), span.x), record.x);
    }
    let far = array<u32, 3>(0u, 2u, 1u);
    return in_strips(extruded(cap_corner(record, far[i % CAP_VERTICES]), span.y), record.x);
}

// A fan cap's triangle (volumes/records.wgsl `append_fans`): from the caster's fan corner to
// its silhouette edge, as the edge's lit triangle winds it where the interval starts, the
// other way where it ends. The two edges at the corner draw nothing (compared in the mesh's
// space: each vertex moves only its own corner into the world).
fn fan_cap(i: u32, record: vec2<u32>) -> VolumeOut {
    let c = casters[record.x & CASTER_BITS];
    let e = edges[record.y & TRIANGLE_BITS];
    let apex = ~anchors[record.x & CASTER_BITS];
    let corner = local_vertex(c.base_vertex + apex);
    if (all(local_vertex(c.base_vertex + e.a) == corner)
        || all(local_vertex(c.base_vertex + e.b) == corner)) {
        return nothing();
    }
    let at_start = (record.y & AT_START) != 0u;
    let swapped = ((record.y & REVERSED) != 0u) == at_start;
    let corners = array<u32, 3>(apex, select(e.a, e.b, swapped), select(e.b, e.a, swapped));
    let span = interval_of(record.x);
    let p = world_vertex(c, corners[i % CAP_VERTICES]);
    return in_strips(extruded(p, select(span.y, span.x, at_start)), record.x);
}

@vertex
fn vs_fan_cap(@builtin(vertex_index) i: u32) -> VolumeOut {
    return fan_cap(i, fan_records[i / CAP_VERTICES]);
}

@vertex
fn vs_fan_cap_pass(@builtin(vertex_index) i: u32) -> VolumeOut {
    return fan_cap(i, fan_records[from_end(i / CAP_VERTICES, arrayLength(&fan_records))]);
}

fn nothing() -> VolumeOut {
    return at_clip(vec4<f32>(0.0, 0.0, 0.0, 1.0));
}

@vertex
fn vs_near_cap(@builtin(vertex_index) i: u32) -> VolumeOut {
    return cap_at_caster(i, cap_record(CAPS_AT_CASTERS, i), false);
}

@vertex
fn vs_past_far_cap(@builtin(vertex_index) i: u32) -> VolumeOut {
    return cap_at_caster(i, cap_record(CAPS_AT_CASTERS, i), true);
}

@vertex
fn vs_moved_cap(@builtin(vertex_index) i: u32) -> VolumeOut {
    return moved_cap(i, cap_record(MOVED_CAPS, i));
}

// Z-pass: only open meshes have caps at their casters (volumes/records.wgsl `find_caps`).
@vertex
fn vs_near_cap_pass(@builtin(vertex_index) i: u32) -> VolumeOut {
    return cap_at_caster(i, cap_record(Z_PASS_DRAWS + CAPS_AT_CASTERS, i), false);
}

@vertex
fn vs_past_far_cap_pass(@builtin(vertex_index) i: u32) -> VolumeOut {
    return cap_at_caster(i, cap_record(Z_PASS_DRAWS + CAPS_AT_CASTERS, i), true);
}

@vertex
fn vs_moved_cap_pass(@builtin(vertex_index) i: u32) -> VolumeOut {
    return moved_cap(i, cap_record(Z_PASS_DRAWS + MOVED_CAPS, i));
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
