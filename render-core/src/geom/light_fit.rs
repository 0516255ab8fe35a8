//! Fitting a directional light's orthographic frustum to the camera and the scene.
//!
//! The x/y extent covers the part of the view frustum inside the scene bounds, so no visible
//! receiver falls outside the shadow map. The near plane is pulled back to the scene's extent
//! towards the sun, so every caster between the sun and the view frustum is rendered. All maths
//! runs in f64 around an anchor at the scene's centre, so a camera 100 km out loses nothing.

use glam::dcamera::rh::{proj::directx::orthographic, view::look_to_mat4};
use glam::{DVec3, Mat4, Vec3};

use super::{Aabb, Camera, basis_for_direction};

/// The fitted light frustum of a directional light, and facts about it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightFrustum {
    pub light_from_world: Mat4,
    pub clip_from_light: Mat4,
    pub light_clip_from_world: Mat4,
    /// Unit vector the light travels along (from the sun into the scene).
    pub light_direction: Vec3,
    /// World size of one shadow-map texel along x and y.
    pub texel_size_m: [f32; 2],
    /// Distance from the near to the far plane.
    pub depth_range_m: f32,
    /// True when the view frustum does not meet the scene, so the map covers the whole scene.
    pub covers_whole_scene: bool,
    /// For a warped (LiSPSM) frustum, where texel size and depth range vary over the map
    /// (`geom::lispsm`); `None` for an orthographic one. `texel_size_m` and `depth_range_m`
    /// are then the coarsest, at the far end.
    pub warp: Option<super::Warp>,
    /// For a texel-snapped (stabilised) frustum, its texel grid, so shaders place points on
    /// it exactly (`TexelGrid`); `None` otherwise.
    pub grid: Option<TexelGrid>,
    /// For a perspective frustum from a point (a spot light, a point light's cube face),
    /// how its texels and depths scale with distance (`geom::punctual`); `None` for the sun.
    pub perspective: Option<super::Perspective>,
}

/// A snapped orthographic frustum's texel grid: texels per metre across the light, and the
/// light-space position of the map's centre in whole texels (an integer, as the square's
/// first texel lies on the grid). Shaders compute a point's position as its light-space
/// metres times `per_metre`, minus `centre_texel`: with the same point, rotation and texel
/// size, two frames whose squares lie whole texels apart then give positions exactly that
/// many texels apart, not the last bits of a different matrix, so not a depth comparison
/// changes as the camera turns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelGrid {
    pub per_metre: [f32; 2],
    pub centre_texel: [f32; 2],
}

impl TexelGrid {
    /// The grid of a square `resolution` texels of `texel` metres wide from `min` (light
    /// space, on whole texels).
    pub(super) fn of(min: DVec3, texel: f64, resolution: u32) -> Self {
        let half = f64::from(resolution) * 0.5;
        let centre = |axis: usize| ((min[axis] / texel).round() + half) as f32;
        Self {
            per_metre: [(1.0 / texel) as f32; 2],
            centre_texel: [centre(0), centre(1)],
        }
    }
}

/// Light-space extent as `(min, max)` with x, y across the light and z along its direction.
pub(super) type Extent = (DVec3, DVec3);

/// Fits the light frustum for `camera` (with `aspect` = width / height) and the scene bounds.
pub fn fit_directional_light(
    camera: &Camera,
    aspect: f32,
    direction_to_sun: Vec3,
    scene_bounds: &Aabb,
    resolution: u32,
) -> LightFrustum {
    fit_focused_light(
        camera,
        aspect,
        direction_to_sun,
        scene_bounds,
        None,
        resolution,
    )
}

/// A light frustum over the whole scene, whatever the camera sees: a statically focused map
/// (Bittner 5.1).
pub fn fit_whole_scene(
    direction_to_sun: Vec3,
    scene_bounds: &Aabb,
    resolution: u32,
) -> LightFrustum {
    fit(None, direction_to_sun, scene_bounds, None, resolution)
}

/// Like [`fit_directional_light`], and where `receivers` (the visible receivers' bounds) is
/// given, the map's x/y extent and far plane shrink to them (Bittner 5.2, FOCUS): only the
/// light's near plane still reaches the scene's edge, for the casters between.
pub fn fit_focused_light(
    camera: &Camera,
    aspect: f32,
    direction_to_sun: Vec3,
    scene_bounds: &Aabb,
    receivers: Option<&Aabb>,
    resolution: u32,
) -> LightFrustum {
    fit(
        Some((camera, aspect)),
        direction_to_sun,
        scene_bounds,
        receivers,
        resolution,
    )
}

