//! Stencil shadow volumes (`--shadow volumes`) against the exact shadow: a box on a plane,
//! the camera inside the box's shadow and the near plane cutting the box (where z-pass would
//! fail, so the per-caster choice must take z-fail), an open quad lit from its back, and a
//! city street.

use glam::{Mat4, Vec3};
use render_core::frame::{FrameRenderer, FrameReport, FrameSettings, Method, ShadowSetup};
use render_core::geom::Camera;
use render_core::metrics::ShadowError;
use render_core::scene::{Instance, Mesh, PointShadow, Scene, Sun, load_builtin};
use render_core::truth::{SurfacePoint, TruthCache};
use render_core::volumes::{VolumeClamp, VolumePassChoice};
use shadowlab_tests::{
    box_mesh, box_on_plane, city_small_street_camera, expected_shadow, gpu, render, scene_of,
};

const BOX: Vec3 = Vec3::new(2.0, 3.0, 1.5);
const SIZE: (u32, u32) = (320, 240);

fn sun() -> Sun {
    Sun::from_azimuth_elevation_deg(20.0, 40.0)
}

fn volumes(sun: Sun) -> FrameSettings {
    FrameSettings {
        sun,
        setup: ShadowSetup::Volumes,
        ..FrameSettings::default()
    }
}

/// One frame of `settings` at [`SIZE`] against the exact shadow (`shadowlab_tests`), by the
/// technique it asks for.
fn against_truth(
    scene: &Scene,
    camera: &Camera,
    settings: &FrameSettings,
) -> (ShadowError, u32, FrameRenderer, FrameReport) {
    let out = shadowlab_tests::against_truth(scene, camera, settings, SIZE);
    assert_eq!(out.3.technique, settings.setup.name());
    out
}

/// The light at every ground point of the view against the box's analytic shadow, away from
/// its edges (10 cm): returns (shadowed, lit) points checked.
#[allow(clippy::float_cmp, reason = "hard shadows are exactly 0 or 1")]
fn check_ground_against_analytic(
    scene: &Scene,
    camera: &Camera,
    renderer: &FrameRenderer,
) -> (u32, u32) {
    let b = scene.instances[1].aabb_in_world;
    let sun = scene.sun.direction_to_sun;
    let mut truth = TruthCache::default();
    let exact = truth.exact(scene, camera, SIZE, sun);
    let ground: Vec<SurfacePoint> = exact
        .points
        .iter()
        .filter(|p| p.position[1].abs() < 1e-3 && p.normal[1] > 0.99)
        .copied()
        .collect();
    let light = renderer.light_at(gpu(), &ground).expect("read back");
    let (mut shadowed, mut lit) = (0, 0);
    for (p, light) in ground.iter().zip(light) {
        let p = Vec3::from_slice(&p.position[..3]);
        match expected_shadow(p, sun, b.min, b.max, 0.1) {
            Some(true) => {
                assert_eq!(light, 0.0, "ground at {p} is in the box's shadow");
                shadowed += 1;
            }
            Some(false) => {
                assert_eq!(light, 1.0, "ground at {p} is lit");
                lit += 1;
            }
            None => {}
        }
    }
    (shadowed, lit)
}

fn counting(pass: VolumePassChoice) -> FrameSettings {
    let mut settings = volumes(sun());
    settings.volumes.pass = pass;
    // Unclamped: a clamped volume may start past a camera inside the caster's shadow (where
    // no receiver lies between them), and then z-pass counts it right too.
    settings.volumes.clamp = VolumeClamp::None;
    settings
}

/// The light at every exact point of the view with each way of counting (auto, z-fail,
/// z-pass), and auto's report.
fn light_by_counting(scene: &Scene, camera: &Camera) -> ([Vec<f32>; 3], FrameReport) {
    let mut truth = TruthCache::default();
    let exact = truth.exact(scene, camera, SIZE, scene.sun.direction_to_sun);
    let mut auto_report = None;
    let lights = [
        VolumePassChoice::Auto,
        VolumePassChoice::ZFail,
        VolumePassChoice::ZPass,
    ]
    .map(|pass| {
        let (_, _, renderer, report) = against_truth(scene, camera, &counting(pass));
        auto_report.get_or_insert(report);
        renderer.light_at(gpu(), &exact.points).expect("read back")
    });
    (lights, auto_report.expect("auto ran first"))
}

/// Points where two lights differ.
#[allow(clippy::float_cmp, reason = "hard shadows are exactly 0 or 1")]
fn differing(a: &[f32], b: &[f32]) -> usize {
    a.iter().zip(b).filter(|(a, b)| a != b).count()
}

/// Above and away from the box on its plane, its shadow in view.
fn above_the_box() -> Camera {
    Camera::look_at(
        Vec3::new(-6.0, 9.0, 8.0),
        Vec3::new(-1.0, 0.0, 0.0),
        60f32.to_radians(),
        0.1,
        200.0,
    )
}

