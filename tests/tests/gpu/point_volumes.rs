//! Shadow volumes of a point light (`--light point`): a lifted box on a plane, lit from beside
//! and above by a light inside the view, against the exact shadow and known points; the
//! camera inside the box's shadow (where z-pass would fail); CC volumes against standard
//! ones; and shadow maps, which cannot cast a point light's shadows, saying so.

use glam::Vec3;
use render_core::frame::{FrameReport, FrameSettings, Method, ShadowSetup};
use render_core::geom::Camera;
use render_core::metrics::ShadowError;
use render_core::scene::{PointShadow, Scene, ShadowLight, Sun, load_builtin};
use render_core::truth::{ExactShadow, SurfacePoint, TruthCache};
use render_core::volumes::{VolumeClamp, VolumePassChoice};
use shadowlab_tests::{
    LIGHT_BESIDE_THE_BOX, against_truth, box_on_plane, gpu, ground_point, overlooking_the_box,
    render,
};

const SIZE: (u32, u32) = (320, 240);
fn scene() -> Scene {
    box_on_plane(20.0, Vec3::new(2.0, 3.0, 1.5), 1.0, Sun::default())
}

fn point_volumes(method: Method, clamp: VolumeClamp, pass: VolumePassChoice) -> FrameSettings {
    let mut settings = FrameSettings {
        setup: ShadowSetup::Volumes,
        method,
        point_light: Some(PointShadow::omni(LIGHT_BESIDE_THE_BOX, 2.0e6)),
        ..FrameSettings::default()
    };
    settings.volumes.clamp = clamp;
    settings.volumes.pass = pass;
    settings
}

fn standard() -> FrameSettings {
    point_volumes(Method::None, VolumeClamp::None, VolumePassChoice::Auto)
}

/// One frame: its error against the exact shadow of the point light, the light at `points`
/// and the report.
fn frame(
    camera: &Camera,
    settings: &FrameSettings,
    points: &[SurfacePoint],
) -> (ShadowError, Vec<f32>, FrameReport) {
    let (error, _, renderer, report) = against_truth(&scene(), camera, settings, SIZE);
    let light = renderer.light_at(gpu(), points).expect("read back");
    (error, light, report)
}

/// The exact points of a view, and how many are shadowed.
fn exact_points(camera: &Camera) -> (Vec<SurfacePoint>, usize) {
    let mut truth = TruthCache::default();
    let exact = truth.exact(&scene(), camera, SIZE, standard().shadow_light());
    let shadowed = (0..exact.points.len())
        .filter(|&i| exact.shadowed(i))
        .count();
    (exact.points.clone(), shadowed)
}

/// At most two in ten thousand visible pixels off the exact shadow, every one on an edge.
fn assert_exact_but_edges(error: &ShadowError) {
    let wrong = error.missing_shadow_px + error.extra_shadow_px;
    assert!(wrong * 10_000 <= error.visible_px * 2, "{error:?}");
    assert_eq!(
        error.off_edge_px,
        Some(0),
        "every wrong pixel is on an edge"
    );
}

#[allow(clippy::float_cmp, reason = "hard shadows are exactly 0 or 1")]
fn differing(a: &[f32], b: &[f32]) -> usize {
    a.iter().zip(b).filter(|(a, b)| a != b).count()
}

#[test]
fn a_point_light_in_the_view_casts_the_boxs_exact_shadow() {
    let camera = overlooking_the_box();
    let (points, shadowed) = exact_points(&camera);
    assert!(shadowed > 500, "{shadowed} shadowed points");
    // The ground where the ray from the light through the box's centre lands; under the
    // light, and far out on its side.
    let centre = Vec3::new(0.0, 2.5, 0.0);
    let t = LIGHT_BESIDE_THE_BOX.y / (LIGHT_BESIDE_THE_BOX.y - centre.y);
    let behind = LIGHT_BESIDE_THE_BOX + (centre - LIGHT_BESIDE_THE_BOX) * t;
    let known = [
        ground_point(behind.x, behind.z),
        ground_point(LIGHT_BESIDE_THE_BOX.x, LIGHT_BESIDE_THE_BOX.z),
        ground_point(8.0, 6.0),
    ];
    let (error, light, report) = frame(&camera, &standard(), &known);
    assert_eq!(report.shadow_failure, None);
    assert_eq!(
        light,
        [0.0, 1.0, 1.0],
        "behind the box, under the light, far out"
    );
    assert_exact_but_edges(&error);
    let (_, standard_light, _) = frame(&camera, &standard(), &points);
    for clamp in [VolumeClamp::Continuous, VolumeClamp::Conservative] {
        let settings = point_volumes(Method::Bvol, clamp, VolumePassChoice::Auto);
        let (cc_error, cc_light, cc) = frame(&camera, &settings, &points);
        assert_eq!(differing(&cc_light, &standard_light), 0, "{clamp:?}");
        assert_eq!(cc_error, error, "{clamp:?}");
        assert_eq!(
            cc.counts.casters_rendered, 2,
            "both volumes reach receivers"
        );
    }
}

