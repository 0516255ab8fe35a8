//! The exact shadow (a ray per pixel through a BVH of the scene, then one towards the sun):
//! against the analytic shadow of a box, in hard cases, and as the measure of a shadow map's
//! error.

use glam::Vec3;
use render_core::frame::{
    FrameInput, FrameRenderer, FrameSettings, PcfKernel, SceneGpu, ShadowSetup,
};
use render_core::geom::Camera;
use render_core::scene::{Scene, ShadowLight, Sun, load_builtin};
use render_core::truth::{ExactShadow, PixelTruth, SurfacePoint, TruthCache};
use shadowlab_tests::{box_on_plane, expected_shadow, gpu, translated};

const BOX: Vec3 = Vec3::new(2.0, 3.0, 1.5);

fn sun() -> Sun {
    Sun::from_azimuth_elevation_deg(20.0, 40.0)
}

/// Looking down at the box and its shadow from the south-west.
fn camera_at(offset: Vec3) -> Camera {
    Camera::look_at(
        offset + Vec3::new(-6.0, 9.0, 8.0),
        offset + Vec3::new(-1.0, 0.0, 0.0),
        60f32.to_radians(),
        0.1,
        200.0,
    )
}

fn box_bounds(scene: &Scene) -> (Vec3, Vec3) {
    let b = scene.instances[1].aabb_in_world;
    (b.min, b.max)
}

/// Every counted pixel of the view against the box's analytic shadow: ground points in the
/// box's shadow volume, box faces lit (nothing stands between them and the sun). Pixels
/// within `margin_m` of the shadow's edge are left out. Returns (shadowed, lit) pixels.
fn check_against_analytic(scene: &Scene, exact: &ExactShadow, margin_m: f32) -> (u32, u32) {
    let (min, max) = box_bounds(scene);
    let ShadowLight::Sun(sun) = exact.key.light else {
        panic!("the analytic shadow is the sun's");
    };
    let ground_y = scene.instances[0].aabb_in_world.max.y;
    let (mut shadowed, mut lit) = (0, 0);
    for (i, point) in exact.points.iter().enumerate() {
        let p = Vec3::from_slice(&point.position[..3]);
        let n = Vec3::from_slice(&point.normal[..3]);
        assert!(p.is_finite() && n.is_finite(), "point {i}: {p} {n}");
        assert!((n.length() - 1.0).abs() < 1e-4, "unit normal: {n}");
        let truth = exact.shadowed(i);
        let on_ground = (p.y - ground_y).abs() < margin_m.max(1e-3) && n.y > 0.99;
        let expected = if on_ground {
            expected_shadow(p, sun, min, max, margin_m)
        } else {
            Some(false)
        };
        if let Some(expected) = expected {
            assert_eq!(
                truth, expected,
                "pixel {} at {p} (normal {n}): exact {truth}, analytic {expected}",
                exact.point_pixels[i]
            );
        }
        if truth {
            shadowed += 1;
        } else {
            lit += 1;
        }
    }
    (shadowed, lit)
}

#[test]
fn the_exact_shadow_of_a_box_is_its_analytic_shadow() {
    let scene = box_on_plane(20.0, BOX, 0.0, sun());
    let mut truth = TruthCache::default();
    let exact = truth
        .exact(
            &scene,
            &camera_at(Vec3::ZERO),
            (320, 240),
            sun().direction_to_sun,
        )
        .clone();
    let (shadowed, lit) = check_against_analytic(&scene, &exact, 1e-3);
    assert!(
        shadowed > 1000 && lit > 10_000,
        "the view shows the shadow and lit ground: {shadowed} shadowed, {lit} lit"
    );
    // Faces turned from the sun are not counted, nor is anything off the ground.
    let away = exact
        .pixels
        .iter()
        .filter(|p| **p == PixelTruth::FacesAway)
        .count();
    assert!(away > 100, "the box's shaded sides face away: {away}");
    assert_eq!(
        exact.points.len() + away,
        exact
            .pixels
            .iter()
            .filter(|p| **p != PixelTruth::Sky)
            .count(),
        "every pixel on a surface is counted or faces away"
    );
}