/// The light's frame: x, y across its direction and z along it, around an anchor at the
/// scene's centre (so far-away cameras keep their precision).
pub(super) struct LightSpace {
    anchor: DVec3,
    right: DVec3,
    up: DVec3,
    direction: DVec3,
    /// The scene's bounds (a unit box around the origin when they are empty or not finite)
    /// and their light-space extent.
    pub scene: Aabb,
    pub scene_extent: Extent,
}

impl LightSpace {
    pub fn new(direction_to_sun: Vec3, scene_bounds: &Aabb) -> Self {
        let direction = (-direction_to_sun.as_dvec3())
            .try_normalize()
            .unwrap_or(DVec3::NEG_Y);
        let (right, up) = basis_for_direction(direction);
        let scene = if scene_bounds.is_empty()
            || !scene_bounds.min.is_finite()
            || !scene_bounds.max.is_finite()
        {
            Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
        } else {
            *scene_bounds
        };
        let mut space = Self {
            anchor: scene.center().as_dvec3(),
            right,
            up,
            direction,
            scene,
            scene_extent: (DVec3::ZERO, DVec3::ZERO),
        };
        space.scene_extent = extent_of(&scene.corners().map(|c| space.to_light(c.as_dvec3())));
        space
    }

    pub fn to_light(&self, p: DVec3) -> DVec3 {
        let q = p - self.anchor;
        DVec3::new(q.dot(self.right), q.dot(self.up), q.dot(self.direction))
    }

    /// The orthographic frustum of the light-space box `min..max`, for a map `resolution`
    /// texels square.
    pub fn frustum(
        &self,
        (min, max): Extent,
        resolution: u32,
        covers_whole_scene: bool,
    ) -> LightFrustum {
        let light_from_world = look_to_mat4(self.anchor, self.direction, self.up);
        // The view looks down -z, so light depth d maps to view z = -d: near/far are depths.
        let clip_from_light = orthographic(min.x, max.x, min.y, max.y, min.z, max.z);
        let res = f64::from(resolution);
        LightFrustum {
            light_from_world: light_from_world.as_mat4(),
            clip_from_light: clip_from_light.as_mat4(),
            light_clip_from_world: (clip_from_light * light_from_world).as_mat4(),
            light_direction: self.direction.as_vec3(),
            texel_size_m: [
                ((max.x - min.x) / res) as f32,
                ((max.y - min.y) / res) as f32,
            ],
            depth_range_m: (max.z - min.z) as f32,
            covers_whole_scene,
            warp: None,
            grid: None,
            perspective: None,
        }
    }
}

fn fit(
    view: Option<(&Camera, f32)>,
    direction_to_sun: Vec3,
    scene_bounds: &Aabb,
    receivers: Option<&Aabb>,
    resolution: u32,
) -> LightFrustum {
    let space = LightSpace::new(direction_to_sun, scene_bounds);
    let scene_extent = space.scene_extent;
    let view = view.and_then(|(camera, aspect)| {
        view_corners(camera, aspect, &space.scene, None)
            .map(|c| extent_of(&c.map(|p| space.to_light(p))))
    });
    let (extent, covers_whole_scene) = match view {
        Some(view) => {
            let min = DVec3::new(
                view.0.x.max(scene_extent.0.x),
                view.0.y.max(scene_extent.0.y),
                scene_extent.0.z,
            );
            let max = DVec3::new(
                view.1.x.min(scene_extent.1.x),
                view.1.y.min(scene_extent.1.y),
                view.1.z.min(scene_extent.1.z),
            );
            if min.cmplt(max).all() {
                (Some((min, max)), false)
            } else {
                (None, true)
            }
        }
        None => (None, true),
    };
    let (mut min, mut max) = extent.unwrap_or(scene_extent);
    if let Some(focus) =
        receivers.filter(|r| !r.is_empty() && r.min.is_finite() && r.max.is_finite())
    {
        let (lo, hi) = extent_of(&focus.corners().map(|c| space.to_light(c.as_dvec3())));
        let (fmin, fmax) = (
            DVec3::new(min.x.max(lo.x), min.y.max(lo.y), min.z),
            DVec3::new(max.x.min(hi.x), max.y.min(hi.y), max.z.min(hi.z)),
        );
        if fmin.cmplt(fmax).all() {
            (min, max) = (fmin, fmax);
        }
    }
    let resolution = resolution.max(16);
    space.frustum(
        pad_and_snap((min, max), resolution),
        resolution,
        covers_whole_scene,
    )
}