/// A ground point behind the box, seen from the sun.
fn behind() -> Vec3 {
    let to_sun = sun().direction_to_sun;
    -Vec3::new(to_sun.x, 0.0, to_sun.z).normalize() * 3.0
}

#[test]
fn the_volumes_of_a_box_give_its_exact_shadow() {
    let scene = box_on_plane(20.0, BOX, 0.0, sun());
    let camera = above_the_box();
    let (error, shadowed, renderer, _) = against_truth(&scene, &camera, &volumes(sun()));
    assert!(shadowed > 1_000, "the view shows the shadow: {shadowed} px");
    let (in_shadow, lit) = check_ground_against_analytic(&scene, &camera, &renderer);
    assert!(
        in_shadow > 500 && lit > 10_000,
        "{in_shadow} shadowed, {lit} lit"
    );
    // Per pixel and exact: at most 0.01% of the visible pixels (a silhouette edge through a
    // pixel centre), and none on the box's own lit faces (where the near cap lies on them).
    let wrong = error.missing_shadow_px + error.extra_shadow_px;
    assert!(
        wrong * 10_000 <= error.visible_px,
        "{error:?} of {shadowed} shadowed"
    );
    assert_eq!(
        error.off_edge_px,
        Some(0),
        "every wrong pixel is on an edge"
    );
    // A map of the same view misses far more.
    let map = FrameSettings {
        sun: sun(),
        ..FrameSettings::default()
    };
    let (map_error, _, _, _) = against_truth(&scene, &camera, &map);
    let map_wrong = map_error.missing_shadow_px + map_error.extra_shadow_px;
    assert!(
        map_wrong > wrong * 4,
        "map {map_error:?}, volumes {error:?}"
    );
}

#[test]
fn the_camera_inside_the_shadow_sees_it_correctly() {
    let scene = box_on_plane(20.0, BOX, 0.0, sun());
    let behind = behind();
    // Low behind the box, inside its shadow volume, looking along the shadow and back at the
    // box: the near plane cuts the volume (z-pass would count it wrong).
    let eye = behind * 0.8 + Vec3::Y * 0.6;
    for target in [behind * 2.0, Vec3::new(0.0, 1.0, 0.0)] {
        let camera = Camera::look_at(eye, target, 70f32.to_radians(), 0.05, 200.0);
        let (error, shadowed, renderer, _) = against_truth(&scene, &camera, &volumes(sun()));
        assert!(shadowed > 500, "{shadowed}");
        let wrong = error.missing_shadow_px + error.extra_shadow_px;
        assert!(
            wrong * 10_000 <= error.visible_px,
            "towards {target}: {error:?} of {shadowed} shadowed"
        );
        let (in_shadow, _) = check_ground_against_analytic(&scene, &camera, &renderer);
        assert!(
            in_shadow > 500,
            "towards {target}: {in_shadow} shadowed ground points"
        );
        // The near rectangle lies in the box's volume: auto counts it z-fail, exactly as
        // z-fail everywhere does, and z-pass would lose the shadow around the camera.
        let ([auto, z_fail, z_pass], report) = light_by_counting(&scene, &camera);
        let passes = report.volume_passes.expect("counted");
        assert!(passes.z_fail >= 1, "towards {target}: {passes:?}");
        assert_eq!(differing(&auto, &z_fail), 0, "towards {target}");
        let wrong = differing(&z_pass, &z_fail);
        assert!(wrong > 1_000, "towards {target}: z-pass differs at {wrong}");
    }
}

#[test]
fn auto_counts_a_volume_z_pass_only_where_the_near_rectangle_is_outside_it() {
    let scene = box_on_plane(20.0, BOX, 0.0, sun());
    // Above and away from the box: its volume cannot hold the near rectangle.
    let above = above_the_box();
    let ([auto, z_fail, _], report) = light_by_counting(&scene, &above);
    let passes = report.volume_passes.expect("counted");
    assert!(passes.z_pass >= 1, "the box is counted z-pass: {passes:?}");
    assert_eq!(differing(&auto, &z_fail), 0);
    // 2 cm outside the box's lit +z face, looking along it into the box's shadow: the near
    // plane (5 cm) cuts the box, and with it the box's volume.
    let beside = Camera::look_at(
        Vec3::new(0.5, 1.0, BOX.z * 0.5 + 0.02),
        Vec3::new(-8.0, 0.0, BOX.z * 0.5 + 0.02),
        70f32.to_radians(),
        0.05,
        200.0,
    );
    let ([auto, z_fail, z_pass], report) = light_by_counting(&scene, &beside);
    let passes = report.volume_passes.expect("counted");
    assert!(passes.z_fail >= 1, "the box is counted z-fail: {passes:?}");
    assert_eq!(differing(&auto, &z_fail), 0);
    let wrong = differing(&z_pass, &z_fail);
    assert!(wrong > 1_000, "z-pass differs at {wrong}");
    let (error, shadowed, _, _) = against_truth(&scene, &beside, &counting(VolumePassChoice::Auto));
    assert!(shadowed > 1_000, "{shadowed}");
    // Near caps are clipped at the near plane as the camera's passes are, so the box's lit
    // face seen edge-on keeps its light (clamped, they interpolated other depths there).
    let wrong = error.missing_shadow_px + error.extra_shadow_px;
    assert!(
        wrong * 10_000 <= error.visible_px,
        "{error:?} of {shadowed} shadowed"
    );
}

