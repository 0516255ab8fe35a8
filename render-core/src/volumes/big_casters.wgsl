// Casters too big for the cull's workgroup (part of volumes/find.wgsl): a caster whose cells
// would take a lane of `cull_casters` past its budget of loop iterations
// (`VolumeFrame::steps.x`: llvmpipe silently ends a shader's loops after 65,535 iterations,
// and on a GPU one lane's loop is serial) is listed here instead, up to `steps.z` of them (at
// most BIG_CASTERS). Then `steps.w / BIG_LANES` workgroups per listed caster share its cells
// among their lanes, each within `steps.y` iterations (`gather_big_casters`), merging what
// they gather in the workgroup and then into the list with atomics, and one invocation per
// caster finishes it as `cull_casters` would have
// (`finish_big_casters`). A floor or a wall, whose box lies over every cell, is culled or
// clamped like any strut, where it would keep its whole volume. Past `steps.z` casters, or
// where a lane still runs past its budget, the volume is whole; counters 8 and 9 count the
// casters listed and those kept whole so (volumes/mod.rs reports them).

// Keep in sync with volumes/pipelines.rs.
const BIG_CASTERS: u32 = 1024u;
const BIG_LANES: u32 = 256u;

// Per listed caster, what its lanes have merged: per slice the shallowest depth's bits, the
// deepest's bits plus 1 (0: none; an integer step, so the depth comes back to the bit) and
// the bins (depths are never negative, so their bits order as they do); then whether a
// lane ran past the budget.
const BIG_WORDS: u32 = 3u * MAX_SLICES + 1u;
const BIG_OVER: u32 = 3u * MAX_SLICES;

// 0: how many casters were listed; 1 to BIG_CASTERS: the casters; then BIG_WORDS per caster.
@group(2) @binding(13) var<storage, read_write> big: array<atomic<u32>>;

fn big_word(g: u32, word: u32) -> u32 {
    return 1u + BIG_CASTERS + g * BIG_WORDS + word;
}

// How many casters are listed.
fn big_count() -> u32 {
    return min(atomicLoad(&big[0]), big_room());
}

// The most casters this frame lists.
fn big_room() -> u32 {
    return min(volume.steps.z, BIG_CASTERS);
}

// Lists caster `ci` for the workgroups, with nothing merged yet; false where the list is full.
fn defer_caster(ci: u32) -> bool {
    let g = atomicAdd(&big[0], 1u);
    if (g >= big_room()) {
        return false;
    }
    atomicAdd(&counters[8], 1u);
    atomicStore(&big[1u + g], ci);
    for (var slice = 0u; slice < MAX_SLICES; slice++) {
        atomicStore(&big[big_word(g, 3u * slice)], 0xffffffffu);
        atomicStore(&big[big_word(g, 3u * slice + 1u)], 0u);
        atomicStore(&big[big_word(g, 3u * slice + 2u)], 0u);
    }
    atomicStore(&big[big_word(g, BIG_OVER)], 0u);
    return true;
}

// The words after the list (volumes/pipelines.rs `BIG_DISPATCH_OFFSET`): the workgroups of
// `gather_big_casters` and of `finish_big_casters`, x y z each, copied to the indirect
// dispatch buffer (volumes/find_passes.rs).
const BIG_DISPATCH: u32 = 1u + BIG_CASTERS * (1u + BIG_WORDS);

// After the cull: the listed casters' workgroups, `steps.w` lanes each, and the
// invocations that finish them.
@compute @workgroup_size(1)
fn size_big_casters() {
    let n = big_count();
    atomicStore(&big[BIG_DISPATCH], n);
    atomicStore(&big[BIG_DISPATCH + 1u], max(volume.steps.w / BIG_LANES, 1u));
    atomicStore(&big[BIG_DISPATCH + 2u], 1u);
    atomicStore(&big[BIG_DISPATCH + 4u], (n + 63u) / 64u);
    atomicStore(&big[BIG_DISPATCH + 5u], 1u);
    atomicStore(&big[BIG_DISPATCH + 6u], 1u);
}

// Listed caster `group.x`: this lane's share of its cells (the `group.y`-th of its
// workgroups), merged in the workgroup, then by its first lane into the list.
@compute @workgroup_size(BIG_LANES)
fn gather_big_casters(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let g = group.x;
    let listed = g < big_count();
    clear_merged(local, BIG_LANES);
    workgroupBarrier();
    if (listed) {
        let lanes = vec2<u32>(group.y * BIG_LANES + local, max(volume.steps.w, BIG_LANES));
        gather_lane(atomicLoad(&big[1u + g]), lanes);
    }
    workgroupBarrier();
    if (!listed || local != 0u) {
        return;
    }
    for (var slice = 0u; slice < volume.grid.x; slice++) {
        let deepest = atomicLoad(&merged[3u * slice + 1u]);
        if (deepest != 0u) {
            atomicMin(&big[big_word(g, 3u * slice)], atomicLoad(&merged[3u * slice]));
            atomicMax(&big[big_word(g, 3u * slice + 1u)], deepest);
            atomicOr(&big[big_word(g, 3u * slice + 2u)], atomicLoad(&merged[3u * slice + 2u]));
        }
    }
    if (atomicLoad(&merged[BIG_OVER]) != 0u) {
        atomicStore(&big[big_word(g, BIG_OVER)], 1u);
    }
}

