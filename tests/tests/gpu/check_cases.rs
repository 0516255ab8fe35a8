//! `shadowlab check`'s hard cases on the house of `assets/scenes/house.gltf` (a floor, four
//! walls with a door gap and a roof, one mesh, cut into chunks as any glTF is), at the sizes
//! where they once failed: shadow volumes against the exact shadow with the camera inside the
//! house, under a sun at the zenith, and 100 km from the origin.

use std::path::PathBuf;

use glam::Vec3;
use render_core::frame::{FrameSettings, Method, ShadowSetup};
use render_core::geom::Camera;
use render_core::metrics::ShadowError;
use render_core::scene::{ChunkSettings, Scene, Sun, import_gltf};
use render_core::shadow_view::VolumeClamp;
use shadowlab_tests::{against_truth, gpu, translated};

/// The house as `shadowlab check assets/scenes/house.gltf --sun 0.5,0.8,0.3` loads it.
fn house(sun: Sun) -> Scene {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/house.gltf");
    let mut scene = import_gltf(&path, &ChunkSettings::default()).expect("the house loads");
    scene.sun = sun;
    scene
}

/// `check`'s own view of a glTF scene, moved by `offset`.
fn outside(offset: Vec3) -> Camera {
    Camera::look_at(
        offset + Vec3::new(-15.018_559, 16.217_012, 15.018_559),
        offset + Vec3::new(-14.425_197, 15.673_098, 14.425_197),
        60f32.to_radians(),
        0.01,
        51.3,
    )
}

fn volumes(clamp: VolumeClamp, method: Method, sun: Sun) -> FrameSettings {
    let mut settings = FrameSettings {
        sun,
        setup: ShadowSetup::Volumes,
        method,
        ..FrameSettings::default()
    };
    settings.volumes.clamp = clamp;
    settings
}

/// Standard volumes and conservative CC volumes (as `check` runs them).
fn both(sun: Sun) -> [(&'static str, FrameSettings); 2] {
    [
        ("standard", volumes(VolumeClamp::None, Method::None, sun)),
        (
            "conservative CC",
            volumes(VolumeClamp::Conservative, Method::Vfc, sun),
        ),
    ]
}

/// `check`'s bound on volumes: at most a ten-thousandth of the visible pixels off the exact
/// shadow's edges.
fn assert_within_check(error: &ShadowError, case: &str) {
    let off = error.off_edge_px.expect("counted");
    assert!(
        f64::from(off) <= 1e-4 * f64::from(error.visible_px),
        "{case}: {error:?}"
    );
}

#[test]
fn the_roofs_volume_kept_whole_past_the_culls_budget_shadows_the_house_inside() {
    // The camera in the house, under the roof's shadow: at 1280x720 the roof's chunks hold
    // so many receiver points that gathering them runs past every budget on a CPU adapter,
    // and their volumes are kept whole, which must cover the whole picture, not only the
    // strips of the view that the gather reached before it gave up.
    let sun = Sun::from_direction(Vec3::new(0.5, 0.8, 0.3));
    let scene = house(sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 2.6, 0.0),
        Vec3::new(0.593_361_9, 2.056_085, -0.593_361_9),
        60f32.to_radians(),
        0.01,
        51.3,
    );
    let settings = volumes(VolumeClamp::Conservative, Method::Vfc, sun);
    let (error, shadowed, _, report) = against_truth(&scene, &camera, &settings, (1280, 720));
    let passes = report.volume_passes.expect("volumes report their passes");
    if gpu().adapter_description().contains("Cpu") {
        assert!(passes.whole_past_budget > 0, "{passes:?}");
    }
    assert!(
        shadowed > 500_000,
        "the house's inside is in shadow: {shadowed}"
    );
    assert_eq!(
        error.missing_shadow_px + error.extra_shadow_px,
        0,
        "{error:?} {passes:?}"
    );
}

#[test]
fn walls_under_a_sun_at_the_zenith_graze_it_and_are_not_counted() {
    // `Sun::from_azimuth_elevation_deg(_, 90)` leans by the rounding of 90 degrees: the walls
    // face it by 4e-8, and a roof's volume runs down along them a fraction of a micrometre
    // away. Such faces receive nothing; the truth does not count them.
    let (azimuth, _) = Sun::from_direction(Vec3::new(0.5, 0.8, 0.3)).azimuth_elevation_deg();
    let sun = Sun::from_azimuth_elevation_deg(azimuth, 90.0);
    let scene = house(sun);
    for (name, settings) in both(sun) {
        let (error, _, _, _) = against_truth(&scene, &outside(Vec3::ZERO), &settings, (640, 360));
        assert_within_check(&error, &format!("{name} volumes, sun at the zenith"));
    }
}

#[test]
fn volumes_hold_100_km_from_the_origin() {
    let sun = Sun::from_direction(Vec3::new(0.5, 0.8, 0.3));
    let far = Vec3::new(100_000.0, 0.0, 100_000.0);
    let scene = translated(&house(sun), far);
    for (name, settings) in both(sun) {
        let (error, shadowed, _, _) = against_truth(&scene, &outside(far), &settings, (1280, 720));
        assert!(
            shadowed > 2_000,
            "{name}: the house's shadow is in view: {shadowed}"
        );
        assert_within_check(&error, &format!("{name} volumes 100 km out"));
    }
}

#[test]
fn the_camera_inside_a_wall_sees_the_floor_before_it_lit() {
    // `check builtin:robots`'s "inside the largest": the camera inside the hall's south
    // wall looks out through its lit face at the floor before it. The wall's volume is
    // z-fail, its lit face a cap seen from inside; pushed back by twice its depth slope as a
    // cap seen from outside is, it fell behind the floor in a band along the wall's foot,
    // centimetres wide 15 m away.
    let sun = Sun::from_direction(Vec3::new(0.879_386_5, 0.241_921_9, 0.410_064_7));
    let floor = shadowlab_tests::box_mesh("floor", Vec3::new(30.6, 0.05, 20.6));
    let wall = shadowlab_tests::box_mesh("wall", Vec3::new(30.6, 3.5, 0.3));
    let scene = shadowlab_tests::scene_of(
        "test:wall-and-floor",
        sun,
        vec![
            (floor, Vec3::new(0.0, -0.05, 0.0)),
            (wall, Vec3::new(0.0, 3.5, -20.3)),
        ],
    );
    let eye = Vec3::new(0.0, 3.5, -20.3);
    let camera = Camera::look_at(
        eye,
        eye + Vec3::new(0.593_361_6, -0.543_915_5, -0.593_36),
        60f32.to_radians(),
        0.01,
        142.6,
    );
    for (name, settings) in both(sun) {
        let (error, shadowed, _, _) = against_truth(&scene, &camera, &settings, (1280, 720));
        assert!(
            shadowed > 10_000,
            "{name}: the floor under the wall is in view"
        );
        // Before the fix: 1,058 wrong pixels, 294 off the edges.
        assert!(
            error.missing_shadow_px + error.extra_shadow_px < 10 && error.off_edge_px == Some(0),
            "{name} volumes: {error:?}"
        );
    }
}