#[test]
fn z_pass_draws_no_cap_of_a_closed_caster_or_at_infinity() {
    // The light lights the box's +x and top faces (four triangles inside a silhouette of six
    // edges: it lies between the box's z faces) and the ground box's top (two triangles,
    // four edges); both are closed, and standard volumes reach infinity.
    let triangles = |pass| {
        let settings = point_volumes(Method::None, VolumeClamp::None, pass);
        let (report, _) = render(&scene(), &overlooking_the_box(), &settings, SIZE.0, SIZE.1);
        let passes = report.volume_passes.expect("counted");
        (
            passes.quad_triangles,
            passes.cap_triangles,
            report.counts.triangles_shadow,
        )
    };
    assert_eq!(
        triangles(VolumePassChoice::ZPass),
        (20, 0, 20),
        "ten quads and no caps: a closed caster's own caps and caps at infinity count nowhere"
    );
    assert_eq!(
        triangles(VolumePassChoice::ZFail),
        (20, 12, 32),
        "ten quads, each lit triangle where the volume starts and at infinity"
    );
}

#[test]
fn a_fan_over_the_silhouette_closes_a_box_lit_on_three_faces() {
    // Above the box's +x, +y, +z corner, the light lights three of its faces (six triangles
    // inside a silhouette of six edges) and the ground box's top (two triangles, four edges).
    let mut settings = point_volumes(Method::None, VolumeClamp::None, VolumePassChoice::ZFail);
    settings.point_light = Some(PointShadow::omni(Vec3::new(4.0, 7.0, 3.0), 2.0e6));
    let (error, _, _, report) = against_truth(&scene(), &overlooking_the_box(), &settings, SIZE);
    let passes = report.volume_passes.expect("counted");
    assert_eq!(
        (passes.quad_triangles, passes.cap_triangles),
        (20, 14),
        "ten quads, the eight lit triangles where the volumes start, and \
         at infinity fans of four and two triangles (the lit triangles would be six and two)"
    );
    assert_exact_but_edges(&error);
}

#[test]
fn the_camera_in_a_point_lights_shadow_counts_the_box_z_fail() {
    // The ray from the light to the eye crosses the box: the eye is in its shadow.
    let camera = Camera::look_at(
        Vec3::new(-4.0, 0.8, -0.3),
        Vec3::new(-9.0, 0.0, -4.0),
        60f32.to_radians(),
        0.1,
        200.0,
    );
    let (points, shadowed) = exact_points(&camera);
    assert!(
        shadowed > 1_000,
        "{shadowed}: the camera looks over shadowed ground"
    );
    let run = |pass| {
        frame(
            &camera,
            &point_volumes(Method::None, VolumeClamp::None, pass),
            &points,
        )
    };
    let (error, auto, report) = run(VolumePassChoice::Auto);
    let (_, z_fail, _) = run(VolumePassChoice::ZFail);
    let (_, z_pass, _) = run(VolumePassChoice::ZPass);
    let passes = report.volume_passes.expect("counted");
    assert!(
        passes.z_fail >= 1,
        "{passes:?}: the box's volume holds the eye"
    );
    assert_eq!(differing(&auto, &z_fail), 0);
    assert!(
        differing(&z_pass, &z_fail) > 1_000,
        "z-pass everywhere misses the shadow the eye stands in"
    );
    let wrong = error.missing_shadow_px + error.extra_shadow_px;
    assert!(wrong * 10_000 <= error.visible_px * 2, "{error:?}");
}