/// A pixel is on an edge of the exact picture where the box's shadow or an outline passes
/// next to it: a ground pixel whose neighbours all show the ground only within a few pixels'
/// width of the analytic shadow's edge. An everywhere-lit light is wrong on every shadowed
/// pixel, and only those on the edges are put down to sampling.
#[test]
fn the_pixels_on_edges_are_those_along_the_shadows_outline() {
    const NEAR_M: f32 = 0.3;
    const WIDTH: u32 = 320;
    let scene = box_on_plane(20.0, BOX, 0.0, sun());
    let mut truth = TruthCache::default();
    let exact = truth.exact(
        &scene,
        &camera_at(Vec3::ZERO),
        (WIDTH, 240),
        sun().direction_to_sun,
    );
    let (min, max) = box_bounds(&scene);
    let ground_y = scene.instances[0].aabb_in_world.max.y;
    let mut point_at = vec![None; exact.pixels.len()];
    for (i, &pixel) in exact.point_pixels.iter().enumerate() {
        point_at[pixel as usize] = Some(i);
    }
    let on_ground = |i: usize| (exact.points[i].position[1] - ground_y).abs() < 1e-3;
    // Whether every neighbour of pixel `pixel` shows the ground (the box, the sky and the
    // rim of the ground are outlines).
    let ground_around = |pixel: u32| {
        let (x, y) = ((pixel % WIDTH) as i32, (pixel / WIDTH) as i32);
        (-1..=1).all(|dy| {
            (-1..=1).all(|dx| {
                let n = (y + dy) * WIDTH as i32 + x + dx;
                (x + dx) >= 0
                    && (x + dx) < WIDTH as i32
                    && usize::try_from(n)
                        .ok()
                        .and_then(|n| point_at.get(n).copied().flatten())
                        .is_some_and(on_ground)
            })
        })
    };
    let (mut shadowed_on_edge, mut shadow_edge) = (0, 0);
    for (i, point) in exact.points.iter().enumerate() {
        if !exact.on_edge[i] {
            continue;
        }
        shadowed_on_edge += u32::from(exact.shadowed(i));
        let pixel = exact.point_pixels[i];
        if !on_ground(i) || !ground_around(pixel) {
            continue;
        }
        let p = Vec3::from_slice(&point.position[..3]);
        assert_eq!(
            expected_shadow(p, sun().direction_to_sun, min, max, NEAR_M),
            None,
            "ground pixel {pixel} at {p} is on an edge {NEAR_M} m from the shadow's"
        );
        shadow_edge += 1;
    }
    let shadowed = (0..exact.points.len())
        .filter(|&i| exact.shadowed(i))
        .count() as u32;
    assert!(
        shadow_edge > 100,
        "{shadow_edge} pixels along the shadow's edge"
    );
    let error = exact.error_of(&vec![1.0; exact.points.len()]);
    assert_eq!(
        (error.missing_shadow_px, error.extra_shadow_px),
        (shadowed, 0)
    );
    assert!(
        shadowed_on_edge > 50 && shadowed_on_edge * 5 < shadowed,
        "{shadowed_on_edge} of {shadowed} shadowed pixels on edges"
    );
    assert_eq!(error.off_edge_px, Some(shadowed - shadowed_on_edge));
}

#[test]
fn the_exact_shadow_holds_far_from_the_origin_and_for_a_lifted_box() {
    // 100 km out, a box floating 1 m up: its shadow leaves the ground under it lit near the
    // box's foot.
    let offset = Vec3::new(100_000.0, 0.0, -100_000.0);
    let scene = translated(&box_on_plane(20.0, BOX, 1.0, sun()), offset);
    let mut truth = TruthCache::default();
    let exact = truth
        .exact(
            &scene,
            &camera_at(offset),
            (256, 192),
            sun().direction_to_sun,
        )
        .clone();
    // f32 positions 100 km out are good to 8 mm.
    let (shadowed, lit) = check_against_analytic(&scene, &exact, 0.03);
    assert!(
        shadowed > 500 && lit > 5000,
        "{shadowed} shadowed, {lit} lit"
    );
}

#[test]
fn a_view_of_sky_has_no_counted_pixels_and_the_truth_is_cached() {
    let scene = box_on_plane(20.0, BOX, 0.0, sun());
    let up = Camera::look_at(
        Vec3::new(0.0, 5.0, 0.0),
        Vec3::new(0.0, 50.0, 1.0),
        60f32.to_radians(),
        0.1,
        200.0,
    );
    let mut truth = TruthCache::default();
    let exact = truth.exact(&scene, &up, (64, 48), sun().direction_to_sun);
    assert!(exact.pixels.iter().all(|p| *p == PixelTruth::Sky));
    assert!(exact.points.is_empty());
    truth.exact(&scene, &up, (64, 48), sun().direction_to_sun);
    assert_eq!(truth.views_cast(), 1, "the same view is not cast twice");
    truth.exact(&scene, &up, (64, 48), Vec3::Y);
    assert_eq!(truth.views_cast(), 2, "another sun is another view");
}