pub(super) fn extent_of(points: &[DVec3]) -> Extent {
    points
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        })
}

/// The view depths `(near, far)` where the view frustum can meet the scene: the camera's
/// near and far planes cut to the depths of the scene's corners; `None` when the scene lies
/// wholly behind or beyond the view.
pub fn view_depth_range(camera: &Camera, scene: &Aabb) -> Option<(f64, f64)> {
    let eye = camera.eye.as_dvec3();
    let forward = camera
        .forward
        .as_dvec3()
        .try_normalize()
        .unwrap_or(DVec3::NEG_Z);
    let depths = scene.corners().map(|c| (c.as_dvec3() - eye).dot(forward));
    let scene_far = depths.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let scene_near = depths.iter().copied().fold(f64::INFINITY, f64::min);
    let near = f64::from(camera.near_m).max(scene_near).max(1e-6);
    let far = f64::from(camera.far_m).min(scene_far);
    (far.is_finite() && far > near).then_some((near, far))
}

/// Distances from the eye: the camera's near plane to the furthest the scene can be in any
/// direction, rounded up to a sixteenth of its octave, and no further than the far plane's
/// corners (`aspect` = width / height). Unlike [`view_depth_range`] it does not change when
/// the camera turns, and rarely when it moves a little, so splits over it stay put (the
/// stabilised cascades' range). `None` when the scene is out of the camera's reach.
pub fn stable_depth_range(camera: &Camera, aspect: f64, scene: &Aabb) -> Option<(f64, f64)> {
    let eye = camera.eye.as_dvec3();
    let reach = scene
        .corners()
        .map(|c| c.as_dvec3().distance(eye))
        .into_iter()
        .fold(0.0, f64::max);
    if !(reach.is_finite() && reach > 0.0) {
        return None;
    }
    let step = 2f64.powi(reach.log2().floor() as i32 - 4);
    let reach = (reach / step).ceil() * step;
    let near = f64::from(camera.near_m).max(1e-6);
    let far = (f64::from(camera.far_m) / camera.corner_cosine(aspect)).min(reach);
    (far > near).then_some((near, far))
}

/// The world corners of the view frustum between the depths where it can meet the scene,
/// further cut to `depths` when given; `None` when nothing of it is left.
pub(super) fn view_corners(
    camera: &Camera,
    aspect: f32,
    scene: &Aabb,
    depths: Option<[f64; 2]>,
) -> Option<[DVec3; 8]> {
    let (mut near, mut far) = view_depth_range(camera, scene)?;
    if let Some([lo, hi]) = depths {
        (near, far) = (near.max(lo), far.min(hi));
    }
    if far.is_nan() || far <= near {
        return None;
    }
    let aspect = if aspect.is_finite() && aspect > 0.0 {
        f64::from(aspect)
    } else {
        1.0
    };
    Some(camera.frustum_corners_world(aspect, near, far))
}