#[test]
fn shadow_maps_say_they_cannot_cast_a_point_lights_shadows() {
    let camera = overlooking_the_box();
    let settings = FrameSettings {
        setup: ShadowSetup::Single,
        ..standard()
    };
    let (_, light, report) = frame(&camera, &settings, &[ground_point(-2.1, -0.4)]);
    let failure = report.shadow_failure.expect("a failure is reported");
    assert!(failure.contains("--shadow volumes"), "{failure}");
    assert_eq!(light, [1.0], "no shadows drawn rather than the sun's");
}

/// Lloyd's corridor (`builtin:corridor`), down its length from the west end towards its
/// lamp over the trusses: every strut's volume runs down through empty air. Standard volumes
/// differ from the exact shadow only on its edges; CC volumes, continuous or over slices of
/// the view, change no pixel of the picture and draw far less, and exactly clamped ones (the
/// limit) less still, parting from standard ones only on edges.
const CORRIDOR_SIZE: (u32, u32) = (320, 180);

/// The corridor from its end at eye height, under its lamp, and the exact shadow there.
fn corridor_under_its_lamp() -> (Scene, Camera, PointShadow, ExactShadow) {
    let scene = load_builtin("corridor", 0).expect("corridor");
    let camera = Camera::look_at(
        Vec3::new(-38.0, 1.7, 1.0),
        Vec3::new(0.0, 3.0, 0.0),
        60f32.to_radians(),
        0.1,
        200.0,
    );
    let lamp = PointShadow::of_scene(&scene, 0).expect("the corridor's lamp");
    let mut truth = TruthCache::default();
    let exact = truth
        .exact(
            &scene,
            &camera,
            CORRIDOR_SIZE,
            ShadowLight::Point(lamp.position),
        )
        .clone();
    (scene, camera, lamp, exact)
}

#[test]
fn the_corridors_lamp_casts_exact_shadows_and_cc_volumes_fill_less() {
    let (scene, camera, lamp, exact) = corridor_under_its_lamp();
    let run = |method, clamp| {
        let mut settings = FrameSettings {
            setup: ShadowSetup::Volumes,
            method,
            point_light: Some(lamp),
            ..FrameSettings::default()
        };
        settings.volumes.clamp = clamp;
        settings.volumes.slices = 16;
        settings.overlays.fill = true;
        let (error, shadowed, renderer, report) =
            against_truth(&scene, &camera, &settings, CORRIDOR_SIZE);
        let light = renderer.light_at(gpu(), &exact.points).expect("read back");
        let fill = report.volume_fill.expect("fill counted").fragments;
        settings.overlays.fill = false;
        let (_, capture) = render(&scene, &camera, &settings, CORRIDOR_SIZE.0, CORRIDOR_SIZE.1);
        (error, shadowed, light, fill, capture.color)
    };
    let (error, shadowed, standard, standard_fill, picture) = run(Method::None, VolumeClamp::None);
    let on_edge = &exact.on_edge;
    assert!(
        shadowed > 5_000,
        "the struts' shadows are in view: {shadowed}"
    );
    assert_eq!(error.off_edge_px, Some(0), "{error:?}");
    let mut fills = Vec::new();
    for clamp in [
        VolumeClamp::Continuous,
        VolumeClamp::Conservative,
        VolumeClamp::Exact,
    ] {
        let (cc_error, _, cc, cc_fill, cc_picture) = run(Method::Bvol, clamp);
        fills.push(cc_fill);
        // Where the picture shows a surface turned from the lamp (dark whatever shadows it),
        // a clamped volume need not reach: the light read there for an exact point seen
        // past that surface's outline may part from standard volumes', and only there.
        let parted: Vec<usize> = (0..cc.len())
            .filter(|&i| differing(&cc[i..=i], &standard[i..=i]) > 0)
            .collect();
        if clamp == VolumeClamp::Exact {
            // Rays through pixel centres find the casters: where a volume covers a centre only
            // by a rounding of its rasterised edge, the two may part, and only on edges.
            assert!(parted.iter().all(|&i| on_edge[i]), "{parted:?}");
            assert!(parted.len() * 10_000 <= cc.len(), "{parted:?}");
            assert_eq!(cc_error.off_edge_px, Some(0), "{cc_error:?}");
        } else {
            // Conservative clamping clips each interval to its strips of the picture: the
            // clipped faces are rasterised from new vertices, so a pixel whose centre lies
            // on a volume's outline may fall the other way: a pixel the truth counts on an
            // edge, or one it does not count (its surface turned from the lamp at the
            // pixel's centre: it grazes the light).
            let changed = changed_pixels(picture.as_raw(), cc_picture.as_raw());
            let counted_off_edges: std::collections::HashSet<u32> = exact
                .point_pixels
                .iter()
                .zip(on_edge)
                .filter_map(|(&p, &edge)| (!edge).then_some(p))
                .collect();
            assert!(
                changed.iter().all(|p| !counted_off_edges.contains(p)),
                "{clamp:?}: {changed:?}"
            );
            assert!(changed.len() * 10_000 <= cc.len(), "{clamp:?}: {changed:?}");
            assert!(parted.iter().all(|&i| on_edge[i]), "{clamp:?}: {parted:?}");
            assert!(parted.len() * 10_000 <= cc.len(), "{clamp:?}: {parted:?}");
            assert_eq!(cc_error.off_edge_px, Some(0), "{clamp:?}: {cc_error:?}");
        }
        assert!(
            cc_fill * 3 < standard_fill * 2,
            "{clamp:?}: CC fill {cc_fill} against {standard_fill}"
        );
    }
    // Exact clamping is the limit of clamping in depth (Lloyd's CCe): continuous clamping
    // fills more. Conservative clamping also clips each interval to its strips of the
    // picture, which exact clamping's intervals are not: 1.04 M fragments against 1.28 M
    // when this was written.
    assert!(fills[2] < fills[0] && fills[1] < fills[2], "{fills:?}");
}