#[test]
fn an_open_quad_lit_from_its_back_still_casts() {
    let sun = sun();
    let ground = box_mesh("ground", Vec3::new(20.0, 0.5, 20.0));
    // One quad facing down, 2 m up: the sun sees its back; the mesh is not closed.
    let quad = Mesh::new(
        "roof",
        vec![
            Vec3::new(-1.5, 0.0, -1.5),
            Vec3::new(1.5, 0.0, -1.5),
            Vec3::new(1.5, 0.0, 1.5),
            Vec3::new(-1.5, 0.0, 1.5),
        ],
        None,
        vec![0, 1, 2, 0, 2, 3],
    );
    assert!(quad.normals[0].y < 0.0, "the quad faces down");
    let scene = scene_of(
        "test:open-quad",
        sun,
        vec![
            (ground, Vec3::new(0.0, -0.5, 0.0)),
            (quad, Vec3::new(0.0, 2.0, 0.0)),
        ],
    );
    let camera = Camera::look_at(
        Vec3::new(-7.0, 8.0, 7.0),
        Vec3::new(-1.0, 0.0, 0.0),
        60f32.to_radians(),
        0.1,
        200.0,
    );
    let (error, shadowed, _, _) = against_truth(&scene, &camera, &volumes(sun));
    assert!(shadowed > 1_000, "the quad's shadow is in view: {shadowed}");
    let wrong = error.missing_shadow_px + error.extra_shadow_px;
    assert!(
        wrong * 10_000 <= error.visible_px,
        "{error:?} of {shadowed} shadowed"
    );
}

#[test]
fn a_city_street_in_volumes_is_all_but_exact_and_cc_volumes_fill_far_less() {
    let scene = load_builtin("city-small", 0).expect("city-small");
    let camera = city_small_street_camera();
    let run = |method, clamp| {
        let mut settings = FrameSettings {
            method,
            ..volumes(scene.sun)
        };
        settings.volumes.clamp = clamp;
        settings.overlays.fill = true;
        let (error, shadowed, _, report) = against_truth(&scene, &camera, &settings);
        (error, shadowed, report)
    };
    let (error, shadowed, standard) = run(Method::None, VolumeClamp::None);
    assert!(shadowed > 1_000, "{shadowed}");
    let wrong = error.missing_shadow_px + error.extra_shadow_px;
    assert!(
        wrong * 10_000 <= error.visible_px,
        "{error:?} of {shadowed} shadowed"
    );
    assert_eq!(
        error.off_edge_px,
        Some(0),
        "every wrong pixel is on an edge"
    );
    let (cc_error, _, cc) = run(Method::Bvol, VolumeClamp::Continuous);
    assert_eq!(
        cc_error, error,
        "culling and clamping change no visible pixel"
    );
    let (all, kept) = (standard.counts.casters_rendered, cc.counts.casters_rendered);
    assert!(kept * 2 < all, "{kept} of {all} volumes kept");
    let (f0, f1) = (
        standard.volume_fill.expect("fill").fragments,
        cc.volume_fill.expect("fill").fragments,
    );
    assert!(f1 * 2 < f0, "CC fill {f1} against {f0}");
}

/// Clamped volumes start just above the receivers under them; a street seen at a grazing
/// angle once pushed such caps behind the road by the near caps' depth bias (two pixels
/// here, 16 on the full city's street).
#[test]
fn cc_volumes_equal_standard_ones_pixel_for_pixel_down_a_grazing_street() {
    let scene = load_builtin("city-small", 0).expect("city-small");
    let camera = Camera::look_at(
        Vec3::new(-45.0, 2.0, 10.0),
        Vec3::new(60.0, 4.0, 10.0),
        60f32.to_radians(),
        0.1,
        2000.0,
    );
    let mut truth = TruthCache::default();
    let exact = truth.exact(&scene, &camera, SIZE, scene.sun.direction_to_sun);
    let light = |method, clamp| {
        let mut settings = FrameSettings {
            method,
            ..volumes(scene.sun)
        };
        settings.volumes.clamp = clamp;
        let (_, _, renderer, _) = against_truth(&scene, &camera, &settings);
        renderer.light_at(gpu(), &exact.points).expect("read back")
    };
    let standard = light(Method::None, VolumeClamp::None);
    assert!(standard.iter().filter(|&&l| l == 0.0).count() > 1_000);
    for clamp in [VolumeClamp::Continuous, VolumeClamp::Conservative] {
        let cc = light(Method::Bvol, clamp);
        assert_eq!(differing(&cc, &standard), 0, "{clamp:?}");
    }
}