/// Grows the extent by a margin and snaps x/y to whole texels so the map does not shimmer when
/// the camera only translates.
pub(super) fn pad_and_snap((min, max): Extent, resolution: u32) -> Extent {
    let size = max - min;
    let z_margin = size.z.abs() * 1e-3 + 1e-2;
    let (mut min, mut max) = (
        min - DVec3::new(0.0, 0.0, z_margin),
        max + DVec3::new(0.0, 0.0, z_margin),
    );
    let res = f64::from(resolution);
    for axis in 0..2 {
        let width = size[axis].max(1e-3);
        let texel = width / (res - 2.0).max(1.0);
        let lo = (min[axis] / texel).floor() * texel;
        min[axis] = lo;
        max[axis] = lo + texel * res;
    }
    (min, max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::float_cmp, reason = "the range must not change in any bit")]
    fn the_stable_depth_range_ignores_turns_and_small_moves() {
        let scene = Aabb::new(
            Vec3::new(-500.0, 0.0, -500.0),
            Vec3::new(500.0, 80.0, 500.0),
        );
        let camera = |eye: Vec3, forward: Vec3| Camera {
            eye,
            forward: forward.normalize(),
            ..Camera::default()
        };
        let eye = Vec3::new(-40.0, 3.5, 2.0);
        let (near, far) = stable_depth_range(&camera(eye, Vec3::X), 1.5, &scene).expect("in reach");
        assert_eq!(near, f64::from(Camera::default().near_m).max(1e-6));
        // The furthest corner is sqrt(540^2 + 76.5^2 + 502^2) = 741.2 m, rounded up to a
        // sixteenth of its octave (512 m / 16 = 32 m).
        assert_eq!(far, 768.0);
        for forward in [Vec3::NEG_X, Vec3::Z, Vec3::new(0.3, -0.9, 0.2)] {
            assert_eq!(
                stable_depth_range(&camera(eye, forward), 1.5, &scene),
                Some((near, far))
            );
        }
        let nudged = camera(eye + Vec3::new(0.01, 0.0, 0.0), Vec3::X);
        assert_eq!(stable_depth_range(&nudged, 1.5, &scene), Some((near, far)));
    }

    /// `SplitMix64`: a small deterministic generator for test inputs.
    struct Rng(u64);
    impl Rng {
        fn next_f64(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        }
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next_f64()
        }
        fn unit_vector(&mut self) -> DVec3 {
            loop {
                let v = DVec3::new(
                    self.range(-1.0, 1.0),
                    self.range(-1.0, 1.0),
                    self.range(-1.0, 1.0),
                );
                if let Some(n) = v.try_normalize() {
                    return n;
                }
            }
        }
    }

    fn light_clip(fit: &LightFrustum, p: DVec3) -> DVec3 {
        fit.light_clip_from_world.as_dmat4().project_point3(p)
    }

    /// Checks that every sampled point of the view frustum inside the scene, and every scene
    /// corner's depth, lies in the light frustum; returns how many frustum points were checked.
    fn check_case(camera: &Camera, aspect: f32, sun: Vec3, scene: &Aabb, rng: &mut Rng) -> usize {
        let fit = fit_directional_light(camera, aspect, sun, scene, 2048);
        let m = fit.light_clip_from_world;
        assert!(
            m.is_finite() && fit.light_from_world.is_finite(),
            "non-finite matrix for {camera:?} sun {sun}"
        );
        assert!(fit.texel_size_m.iter().all(|t| t.is_finite() && *t > 0.0));
        let tol = 1e-3;
        // Casters between the sun and the frustum: no scene corner is in front of the near plane.
        for c in scene.corners() {
            let z = light_clip(&fit, c.as_dvec3()).z;
            assert!(
                z >= -tol,
                "scene corner {c} before the light's near plane (z = {z})"
            );
        }
        let corners = camera.frustum_corners_world(
            f64::from(aspect),
            f64::from(camera.near_m),
            f64::from(camera.far_m),
        );
        let scene_d = Aabb::new(scene.min, scene.max);
        let mut checked = 0;
        let mut samples: Vec<DVec3> = corners.to_vec();
        for _ in 0..400 {
            let (u, v, t) = (rng.next_f64(), rng.next_f64(), rng.next_f64());
            let near = corners[0]
                .lerp(corners[1], u)
                .lerp(corners[2].lerp(corners[3], u), v);
            let far = corners[4]
                .lerp(corners[5], u)
                .lerp(corners[6].lerp(corners[7], u), v);
            samples.push(near.lerp(far, t));
        }
        for p in samples {
            if !scene_d.contains_point(p.as_vec3()) {
                continue;
            }
            let q = light_clip(&fit, p);
            assert!(
                q.x.abs() <= 1.0 + tol && q.y.abs() <= 1.0 + tol && q.z >= -tol && q.z <= 1.0 + tol,
                "visible point {p} outside the light frustum: clip {q}; camera {camera:?}, sun {sun}"
            );
            checked += 1;
        }
        checked
    }

    fn random_camera(rng: &mut Rng, centre: DVec3, spread: f64, near: f32, far: f32) -> Camera {
        let eye = centre
            + DVec3::new(
                rng.range(-spread, spread),
                rng.range(0.5, spread * 0.3),
                rng.range(-spread, spread),
            );
        Camera {
            eye: eye.as_vec3(),
            forward: rng.unit_vector().as_vec3(),
            fov_y_rad: rng.range(0.3, 1.8) as f32,
            near_m: near,
            far_m: far,
            world_up: Vec3::Y,
        }
    }

    #[test]
    fn light_frustum_contains_visible_scene_for_random_cameras_and_suns() {
        let mut rng = Rng(7);
        let scene = Aabb::new(
            Vec3::new(-500.0, 0.0, -500.0),
            Vec3::new(500.0, 300.0, 500.0),
        );
        let mut checked = 0;
        for _ in 0..300 {
            let camera = random_camera(&mut rng, DVec3::ZERO, 600.0, 0.1, 3000.0);
            let mut sun = rng.unit_vector();
            sun.y = sun.y.abs().max(0.02);
            checked += check_case(
                &camera,
                rng.range(0.5, 2.5) as f32,
                sun.as_vec3(),
                &scene,
                &mut rng,
            );
        }
        assert!(
            checked > 5_000,
            "too few visible points were checked: {checked}"
        );
    }

    #[test]
    fn hard_cases_stay_finite_and_contain_the_view() {
        let mut rng = Rng(11);
        let city = Aabb::new(
            Vec3::new(-1000.0, 0.0, -1000.0),
            Vec3::new(1000.0, 300.0, 1000.0),
        );
        let street = Camera::look_at(
            Vec3::new(10.0, 1.7, 5.0),
            Vec3::new(200.0, 20.0, -100.0),
            1.0,
            0.1,
            2000.0,
        );
        let down = Camera::look_at(Vec3::new(0.0, 500.0, 0.0), Vec3::ZERO, 1.0, 0.1, 2000.0);
        let zenith = Vec3::Y;
        let grazing = Sun::from_azimuth_elevation_deg(30.0, 1.0).direction_to_sun;
        let mut checked = 0;
        // Sun straight down (naive look-at up vector degenerates), camera also straight down.
        checked += check_case(&street, 16.0 / 9.0, zenith, &city, &mut rng);
        checked += check_case(&down, 16.0 / 9.0, zenith, &city, &mut rng);
        checked += check_case(&down, 1.0, -Vec3::Y, &city, &mut rng);
        // Sun one degree above the horizon.
        checked += check_case(&street, 16.0 / 9.0, grazing, &city, &mut rng);
        checked += check_case(&down, 16.0 / 9.0, grazing, &city, &mut rng);
        // Near 0.01 m and far 10 km.
        let wide = Camera::look_at(
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(1.0, 1.9, 1.0),
            1.2,
            0.01,
            10_000.0,
        );
        checked += check_case(&wide, 2.0, grazing, &city, &mut rng);
        // Camera 100 km from the origin, in a huge scene around it.
        let far_out = Vec3::new(100_000.0, 50.0, -70_000.0);
        let huge = Aabb::new(
            far_out - Vec3::new(20_000.0, 50.0, 20_000.0),
            far_out + Vec3::new(20_000.0, 500.0, 20_000.0),
        );
        for sun in [zenith, grazing, Vec3::new(0.2, 0.5, -0.3)] {
            let cam = Camera::look_at(
                far_out + Vec3::Y * 2.0,
                far_out + Vec3::new(300.0, 0.0, 50.0),
                1.0,
                0.01,
                10_000.0,
            );
            checked += check_case(&cam, 16.0 / 9.0, sun, &huge, &mut rng);
        }
        assert!(
            checked > 500,
            "too few visible points were checked: {checked}"
        );
        // Camera 100 km from a small scene at the origin: nothing visible, a finite fallback.
        let lost = Camera::look_at(
            Vec3::new(100_000.0, 10.0, 0.0),
            Vec3::new(200_000.0, 10.0, 0.0),
            1.0,
            0.01,
            10_000.0,
        );
        let fit = fit_directional_light(&lost, 1.5, grazing, &city, 1024);
        assert!(fit.covers_whole_scene && fit.light_clip_from_world.is_finite());
        for c in city.corners() {
            let q = light_clip(&fit, c.as_dvec3());
            assert!(
                q.x.abs() <= 1.001 && q.y.abs() <= 1.001 && (-0.001..=1.001).contains(&q.z),
                "{q}"
            );
        }
    }

    #[test]
    fn degenerate_inputs_give_finite_frusta() {
        let cam = Camera::look_at(Vec3::ZERO, Vec3::ZERO, 1.0, 0.1, 100.0);
        for sun in [Vec3::ZERO, Vec3::Y, -Vec3::Y, Vec3::X] {
            for scene in [
                Aabb::EMPTY,
                Aabb::new(Vec3::ZERO, Vec3::ZERO),
                Aabb::new(Vec3::splat(-1.0), Vec3::ONE),
            ] {
                for aspect in [0.0, f32::NAN, 1.0] {
                    let fit = fit_directional_light(&cam, aspect, sun, &scene, 0);
                    assert!(
                        fit.light_clip_from_world.is_finite(),
                        "sun {sun} scene {scene:?} aspect {aspect}"
                    );
                }
            }
        }
    }

    use crate::scene::Sun;
}
