//! Light-space perspective shadow maps (Wimmer, Scherzer and Purgathofer, "Light Space
//! Perspective Shadow Maps", EGSR 2004): one map of the sun warped by a perspective whose axis
//! lies across the light, along the view direction as the light sees it. A directional light
//! stays directional after the warp (its rays keep their distance from the perspective's
//! centre), so the map is still rendered with parallel rays, but texels near the viewer are
//! smaller and far ones larger.
//!
//! The warp's free parameter is the distance `n` from the perspective's centre to the near
//! plane of the body it frames. Its optimum for a directional light is the paper's
//! `n_opt = (z_n + sqrt(z_n z_f)) / sin γ` (section 5.2: `z_n`, `z_f` the view's near and far
//! depths where it meets the scene, γ the angle between the view and light directions); Ogre's
//! `LiSPSMShadowCameraSetup::calculateNOptSimple` uses the same `z_n + sqrt(z_n z_f)` before
//! its adjustment factor. As γ goes to 0 (looking along the light: dueling frusta) `n` grows
//! without bound and the warp tends to a uniform map, so below [`MIN_SIN_GAMMA`] the uniform
//! map is used outright.
//!
//! In the warped view `t` (the light-space distance along the perspective's axis from its
//! centre) is the clip-space w: across the map a texel spans `k_u t` metres, along it `k_v t^2`,
//! and the normalised depth changes by `1 / (r t)` per metre along the light. Those per-w
//! factors travel with the view ([`LightFrustum::warp`]) so the lookup scales the normal offset
//! and the receiver plane to the point it shades.

use glam::dcamera::rh::view::look_to_mat4;
use glam::{DMat4, DVec3, DVec4, Vec3};

use super::light_fit::{LightSpace, view_corners};
use super::{Aabb, Camera, LightFrustum, fit_focused_light};

/// Below this sine of the angle between view and light (about 3 degrees) the map is uniform.
pub const MIN_SIN_GAMMA: f64 = 0.05;

/// How a warped map came out, and what its lookups scale by.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Warp {
    /// Texel size across the map per unit of clip w, and along it per w squared, metres.
    pub texel_per_w: [f32; 2],
    /// Depth range per w, metres.
    pub range_per_w: f32,
    /// The distance `n` used, metres: the paper's optimum times the user's scale.
    pub n_m: f64,
    /// The paper's optimum for this view.
    pub n_opt_m: f64,
    /// Sine of the angle between the view and light directions.
    pub sin_gamma: f64,
}