#[test]
fn culling_and_clamping_by_the_visible_receivers_change_no_pixel() {
    // A ground of 60 m; the camera sees only its middle, with a box on it. A second box
    // stands in a corner under a sun nearly overhead: no visible point lies under it.
    let sun = Sun::from_azimuth_elevation_deg(30.0, 80.0);
    let ground = box_mesh("ground", Vec3::new(30.0, 0.5, 30.0));
    let cube = box_mesh("box", Vec3::new(1.0, 1.5, 1.0));
    let mut instances = vec![Instance::new(
        "ground",
        0,
        &ground,
        Mat4::from_translation(Vec3::new(0.0, -0.5, 0.0)),
    )];
    for (name, at) in [
        ("seen", Vec3::new(2.0, 1.5, 1.0)),
        ("hidden", Vec3::new(-22.0, 1.5, -22.0)),
    ] {
        instances.push(Instance::new(name, 1, &cube, Mat4::from_translation(at)));
    }
    let scene = Scene::new("test:corner-box", vec![ground, cube], instances, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 25.0, 0.5),
        Vec3::ZERO,
        30f32.to_radians(),
        0.1,
        200.0,
    );
    let frame = |method, clamp| {
        let mut settings = FrameSettings {
            method,
            ..volumes(sun)
        };
        settings.volumes.clamp = clamp;
        settings.overlays.fill = true;
        let (error, _, renderer, report) = against_truth(&scene, &camera, &settings);
        let fill = report.volume_fill.expect("fill counted");
        // Per instance (ground, seen box, hidden box), whether its volume is drawn.
        let drawn: Vec<bool> = (0..3)
            .map(|i| {
                renderer
                    .read_volume_intervals(gpu(), i)
                    .expect("read back")
                    .is_some_and(|spans| !spans.is_empty())
            })
            .collect();
        (report, error, fill, drawn)
    };
    let (all, all_error, all_fill, _) = frame(Method::None, VolumeClamp::None);
    assert_eq!(all.counts.casters_total, 3);
    assert_eq!(all.counts.casters_rendered, 3, "none draws every volume");
    assert!(all_error.visible_px > 10_000, "{all_error:?}");
    assert!(all_error.missing_shadow_px + all_error.extra_shadow_px < 20);
    // The hidden box's volume is dropped, and so is the ground's: the only points in the
    // ground's box are its own, lit, and the seen box's foot, whose rays to the sun run up
    // away from it.
    let (culled, culled_error, culled_fill, drawn) = frame(Method::Bvol, VolumeClamp::None);
    assert_eq!(drawn, [false, true, false], "{:?}", culled.stages);
    assert_eq!(culled.counts.casters_rendered, 1);
    assert_eq!(culled.stages.last().map(|s| s.remaining), Some(1));
    assert_eq!(culled_error, all_error, "culling changes no visible pixel");
    assert!(culled_fill.fragments < all_fill.fragments);
    let (_, clamped_error, clamped_fill, drawn) = frame(Method::Bvol, VolumeClamp::Continuous);
    assert_eq!(drawn, [false, true, false]);
    assert_eq!(
        clamped_error, all_error,
        "clamping changes no visible pixel"
    );
    // The volumes end just below the ground instead of past the scene (seen from above
    // that saves little; at street level, most: see the closing figures of issue 13).
    assert!(
        clamped_fill.fragments < culled_fill.fragments,
        "{clamped_fill:?} against {culled_fill:?}"
    );
}

/// The caster's instance in [`caster_over_a_platform_edge`].
const CASTER: u32 = 2;

/// A caster high above the edge of a platform: the visible receiver points under it lie on
/// the platform and, 8 m further along the light, on the ground beside it.
fn caster_over_a_platform_edge() -> (Scene, Camera) {
    let sun = Sun::from_azimuth_elevation_deg(0.0, 80.0);
    let ground = box_mesh("ground", Vec3::new(30.0, 0.5, 30.0));
    let platform = box_mesh("platform", Vec3::new(3.0, 0.25, 3.0));
    let caster = box_mesh("caster", Vec3::new(1.5, 0.5, 1.5));
    let scene = scene_of(
        "test:platform-edge",
        sun,
        vec![
            (ground, Vec3::new(0.0, -0.5, 0.0)),
            (platform, Vec3::new(0.0, 8.0, 0.0)),
            (caster, Vec3::new(3.0, 18.5, 0.0)),
        ],
    );
    let camera = Camera::look_at(
        Vec3::new(25.0, 12.0, 4.0),
        Vec3::new(0.0, 5.0, 0.0),
        60f32.to_radians(),
        0.1,
        200.0,
    );
    (scene, camera)
}

