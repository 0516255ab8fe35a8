//! Flicker: the pixels whose shadow changes when only the camera moves 1 cm or turns 0.1
//! degrees, read at the first view's surface points. Stabilised cascades (a texel-snapped
//! sphere per slice, over splits that do not follow the camera's turns) give none; the tight
//! fit follows the camera and does.

use glam::{Mat4, Vec3};
use render_core::cascades::{CascadeFit, CascadeSelection, CascadeSettings};
use render_core::frame::{
    Flicker, FrameInput, FrameRenderer, FrameSettings, Method, SceneGpu, ShadowSetup, moved, turned,
};
use render_core::geom::Camera;
use render_core::scene::{Instance, Scene, Sun, load_builtin};
use render_core::truth::{SHADOWED_BELOW, SurfacePoint, TruthCache};
use shadowlab_tests::{box_mesh, city_small_street_camera, gpu};

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

/// A ground and 400 specks of 12 cm floating over it: their shadows are a few texels each,
/// some narrower than the ground a pixel spans (about 0.15 m here).
fn specks() -> (Scene, Camera) {
    let ground = box_mesh("ground", Vec3::new(20.0, 0.25, 20.0));
    let speck = box_mesh("speck", Vec3::splat(0.06));
    let mut instances = vec![Instance::new(
        "ground",
        0,
        &ground,
        Mat4::from_translation(Vec3::new(0.0, -0.25, 0.0)),
    )];
    // A fixed scatter (a Weyl sequence), so that every run tests the same specks.
    for i in 0..400u32 {
        let (u, v, w) = (
            (f64::from(i) * 0.618_034).fract() as f32,
            (f64::from(i) * 0.754_878).fract() as f32,
            (f64::from(i) * 0.569_840).fract() as f32,
        );
        let at = Vec3::new(u * 16.0 - 8.0, 0.5 + w, v * 16.0 - 8.0);
        let mut inst = Instance::new(format!("speck {i}"), 1, &speck, Mat4::from_translation(at));
        inst.receives_shadow = false;
        instances.push(inst);
    }
    let sun = Sun::from_direction(Vec3::new(0.4, 1.0, 0.3));
    let scene = Scene::new("test:specks", vec![ground, speck], instances, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 14.0, -14.0),
        Vec3::ZERO,
        60f32.to_radians(),
        0.1,
        40.0,
    );
    (scene, camera)
}

/// The shadow `method` gives at `points`, read with the maps of a frame of `camera`.
fn light_at_points(
    (scene, camera): (&Scene, &Camera),
    method: Method,
    settings: &FrameSettings,
    points: &[SurfacePoint],
) -> Vec<f32> {
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, scene);
    let mut renderer = FrameRenderer::new(ctx);
    let settings = FrameSettings {
        method,
        ..*settings
    };
    let input = FrameInput {
        camera,
        width: 320,
        height: 200,
        settings: &settings,
    };
    // Two frames, so FRAG's first phase has last frame's light-visible receivers.
    for _ in 0..2 {
        renderer
            .render_and_wait(ctx, scene, &scene_gpu, &input)
            .expect("frame");
    }
    renderer.light_at(ctx, points).expect("light at points")
}

#[test]
fn frags_mask_shadows_the_points_between_its_pixel_centres_as_drawing_every_caster_does() {
    // The view's points at twice its resolution lie between its pixel centres, where a mask
    // of the pixel centres' own taps leaves out a speck whose shadow no centre reads (26, 7
    // and 47 points of these three setups differed with such a mask). FRAG's
    // mask holds what each pixel's footprint reads, so its maps shadow every such point as
    // the maps of every caster do, in every setup and selection.
    let (scene, camera) = specks();
    let mut truth = TruthCache::default();
    let points = truth
        .exact(&scene, &camera, (640, 400), scene.sun.direction_to_sun)
        .points
        .clone();
    assert!(points.len() > 100_000, "{} points", points.len());
    let single = FrameSettings {
        sun: scene.sun,
        ..FrameSettings::default()
    };
    let cascades = |selection| FrameSettings {
        setup: ShadowSetup::Cascades,
        cascades: CascadeSettings {
            count: 4,
            fit: CascadeFit::Sphere,
            selection,
            ..CascadeSettings::default()
        },
        ..single
    };
    for (name, settings) in [
        ("single", single),
        ("cascades by depth", cascades(CascadeSelection::Depth)),
        ("cascades by map", cascades(CascadeSelection::Map)),
    ] {
        let shadowed = |method| -> Vec<bool> {
            light_at_points((&scene, &camera), method, &settings, &points)
                .iter()
                .map(|l| *l < SHADOWED_BELOW)
                .collect()
        };
        let (all, frag) = (shadowed(Method::None), shadowed(Method::Frag));
        let in_shadow = all.iter().filter(|s| **s).count();
        assert!(in_shadow > 1_000, "{name}: {in_shadow} points in shadow");
        let differ = all.iter().zip(&frag).filter(|(a, f)| a != f).count();
        assert_eq!(
            differ, 0,
            "{name}: points FRAG shadows otherwise, of {in_shadow} in shadow"
        );
    }
}
