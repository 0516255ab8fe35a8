//! A second, brute-force truth to arbitrate the exact shadow on small scenes: every triangle
//! of every instance in world space in f64, no trees, no offsets; the camera ray through each
//! pixel centre meets the nearest front face, and from that point (f64 along the ray: its
//! error at 100 km is picometres) a ray towards the sun tests every casting triangle past a
//! micrometre. Where `check` once failed (issue 47: the house's inside, its zenith, 100 km
//! out; the wall seen from 60 m), the exact shadow must agree with it on every counted pixel
//! off the edges.

use std::path::PathBuf;

use glam::{DVec3, Mat4, Vec3};

use super::{ExactShadow, GRAZING, PixelTruth, SceneRays, ViewKey};
use crate::geom::Camera;
use crate::scene::{ChunkSettings, Scene, ShadowLight, Sun, import_gltf};

struct WorldTriangle {
    v: [DVec3; 3],
    casts: bool,
    receives: bool,
}

fn world_triangles(scene: &Scene) -> Vec<WorldTriangle> {
    let mut out = Vec::new();
    for instance in &scene.instances {
        let m = instance.world_from_local.as_dmat4();
        let mesh = &scene.meshes[instance.mesh as usize];
        for t in mesh.indices.chunks_exact(3) {
            let v = |i: u32| m.transform_point3(mesh.positions[i as usize].as_dvec3());
            out.push(WorldTriangle {
                v: [v(t[0]), v(t[1]), v(t[2])],
                casts: instance.casts_shadow,
                receives: instance.receives_shadow,
            });
        }
    }
    out
}

/// Möller and Trumbore in f64: `t` where the ray meets the triangle (either side).
fn meets(origin: DVec3, direction: DVec3, [v0, v1, v2]: &[DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (*v1 - *v0, *v2 - *v0);
    let p = direction.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let s = origin - *v0;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = direction.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0).then_some(t)
}

/// The brute-force truth of every pixel of `camera`'s `width` x `height` view under a sun
/// in direction `to_sun`.
fn brute_force(
    scene: &Scene,
    camera: &Camera,
    (width, height): (u32, u32),
    to_sun: Vec3,
) -> Vec<PixelTruth> {
    let triangles = world_triangles(scene);
    let to_sun = to_sun.normalize().as_dvec3();
    let (right, up) = camera.basis();
    let (right, up) = (right.as_dvec3(), up.as_dvec3());
    let forward = camera.forward.normalize().as_dvec3();
    let eye = camera.eye.as_dvec3();
    let tan_half = f64::from(camera.fov_y_rad * 0.5).tan();
    let (w, h) = (f64::from(width), f64::from(height));
    let (near, far) = (f64::from(camera.near_m), f64::from(camera.far_m));
    let mut out = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let ndc_x = 2.0 * (f64::from(x) + 0.5) / w - 1.0;
            let ndc_y = 1.0 - 2.0 * (f64::from(y) + 0.5) / h;
            let d = forward + right * (ndc_x * tan_half * w / h) + up * (ndc_y * tan_half);
            let nearest = triangles
                .iter()
                .filter(|tri| (tri.v[1] - tri.v[0]).cross(tri.v[2] - tri.v[0]).dot(d) < 0.0)
                .filter_map(|tri| Some((meets(eye, d, &tri.v)?, tri)))
                .filter(|(t, _)| (near..=far).contains(t))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let Some((t, tri)) = nearest else {
                out.push(PixelTruth::Sky);
                continue;
            };
            let normal = (tri.v[1] - tri.v[0]).cross(tri.v[2] - tri.v[0]).normalize();
            out.push(if !tri.receives {
                PixelTruth::NotReceiver
            } else if normal.dot(to_sun) <= f64::from(GRAZING) {
                PixelTruth::FacesAway
            } else {
                let p = eye + d * t;
                let blocked = triangles
                    .iter()
                    .filter(|other| other.casts)
                    .any(|other| meets(p, to_sun, &other.v).is_some_and(|t| t > 1e-6));
                if blocked {
                    PixelTruth::Shadowed
                } else {
                    PixelTruth::Lit
                }
            });
        }
    }
    out
}

