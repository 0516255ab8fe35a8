//! A directional light's frustum fitted to one depth slice of the view frustum: a cascade.
//! Its near plane reaches back to the scene's edge towards the sun, so every caster between
//! the sun and the slice is rendered (Engel: casters outside the view that shadow into it).
//! In f64 around the scene's centre, as `light_fit`.

use glam::{DVec3, Vec3};

use super::light_fit::{Extent, LightSpace, extent_of, pad_and_snap, view_corners};
use super::{Aabb, Camera, LightFrustum, TexelGrid};

/// How the light box follows its slice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SliceFit {
    /// The light-space box of the slice's corners, cut to the scene.
    Tight,
    /// A square around the slice's bounding sphere, moved in whole texels. Its size depends
    /// only on the slice's depths, field of view and aspect, and its texel grid is fixed in the
    /// light's frame: moving or turning the camera does not move a shadow edge (stabilised).
    Sphere,
}

/// The light frustum of the slice `depths` (view depths in metres) of `camera`'s view
/// frustum (`aspect` = width / height), for a map `resolution` texels square. When the slice
/// does not meet the scene, the whole scene.
pub fn fit_view_slice(
    (camera, aspect): (&Camera, f32),
    direction_to_sun: Vec3,
    scene_bounds: &Aabb,
    depths: [f64; 2],
    (resolution, fit): (u32, SliceFit),
) -> LightFrustum {
    fit_focused_slice(
        (camera, aspect),
        direction_to_sun,
        scene_bounds,
        (depths, None),
        (resolution, fit),
    )
}

/// Like [`fit_view_slice`], and with `receivers` (the visible receivers' bounds) a tight
/// slice's box across the light and its far side shrink to them (Bittner's FOCUS per
/// cascade); the near side still reaches the scene's edge for the casters between. A sphere
/// fit ignores them, or it would no longer stand still.
pub fn fit_focused_slice(
    (camera, aspect): (&Camera, f32),
    direction_to_sun: Vec3,
    scene_bounds: &Aabb,
    (depths, receivers): ([f64; 2], Option<&Aabb>),
    (resolution, fit): (u32, SliceFit),
) -> LightFrustum {
    let resolution = resolution.max(16);
    let space = LightSpace::new(direction_to_sun, scene_bounds);
    let scene = space.scene_extent;
    let Some(mut corners) = view_corners(camera, aspect, &space.scene, Some(depths)) else {
        return space.frustum(pad_and_snap(scene, resolution), resolution, true);
    };
    if fit == SliceFit::Sphere {
        // A sphere's slice is the one asked for, not cut to the scene, so it keeps its shape
        // as the camera turns.
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        corners = camera.frustum_corners_world(f64::from(aspect), depths[0], depths[1]);
    }
    let corners = corners.map(|p| space.to_light(p));
    let extent = match fit {
        SliceFit::Tight => tight(&corners, scene).map(|e| match receivers {
            Some(r) if !r.is_empty() && r.min.is_finite() && r.max.is_finite() => {
                let (lo, hi) = extent_of(&r.corners().map(|c| space.to_light(c.as_dvec3())));
                let min = DVec3::new(e.0.x.max(lo.x), e.0.y.max(lo.y), e.0.z);
                let max = DVec3::new(e.1.x.min(hi.x), e.1.y.min(hi.y), e.1.z.min(hi.z));
                if min.cmplt(max).all() { (min, max) } else { e }
            }
            _ => e,
        }),
        SliceFit::Sphere => sphere(&corners, scene, resolution),
    };
    match extent {
        Some(extent) if fit == SliceFit::Tight => {
            space.frustum(pad_and_snap(extent, resolution), resolution, false)
        }
        Some(extent) => {
            let texel = (extent.1.x - extent.0.x) / f64::from(resolution);
            LightFrustum {
                grid: Some(TexelGrid::of(extent.0, texel, resolution)),
                ..space.frustum(extent, resolution, false)
            }
        }
        None => space.frustum(pad_and_snap(scene, resolution), resolution, true),
    }
}