#[test]
fn discrete_clamping_skips_the_empty_space_between_receivers_and_changes_no_pixel() {
    let (scene, camera) = caster_over_a_platform_edge();
    let mut truth = TruthCache::default();
    let exact = truth.exact(&scene, &camera, SIZE, scene.sun.direction_to_sun);
    let run = |clamp, slices| {
        let mut settings = FrameSettings {
            method: Method::Bvol,
            ..volumes(scene.sun)
        };
        settings.volumes.clamp = clamp;
        settings.volumes.slices = slices;
        // Gaps split where they cost more pixels than their caps, whatever this device's
        // vertices cost (the V > R rule is checked below).
        settings.volumes.vertex_pixels = Some(0);
        settings.overlays.fill = true;
        let (error, shadowed, renderer, report) = against_truth(&scene, &camera, &settings);
        let light = renderer.light_at(gpu(), &exact.points).expect("read back");
        let intervals = renderer
            .read_volume_intervals(gpu(), CASTER)
            .expect("read back")
            .expect("a caster's volume");
        (error, shadowed, light, report, intervals)
    };
    let (error, shadowed, standard, _, whole) = run(VolumeClamp::None, 1);
    assert_eq!(whole.len(), 1, "{whole:?}");
    assert!(
        whole[0][0] == 0.0 && whole[0][1] > 40.0,
        "past the scene: {whole:?}"
    );
    assert!(shadowed > 500, "{shadowed}");
    let wrong = error.missing_shadow_px + error.extra_shadow_px;
    assert!(wrong * 10_000 <= error.visible_px, "{error:?}");
    // The platform 9.75 to 10.75 m below the caster's faces (9.9 to 10.9 m along the light
    // at 80 degrees) and the ground 18 to 19 m below (18.3 to 19.3 m), with nothing drawn
    // across the empty space between them, nor from the caster down to the platform: its
    // top faces the sun (its own, convex, lit) and its sides facing away from it are dark
    // whatever shadows them.
    let covers = |span: [f32; 2], from: f32, to: f32| span[0] <= from && span[1] >= to;
    let two = |spans: &[[f32; 2]]| {
        spans.len() == 2
            && spans[0][0] > 8.0
            && covers(spans[0], 9.9, 10.9)
            && covers(spans[1], 18.3, 19.3)
            && spans[0][1] < spans[1][0]
    };
    // Continuous clamping tells them apart by the grid's depth bins (`volumes/grid.wgsl`):
    // one cell over the platform's edge holds platform and ground points, 8 m apart.
    let (_, _, continuous, one, clamped) = run(VolumeClamp::Continuous, 1);
    assert!(two(&clamped), "continuous: {clamped:?}");
    assert_eq!(differing(&continuous, &standard), 0);
    for slices in [4, 8, 32] {
        // Slices of the view tell them apart by where they are seen, and end each interval
        // at its receivers' own depths rather than at a bin's end.
        let (_, _, discrete, _, spans) = run(VolumeClamp::Conservative, slices);
        assert!(two(&spans), "{slices} slices: {spans:?}");
        assert!(
            spans[0][1] - spans[0][0] <= clamped[0][1] - clamped[0][0],
            "{slices} slices: {spans:?} against continuous {clamped:?}"
        );
        assert_eq!(
            differing(&discrete, &standard),
            0,
            "{slices} slices change no point's light"
        );
    }
    // Exact clamping, the limit: only the platform and the ground that the caster's own
    // faces shadow.
    let (_, _, exact_light, limit, spans) = run(VolumeClamp::Exact, 1);
    assert!(two(&spans), "{spans:?}");
    assert_eq!(differing(&exact_light, &standard), 0);
    assert!(limit.volume_fill.expect("fill").fragments < one.volume_fill.expect("fill").fragments);
}

#[test]
fn the_volumes_overlay_tints_the_shadowed_ground_seen_through_its_volume() {
    let scene = box_on_plane(20.0, BOX, 0.0, sun());
    let camera = above_the_box();
    let plain = volumes(sun());
    let mut shown = plain;
    shown.overlays.volumes = true;
    let (_, without) = render(&scene, &camera, &plain, SIZE.0, SIZE.1);
    let (_, with) = render(&scene, &camera, &shown, SIZE.0, SIZE.1);
    let (mut shadowed, mut tinted, mut sky_changed) = (0, 0, 0);
    for (i, (a, b)) in without.color.pixels().zip(with.color.pixels()).enumerate() {
        let yellower = b[0] > a[0] && b[1] > a[1] && b[2] <= a[2];
        if without.ids[i] == 0 {
            sky_changed += usize::from(a != b);
        } else if without.ids[i] == 1 && without.shadow[i] == 0 {
            // Ground in the box's shadow: the ray to it crosses the volume above the ground.
            shadowed += 1;
            tinted += usize::from(yellower);
        }
    }
    assert!(shadowed > 1_000, "{shadowed}");
    assert!(tinted * 10 >= shadowed * 9, "{tinted} of {shadowed} tinted");
    assert_eq!(sky_changed, 0, "no volume lies in front of the sky here");
}