/// Casts the exact shadow and the brute-force one; returns the counted pixels off the edges
/// where they disagree (pixel, exact, brute force) and the exact shadow's shadowed pixels.
fn disagreements(
    scene: &Scene,
    camera: Camera,
    size: (u32, u32),
    to_sun: Vec3,
) -> (Vec<(u32, PixelTruth, PixelTruth)>, usize) {
    let rays = SceneRays::new(scene);
    let key = ViewKey {
        camera,
        width: size.0,
        height: size.1,
        light: ShadowLight::Sun(to_sun.normalize()),
        poses: rays.version,
    };
    let exact = ExactShadow::cast(&rays, key);
    let brute = brute_force(scene, &camera, size, to_sun);
    let differ = (0..exact.points.len())
        .filter(|&i| !exact.on_edge[i])
        .map(|i| exact.point_pixels[i])
        .filter(|&p| exact.pixels[p as usize] != brute[p as usize])
        .map(|p| (p, exact.pixels[p as usize], brute[p as usize]))
        .collect();
    let shadowed = (0..exact.points.len())
        .filter(|&i| exact.shadowed(i))
        .count();
    (differ, shadowed)
}

fn asset(name: &str) -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../assets/scenes")
        .join(name);
    import_gltf(&path, &ChunkSettings::default()).expect("the scene loads")
}

fn moved(scene: &Scene, offset: Vec3) -> Scene {
    let mut instances = scene.instances.clone();
    for instance in &mut instances {
        instance.world_from_local = Mat4::from_translation(offset) * instance.world_from_local;
        instance.aabb_in_world = scene.meshes[instance.mesh as usize]
            .aabb_in_local
            .transformed(&instance.world_from_local);
    }
    Scene::new("test:moved", scene.meshes.clone(), instances, scene.sun)
}

#[test]
fn the_exact_shadow_agrees_with_a_brute_force_cast_where_check_failed() {
    let house = asset("house.gltf");
    let sun = Vec3::new(0.5, 0.8, 0.3);
    let (azimuth, _) = Sun::from_direction(sun).azimuth_elevation_deg();
    let zenith = Sun::from_azimuth_elevation_deg(azimuth, 90.0).direction_to_sun;
    // `check`'s own views of a glTF scene: from outside, and from inside its largest object.
    let view = |offset: Vec3, eye: Vec3, target: Vec3| {
        Camera::look_at(
            offset + eye,
            offset + target,
            60f32.to_radians(),
            0.01,
            51.3,
        )
    };
    let outside = |offset| {
        view(
            offset,
            Vec3::new(-15.018_559, 16.217_012, 15.018_559),
            Vec3::new(-14.425_197, 15.673_098, 14.425_197),
        )
    };
    let inside = view(
        Vec3::ZERO,
        Vec3::new(0.0, 2.6, 0.0),
        Vec3::new(0.593_361_9, 2.056_085, -0.593_361_9),
    );
    let far = Vec3::new(100_000.0, 0.0, 100_000.0);
    let wall = asset("wall.gltf");
    let from_60_m = Camera::look_at(
        Vec3::new(60.0, 3.0, 5.0),
        Vec3::new(0.0, 2.0, 0.0),
        10f32.to_radians(),
        0.05,
        500.0,
    );
    let moved_house = moved(&house, far);
    let small = (320, 180);
    // Under the zenith sun the house's shadow lies under it, but for the eaves' rim.
    let cases = [
        (
            "the house from outside",
            &house,
            outside(Vec3::ZERO),
            sun,
            small,
            500,
        ),
        ("the house inside", &house, inside, sun, small, 500),
        (
            "the house, sun at the zenith",
            &house,
            outside(Vec3::ZERO),
            zenith,
            small,
            1,
        ),
        (
            "the house 100 km out",
            &moved_house,
            outside(far),
            sun,
            small,
            500,
        ),
        (
            "the wall from 60 m",
            &wall,
            from_60_m,
            Vec3::new(0.8, 0.5, 0.3),
            (640, 360),
            100,
        ),
    ];
    for (case, scene, camera, to_sun, size, least_shadow) in cases {
        let (differ, shadowed) = disagreements(scene, camera, size, to_sun);
        assert!(
            shadowed >= least_shadow,
            "{case}: a shadow in view ({shadowed} pixels)"
        );
        assert!(
            differ.is_empty(),
            "{case}: {} counted pixels off the edges disagree (pixel, exact, brute force): {:?}",
            differ.len(),
            &differ[..differ.len().min(8)]
        );
    }
}
