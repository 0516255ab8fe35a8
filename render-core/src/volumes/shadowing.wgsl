// Whether a caster can shadow a receiver point (part of volumes/find.wgsl): the ray from the
// point towards the light against the caster's box in the world (its mesh's box turned with
// it), or where its mesh is convex and small, against the mesh itself, as the planes of its
// faces. `gather_receivers` (volumes/grid.wgsl) asks it of every point in a caster's cells.

// A caster as the per-point test sees it (`caster_box`): its mesh's box in the world as
// three pairs of faces, each a unit normal (xyz) with its offset at the first face (w), and
// how far along it the second lies (`widths`); and where its mesh is convex and small, the
// mesh itself, as the planes of its faces (`hull`).
struct CasterBox {
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
    widths: vec3<f32>,
    instance: u32,
    // Whether its cells' points are tested one by one; whether its mesh is convex.
    points: bool,
    convex: bool,
    // Up to HULL_PLANES planes, four to a matrix: column j holds a unit normal out of the
    // mesh (xyz) and its offset (w), a point x lying inside where dot(normal, x) <= offset;
    // an unused one (0, 0, 0, 1e30). Whether the hull replaces the box.
    hull: array<mat4x4<f32>, 4>,
    hulled: bool,
}

// The most planes of a caster's hull, and the most triangles a mesh may have for one.
const HULL_PLANES: u32 = 16u;
const HULL_TRIANGLES: u32 = 32u;

// Caster `ci`'s box (`CasterBox`), tested point by point where `points`. A box flat in one
// way gets 2 mm of thickness; one flat in two ways is tested by cells only. Adds the loop
// iterations it takes to `steps`.
fn caster_box(ci: u32, points: bool, steps: ptr<function, i32>) -> CasterBox {
    let c = casters[ci];
    var box: CasterBox;
    box.instance = c.instance;
    box.convex = c.convex != 0u;
    var o = oriented_corner(c, 0u);
    var e = array<vec3<f32>, 3>(
        oriented_corner(c, 1u) - o,
        oriented_corner(c, 2u) - o,
        oriented_corner(c, 4u) - o,
    );
    var flat = 0u;
    for (var i = 0u; i < 3u; i++) {
        flat += select(0u, 1u, length(e[i]) < 1e-4);
    }
    if (flat > 1u || !points) {
        return box;
    }
    for (var i = 0u; i < 3u; i++) {
        if (length(e[i]) < 1e-4) {
            let n = normalize(cross(e[(i + 1u) % 3u], e[(i + 2u) % 3u]));
            e[i] = n * 2e-3;
            o -= n * 1e-3;
        }
    }
    var slabs: array<vec4<f32>, 3>;
    for (var i = 0u; i < 3u; i++) {
        let n = cross(e[(i + 1u) % 3u], e[(i + 2u) % 3u]);
        if (length(n) < 1e-12) {
            return box;
        }
        let u = normalize(n);
        slabs[i] = vec4<f32>(u, dot(u, o));
        box.widths[i] = dot(u, e[i]);
    }
    box.a = slabs[0];
    box.b = slabs[1];
    box.c = slabs[2];
    box.points = true;
    caster_hull(ci, &box, steps);
    return box;
}

// The planes of caster `ci`'s faces into `box`, where its mesh is convex (every point of it
// lies behind every face's plane, so the mesh is where all of them hold) with at most
// HULL_TRIANGLES triangles in at most HULL_PLANES planes: a strut's prism, not its box,
// whose corners a ray from a lit point beside it may cross. Adds its loop iterations to
// `steps`.
fn caster_hull(ci: u32, box: ptr<function, CasterBox>, steps: ptr<function, i32>) {
    let c = casters[ci];
    let end = select(volume.counts.y, casters[ci + 1u].triangle_start, ci + 1u < volume.counts.z);
    let triangles = end - c.triangle_start;
    if (!(*box).convex || triangles > HULL_TRIANGLES) {
        return;
    }
    var planes: array<vec4<f32>, HULL_PLANES>;
    var n = 0u;
    var centre = vec3<f32>(0.0);
    for (var t = 0u; t < triangles; t++) {
        let p = triangle(c, t);
        centre += p[0] + p[1] + p[2];
        let normal = cross(p[1] - p[0], p[2] - p[0]);
        *steps += 1 + i32(n);
        if (length(normal) < 1e-12) {
            continue;
        }
        let u = normalize(normal);
        let offset = dot(u, p[0]);
        var known = false;
        for (var k = 0u; k < n; k++) {
            known = known
                || (dot(u, planes[k].xyz) > 0.99999 && abs(offset - planes[k].w) < 1e-4 + 1e-6 * abs(offset));
        }
        if (known) {
            continue;
        }
        if (n == HULL_PLANES) {
            return;
        }
        planes[n] = vec4<f32>(u, offset);
        n++;
    }
    if (n < 4u) {
        return;
    }
    // A mirrored instance turns its triangles inside out: their planes face in.
    centre /= 3.0 * f32(triangles);
    let flip = dot(planes[0].xyz, centre) > planes[0].w;
    for (var k = 0u; k < HULL_PLANES; k++) {
        var plane = vec4<f32>(0.0, 0.0, 0.0, 1e30);
        if (k < n) {
            plane = select(planes[k], -planes[k], flip);
        }
        (*box).hull[k / 4u][k % 4u] = plane;
    }
    *steps += i32(HULL_PLANES);
    (*box).hulled = true;
}