/// A LiSPSM light frustum for `camera`'s view of the scene (its [`LightFrustum::warp`] says
/// how); the uniform (focused orthographic) map, with no warp, when the view looks along the
/// light or does not meet the scene. `n_scale` multiplies the optimal `n` (1: the paper's).
pub fn fit_lispsm(
    (camera, aspect): (&Camera, f32),
    direction_to_sun: Vec3,
    scene_bounds: &Aabb,
    resolution: u32,
    n_scale: f32,
) -> LightFrustum {
    let uniform = || {
        fit_focused_light(
            camera,
            aspect,
            direction_to_sun,
            scene_bounds,
            None,
            resolution,
        )
    };
    let space = LightSpace::new(direction_to_sun, scene_bounds);
    let Some(corners) = view_corners(camera, aspect, &space.scene, None) else {
        return uniform();
    };
    let Some((near, far)) = super::view_depth_range(camera, &space.scene) else {
        return uniform();
    };
    let light = -direction_to_sun
        .as_dvec3()
        .try_normalize()
        .unwrap_or(DVec3::Y);
    let view = camera
        .forward
        .as_dvec3()
        .try_normalize()
        .unwrap_or(DVec3::NEG_Z);
    // The view direction as the light sees it: the perspective's axis.
    let across = view - light * view.dot(light);
    let sin_gamma = across.length();
    if sin_gamma.is_nan() || sin_gamma < MIN_SIN_GAMMA {
        return uniform();
    }
    let n_opt = (near + (near * far).sqrt()) / sin_gamma;
    let n = n_opt * f64::from(n_scale.clamp(0.01, 100.0));
    if !(n.is_finite() && n > 0.0) {
        return uniform();
    }
    let anchor = space.scene.center().as_dvec3();
    // Light view: x across, y along the warp's axis, z = -depth along the light.
    let light_from_world = look_to_mat4(anchor, light, across / sin_gamma);
    let to_light = |p: DVec3| light_from_world.transform_point3(p);
    let body: Vec<DVec3> = corners.iter().map(|c| to_light(*c)).collect();
    let scene: Vec<DVec3> = space
        .scene
        .corners()
        .iter()
        .map(|c| to_light(c.as_dvec3()))
        .collect();
    let lo = |pts: &[DVec3], f: fn(DVec3) -> f64| {
        pts.iter().map(|p| f(*p)).fold(f64::INFINITY, f64::min)
    };
    let hi = |pts: &[DVec3], f: fn(DVec3) -> f64| {
        pts.iter().map(|p| f(*p)).fold(f64::NEG_INFINITY, f64::max)
    };
    // The body's extent along the axis, cut to the scene's.
    let y_min = lo(&body, |p| p.y).max(lo(&scene, |p| p.y));
    let y_max = hi(&body, |p| p.y).min(hi(&scene, |p| p.y));
    if y_max.is_nan() || y_min.is_nan() || y_max <= y_min {
        return uniform();
    }
    let d = y_max - y_min;
    let centre_y = y_min - n;
    let (t_near, t_far) = (n, n + d);
    // The body between y_min and y_max: the view frustum's edges clipped to that slab give the
    // corners of their intersection, whose projections bound the map.
    let pts = clipped_edges(&body, y_min, y_max);
    if pts.is_empty() {
        return uniform();
    }
    let u_of = |p: &DVec3| p.x / (p.y - centre_y);
    let (sx_lo, sx_hi) = (lo(&scene, |p| p.x), hi(&scene, |p| p.x));
    let u_min = pts
        .iter()
        .map(u_of)
        .fold(f64::INFINITY, f64::min)
        .max((sx_lo / t_near).min(sx_lo / t_far));
    let u_max = pts
        .iter()
        .map(u_of)
        .fold(f64::NEG_INFINITY, f64::max)
        .min((sx_hi / t_near).max(sx_hi / t_far));
    if u_max.is_nan() || u_min.is_nan() || u_max <= u_min {
        return uniform();
    }
    // Depth along the light: from the scene's edge towards the sun (its casters) to the
    // body's far side, over the body's range of t.
    let s_min = lo(&scene, |p| -p.z);
    let s_max = hi(&pts, |p| -p.z).min(hi(&scene, |p| -p.z));
    let q: Vec<f64> = [s_min, s_max]
        .iter()
        .flat_map(|s| [s / t_near, s / t_far])
        .collect();
    let (q_lo, q_hi) = (
        q.iter().copied().fold(f64::INFINITY, f64::min),
        q.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    let margin = (q_hi - q_lo).abs() * 1e-3 + 1e-9;
    let (q_lo, q_hi) = (q_lo - margin, q_hi + margin);
    let du = (u_max - u_min).max(1e-12);
    let dq = q_hi - q_lo;
    if !(du.is_finite() && dq.is_finite() && dq > 0.0) {
        return uniform();
    }
    // The perspective along y: t = y - centre_y is w; v = (A t + B) / t spans -1..1 over the
    // body's t; u and depth are linear in x and s over t.
    let a = (t_far + t_near) / (t_far - t_near);
    let b = -2.0 * t_far * t_near / (t_far - t_near);
    let cu = (u_max + u_min) / du;
    // Rows of clip_from_light acting on (x, y, z, 1) with s = -z.
    let rows = [
        DVec4::new(2.0 / du, -cu, 0.0, cu * centre_y),
        DVec4::new(0.0, a, 0.0, b - a * centre_y),
        DVec4::new(0.0, -q_lo / dq, -1.0 / dq, q_lo * centre_y / dq),
        DVec4::new(0.0, 1.0, 0.0, -centre_y),
    ];
    let clip_from_light = DMat4::from_cols_array_2d(&[
        [rows[0].x, rows[1].x, rows[2].x, rows[3].x],
        [rows[0].y, rows[1].y, rows[2].y, rows[3].y],
        [rows[0].z, rows[1].z, rows[2].z, rows[3].z],
        [rows[0].w, rows[1].w, rows[2].w, rows[3].w],
    ]);
    let res = f64::from(resolution.max(16));
    let k_u = du / res;
    let k_v = d / (res * t_far * t_near);
    let light_clip_from_world = clip_from_light * light_from_world;
    LightFrustum {
        light_from_world: light_from_world.as_mat4(),
        clip_from_light: clip_from_light.as_mat4(),
        light_clip_from_world: light_clip_from_world.as_mat4(),
        light_direction: light.as_vec3(),
        // The coarsest texel and the longest depth per unit of normalised depth: at the far end.
        texel_size_m: [(k_u * t_far) as f32, (k_v * t_far * t_far) as f32],
        depth_range_m: (dq * t_far) as f32,
        covers_whole_scene: false,
        warp: Some(Warp {
            texel_per_w: [k_u as f32, k_v as f32],
            range_per_w: dq as f32,
            n_m: n,
            n_opt_m: n_opt,
            sin_gamma,
        }),
        grid: None,
        perspective: None,
    }
}

/// The frustum's 12 edges (corners as `Camera::frustum_corners_world` orders them) clipped to
/// `y_min..=y_max`: the ends that lie in that slab.
fn clipped_edges(corners: &[DVec3], y_min: f64, y_max: f64) -> Vec<DVec3> {
    let mut out = Vec::new();
    for (i, j) in super::BOX_EDGES {
        let (a, b) = (corners[i], corners[j]);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let dy = b.y - a.y;
        if dy.abs() < 1e-12 {
            if a.y < y_min || a.y > y_max {
                continue;
            }
        } else {
            let (ta, tb) = ((y_min - a.y) / dy, (y_max - a.y) / dy);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
            if t0 > t1 {
                continue;
            }
        }
        out.push(a + (b - a) * t0);
        out.push(a + (b - a) * t1);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn city() -> Aabb {
        Aabb::new(
            Vec3::new(-500.0, 0.0, -500.0),
            Vec3::new(500.0, 120.0, 500.0),
        )
    }

    fn street() -> Camera {
        Camera::look_at(
            Vec3::new(-300.0, 2.0, 4.0),
            Vec3::new(0.0, 8.0, 4.0),
            60f32.to_radians(),
            0.1,
            2000.0,
        )
    }

    fn sun() -> Vec3 {
        Vec3::new(0.3, 0.8, 0.5).normalize()
    }

    fn clip(f: &LightFrustum, p: Vec3) -> glam::Vec4 {
        f.light_clip_from_world * p.extend(1.0)
    }

    #[test]
    fn n_is_the_papers_optimum_for_the_views_depths_and_angle() {
        let camera = street();
        let warp = fit_lispsm((&camera, 1.5), sun(), &city(), 2048, 1.0)
            .warp
            .expect("a street view is warped");
        let (near, far) = crate::geom::view_depth_range(&camera, &city()).unwrap();
        let view = camera.forward.as_dvec3();
        let light = -sun().as_dvec3();
        let sin_gamma = view.cross(light).length();
        assert!((warp.sin_gamma - sin_gamma).abs() < 1e-6);
        let expected = (near + (near * far).sqrt()) / sin_gamma;
        assert!((warp.n_opt_m - expected).abs() < 1e-5 * expected);
        let scaled = fit_lispsm((&camera, 1.5), sun(), &city(), 2048, 2.5)
            .warp
            .unwrap();
        assert!((scaled.n_m - 2.5 * expected).abs() < 1e-5 * expected);
    }

    #[test]
    fn the_view_frustum_in_the_scene_maps_into_the_map_and_light_rays_stay_parallel() {
        let camera = street();
        let f = fit_lispsm((&camera, 1.5), sun(), &city(), 2048, 1.0);
        // Every point of the scene the camera sees lies in the map.
        let camera_clip = camera.clip_from_world(1.5);
        let b = city();
        let mut checked = 0;
        for i in 0..=40 {
            for j in 0..=12 {
                for k in 0..=40 {
                    let p = b.min
                        + (b.max - b.min)
                            * Vec3::new(i as f32 / 40.0, j as f32 / 12.0, k as f32 / 40.0);
                    let c = camera_clip * p.extend(1.0);
                    if !(c.w > 0.0
                        && c.x.abs() <= c.w
                        && c.y.abs() <= c.w
                        && (0.0..=c.w).contains(&c.z))
                    {
                        continue;
                    }
                    let q = clip(&f, p);
                    assert!(q.w > 0.0);
                    let ndc = q.truncate() / q.w;
                    assert!(
                        ndc.x.abs() <= 1.0 + 1e-3
                            && ndc.y.abs() <= 1.0 + 1e-3
                            && (-1e-3..=1.0 + 1e-3).contains(&ndc.z),
                        "{p} at {ndc}"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 1000, "{checked} points checked");
        // Two points on one ray of the sun land on one texel, the nearer to the sun shallower.
        let p = Vec3::new(-250.0, 0.0, 10.0);
        let up_the_ray = p + sun() * 60.0;
        let (a, b) = (clip(&f, p), clip(&f, up_the_ray));
        let (a, b) = (a.truncate() / a.w, b.truncate() / b.w);
        assert!(
            (a.x - b.x).abs() < 1e-5 && (a.y - b.y).abs() < 1e-5,
            "{a} {b}"
        );
        assert!(b.z < a.z, "depth grows away from the sun: {a} {b}");
    }

    #[test]
    fn near_texels_are_finer_than_a_uniform_maps() {
        let camera = street();
        let f = fit_lispsm((&camera, 1.5), sun(), &city(), 2048, 1.0);
        let uniform = fit_focused_light(&camera, 1.5, sun(), &city(), None, 2048);
        let [k_u, k_v] = f.warp.expect("warped").texel_per_w;
        // Right in front of the camera.
        let p = camera.eye + camera.forward * 5.0 - Vec3::Y;
        let w = clip(&f, p).w;
        let near_texel = (k_u * w).max(k_v * w * w);
        assert!(
            near_texel * 4.0 < uniform.texel_size_m[0].min(uniform.texel_size_m[1]),
            "LiSPSM {near_texel} m against uniform {:?}",
            uniform.texel_size_m
        );
    }

    #[test]
    fn looking_along_the_light_falls_back_to_the_uniform_map() {
        let sun = Vec3::new(0.0, 1.0, 0.0);
        for forward in [Vec3::NEG_Y, Vec3::new(0.01, 1.0, 0.0)] {
            let camera = Camera {
                eye: Vec3::new(0.0, 60.0, 0.0),
                forward: forward.normalize(),
                ..Camera::default()
            };
            let f = fit_lispsm((&camera, 1.0), sun, &city(), 1024, 1.0);
            assert!(f.warp.is_none(), "{forward}");
            assert!(f.light_clip_from_world.is_finite());
        }
    }

    #[test]
    fn hard_views_stay_finite() {
        // 100 km out, near 0.01 and far 10 km, the sun 1 degree up and at the zenith.
        for sun in [Vec3::new(1.0, 0.0175, 0.0).normalize(), Vec3::Y] {
            let mut camera = Camera::look_at(
                Vec3::new(100_000.0, 2.0, 0.0),
                Vec3::new(0.0, 2.0, 0.0),
                1.0,
                0.01,
                10_000.0,
            );
            let f = fit_lispsm((&camera, 1.7), sun, &city(), 4096, 1.0);
            assert!(f.light_clip_from_world.is_finite());
            camera.eye = Vec3::new(0.0, 3.0, 0.0);
            let f = fit_lispsm(
                (&camera, 1.7),
                sun,
                &Aabb::new(Vec3::ZERO, Vec3::ONE),
                4096,
                1.0,
            );
            assert!(f.light_clip_from_world.is_finite());
            assert!(f.texel_size_m.iter().all(|t| t.is_finite() && *t > 0.0));
        }
    }
}