/// One frame of `settings` and its renderer, for reading the light at points.
fn rendered(scene: &Scene, camera: &Camera, settings: &FrameSettings) -> FrameRenderer {
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, scene);
    let mut renderer = FrameRenderer::new(ctx);
    let input = FrameInput {
        camera,
        width: 320,
        height: 240,
        settings,
    };
    renderer
        .render_and_wait(ctx, scene, &scene_gpu, &input)
        .expect("frame renders");
    renderer
}

#[test]
fn the_map_is_read_at_the_truths_points_and_its_error_counted() {
    let scene = box_on_plane(20.0, BOX, 0.0, sun());
    let camera = camera_at(Vec3::ZERO);
    let mut truth = TruthCache::default();
    let exact = truth
        .exact(&scene, &camera, (320, 240), sun().direction_to_sun)
        .clone();
    let rays = truth.rays(&scene);
    let truth_shadowed = (0..exact.points.len())
        .filter(|&i| exact.shadowed(i))
        .count() as u32;
    let mut settings = FrameSettings {
        sun: sun(),
        ..FrameSettings::default()
    };
    settings.shadow.resolution = 4096;
    settings.shadow.pcf = PcfKernel::Off;

    // A point in the middle of the box's shadow and one far from it.
    let renderer = rendered(&scene, &camera, &settings);
    let to_sun = sun().direction_to_sun;
    let behind = -Vec3::new(to_sun.x, 0.0, to_sun.z).normalize() * 3.0;
    let at = |p: Vec3| SurfacePoint {
        position: p.extend(1.0).to_array(),
        normal: [0.0, 1.0, 0.0, 0.0],
    };
    let light = renderer
        .light_at(gpu(), &[at(behind), at(Vec3::new(-8.0, 0.0, 6.0))])
        .expect("read back");
    assert_eq!(
        light,
        vec![0.0, 1.0],
        "shadowed behind the box, lit far away"
    );

    // A fine map misses the exact shadow only along its edges.
    let error = renderer
        .exact_error(gpu(), (&exact, rays))
        .expect("read back");
    assert_eq!(error.visible_px, exact.points.len() as u32);
    let wrong = error.missing_shadow_px + error.extra_shadow_px;
    assert!(
        wrong * 50 < truth_shadowed,
        "at 4096 the map differs from the exact shadow in {wrong} of {truth_shadowed} shadowed pixels"
    );
    assert_eq!(error.off_edge_px, Some(0), "{error:?}");

    // Without shadows, every exactly shadowed pixel is missing, and nothing is extra.
    settings.shadow.shadows_enabled = false;
    let renderer = rendered(&scene, &camera, &settings);
    let error = renderer
        .exact_error(gpu(), (&exact, rays))
        .expect("read back");
    assert_eq!(
        (error.missing_shadow_px, error.extra_shadow_px),
        (truth_shadowed, 0)
    );
    // Most of those lie inside the shadow, away from its edges.
    let off = error.off_edge_px.expect("counted");
    assert!(
        off * 10 > truth_shadowed * 7 && off < truth_shadowed,
        "{off} of {truth_shadowed} off edges"
    );
}

/// One robot of the crowd (`builtin:robots`, its six parts alone), seen so that the top rim of its arm, a
/// silhouette edge, crosses the centre of pixel (136, 235) at 640x360: the centre's ray meets
/// the chest behind the rim, lit, and a hundredth of a pixel lower the arm's top, lit too.
/// Which of the two a rasteriser shows there is its rounding, and two passes may round
/// apart: shadow volumes on llvmpipe count the side of the arm's volume that starts on the
/// rim, where the arm's top was not drawn, and shadow that pixel. A shadow there is an
/// error on an edge; one on the chest away from the rim is an error off the edges.
#[test]
fn a_silhouette_edge_across_a_pixel_centre_is_an_edge() {
    let crowd = load_builtin("robots", 0).expect("a built-in scene");
    // The 101st robot: the floor and the four walls come first, then six parts a robot.
    let robot = crowd.instances[605..611].to_vec();
    assert!(robot.iter().all(|i| i.name.starts_with("robot_4_4_")));
    let scene = Scene::new("robot".to_string(), crowd.meshes.clone(), robot, crowd.sun);
    let camera = Camera::look_at(
        Vec3::new(-19.42857, 1.7, -7.058_822_6),
        Vec3::new(4.285_714_6, 1.7, -7.058_822),
        60f32.to_radians(),
        0.01,
        142.577_79,
    );
    let mut truth = TruthCache::default();
    let (exact, rays) =
        truth.exact_and_rays(&scene, &camera, (640, 360), crowd.sun.direction_to_sun);
    let point_at = |x: u32, y: u32| {
        exact
            .point_pixels
            .iter()
            .position(|&p| p == y * 640 + x)
            .expect("a counted pixel")
    };
    let shadowed_only_at = |i: usize| -> Vec<f32> {
        (0..exact.points.len())
            .map(|k| {
                if k == i || exact.shadowed(k) {
                    0.0
                } else {
                    1.0
                }
            })
            .collect()
    };
    for ((x, y), off_edge) in [((136, 235), 0), ((141, 230), 1)] {
        let i = point_at(x, y);
        let normal = exact.points[i].normal;
        assert!(
            !exact.shadowed(i) && normal[2] > 0.99,
            "pixel ({x}, {y}) shows the chest, lit"
        );
        let error = exact.error_within(rays, &shadowed_only_at(i));
        assert_eq!(
            (
                error.extra_shadow_px,
                error.missing_shadow_px,
                error.off_edge_px
            ),
            (1, 0, Some(off_edge)),
            "a shadow at ({x}, {y})"
        );
    }
    // Standard shadow volumes of the robot: wrong at most on 0.01% of the visible pixels,
    // every one on an edge.
    let volumes = FrameSettings {
        sun: crowd.sun,
        setup: ShadowSetup::Volumes,
        ..FrameSettings::default()
    };
    let (error, _, _, _) = shadowlab_tests::against_truth(&scene, &camera, &volumes, (640, 360));
    let wrong = error.missing_shadow_px + error.extra_shadow_px;
    assert!(wrong * 10_000 <= error.visible_px, "{error:?}");
    assert_eq!(error.off_edge_px, Some(0), "{error:?}");
}