// Narrows `t` (distances along the ray from `p` towards `towards`) to where the ray lies
// between the two faces of `slab` (`width` apart), with `pad` to spare; false where the ray
// runs beside them.
fn within_slab(
    slab: vec4<f32>,
    width: f32,
    ray: array<vec3<f32>, 2>,
    pad: f32,
    t: ptr<function, vec2<f32>>,
) -> bool {
    let s = dot(slab.xyz, ray[0]) - slab.w;
    let rate = dot(slab.xyz, ray[1]);
    let lo = min(0.0, width) - pad;
    let hi = max(0.0, width) + pad;
    if (abs(rate) < 1e-7) {
        return s >= lo && s <= hi;
    }
    let a = (lo - s) / rate;
    let b = (hi - s) / rate;
    *t = vec2<f32>(max((*t).x, min(a, b)), min((*t).y, max(a, b)));
    return true;
}

// Whether the ray from `p` towards the light meets `box` ahead of `p` (its hull, where it has
// one): whether the caster in it can shadow `p` (its mesh lies in the box), with `pad` to
// spare around it. A point
// within that padding (a crate's foot on the floor, the floor beside a wall) counts only
// where its ray meets the box itself: one whose ray runs away from the box is not shadowed
// by it, however close it lies.
fn ray_meets_box(p: vec3<f32>, box: ptr<function, CasterBox>, pad: f32) -> bool {
    let ray = array<vec3<f32>, 2>(p, to_volume_light(p));
    let end = select(1e30, distance(volume.point.xyz, p), from_point());
    var t = vec2<f32>(0.0, end);
    if (!ray_within_box(ray, box, pad, &t)) {
        return false;
    }
    if (t.x > 0.0) {
        return true;
    }
    t = vec2<f32>(0.0, end);
    return ray_within_box(ray, box, 0.0, &t);
}

// Narrows `t` to where `ray` lies in `box` (or its hull) grown by `pad`; false where it
// misses it there.
fn ray_within_box(
    ray: array<vec3<f32>, 2>,
    box: ptr<function, CasterBox>,
    pad: f32,
    t: ptr<function, vec2<f32>>,
) -> bool {
    if ((*box).hulled) {
        return within_planes((*box).hull[0], ray, pad, t) && within_planes((*box).hull[1], ray, pad, t)
            && within_planes((*box).hull[2], ray, pad, t) && within_planes((*box).hull[3], ray, pad, t);
    }
    let w = (*box).widths;
    return within_slab((*box).a, w.x, ray, pad, t) && within_slab((*box).b, w.y, ray, pad, t)
        && within_slab((*box).c, w.z, ray, pad, t) && (*t).x <= (*t).y;
}

// The room the per-point test leaves a point at `p` (world space): a hundredth of a
// millimetre and 16 steps of a float at its distance from the origin, what its position and
// the box's corners may have lost. A neighbour's point a tenth of a millimetre beside the
// caster (a crate on the floor, a wall's foot), whose ray to the light runs away from it, is
// not counted: the caster's own padding would count it and stretch the caster's volume to
// that point's depth.
fn point_pad(p: vec3<f32>) -> f32 {
    let a = abs(p);
    return 1e-5 + 2e-6 * max(a.x, max(a.y, a.z));
}

// Narrows `t` to where `ray` lies behind all four `planes` (as `CasterBox::hull` holds
// them) grown by `pad`; false where it misses them. Four planes at once, without a loop.
fn within_planes(
    planes: mat4x4<f32>,
    ray: array<vec3<f32>, 2>,
    pad: f32,
    t: ptr<function, vec2<f32>>,
) -> bool {
    let beyond = vec4<f32>(ray[0], -1.0) * planes;
    let rate = vec4<f32>(ray[1], 0.0) * planes;
    let moving = abs(rate) > vec4<f32>(1e-9);
    if (any(!moving & (beyond > vec4<f32>(pad)))) {
        return false;
    }
    let bound = (vec4<f32>(pad) - beyond) / select(vec4<f32>(1.0), rate, moving);
    let hi = select(vec4<f32>(1e30), bound, moving & (rate > vec4<f32>(0.0)));
    let lo = select(vec4<f32>(-1e30), bound, moving & (rate < vec4<f32>(0.0)));
    *t = vec2<f32>(
        max((*t).x, max(max(lo.x, lo.y), max(lo.z, lo.w))),
        min((*t).y, min(min(hi.x, hi.y), min(hi.z, hi.w))),
    );
    return (*t).x <= (*t).y;
}
