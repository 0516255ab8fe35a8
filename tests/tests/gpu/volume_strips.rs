//! Clamped shadow volumes cut to the strips of the picture their receivers lie in (Lloyd's
//! slicing planes through the eye, `volumes/strips_clipped.wgsl`): a pixel centre that lies
//! on a cut sees the cut faces edge-on, and each face's cut edge is rounded on its own, so
//! the piece must count there as wholly absent, never as part of a volume.

use glam::Vec3;
use render_core::frame::{FrameSettings, Method, ShadowSetup};
use render_core::geom::Camera;
use render_core::scene::load_builtin;
use render_core::truth::TruthCache;
use render_core::volumes::VolumeClamp;
use shadowlab_tests::{against_truth, gpu};

const SIZE: (u32, u32) = (640, 360);

/// The corridor's walk, first frame: three pixel centres lie within a millionth of a strip
/// of a cut (8 slices): (375, 216) and (548, 331) on the ground in shadow, (357, 303) on the
/// ground in the light. Before pieces were kept only where whole, conservative clamping lit
/// the first two and shadowed the third.
#[test]
fn pixel_centres_on_a_strips_cut_get_the_light_of_standard_volumes() {
    let scene = load_builtin("corridor", 0).expect("a built-in scene");
    let camera = Camera::look_at(
        Vec3::new(-38.0, 1.7, -1.5),
        Vec3::new(0.0, 1.7, 0.0),
        60f32.to_radians(),
        0.1,
        200.0,
    );
    let volumes = |method, clamp| {
        let mut settings = FrameSettings {
            sun: scene.sun,
            setup: ShadowSetup::Volumes,
            method,
            ..FrameSettings::default()
        };
        settings.volumes.clamp = clamp;
        settings
    };
    let mut truth = TruthCache::default();
    let exact = truth.exact(&scene, &camera, SIZE, scene.sun.direction_to_sun);
    let at = |x: u32, y: u32| {
        exact
            .point_pixels
            .iter()
            .position(|&p| p == y * SIZE.0 + x)
            .expect("a counted pixel")
    };
    let pixels = [(375, 216, true), (548, 331, true), (357, 303, false)];
    let points: Vec<_> = pixels
        .iter()
        .map(|&(x, y, _)| exact.points[at(x, y)])
        .collect();
    for &(x, y, shadowed) in &pixels {
        assert_eq!(
            exact.shadowed(at(x, y)),
            shadowed,
            "the truth at ({x}, {y})"
        );
    }
    let expected: Vec<f32> = pixels
        .iter()
        .map(|&(_, _, shadowed)| if shadowed { 0.0 } else { 1.0 })
        .collect();
    for (method, clamp) in [
        (Method::None, VolumeClamp::None),
        (Method::Bvol, VolumeClamp::Conservative),
        (Method::Bvol, VolumeClamp::Discrete),
    ] {
        let (error, _, renderer, report) =
            against_truth(&scene, &camera, &volumes(method, clamp), SIZE);
        assert!(
            report.notes.iter().all(|n| !n.contains("CLIP_DISTANCES")),
            "the adapter cuts pieces to strips: {:?}",
            report.notes
        );
        let light = renderer.light_at(gpu(), &points).expect("read back");
        assert_eq!(light, expected, "{clamp:?}");
        assert_eq!(error.off_edge_px, Some(0), "{clamp:?}: {error:?}");
    }
}