#[test]
#[allow(
    clippy::float_cmp,
    reason = "a merged interval starts where its first piece does, exactly"
)]
fn the_v_over_r_rule_merges_gaps_whose_vertices_cost_more_than_their_pixels() {
    let (scene, camera) = caster_over_a_platform_edge();
    let spans = |vertex_pixels| {
        let mut settings = FrameSettings {
            method: Method::Bvol,
            ..volumes(scene.sun)
        };
        settings.volumes.clamp = VolumeClamp::Conservative;
        settings.volumes.vertex_pixels = Some(vertex_pixels);
        let (error, _, renderer, _) = against_truth(&scene, &camera, &settings);
        let spans = renderer
            .read_volume_intervals(gpu(), CASTER)
            .expect("read back")
            .expect("a caster's volume");
        (error, spans)
    };
    // The platform and the ground under the caster, 8 m apart along the light.
    let (split_error, split) = spans(0);
    assert_eq!(split.len(), 2, "{split:?}");
    // A vertex worth a million pixels: no gap here is worth a new interval.
    let (merged_error, merged) = spans(1_000_000);
    assert_eq!(merged.len(), 1, "{merged:?}");
    assert_eq!(merged[0][0], split[0][0]);
    assert!(
        (merged[0][1] - split[1][1]).abs() < 1e-4,
        "{merged:?} {split:?}"
    );
    assert_eq!(merged_error, split_error, "merging changes no pixel");
}

#[test]
fn a_diagonal_struts_volume_is_culled_where_only_its_world_box_covers_receivers() {
    // A strut 14 m long across the diagonal, over two slabs in the other corners of its
    // world box: the sun, nearly overhead, casts its shadow on nothing visible between them.
    // Its mesh's own box, turned with it, is a band 0.2 m wide that misses both slabs, so
    // culling drops its volume (the world box would keep it); a cube over one slab keeps its.
    // A slab's own top faces the light and its mesh is convex, so it is not in its own
    // shadow: the bare slab's volume is dropped too.
    let sun = Sun::from_azimuth_elevation_deg(30.0, 85.0);
    let slab = box_mesh("slab", Vec3::new(1.0, 0.2, 1.0));
    let strut = box_mesh("strut", Vec3::new(7.0, 0.1, 0.1));
    let cube = box_mesh("cube", Vec3::splat(0.4));
    let mut instances: Vec<Instance> = [(4.0, -4.0), (-4.0, 4.0)]
        .iter()
        .map(|&(x, z)| {
            Instance::new(
                "slab",
                0,
                &slab,
                Mat4::from_translation(Vec3::new(x, -0.2, z)),
            )
        })
        .collect();
    instances.push(Instance::new(
        "strut",
        1,
        &strut,
        Mat4::from_translation(Vec3::new(0.0, 3.0, 0.0))
            * Mat4::from_rotation_y(-std::f32::consts::FRAC_PI_4),
    ));
    instances.push(Instance::new(
        "cube",
        2,
        &cube,
        Mat4::from_translation(Vec3::new(4.0, 2.0, -4.0)),
    ));
    // Only the slabs receive: the strut's own top would keep its volume.
    for caster in &mut instances[2..] {
        caster.receives_shadow = false;
    }
    // Out of view and casting nothing, they widen the scene: the strut's box then spans
    // fewer cells of the receiver grid than a caster may test (a larger one is kept whole),
    // and the slabs lie off the grid's border cells (which also hold what lies beyond).
    for at in [-60.0, 60.0] {
        let mut far = Instance::new(
            "far slab",
            0,
            &slab,
            Mat4::from_translation(Vec3::new(at, -0.2, at)),
        );
        far.casts_shadow = false;
        instances.push(far);
    }
    let strut_box = instances[2].aabb_in_world;
    for slab in &instances[..2] {
        let b = slab.aabb_in_world;
        assert!(
            b.min.x >= strut_box.min.x - 0.1 && b.max.x <= strut_box.max.x + 0.1,
            "the slabs lie under the strut's world box"
        );
    }
    let scene = Scene::new(
        "test:diagonal-strut",
        vec![slab, strut, cube],
        instances,
        sun,
    );
    let camera = Camera::look_at(
        Vec3::new(0.0, 30.0, 0.5),
        Vec3::ZERO,
        40f32.to_radians(),
        0.1,
        200.0,
    );
    // The sun, or a lamp high over the strut (its box seen within 45 degrees).
    let lamp = PointShadow::omni(Vec3::new(0.3, 25.0, 0.2), 5_000.0);
    for point_light in [None, Some(lamp)] {
        let frame = |method, clamp| {
            let mut settings = FrameSettings {
                method,
                point_light,
                ..volumes(sun)
            };
            settings.volumes.clamp = clamp;
            let (error, _, renderer, report) = against_truth(&scene, &camera, &settings);
            let culled: Vec<bool> = (0..4)
                .map(|i| {
                    renderer
                        .read_volume_intervals(gpu(), i)
                        .expect("read back")
                        .is_some_and(|spans| spans.is_empty())
                })
                .collect();
            (report.counts.casters_rendered, error, culled)
        };
        let (all, all_error, _) = frame(Method::None, VolumeClamp::None);
        assert_eq!(all, 4, "none draws every volume");
        assert!(all_error.visible_px > 500, "{all_error:?}");
        for clamp in [
            VolumeClamp::None,
            VolumeClamp::Continuous,
            VolumeClamp::Conservative,
        ] {
            let (kept, error, culled) = frame(Method::Bvol, clamp);
            let light = if point_light.is_some() { "lamp" } else { "sun" };
            // Instances: the slab under the cube, the bare slab, the strut, the cube. The
            // slab under the cube shadows nothing in view either: the points in its box are
            // its own top, lit, its sides facing away from the light, dark whatever shadows
            // them, and the cube's foot, whose rays run up away from it.
            assert_eq!(
                culled,
                [true, true, true, false],
                "{light}, {clamp:?}: only the cube's volume is kept"
            );
            assert_eq!(kept, 1, "{culled:?}");
            assert_eq!(
                error, all_error,
                "{light}, {clamp:?}: no visible pixel changes"
            );
        }
    }
}

