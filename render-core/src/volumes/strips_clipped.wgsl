// The volumes' vertices where the adapter has CLIP_DISTANCES (volumes/pipelines.rs imports
// this as volumes/strips.wgsl, after `enable clip_distances;`): each interval of a volume
// is clipped to the strips of the picture its receivers lie in (Lloyd's discrete clamping,
// 3.2.2). The strips lie between planes through the eye, so the volume is cut along faces
// seen edge-on: the pieces need no caps there, and a pixel of a strip sees the whole
// volume of every interval drawn across it.

// Invariant as the camera's vertex stage (view/camera_vertex.wgsl): a near cap, a caster's
// own lit triangle, lands at the visible surface's depth there, and the caps' depth bias
// (volumes/pipelines.rs) puts it just behind, so a point on a lit face is outside the
// volume.
struct VolumeOut {
    @builtin(position) @invariant clip: vec4<f32>,
    // Past the first strip's start and before the last one's end: both at least 0 inside.
    @builtin(clip_distances) strip: array<f32, 2>,
    // The strip coordinates the piece is clipped at (`in_strips`).
    @location(0) @interpolate(flat) cut: vec2<f32>,
}

// What the fragment stages read.
struct FragmentIn {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) cut: vec2<f32>,
}

// Past every strip coordinate.
const UNCUT: vec2<f32> = vec2<f32>(-4.0, 4.0);
// How far inside its cuts a pixel centre must lie for the piece to be drawn there: a pixel
// centre on a cut sees the faces cut there edge-on, and the rasteriser rounds each face's
// cut edge on its own, so the piece counts there as neither whole nor absent. The pixels of
// the strips the piece is drawn across lie CUT_MARGIN inside, twice this.
const CUT_GUARD: f32 = 5e-4;
const CUT_MARGIN: f32 = 1e-3;

// A vertex at clip-space position `clip`, in every strip.
fn at_clip(clip: vec4<f32>) -> VolumeOut {
    return VolumeOut(clip, array<f32, 2>(1.0, 1.0), UNCUT);
}

// Whether the piece a fragment belongs to is whole at its pixel centre: well inside the cuts.
// Where it is not, the pixel lies in no strip the piece is drawn across, so no volume is lost.
fn whole_at(f: FragmentIn) -> bool {
    let u = strip_coordinate(f.position.xy);
    return u >= f.cut.x + CUT_GUARD && u <= f.cut.y - CUT_GUARD;
}

// `v` clipped to the strips of the interval of `caster_word` (volumes/find.wgsl
// `strips_word`: the first strip in bits 0 to 7, the last in 8 to 15), whose pixel centres
// `slice_of` (volumes/grid.wgsl) puts in them, with a thousandth of the picture to spare.
fn in_strips(v: VolumeOut, caster_word: u32) -> VolumeOut {
    let caster = caster_word & CASTER_BITS;
    let word = strips[caster * MAX_INTERVALS + (caster_word >> INTERVAL_SHIFT)];
    let k = f32(volume.grid.x);
    let first = f32(word & 0xffu);
    let last = f32((word >> 8u) & 0xffu);
    let u = dot(v.clip.xy, volume.slicing.xy) / max(volume.slicing.z, 1e-6);
    let start = -1.0 + 2.0 * first / k - CUT_MARGIN;
    let end = -1.0 + 2.0 * (last + 1.0) / k + CUT_MARGIN;
    return VolumeOut(
        v.clip,
        array<f32, 2>(
            select(u - start * v.clip.w, 1.0, first == 0.0),
            select(end * v.clip.w - u, 1.0, last >= k - 1.0),
        ),
        vec2<f32>(select(start, UNCUT.x, first == 0.0), select(end, UNCUT.y, last >= k - 1.0)),
    );
}
