// Measurement, group 2 of the shading pass (metrics/mod.rs): the oracle flags (a block per
// shadow view), the counters, and the per-object outcomes the `casters` overlay tints by.
// Written only when frame.params.z != 0 (measuring); the outcomes are read when tinting.
#import view/common.wgsl

// Keep in sync with metrics/mod.rs (`take_latest`).
struct Measured {
    visible_px: atomic<u32>,
    missing_px: atomic<u32>,
    extra_px: atomic<u32>,
    // Per view: casters in its oracle set.
    oracle_casters: array<atomic<u32>>,
}

@group(2) @binding(0) var<storage, read_write> oracle: array<atomic<u32>>;
@group(2) @binding(1) var<storage, read_write> measured: Measured;
// Per view and object, the outcome code in the low byte (culling/codes.wgsl).
@group(2) @binding(2) var<storage, read> outcomes: array<u32>;

// Caster `id` (instance index + 1) wins a shadowed tap of view `v`: it is in the view's oracle.
fn mark_oracle(v: u32, id: u32) {
    if (id != 0u && atomicOr(&oracle[v * frame.views.y + id - 1u], 1u) == 0u) {
        atomicAdd(&measured.oracle_casters[v], 1u);
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