/// The corners' box cut to the scene across the light, from the scene's near edge.
fn tight(corners: &[DVec3; 8], scene: Extent) -> Option<Extent> {
    let (lo, hi) = extent_of(corners);
    let min = DVec3::new(lo.x.max(scene.0.x), lo.y.max(scene.0.y), scene.0.z);
    let max = DVec3::new(
        hi.x.min(scene.1.x),
        hi.y.min(scene.1.y),
        hi.z.min(scene.1.z),
    );
    min.cmplt(max).all().then_some((min, max))
}

/// The square around the corners' bounding sphere, its first texel on a fixed grid; depth
/// over the whole scene, which does not change as the camera moves.
fn sphere(corners: &[DVec3; 8], scene: Extent, resolution: u32) -> Option<Extent> {
    let centre = corners.iter().copied().sum::<DVec3>() / 8.0;
    let radius = corners
        .iter()
        .map(|c| c.distance(centre))
        .fold(0.0, f64::max);
    if !(radius.is_finite() && radius > 0.0) {
        return None;
    }
    // The radius only depends on the slice's shape, but rounding in its corners would change
    // it in the last bits; a coarse step keeps it, and so the texel size, exactly the same.
    let step = 2f64.powi(radius.log2().floor() as i32 - 10);
    let radius = (radius / step).ceil() * step;
    let res = f64::from(resolution);
    // One texel more than the diameter, so the snapped square still holds the sphere.
    let texel = 2.0 * radius / (res - 1.0);
    let mut min = DVec3::new(0.0, 0.0, scene.0.z);
    let mut max = DVec3::new(0.0, 0.0, scene.1.z);
    for axis in 0..2 {
        min[axis] = ((centre[axis] - radius) / texel).floor() * texel;
        max[axis] = min[axis] + texel * res;
    }
    let z_margin = (scene.1.z - scene.0.z).abs() * 1e-3 + 1e-2;
    min.z -= z_margin;
    max.z += z_margin;
    Some((min, max))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(eye: Vec3, forward: Vec3) -> Camera {
        Camera {
            eye,
            forward: forward.normalize(),
            fov_y_rad: 1.0,
            near_m: 0.1,
            far_m: 5000.0,
            world_up: Vec3::Y,
        }
    }

    fn city() -> Aabb {
        Aabb::new(
            Vec3::new(-700.0, 0.0, -700.0),
            Vec3::new(700.0, 250.0, 700.0),
        )
    }

    /// Light clip coordinates of a world point.
    fn clip(fit: &LightFrustum, p: DVec3) -> DVec3 {
        fit.light_clip_from_world.as_dmat4().project_point3(p)
    }

    #[test]
    fn each_fit_holds_its_slice_inside_the_scene_and_reaches_back_to_the_scene() {
        let scene = city();
        let cam = camera(Vec3::new(-300.0, 3.0, 10.0), Vec3::new(1.0, -0.05, 0.2));
        let sun = Vec3::new(0.4, 0.6, 0.3).normalize();
        for fit in [SliceFit::Tight, SliceFit::Sphere] {
            for depths in [[0.1, 10.0], [10.0, 60.0], [60.0, 400.0], [400.0, 2000.0]] {
                let f = fit_view_slice((&cam, 16.0 / 9.0), sun, &scene, depths, (2048, fit));
                assert!(!f.covers_whole_scene, "{fit:?} {depths:?}");
                let corners = cam.frustum_corners_world(16.0 / 9.0, depths[0], depths[1]);
                for (k, c) in corners.iter().enumerate() {
                    if !scene.contains_point(c.as_vec3()) {
                        continue;
                    }
                    let q = clip(&f, *c);
                    assert!(
                        q.x.abs() <= 1.0 + 1e-4 && q.y.abs() <= 1.0 + 1e-4,
                        "{fit:?} {depths:?}: corner {k} at clip {q}"
                    );
                    assert!(
                        (0.0..=1.0).contains(&q.z),
                        "{fit:?} {depths:?}: depth {}",
                        q.z
                    );
                }
                for c in scene.corners() {
                    assert!(
                        clip(&f, c.as_dvec3()).z >= -1e-4,
                        "{fit:?}: a scene corner before the near plane"
                    );
                }
            }
        }
        // Nearer slices get finer texels.
        let near = fit_view_slice(
            (&cam, 1.5),
            sun,
            &scene,
            [0.1, 10.0],
            (2048, SliceFit::Tight),
        );
        let far = fit_view_slice(
            (&cam, 1.5),
            sun,
            &scene,
            [400.0, 2000.0],
            (2048, SliceFit::Tight),
        );
        assert!(near.texel_size_m[0] * 10.0 < far.texel_size_m[0]);
    }

    /// The texel grid of a sphere fit, in light space: its size and the first texel's position
    /// modulo the size.
    fn grid(f: &LightFrustum) -> (f64, f64, f64) {
        let texel = f64::from(f.texel_size_m[0]);
        // Light-space x of clip -1 (the box's left edge).
        let left = f
            .clip_from_light
            .as_dmat4()
            .inverse()
            .project_point3(DVec3::new(-1.0, -1.0, 0.0));
        (texel, left.x.rem_euclid(texel), left.y.rem_euclid(texel))
    }

    #[test]
    fn a_sphere_fit_keeps_its_texel_grid_when_the_camera_moves_or_turns() {
        let scene = city();
        let sun = Vec3::new(-0.3, 0.8, 0.5).normalize();
        let base = camera(Vec3::new(10.0, 20.0, 30.0), Vec3::new(0.6, -0.3, -0.7));
        let fit = |cam: &Camera| {
            fit_view_slice(
                (cam, 1.6),
                sun,
                &scene,
                [5.0, 80.0],
                (1024, SliceFit::Sphere),
            )
        };
        let (texel, gx, gy) = grid(&fit(&base));
        let mut moved = 0;
        for k in 0..50 {
            let t = f64::from(k) * 0.37;
            let mut cam = base;
            cam.eye += Vec3::new(t.sin() as f32 * 7.3, t.cos() as f32 * 0.9, t as f32 * 0.05);
            let yaw = (t * 0.1) as f32;
            cam.forward = (glam::Quat::from_rotation_y(yaw) * base.forward).normalize();
            let (texel_k, gx_k, gy_k) = grid(&fit(&cam));
            assert!(
                (texel_k - texel).abs() <= texel * 1e-6,
                "texel {texel_k} against {texel}"
            );
            let off = |a: f64, b: f64| {
                let d = (a - b).abs();
                d.min(texel - d)
            };
            // The grid's phase stays, to the precision of f32 matrices.
            assert!(
                off(gx_k, gx) < texel * 1e-3 && off(gy_k, gy) < texel * 1e-3,
                "step {k}"
            );
            moved += 1;
        }
        assert_eq!(moved, 50);
        // A tight fit's texel size changes as the camera turns.
        let tight = |cam: &Camera| {
            fit_view_slice(
                (cam, 1.6),
                sun,
                &scene,
                [5.0, 80.0],
                (1024, SliceFit::Tight),
            )
        };
        let mut turned = base;
        turned.forward = (glam::Quat::from_rotation_y(0.4) * base.forward).normalize();
        let (a, b) = (tight(&base).texel_size_m[0], tight(&turned).texel_size_m[0]);
        assert!((a - b).abs() > a * 1e-4, "texel {a} and {b}");
    }

    /// Where a view with a texel grid places `p`, as `light_clip` does in WGSL, in f32:
    /// texels from the map's centre.
    fn grid_position(f: &LightFrustum, p: Vec3) -> [f32; 2] {
        let g = f.grid.expect("a sphere fit has a grid");
        let light = f.light_from_world.transform_point3(p);
        [
            light.x * g.per_metre[0] - g.centre_texel[0],
            light.y * g.per_metre[1] - g.centre_texel[1],
        ]
    }

    #[test]
    #[allow(
        clippy::float_cmp,
        reason = "the positions must differ by whole texels exactly"
    )]
    fn a_sphere_fit_places_points_whole_texels_apart_in_every_bit_as_the_camera_turns() {
        let scene = city();
        let sun = Vec3::new(-0.3, 0.8, 0.5).normalize();
        let base = camera(Vec3::new(10.0, 20.0, 30.0), Vec3::new(0.6, -0.3, -0.7));
        let fit = |cam: &Camera| {
            fit_view_slice(
                (cam, 1.6),
                sun,
                &scene,
                [5.0, 80.0],
                (2048, SliceFit::Sphere),
            )
        };
        let first = fit(&base);
        let g = first.grid.expect("grid");
        assert!(g.centre_texel.iter().all(|c| c.fract() == 0.0), "{g:?}");
        let points = [
            Vec3::new(31.25, 0.0, -12.5),
            Vec3::new(47.123, 3.77, -40.061),
            Vec3::new(12.9, 18.01, 4.4),
        ];
        let mut shifted = 0;
        for k in 1..=40 {
            let mut cam = base;
            cam.forward = (glam::Quat::from_rotation_y(k as f32 * 0.01) * base.forward).normalize();
            let f = fit(&cam);
            let gk = f.grid.expect("grid");
            assert_eq!(gk.per_metre, g.per_metre, "the texel size keeps every bit");
            assert_eq!(f.light_from_world, first.light_from_world);
            let step = [
                gk.centre_texel[0] - g.centre_texel[0],
                gk.centre_texel[1] - g.centre_texel[1],
            ];
            shifted += usize::from(step != [0.0, 0.0]);
            for p in points {
                let (a, b) = (grid_position(&first, p), grid_position(&f, p));
                assert_eq!([a[0] - b[0], a[1] - b[1]], step, "turn {k}, point {p}");
            }
        }
        assert!(
            shifted > 10,
            "the square moved in only {shifted} of 40 turns"
        );
    }

    /// Stabilised cascades shade the points `near` to `far` from the eye with the sphere of
    /// the slice between those view depths, although some lie nearer than `near` in view depth
    /// (as near as `near c`, `c` the corner cosine). The sphere holds them: around the centroid
    /// of the corners (half-depth h = (far - near) / 2), the radius squared is at least
    /// h^2 + far^2 tan^2, and such a point's distance squared at most h^2 + near (1 - c)
    /// (far + near), which is smaller since tan^2 = (1 - c)(1 + c) / c^2 >= 2 (1 - c).
    #[test]
    fn a_sphere_fit_holds_every_point_at_its_distances_from_the_eye() {
        let scene = city();
        let mut rng = 7_u64;
        let mut next = move || {
            rng = rng
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (rng >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..200 {
            let forward = Vec3::new(
                next() as f32 - 0.5,
                next() as f32 - 0.7,
                next() as f32 - 0.5,
            );
            let mut cam = camera(Vec3::new(-300.0, 4.0 + 50.0 * next() as f32, 20.0), forward);
            cam.fov_y_rad = (0.4 + next() * 1.2) as f32;
            let aspect = 0.5 + next() * 2.0;
            let sun = Vec3::new(
                next() as f32 - 0.5,
                0.2 + next() as f32,
                next() as f32 - 0.5,
            )
            .normalize();
            let near = 1.0 + next() * 100.0;
            let far = near * (1.02 + next() * 0.5);
            let f = fit_view_slice(
                (&cam, aspect as f32),
                sun,
                &scene,
                [near, far],
                (2048, SliceFit::Sphere),
            );
            let (right, up) = cam.basis();
            let t = (f64::from(cam.fov_y_rad) * 0.5).tan();
            for _ in 0..50 {
                // A direction inside the frustum, at a distance between near and far.
                let (sx, sy) = (next() * 2.0 - 1.0, next() * 2.0 - 1.0);
                let dir = (cam.forward.as_dvec3().normalize()
                    + right.as_dvec3() * (sx * t * aspect)
                    + up.as_dvec3() * (sy * t))
                    .normalize();
                let d = near + (far - near) * next();
                let p = cam.eye.as_dvec3() + dir * d;
                let q = clip(&f, p);
                assert!(
                    q.x.abs() <= 1.0 + 1e-4 && q.y.abs() <= 1.0 + 1e-4,
                    "case {case}: {d:.1} m from the eye at clip {q}"
                );
            }
        }
    }

    #[test]
    fn fitted_slices_hold_their_visible_points_for_hundreds_of_random_cameras_and_suns() {
        // A small deterministic generator (SplitMix64).
        let mut state = 11_u64;
        let mut next = move || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let scene = city();
        let mut checked = 0;
        for _ in 0..300 {
            let mut unit = || {
                DVec3::new(next() * 2.0 - 1.0, next() * 2.0 - 1.0, next() * 2.0 - 1.0)
                    .try_normalize()
                    .unwrap_or(DVec3::Y)
            };
            let forward = unit().as_vec3();
            let mut sun = unit().as_vec3();
            sun.y = sun.y.abs().max(0.02);
            let eye = Vec3::new(
                (next() * 1600.0 - 800.0) as f32,
                (next() * 300.0 + 0.5) as f32,
                (next() * 1600.0 - 800.0) as f32,
            );
            let mut cam = camera(eye, forward);
            cam.fov_y_rad = (next() * 1.5 + 0.3) as f32;
            let aspect = (next() * 2.0 + 0.5) as f32;
            let near = next() * 50.0 + 0.1;
            let depths = [near, near * (next() * 20.0 + 1.5)];
            for fit in [SliceFit::Tight, SliceFit::Sphere] {
                let f = fit_view_slice((&cam, aspect), sun, &scene, depths, (2048, fit));
                assert!(f.light_clip_from_world.is_finite());
                let c = cam.frustum_corners_world(f64::from(aspect), depths[0], depths[1]);
                for k in 0..64 {
                    let (u, v, t) = (next(), next(), next());
                    let n = c[0].lerp(c[1], u).lerp(c[2].lerp(c[3], u), v);
                    let fa = c[4].lerp(c[5], u).lerp(c[6].lerp(c[7], u), v);
                    let p = n.lerp(fa, t);
                    if !scene.contains_point(p.as_vec3()) {
                        continue;
                    }
                    let q = clip(&f, p);
                    assert!(
                        q.x.abs() <= 1.0 + 1e-3
                            && q.y.abs() <= 1.0 + 1e-3
                            && (-1e-3..=1.0 + 1e-3).contains(&q.z),
                        "{fit:?} sample {k} at clip {q}: camera {cam:?}, sun {sun}, depths {depths:?}"
                    );
                    checked += 1;
                }
            }
        }
        assert!(
            checked > 5_000,
            "only {checked} points inside the scene were checked"
        );
    }

    #[test]
    fn slices_that_miss_the_scene_and_hard_cameras_stay_finite() {
        let scene = city();
        let sun = Vec3::Y;
        // Looking at the sky above the city: the slice holds no scene.
        let up = camera(Vec3::new(0.0, 300.0, 0.0), Vec3::new(0.0, 1.0, 0.01));
        let f = fit_view_slice(
            (&up, 1.0),
            sun,
            &scene,
            [1.0, 50.0],
            (2048, SliceFit::Sphere),
        );
        assert!(f.covers_whole_scene && f.light_clip_from_world.is_finite());
        // 100 km out, near 0.01 m and far 10 km; the sun at the zenith and 1 degree up.
        for sun in [Vec3::Y, Vec3::new(1.0, 0.0175, 0.0).normalize()] {
            let mut far_out = camera(Vec3::new(100_000.0, 2.0, 0.0), Vec3::new(-1.0, 0.0, 0.0));
            far_out.near_m = 0.01;
            far_out.far_m = 10_000.0;
            for fit in [SliceFit::Tight, SliceFit::Sphere] {
                for depths in [[0.01, 1.0], [1.0, 10_000.0]] {
                    let f = fit_view_slice((&far_out, 1.7), sun, &scene, depths, (4096, fit));
                    assert!(f.light_clip_from_world.is_finite(), "{fit:?} {depths:?}");
                    assert!(f.texel_size_m.iter().all(|t| t.is_finite() && *t > 0.0));
                }
            }
        }
    }
}
