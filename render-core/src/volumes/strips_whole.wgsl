// The volumes' vertices where the adapter has no CLIP_DISTANCES (volumes/pipelines.rs
// imports this as volumes/strips.wgsl): every interval of a volume is drawn across the
// whole picture, as continuous clamping draws it (volumes/strips_clipped.wgsl clips it to
// its strips).

// Invariant as the camera's vertex stage (view/camera_vertex.wgsl): a near cap, a caster's
// own lit triangle, lands at the visible surface's depth there, and the caps' depth bias
// (volumes/pipelines.rs) puts it just behind, so a point on a lit face is outside the
// volume.
struct VolumeOut {
    @builtin(position) @invariant clip: vec4<f32>,
}

// What the fragment stages read.
struct FragmentIn {
    @builtin(position) position: vec4<f32>,
}

// Every piece is whole: nothing is cut.
fn whole_at(f: FragmentIn) -> bool {
    return true;
}

// A vertex at clip-space position `clip`.
fn at_clip(clip: vec4<f32>) -> VolumeOut {
    return VolumeOut(clip);
}

// `v` as it is: no strips without clip distances.
fn in_strips(v: VolumeOut, caster_word: u32) -> VolumeOut {
    return v;
}
