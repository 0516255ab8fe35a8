//! The undersampling measure: octaves of shadow-map texel footprint over pixel footprint at
//! every visible receiver pixel, against the same formula on the CPU, and cascades against
//! one map at street level.

use glam::Vec3;
use render_core::frame::{FrameSettings, ShadowSetup};
use render_core::geom::Camera;
use render_core::metrics::{UNDERSAMPLING_BINS, Undersampling};
use render_core::scene::{Sun, load_builtin};
use shadowlab_tests::{box_on_plane, city_small_street_camera, pixels_of, render};

const GROUND: u32 = 1;

#[test]
fn undersampling_is_the_texel_over_the_pixel_footprint_at_each_pixel() {
    // The sun straight above: a texel's footprint on the flat ground is its square.
    let sun = Sun::from_direction(Vec3::Y);
    let scene = box_on_plane(40.0, Vec3::splat(1.0), 0.0, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 2.5, 0.5),
        Vec3::new(0.0, 0.0, -6.0),
        60f32.to_radians(),
        0.1,
        200.0,
    );
    let mut settings = FrameSettings {
        sun,
        measure: true,
        ..FrameSettings::default()
    };
    settings.shadow.resolution = 512;
    let (width, height) = (480, 320);
    let (report, capture) = render(&scene, &camera, &settings, width, height);
    let measured = report.undersampling.expect("measured");
    let [tx, ty] = report.views[0].texel_size_m;
    let pixel_at_1m = 2.0 * (camera.fov_y_rad * 0.5).tan() / height as f32;
    let mut bins = vec![0u32; UNDERSAMPLING_BINS];
    for (_, p) in pixels_of(&capture, &camera, GROUND) {
        let to_eye = camera.eye - p;
        let distance = to_eye.length();
        let cos_view = (to_eye.y / distance).max(0.02);
        let pixel = distance * pixel_at_1m;
        let octaves = 0.5 * ((tx * ty) / (pixel * pixel / cos_view)).log2();
        let bin = if octaves > 0.0 {
            1 + ((octaves * 4.0) as usize).min(UNDERSAMPLING_BINS - 2)
        } else {
            0
        };
        bins[bin] += 1;
    }
    let expected = Undersampling::from_histogram(&bins).expect("ground pixels");
    assert!(
        expected.median_octaves > 1.0,
        "the case undersamples: {expected:?}"
    );
    // The ground's pixels and the box's top (which the CPU side leaves out) differ a little.
    assert!(
        (measured.median_octaves - expected.median_octaves).abs() <= 0.25
            && (measured.p95_octaves - expected.p95_octaves).abs() <= 0.25,
        "measured {measured:?}, expected {expected:?}"
    );
    assert_eq!(
        report.views[0].undersampling,
        Some(measured),
        "one view: its own is the total"
    );
}

#[test]
fn four_cascades_undersample_the_street_less_than_one_map() {
    let scene = load_builtin("city-small", 0).expect("city-small");
    let camera = city_small_street_camera();
    let single = FrameSettings {
        sun: scene.sun,
        measure: true,
        ..FrameSettings::default()
    };
    let mut cascades = single;
    cascades.setup = ShadowSetup::Cascades;
    cascades.cascades.count = 4;
    let (one, _) = render(&scene, &camera, &single, 512, 320);
    let (four, _) = render(&scene, &camera, &cascades, 512, 320);
    let (one, four) = (
        one.undersampling.expect("single"),
        four.undersampling.expect("cascades"),
    );
    assert!(
        four.p95_octaves < one.p95_octaves && four.median_octaves <= one.median_octaves,
        "single {one:?}, cascades {four:?}"
    );
}