// What the lanes of one workgroup gathered for one caster, laid out as a listed caster's
// words (BIG_WORDS): per slice the shallowest depth's bits, the deepest's bits plus 1 and
// the bins, then whether a lane ran past its budget.
var<workgroup> merged: array<atomic<u32>, BIG_WORDS>;

// Nothing merged yet: this lane's share of the words, of `lanes` lanes.
fn clear_merged(lane: u32, lanes: u32) {
    for (var w = lane; w < BIG_WORDS; w += lanes) {
        atomicStore(&merged[w], select(0u, 0xffffffffu, w < BIG_OVER && w % 3u == 0u));
    }
}

// Lane `lanes.x` of the `lanes.y` sharing caster `ci`: what it gathers from the sun or the
// point light, merged into `merged`.
fn gather_lane(ci: u32, lanes: vec2<u32>) {
    var found: array<vec2<f32>, MAX_SLICES>;
    var bins: array<u32, MAX_SLICES>;
    clear_found(&found, &bins);
    var within: bool;
    if (from_point()) {
        within = gather_from_point(ci, point_caster(ci), lanes, &found, &bins);
    } else {
        within = gather_under(ci, sun_caster(ci), lanes, &found, &bins);
    }
    merge_lane(within, &found, &bins);
}

// One lane's `found` and `bins` (and whether it kept within its budget) into `merged`.
fn merge_lane(
    within: bool,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    bins: ptr<function, array<u32, MAX_SLICES>>,
) {
    if (!within) {
        atomicStore(&merged[BIG_OVER], 1u);
    }
    for (var slice = 0u; slice < volume.grid.x; slice++) {
        let depths = (*found)[slice];
        if (depths.y >= 0.0) {
            atomicMin(&merged[3u * slice], bitcast<u32>(max(depths.x, 0.0)));
            atomicMax(&merged[3u * slice + 1u], bitcast<u32>(max(depths.y, 0.0)) + 1u);
            atomicOr(&merged[3u * slice + 2u], (*bins)[slice]);
        }
    }
}

// `merged` back into `found` and `bins`; whether every lane kept within its budget.
fn read_merged(
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    bins: ptr<function, array<u32, MAX_SLICES>>,
) -> bool {
    clear_found(found, bins);
    for (var slice = 0u; slice < volume.grid.x; slice++) {
        let words = vec3<u32>(
            atomicLoad(&merged[3u * slice]),
            atomicLoad(&merged[3u * slice + 1u]),
            atomicLoad(&merged[3u * slice + 2u]),
        );
        unpack_slice(slice, words, found, bins);
    }
    return atomicLoad(&merged[BIG_OVER]) == 0u;
}

// Slice `slice`'s merged `words` (the shallowest depth's bits, the deepest's bits plus 1, 0
// for none, and the bins) into `found` and `bins`, cleared before.
fn unpack_slice(
    slice: u32,
    words: vec3<u32>,
    found: ptr<function, array<vec2<f32>, MAX_SLICES>>,
    bins: ptr<function, array<u32, MAX_SLICES>>,
) {
    if (words.y != 0u) {
        (*found)[slice] = vec2<f32>(bitcast<f32>(words.x), bitcast<f32>(words.y - 1u));
    }
    (*bins)[slice] = words.z;
}

// Listed caster `id.x`, from what its lanes merged, as `cull_casters` finishes the others.
@compute @workgroup_size(64)
fn finish_big_casters(@builtin(global_invocation_id) id: vec3<u32>) {
    let g = id.x;
    if (g >= big_count()) {
        return;
    }
    let ci = atomicLoad(&big[1u + g]);
    var found: array<vec2<f32>, MAX_SLICES>;
    var bins: array<u32, MAX_SLICES>;
    clear_found(&found, &bins);
    for (var slice = 0u; slice < volume.grid.x; slice++) {
        let words = vec3<u32>(
            atomicLoad(&big[big_word(g, 3u * slice)]),
            atomicLoad(&big[big_word(g, 3u * slice + 1u)]),
            atomicLoad(&big[big_word(g, 3u * slice + 2u)]),
        );
        unpack_slice(slice, words, &found, &bins);
    }
    let within = atomicLoad(&big[big_word(g, BIG_OVER)]) == 0u;
    if (from_point()) {
        let p = point_caster(ci);
        let n = select(TOO_MANY_CELLS, compact_found(p.nearest, p.pad, &found, &bins), within);
        finish_point_caster(ci, p, n, &found);
    } else {
        let s = sun_caster(ci);
        let n = select(TOO_MANY_CELLS, compact_found(s.lo.z, s.pad, &found, &bins), within);
        finish_sun_caster(ci, s, n, &found);
    }
}