/// One frame of CC volumes: the light at the view's exact points, every instance's
/// intervals (`None` where it casts none) and the report.
struct Clamped {
    light: Vec<f32>,
    intervals: Vec<Option<Vec<[f32; 2]>>>,
    report: FrameReport,
}

/// The cull's budget (`VolumeSettings`): loop iterations per lane of a caster, points
/// tested one by one per cell, lanes per caster; `None` for the adapter's.
#[derive(Clone, Copy, Default)]
struct Budget {
    cull_steps: Option<u32>,
    cell_points: Option<u32>,
    cull_lanes: Option<u32>,
}

/// A budget of one loop iteration: every caster goes to workgroups of its own.
const ONE_STEP: Budget = Budget {
    cull_steps: Some(1),
    cell_points: None,
    cull_lanes: None,
};

/// One frame of CC volumes (`bvol`) clamped by `clamp` within the cull's `budget`.
fn clamped_with_budget(
    scene: &Scene,
    camera: &Camera,
    clamp: VolumeClamp,
    budget: Budget,
) -> Clamped {
    let mut truth = TruthCache::default();
    let exact = truth.exact(scene, camera, SIZE, scene.sun.direction_to_sun);
    let mut settings = FrameSettings {
        method: Method::Bvol,
        ..volumes(scene.sun)
    };
    settings.volumes.clamp = clamp;
    settings.volumes.vertex_pixels = Some(0);
    settings.volumes.cull_steps = budget.cull_steps;
    settings.volumes.cell_points = budget.cell_points;
    settings.volumes.cull_lanes = budget.cull_lanes;
    settings.overlays.fill = true;
    let (_, _, renderer, report) = against_truth(scene, camera, &settings);
    let light = renderer.light_at(gpu(), &exact.points).expect("read back");
    let intervals = (0..scene.instances.len() as u32)
        .map(|i| renderer.read_volume_intervals(gpu(), i).expect("read back"))
        .collect();
    Clamped {
        light,
        intervals,
        report,
    }
}

#[test]
fn the_culls_lanes_and_big_casters_workgroups_give_the_same_volumes() {
    // The cull's workgroup culls a caster with lanes that share its rows, each row's cells
    // and each cell's points (`volumes/find.wgsl` `cull_casters`, `grid.wgsl`
    // `gather_footprint`); one whose receivers would take a lane past its budget of loop
    // iterations is gathered by workgroups of its own, which share them likewise
    // (`volumes/big_casters.wgsl`). However many lanes share a caster, and with a budget of
    // one iteration, which sends every caster to those workgroups, nothing may change: the
    // same intervals to the bit, the same light at every point, the same fill. Over the
    // platform's edge the casters span more cells than lanes; the small cubes seen from
    // close span a few dozen cells of about 50 points each, which the lanes left over share.
    for (scene, camera) in [caster_over_a_platform_edge(), small_cubes_seen_from_close()] {
        lanes_and_workgroups_give_the_same_volumes(&scene, &camera);
    }
}

/// A ground and two cubes of 40 cm, one 2 m above it, seen from 3 m: each receiver grid
/// cell (12 cm) under its shadow holds about 50 visible points.
fn small_cubes_seen_from_close() -> (Scene, Camera) {
    let cube = box_mesh("cube", Vec3::splat(0.2));
    let scene = scene_of(
        "test:small-cubes",
        Sun::from_azimuth_elevation_deg(0.0, 80.0),
        vec![
            (
                box_mesh("ground", Vec3::new(30.0, 0.5, 30.0)),
                Vec3::new(0.0, -0.5, 0.0),
            ),
            (cube.clone(), Vec3::new(0.6, 0.2, -0.8)),
            (cube, Vec3::new(0.0, 2.0, 0.0)),
        ],
    );
    let camera = Camera::look_at(
        Vec3::new(0.0, 1.5, 2.6),
        Vec3::new(0.0, 0.0, -0.3),
        60f32.to_radians(),
        0.1,
        200.0,
    );
    (scene, camera)
}

