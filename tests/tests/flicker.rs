//! Flicker: the pixels whose shadow changes when only the camera moves 1 cm or turns 0.1
//! degrees, read at the first view's surface points. Stabilised cascades (a texel-snapped
//! sphere per slice, over splits that do not follow the camera's turns) give none; the tight
//! fit follows the camera and does.

use render_core::cascades::{CascadeFit, CascadeSelection, CascadeSettings};
use render_core::frame::{
    Flicker, FrameInput, FrameRenderer, FrameSettings, Method, SceneGpu, ShadowSetup, moved, turned,
};
use render_core::scene::load_builtin;
use render_core::truth::TruthCache;
use shadowlab_tests::{city_small_street_camera, gpu};

fn flicker_of(fit: CascadeFit, selection: CascadeSelection) -> Flicker {
    let scene = load_builtin("city-small", 0).expect("city-small");
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, &scene);
    let mut renderer = FrameRenderer::new(ctx);
    let settings = FrameSettings {
        sun: scene.sun,
        method: Method::Frag,
        setup: ShadowSetup::Cascades,
        cascades: CascadeSettings {
            count: 4,
            fit,
            selection,
            ..CascadeSettings::default()
        },
        ..FrameSettings::default()
    };
    let camera = city_small_street_camera();
    let input = FrameInput {
        camera: &camera,
        width: 320,
        height: 200,
        settings: &settings,
    };
    let mut truth = TruthCache::default();
    renderer
        .flicker(ctx, (&scene, &scene_gpu), &mut truth, &input)
        .expect("flicker measured")
}

#[test]
fn stabilised_cascades_do_not_flicker_and_tight_ones_do_when_the_camera_turns() {
    for selection in CascadeSelection::ALL {
        let stable = flicker_of(CascadeFit::Sphere, selection);
        assert!(stable.counted_px > 10_000, "{stable:?}");
        assert_eq!(
            (stable.moved_px, stable.turned_px),
            (0, 0),
            "by {selection:?}: {stable:?}"
        );
    }
    let stable = flicker_of(CascadeFit::Sphere, CascadeSelection::Depth);
    let tight = flicker_of(CascadeFit::Tight, CascadeSelection::Depth);
    assert_eq!(tight.counted_px, stable.counted_px, "the same points");
    assert!(
        tight.turned_px > 0,
        "a tight fit follows the turn: {tight:?}"
    );
}

#[test]
fn the_flicker_cameras_move_one_centimetre_and_turn_a_tenth_of_a_degree() {
    let camera = city_small_street_camera();
    let m = moved(&camera);
    assert!(((m.eye - camera.eye).length() - 0.01).abs() < 1e-5);
    assert_eq!(m.forward, camera.forward);
    let t = turned(&camera);
    assert_eq!(t.eye, camera.eye);
    // A yaw about the world's up: the pitch stays, the heading turns 0.1 degrees.
    assert!((t.forward.y - camera.forward.y).abs() < 1e-6);
    let flat = |v: glam::Vec3| glam::Vec3::new(v.x, 0.0, v.z);
    let angle = flat(t.forward)
        .angle_between(flat(camera.forward))
        .to_degrees();
    assert!((angle - 0.1).abs() < 1e-3, "{angle}");
}
