//! FRAG's mask from the prepass's surface targets (a compute pass, one thread per pixel) marks
//! what the second pass over the visible geometry marks: on the hard views both draw the same
//! casters, count the same stages and give the same picture, with zero error on every frame.

use glam::Vec3;
use render_core::culling::FragmentMaskSource;
use render_core::frame::{FrameCapture, FrameReport, Method};
use render_core::geom::Camera;
use render_core::scene::{Scene, Sun, load_builtin};
use shadowlab_tests::{biggest_building, box_on_plane, gpu, measured_frames, translated};

/// Three measured frames of FRAG with its mask from `source`: every report, the drawn
/// casters and the capture of the last.
fn frag(
    scene: &Scene,
    camera: &Camera,
    sun: Sun,
    source: FragmentMaskSource,
) -> (Vec<FrameReport>, Vec<u32>, FrameCapture) {
    let (renderer, _, reports) = measured_frames((scene, camera), (Method::Frag, sun), 3, |r| {
        r.set_fragment_mask_source(source);
    });
    let ctx = gpu();
    let capture = FrameCapture::read(ctx, renderer.targets().expect("targets")).expect("readback");
    (reports, renderer.drawn_casters(), capture)
}

fn hard_views() -> Vec<(&'static str, Scene, Camera, Sun)> {
    let city = load_builtin("city-small", 0).expect("city-small");
    let look =
        |eye: Vec3, target: Vec3| Camera::look_at(eye, target, 60f32.to_radians(), 0.1, 2000.0);
    let street = look(Vec3::new(-40.0, 3.5, 2.0), Vec3::new(60.0, 8.0, 2.0));
    let above = look(Vec3::new(-150.0, 120.0, 150.0), Vec3::ZERO);
    let building = biggest_building(&city).expect("a building");
    let inside_at = building.aabb_in_world.center();
    let inside = look(inside_at, inside_at + Vec3::new(30.0, -5.0, 10.0));
    let sun = city.sun;
    let offset = Vec3::new(100_000.0, 0.0, -60_000.0);
    let far_sun = Sun::from_azimuth_elevation_deg(30.0, 50.0);
    let far = translated(&box_on_plane(30.0, Vec3::splat(4.0), 0.0, far_sun), offset);
    let far_camera = Camera::look_at(
        offset + Vec3::new(0.0, 25.0, 30.0),
        offset,
        55f32.to_radians(),
        0.1,
        500.0,
    );
    vec![
        ("street", city.clone(), street, sun),
        ("above", city.clone(), above, sun),
        (
            "grazing",
            city.clone(),
            street,
            Sun::from_azimuth_elevation_deg(20.0, 1.0),
        ),
        ("zenith", city.clone(), above, Sun::from_direction(Vec3::Y)),
        ("inside a building", city, inside, sun),
        ("100 km from the origin", far, far_camera, far_sun),
    ]
}

#[test]
fn the_mask_from_the_surface_equals_the_mask_from_a_camera_pass() {
    for (name, scene, camera, sun) in hard_views() {
        let (surface, drawn_surface, capture_surface) =
            frag(&scene, &camera, sun, FragmentMaskSource::Surface);
        let (pass, drawn_pass, capture_pass) =
            frag(&scene, &camera, sun, FragmentMaskSource::CameraPass);
        for (frame, (s, p)) in surface.iter().zip(&pass).enumerate() {
            for report in [s, p] {
                let e = report.error.expect("measured");
                assert_eq!(
                    (e.missing_shadow_px, e.extra_shadow_px),
                    (0, 0),
                    "{name}, frame {frame}: no error"
                );
            }
            assert_eq!(
                s.stages, p.stages,
                "{name}, frame {frame}: the same stage counts"
            );
        }
        assert_eq!(drawn_surface, drawn_pass, "{name}: the same casters");
        assert!(
            capture_surface.shadow == capture_pass.shadow,
            "{name}: the same shadows"
        );
        assert!(
            !drawn_surface.is_empty() || name == "inside a building",
            "{name}"
        );
    }
}
