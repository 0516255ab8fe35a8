// Measurement, group 2 of the shading pass (metrics/mod.rs): the oracle flags (a block per
// shadow view), the counters, and the per-object outcomes the `casters` overlay tints by.
// Written only when frame.params.z != 0 (measuring); the outcomes are read when tinting.
#import view/common.wgsl

// Keep in sync with metrics/mod.rs (`take_latest`, `UNDERSAMPLING_BINS`).
struct Measured {
    visible_px: atomic<u32>,
    missing_px: atomic<u32>,
    extra_px: atomic<u32>,
    // Per view (this frame's `frame.views.x`): casters in its oracle set; then per view its
    // undersampling histogram.
    per_view: array<atomic<u32>>,
}

// Undersampling bins: exactly 0 octaves, then quarter octaves up to 8, the last open.
const UNDERSAMPLING_BINS: u32 = 33u;

@group(2) @binding(0) var<storage, read_write> oracle: array<atomic<u32>>;
@group(2) @binding(1) var<storage, read_write> measured: Measured;
// Per view and object, the outcome code in the low byte (culling/codes.wgsl).
@group(2) @binding(2) var<storage, read> outcomes: array<u32>;

// Caster `id` (instance index + 1) wins a shadowed tap of view `v`: it is in the view's oracle.
fn mark_oracle(v: u32, id: u32) {
    if (id != 0u && atomicOr(&oracle[v * frame.views.y + id - 1u], 1u) == 0u) {
        atomicAdd(&measured.per_view[v], 1u);
    }
}

// Counts a visible receiver pixel and whether its shadow differs from the reference.
fn count_error(visibility: f32, reference: f32) {
    atomicAdd(&measured.visible_px, 1u);
    if (reference < visibility) {
        atomicAdd(&measured.missing_px, 1u);
    } else if (reference > visibility) {
        atomicAdd(&measured.extra_px, 1u);
    }
}

// Counts how many octaves view `v` undersamples the visible point at `world_pos` with
// geometric normal `n`: max(0, log2 of a texel's footprint over a pixel's), both as areas on
// the surface (Lauritzen's SDSM reports texels per pixel the same way).
fn count_undersampling(v: u32, world_pos: vec3<f32>, n: vec3<f32>) {
    let view = shadow_views[v];
    let to_eye = frame.eye_world.xyz - world_pos;
    let distance = length(to_eye);
    let pixel_m = distance * frame.camera_forward.w;
    let cos_view = max(abs(dot(n, to_eye / max(distance, 1e-6))), 0.02);
    // A perspective view's light comes from its centre of projection, the world point its
    // clip space puts at (0, 0, z, 0).
    let perspective = view.index.y == 1u;
    var to_light = view.light_dir.xyz;
    if (perspective) {
        let centre = view.world_from_light_clip * vec4<f32>(0.0, 0.0, 1.0, 0.0);
        to_light = normalize(world_pos - centre.xyz / centre.w);
    }
    let cos_light = max(abs(dot(n, to_light)), 0.02);
    // Texels of a warped view grow with w across and w squared along, a perspective view's
    // with w both ways (shadow_view/lookup.wgsl).
    let w = (view.light_clip_from_world * vec4<f32>(world_pos, 1.0)).w;
    let along = select(w, 1.0, perspective);
    let texel_area = view.light_right.w * view.light_up.w * w * w * along / cos_light;
    let pixel_area = pixel_m * pixel_m / cos_view;
    let octaves = 0.5 * log2(max(texel_area, 1e-30) / max(pixel_area, 1e-30));
    var bin = 0u;
    if (octaves > 0.0) {
        bin = 1u + min(u32(octaves * 4.0), UNDERSAMPLING_BINS - 2u);
    }
    atomicAdd(&measured.per_view[frame.views.x + v * UNDERSAMPLING_BINS + bin], 1u);
}