/// The pixels (row by row from the top) where two RGBA pictures differ.
fn changed_pixels(a: &[u8], b: &[u8]) -> Vec<u32> {
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .enumerate()
        .filter(|(_, (x, y))| x != y)
        .map(|(i, _)| i as u32)
        .collect()
}

#[test]
fn intervals_clipped_to_their_strips_fill_less_and_change_no_light_off_the_edges() {
    // Conservative clamping over 16 slices draws each interval only across the strips of the
    // picture its receivers lie in (Lloyd's slicing planes through the eye, clip distances):
    // the same intervals as drawn across the whole picture, less fill, and the same light at
    // every exact point but where a volume's outline crosses its pixel.
    let (scene, camera, lamp, exact) = corridor_under_its_lamp();
    let run = |strips| {
        let mut settings = FrameSettings {
            setup: ShadowSetup::Volumes,
            method: Method::Bvol,
            point_light: Some(lamp),
            ..FrameSettings::default()
        };
        settings.volumes.clamp = VolumeClamp::Conservative;
        settings.volumes.slices = 16;
        settings.volumes.strips = strips;
        settings.volumes.vertex_pixels = Some(0);
        settings.overlays.fill = true;
        let (_, _, renderer, report) = against_truth(&scene, &camera, &settings, CORRIDOR_SIZE);
        let light = renderer.light_at(gpu(), &exact.points).expect("read back");
        (light, report)
    };
    let (clipped, clipped_report) = run(true);
    let (whole, whole_report) = run(false);
    assert!(
        !clipped_report
            .notes
            .iter()
            .any(|n| n.contains("CLIP_DISTANCES")),
        "lavapipe clips: {:?}",
        clipped_report.notes
    );
    let passes = |r: &FrameReport| r.volume_passes.expect("counted");
    assert_eq!(passes(&clipped_report), passes(&whole_report));
    let fill = |r: &FrameReport| r.volume_fill.expect("fill counted").fragments;
    // 1.04 M fragments against 1.36 M when this test was written.
    assert!(
        fill(&clipped_report) * 10 < fill(&whole_report) * 9,
        "{} against {}",
        fill(&clipped_report),
        fill(&whole_report)
    );
    let parted: Vec<usize> = (0..clipped.len())
        .filter(|&i| differing(&clipped[i..=i], &whole[i..=i]) > 0)
        .collect();
    assert!(parted.iter().all(|&i| exact.on_edge[i]), "{parted:?}");
    assert!(parted.len() * 10_000 <= clipped.len(), "{parted:?}");
}