fn lanes_and_workgroups_give_the_same_volumes(scene: &Scene, camera: &Camera) {
    for clamp in [VolumeClamp::Continuous, VolumeClamp::Conservative] {
        let Clamped {
            light,
            intervals,
            report,
        } = clamped_with_budget(scene, camera, clamp, Budget::default());
        let passes = report.volume_passes.expect("counted");
        assert_eq!(passes.whole_past_budget, 0, "{clamp:?}: {passes:?}");
        assert!(
            passes.big_casters < 3,
            "{clamp:?}: the caster is small: {passes:?}"
        );
        let Clamped {
            light: split_light,
            intervals: split_intervals,
            report: split_report,
        } = clamped_with_budget(scene, camera, clamp, ONE_STEP);
        let split = split_report.volume_passes.expect("counted");
        assert_eq!(
            (split.big_casters, split.whole_past_budget),
            (3, 0),
            "{clamp:?}: {split:?}"
        );
        assert_eq!(split_intervals, intervals, "{clamp:?}");
        assert!(
            intervals[CASTER as usize].is_some(),
            "{clamp:?}: the caster is drawn"
        );
        assert_eq!(differing(&split_light, &light), 0, "{clamp:?}");
        assert_eq!(split_report.volume_fill, report.volume_fill, "{clamp:?}");
        // However many lanes of the cull share a caster (4 on a CPU adapter by default).
        for lanes in [1, 32] {
            let shared = clamped_with_budget(
                scene,
                camera,
                clamp,
                Budget {
                    cull_lanes: Some(lanes),
                    ..Budget::default()
                },
            );
            assert_eq!(shared.intervals, intervals, "{clamp:?}, {lanes} lanes");
            assert_eq!(
                differing(&shared.light, &light),
                0,
                "{clamp:?}, {lanes} lanes"
            );
            assert_eq!(
                shared.report.volume_fill, report.volume_fill,
                "{clamp:?}, {lanes} lanes"
            );
        }
        // No point tested one by one: each cell's depths whole, as discrete clamping's
        // cells give them. Looser, never wrong.
        let Clamped {
            light: cells_light,
            intervals: cells_intervals,
            report: cells_report,
        } = clamped_with_budget(
            scene,
            camera,
            clamp,
            Budget {
                cell_points: Some(0),
                ..Budget::default()
            },
        );
        assert_eq!(differing(&cells_light, &light), 0, "{clamp:?}");
        let fill = |r: &FrameReport| r.volume_fill.expect("fill").fragments;
        assert!(fill(&cells_report) >= fill(&report), "{clamp:?}");
        let covers = |outer: &[[f32; 2]], inner: &[[f32; 2]]| {
            inner
                .iter()
                .all(|i| outer.iter().any(|o| o[0] <= i[0] && o[1] >= i[1]))
        };
        let (Some(cells), Some(points)) = (
            &cells_intervals[CASTER as usize],
            &intervals[CASTER as usize],
        ) else {
            panic!("{clamp:?}: the caster is drawn");
        };
        assert!(
            covers(cells, points),
            "{clamp:?}: {cells:?} against {points:?}"
        );
    }
}

#[test]
fn casters_past_every_budget_keep_their_whole_volume_and_are_counted() {
    // 70 crates on a ground and a budget of one loop iteration: every caster is left to
    // workgroups, which a CPU adapter gives 64 casters a frame (`volumes/frame.rs`
    // `StepBudget`); the other 7 keep their whole volumes, which the report counts and
    // notes, and no point's light changes.
    let ground = box_mesh("ground", Vec3::new(40.0, 0.5, 40.0));
    let crate_mesh = box_mesh("crate", Vec3::new(0.5, 0.5, 0.5));
    let mut parts = vec![(ground, Vec3::new(0.0, -0.5, 0.0))];
    for k in 0..70 {
        let at = Vec3::new(
            (k % 10) as f32 * 3.0 - 14.0,
            0.5 + (k / 10) as f32,
            (k / 10) as f32 * 3.0 - 10.0,
        );
        parts.push((crate_mesh.clone(), at));
    }
    let scene = scene_of("test:crates", sun(), parts);
    let camera = Camera::look_at(
        Vec3::new(0.0, 30.0, 30.0),
        Vec3::ZERO,
        60f32.to_radians(),
        0.1,
        200.0,
    );
    let clamp = VolumeClamp::Continuous;
    let Clamped { light, report, .. } =
        clamped_with_budget(&scene, &camera, clamp, Budget::default());
    assert_eq!(report.volume_passes.expect("counted").whole_past_budget, 0);
    let Clamped {
        light: starved,
        report: starved_report,
        ..
    } = clamped_with_budget(&scene, &camera, clamp, ONE_STEP);
    let passes = starved_report.volume_passes.expect("counted");
    assert_eq!(
        (passes.big_casters, passes.whole_past_budget),
        (64, 7),
        "{passes:?}"
    );
    assert!(
        starved_report
            .notes
            .iter()
            .any(|n| n.contains("7 casters kept their whole volume")),
        "{:?}",
        starved_report.notes
    );
    assert_eq!(differing(&starved, &light), 0);
}
