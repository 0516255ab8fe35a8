// What the volume passes share (volumes/mod.rs): the frame's light and extrusion, the scene's
// vertices and indices read as storage, the edges and the casters.
#import view/common.wgsl
struct VolumeFrame {
    // xyz: unit vector towards the sun; w: how far volumes are extruded, metres.
    to_light: vec4<f32>,
    // x: edge work items, y: triangle work items, z: casters; w: the outcome code of a
    // culled caster.
    counts: vec4<u32>,
    // x: instances; y: bit 0 culling, bit 1 clamping, bit 2 cell centres only, bit 3 the
    // CPU's exact intervals, bit 4 no strips (volumes/find.wgsl); z: the cull's lanes per caster; w: how
    // volumes count (0: per caster, 1: all z-pass, 2: all z-fail).
    options: vec4<u32>,
    // The light's frame: xyz two axes across the light and the one it travels; w: where the
    // receiver grid starts along the first two, and the scene's nearest depth along the last.
    right: vec4<f32>,
    up: vec4<f32>,
    travel: vec4<f32>,
    // x: the grid's cell size, metres; y: pixels a volume vertex costs as much as
    // (volumes/calibrate.rs); z: the size of the grid's depth bins, metres (DEPTH_BINS of
    // them span the scene's depths, volumes/grid.wgsl); w: the most receiver points of a
    // cell tested one by one against a caster (more: the cell's depths whole).
    cell: vec4<f32>,
    // The cull's budget of loop iterations (volumes/frame.rs `StepBudget`): x per lane of a
    // caster in `cull_casters`, past which it goes to workgroups of its own; y per lane of
    // those; z
    // the most casters a frame gives workgroups (at most BIG_CASTERS); w their lanes each.
    steps: vec4<u32>,
    // The camera's near rectangle in the light's frame (as `in_light` places points): its
    // box, xyz.
    near_lo: vec4<f32>,
    near_hi: vec4<f32>,
    // The slices' direction in the picture: a pixel's strip coordinate is
    // dot(ndc, xy) / z, from -1 to 1 (volumes/find.wgsl `slice_of`); w: the camera's far
    // plane, metres.
    slicing: vec4<f32>,
    // The receiver grid (volumes/grid.wgsl): x the slices of the view (1 to MAX_SLICES), y
    // and z its columns and rows of cells, w a point light's cells along a cube face's side.
    grid: vec4<u32>,
    // xyz: the point light the volumes are cast from; w: 1 for a point light, 0 for the sun.
    point: vec4<f32>,
    // For a point light, the pyramid from it to the camera's near rectangle: planes
    // (xyz: normal, w: offset) with the pyramid on their positive side (`counts_z_pass`).
    near_planes: array<vec4<f32>, 5>,
    // xy: the picture's size in pixels (written when the volumes are drawn).
    picture: vec4<f32>,
}

// The strip coordinate of picture point `position` (pixels from the top left, a pixel's
// centre at half-integers): -1 to 1 across the picture along `slicing` (volumes/grid.wgsl
// `slice_of` places pixel centres in strips by it).
fn strip_coordinate(position: vec2<f32>) -> f32 {
    let ndc = vec2<f32>(
        2.0 * position.x / volume.picture.x - 1.0,
        1.0 - 2.0 * position.y / volume.picture.y,
    );
    return dot(ndc, volume.slicing.xy) / max(volume.slicing.z, 1e-6);
}

fn from_point() -> bool {
    return volume.point.w > 0.0;
}

// From `p` away from the light (unit): the way its volume is extruded.
fn away_from_light(p: vec3<f32>) -> vec3<f32> {
    if (from_point()) {
        return normalize(p - volume.point.xyz);
    }
    return -volume.to_light.xyz;
}

// Whether a volume that reaches `distance` from its caster is drawn to infinity: a point
// light's that reach past the scene (volumes/draw.wgsl `extruded`).
fn at_infinity(distance: f32) -> bool {
    return from_point() && distance >= volume.to_light.w;
}

// Discrete clamping's most slices, and the most intervals a caster's volume is drawn in.
// Keep in sync with volumes/pipelines.rs.
const MAX_SLICES: u32 = 32u;
const MAX_INTERVALS: u32 = 4u;
// A record's caster word: the caster, and its interval from this bit on.
const INTERVAL_SHIFT: u32 = 28u;
const CASTER_BITS: u32 = 0x0fffffffu;
// The indirect draws of the volume faces (volumes/find.wgsl `draws`, volumes/pipelines.rs
// `DRAWS`): z-fail, then z-pass, each quads, caps at the casters, moved caps, fan caps.
const QUADS: u32 = 0u;
const CAPS_AT_CASTERS: u32 = 1u;
const MOVED_CAPS: u32 = 2u;
const FAN_CAPS: u32 = 3u;
const Z_PASS_DRAWS: u32 = 4u;
// The vertices of one record of draw `k` (volumes/draw.wgsl): a quad's two triangles, or a
// cap's one. The draws are not instanced: a GPU shades tiny instances a warp each, and
// llvmpipe runs its vertex pipeline once per instance.
const QUAD_VERTICES: u32 = 6u;
const CAP_VERTICES: u32 = 3u;
fn record_vertices(k: u32) -> u32 {
    return select(CAP_VERTICES, QUAD_VERTICES, k % Z_PASS_DRAWS == QUADS);
}
// Where cap records lie in their buffer, of CAP_RECORDS a triangle item (volumes/scene.rs):
// first those of the caps at the casters (an interval starting at its caster, as at most one
// of a triangle's does: its near or past-far cap), then those of the caps moved along the
// light (where an interval starting further on starts, and where each ends: two for each
// record of the at most two intervals per triangle item that `within_room` leaves room
// for). Each part holds z-fail records from its start and z-pass records from its end.
const CAP_RECORDS: u32 = 5u;
fn cap_slot(k: u32, n: u32) -> u32 {
    let triangles = volume.counts.y;
    var start = 0u;
    var end = triangles;
    if (k % Z_PASS_DRAWS == MOVED_CAPS) {
        start = triangles;
        end = triangles * CAP_RECORDS;
    }
    return select(start + n, end - 1u - n, k >= Z_PASS_DRAWS);
}

