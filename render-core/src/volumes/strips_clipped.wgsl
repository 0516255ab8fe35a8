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
}

// A vertex at clip-space position `clip`, in every strip.
fn at_clip(clip: vec4<f32>) -> VolumeOut {
    return VolumeOut(clip, array<f32, 2>(1.0, 1.0));
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
    let start = -1.0 + 2.0 * first / k - 1e-3;
    let end = -1.0 + 2.0 * (last + 1.0) / k + 1e-3;
    return VolumeOut(
        v.clip,
        array<f32, 2>(
            select(u - start * v.clip.w, 1.0, first == 0.0),
            select(end * v.clip.w - u, 1.0, last >= k - 1.0),
        ),
    );
}