/// The edge rule excuses only what sampling explains: a map with no bias of any kind under a
/// low sun is speckled with acne across the lit ground, far from any shadow's outline or
/// depth jump, and every speckle there counts as off the edges.
#[test]
fn acne_on_a_uniformly_lit_face_counts_off_the_edges() {
    let sun = Sun::from_azimuth_elevation_deg(20.0, 25.0);
    let scene = box_on_plane(20.0, BOX, 0.0, sun);
    let camera = camera_at(Vec3::ZERO);
    let mut truth = TruthCache::default();
    let exact = truth
        .exact(&scene, &camera, (320, 240), sun.direction_to_sun)
        .clone();
    let rays = truth.rays(&scene);
    let mut settings = FrameSettings {
        sun,
        ..FrameSettings::default()
    };
    settings.shadow.depth_bias_m = 0.0;
    settings.shadow.depth_bias_texels = 0.0;
    settings.shadow.slope_bias = 0.0;
    settings.shadow.normal_offset_texels = 0.0;
    settings.shadow.pcf = PcfKernel::Off;
    let renderer = rendered(&scene, &camera, &settings);
    let light = renderer.light_at(gpu(), &exact.points).expect("read back");
    // The speckles: exactly lit ground points the map shadows, away from the box's shadow,
    // with ground all around (an outline of the box, a depth jump, is an edge).
    let (min, max) = box_bounds(&scene);
    let width = 320;
    let mut ground_at = vec![false; exact.pixels.len()];
    for (i, &pixel) in exact.point_pixels.iter().enumerate() {
        ground_at[pixel as usize] = exact.points[i].position[1].abs() < 1e-3;
    }
    let ground_around = |pixel: u32| {
        let (x, y) = (i64::from(pixel % width), i64::from(pixel / width));
        (-1..=1).all(|dy| {
            (-1..=1).all(|dx| {
                let (nx, ny) = (x + dx, y + dy);
                (0..i64::from(width)).contains(&nx)
                    && usize::try_from(ny * i64::from(width) + nx)
                        .is_ok_and(|n| ground_at.get(n).copied().unwrap_or(false))
            })
        })
    };
    let acne: Vec<usize> = (0..exact.points.len())
        .filter(|&i| {
            let p = Vec3::from_slice(&exact.points[i].position[..3]);
            light[i] < 0.5
                && ground_around(exact.point_pixels[i])
                && expected_shadow(p, sun.direction_to_sun, min, max, 0.5) == Some(false)
        })
        .collect();
    assert!(
        acne.len() > 500,
        "acne with no bias: {} speckles",
        acne.len()
    );
    let on_edge = acne.iter().filter(|&&i| exact.on_edge[i]).count();
    assert_eq!(
        on_edge,
        0,
        "of {} speckles on uniformly lit ground",
        acne.len()
    );
    let error = renderer
        .exact_error(gpu(), (&exact, rays))
        .expect("read back");
    assert!(
        error.off_edge_px.expect("counted") >= acne.len() as u32,
        "{error:?}: the {} speckles are off the edges",
        acne.len()
    );
}