// Whether caster `c`'s moved caps are fans over its silhouette (volumes/records.wgsl
// `append_fans`) instead of its lit triangles: a closed convex mesh's silhouette is one loop
// around its lit triangles, so a fan from one of its corners closes the volume with two
// triangles fewer than it has edges (an 8-sided strut: 8 triangles for its 10 edges, against
// up to 14 lit triangles). The fan's triangles lie inside the mesh's hull moved along the
// light, behind its lit surface: every point between the fan and the lit triangles it stands
// for is inside the caster or in its shadow, and no receiver lies there.
fn fan_capped(c: Caster) -> bool {
    return c.closed != 0u && c.convex != 0u;
}

// One caster: its mesh's edges and triangles, where its vertices start, whether its mesh is
// closed, and its mesh's box (xyz). Keep in sync with volumes/scene.rs (CasterGpu).
struct Caster {
    instance: u32,
    first_edge: u32,
    first_triangle: u32,
    base_vertex: u32,
    // Work items before this caster's edges and triangles.
    edge_start: u32,
    triangle_start: u32,
    closed: u32,
    // 1: the mesh is convex (volumes/edges.rs): its own points facing the light are lit.
    convex: u32,
    local_min: vec4<f32>,
    local_max: vec4<f32>,
}

struct Edge {
    a: u32,
    b: u32,
    face: u32,
    opposite: u32,
}

const NO_FACE: u32 = 0xffffffffu;
// A caster's interval count with this bit is counted z-pass (volumes/find.wgsl
// `cull_casters`).
const Z_PASS: u32 = 0x80000000u;
// ... and with this one, its box reaches past the camera's far plane: its near caps are
// depth clamped too, or the far plane would clip them and not the rest of its volume.
const PAST_FAR: u32 = 0x40000000u;
const COUNT_BITS: u32 = 0x3fffffffu;
// A record's high bit: extruded the other way round (negative multiplicity).
const REVERSED: u32 = 0x80000000u;
// A moved cap record's next bit: the cap where its interval starts (else where it ends).
const AT_START: u32 = 0x40000000u;
const TRIANGLE_BITS: u32 = 0x3fffffffu;
// Float32 per scene vertex: position, then normal (scene_gpu/gpu_data.rs Vertex).
const VERTEX_FLOATS: u32 = 6u;

@group(1) @binding(0) var<uniform> volume: VolumeFrame;
@group(1) @binding(1) var<storage, read> vertices: array<f32>;
@group(1) @binding(2) var<storage, read> indices: array<u32>;
@group(1) @binding(3) var<storage, read> edges: array<Edge>;
@group(1) @binding(4) var<storage, read> casters: array<Caster>;
@group(1) @binding(5) var<storage, read> bounds: array<InstanceBounds>;

fn local_vertex(index: u32) -> vec3<f32> {
    let at = index * VERTEX_FLOATS;
    return vec3<f32>(vertices[at], vertices[at + 1u], vertices[at + 2u]);
}

fn world_vertex(c: Caster, index: u32) -> vec3<f32> {
    return world_position(c.instance, local_vertex(c.base_vertex + index));
}

// Corner `k` of the caster's triangle `t` (of its mesh) in world space.
fn triangle_corner(c: Caster, t: u32, k: u32) -> vec3<f32> {
    return world_vertex(c, indices[(c.first_triangle + t) * 3u + k]);
}

// The caster's triangle `t` (of its mesh) in world space.
fn triangle(c: Caster, t: u32) -> array<vec3<f32>, 3> {
    return array<vec3<f32>, 3>(
        triangle_corner(c, t, 0u),
        triangle_corner(c, t, 1u),
        triangle_corner(c, t, 2u),
    );
}

// +1 when the triangle's front faces the sun; -1 when its back does, which casts only in a
// mesh that is not closed (volumes/edges.rs `face_sign`).
fn face_sign(c: Caster, t: u32) -> i32 {
    let p = triangle(c, t);
    let lit = dot(cross(p[1] - p[0], p[2] - p[0]), -away_from_light(p[0])) > 0.0;
    if (lit) {
        return 1;
    }
    return select(-1, 0, c.closed != 0u);
}

// The caster of work item `item`: the last whose first item is at most it.
fn caster_of(item: u32, triangles: bool) -> u32 {
    var lo = 0u;
    var hi = volume.counts.z;
    while (hi - lo > 1u) {
        let mid = (lo + hi) / 2u;
        let start = select(casters[mid].edge_start, casters[mid].triangle_start, triangles);
        if (start <= item) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}


// Corner `k` (0 to 7) of the box from `lo` to `hi`: bit 0 picks x, bit 1 y, bit 2 z.
fn corner(lo: vec3<f32>, hi: vec3<f32>, k: u32) -> vec3<f32> {
    return select(lo, hi, vec3<bool>((k & 1u) != 0u, (k & 2u) != 0u, (k & 4u) != 0u));
}

fn box_corner(b: InstanceBounds, k: u32) -> vec3<f32> {
    return corner(b.min, b.max, k);
}
