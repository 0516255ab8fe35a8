//! Caster culling per light view (`--shadow lights` with a GPU method, `layered/gpu_culled.rs`):
//! a box in view and a box behind the camera, under a spot light over the first and a point
//! light beside the second. Each method must give the picture `vfc` gives, count no error
//! against the reference maps, and cull the box whose shadows no visible point receives.

use glam::Vec3;
use render_core::cascades::CascadeSelection;
use render_core::culling::CasterOutcome;
use render_core::frame::{
    FrameInput, FrameRenderer, FrameReport, FrameSettings, Method, ShadowSetup,
};
use render_core::geom::Camera;
use render_core::scene::{LightKind, Scene, Sun};
use render_core::scene_gpu::SceneGpu;
use shadowlab_tests::{box_mesh, gpu, punctual_light as light, scene_of};

const SIZE: (u32, u32) = (256, 192);
/// Instances: the ground, the box in view, the box behind the camera.
const SEEN: usize = 1;
const HIDDEN: usize = 2;

/// A 40 m ground, a 2 x 3 x 1.5 m box 1 m above it at the origin, and a 2 m cube on the
/// ground behind the camera; a spot straight above the first, a point light beside the second.
fn scene() -> Scene {
    let mut scene = scene_of(
        "test:lights-culling",
        Sun::default(),
        vec![
            (
                box_mesh("ground", Vec3::new(20.0, 0.5, 20.0)),
                Vec3::new(0.0, -0.5, 0.0),
            ),
            (
                box_mesh("seen", Vec3::new(1.0, 1.5, 0.75)),
                Vec3::new(0.0, 2.5, 0.0),
            ),
            (box_mesh("hidden", Vec3::ONE), Vec3::new(-14.0, 1.0, 17.0)),
        ],
    );
    scene.lights = vec![
        light(
            "above",
            Vec3::new(0.0, 10.0, 0.0),
            LightKind::Spot {
                direction: Vec3::NEG_Y,
                inner_cone_rad: 32f32.to_radians(),
                outer_cone_rad: 40f32.to_radians(),
            },
        ),
        light("behind", Vec3::new(-11.0, 4.0, 14.0), LightKind::Point),
    ];
    scene
}

/// Looking at the first box from (-9, 9, 11): the second is behind the camera, and so is
/// every point of the ground its shadows fall on.
fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(-9.0, 9.0, 11.0),
        Vec3::new(0.0, 1.0, 0.0),
        60f32.to_radians(),
        0.1,
        200.0,
    )
}

/// The third frame of `method` (the GPU methods settle on last frame's light-visible casters):
/// its report, each view's outcome per instance, and the picture's light per pixel.
fn frame(
    scene: &Scene,
    method: Method,
    sun: Option<CascadeSelection>,
) -> (FrameReport, Vec<Vec<CasterOutcome>>, Vec<u8>) {
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, scene);
    let mut renderer = FrameRenderer::new(ctx);
    let mut settings = FrameSettings {
        setup: ShadowSetup::Lights,
        method,
        measure: true,
        ..FrameSettings::default()
    };
    settings.shadow.resolution = 512;
    settings.layered.sun = sun.is_some();
    settings.cascades.count = 2;
    settings.cascades.selection = sun.unwrap_or_default();
    let camera = camera();
    let input = FrameInput {
        camera: &camera,
        width: SIZE.0,
        height: SIZE.1,
        settings: &settings,
    };
    let mut report = None;
    for _ in 0..3 {
        report = Some(
            renderer
                .render_and_wait(ctx, scene, &scene_gpu, &input)
                .expect("frame renders"),
        );
    }
    let capture =
        render_core::frame::FrameCapture::read(ctx, renderer.targets().unwrap()).expect("readback");
    (
        report.expect("three frames"),
        renderer.view_caster_outcomes(),
        capture.shadow,
    )
}

fn rendered_in(outcomes: &[Vec<CasterOutcome>], instance: usize) -> Vec<usize> {
    (0..)
        .zip(outcomes)
        .filter(|(_, o)| o[instance] == CasterOutcome::Rendered)
        .map(|(v, _)| v)
        .collect()
}

#[test]
fn every_method_culls_each_light_view_without_error_and_drops_the_box_behind_the_camera() {
    let scene = scene();
    let (vfc, vfc_outcomes, vfc_light) = frame(&scene, Method::Vfc, None);
    // A spot's view, then the point light's six cube faces.
    assert_eq!(vfc.views.len(), 7);
    assert_eq!(
        rendered_in(&vfc_outcomes, SEEN)[0],
        0,
        "the spot sees the first box"
    );
    assert!(
        !rendered_in(&vfc_outcomes, HIDDEN).is_empty(),
        "the point light's faces hold the second box, so vfc draws it"
    );
    for method in [
        Method::Frag,
        Method::Geom,
        Method::Bvol,
        Method::DrConservative,
        Method::DrProgressive,
        Method::Oracle,
    ] {
        let (report, outcomes, light) = frame(&scene, method, None);
        let error = report.error.expect("measured");
        assert_eq!(
            (error.missing_shadow_px, error.extra_shadow_px),
            (0, 0),
            "{method:?} against the reference maps of every caster"
        );
        assert!(error.visible_px > 10_000, "{method:?}: {error:?}");
        // The picture is vfc's, but for an edge's rounding: the maps come from the map
        // technique's pipeline, vfc's from the lights' own.
        let differ = light
            .iter()
            .zip(&vfc_light)
            .filter(|(a, b)| (**a < 128) != (**b < 128))
            .count();
        assert!(
            differ <= 2,
            "{method:?}: {differ} pixels shadowed unlike vfc's"
        );
        for view in &report.views {
            let oracle = view.casters_oracle.expect("the oracle per view");
            assert!(
                view.casters_rendered >= oracle,
                "{method:?} {}: {} drawn, the oracle needs {oracle}",
                view.name,
                view.casters_rendered
            );
        }
        assert_eq!(
            rendered_in(&outcomes, SEEN).first(),
            Some(&0),
            "{method:?}: the first box's shadow from above is in view"
        );
        // GEOM and BVOL mark the whole ground, a visible receiver, so they keep the box whose
        // shadows fall on its unseen part; the others see that no visible point receives them.
        let hidden = rendered_in(&outcomes, HIDDEN);
        if matches!(method, Method::Geom | Method::Bvol) {
            assert!(!hidden.is_empty(), "{method:?} keeps the second box");
        } else {
            assert!(
                hidden.is_empty(),
                "{method:?} drew the box behind the camera into views {hidden:?}"
            );
        }
    }
}

#[test]
fn frag_culls_the_lights_views_without_error_when_the_suns_cascades_come_first() {
    // The sun's cascades come first (two asked for; one with no visible receiver is
    // skipped), the lights' seven views follow; the error counts the sun's light (the
    // picture's), the oracle each view's.
    let scene = scene();
    for selection in [CascadeSelection::Depth, CascadeSelection::Map] {
        let (report, outcomes, _) = frame(&scene, Method::Frag, Some(selection));
        let cascades = report
            .views
            .iter()
            .take_while(|v| v.name.starts_with("cascade"))
            .count();
        assert!(
            (1..=2).contains(&cascades),
            "{selection:?}: {cascades} cascades"
        );
        assert_eq!(report.views.len(), cascades + 7, "{selection:?}");
        let error = report.error.expect("measured");
        assert_eq!(
            (error.missing_shadow_px, error.extra_shadow_px),
            (0, 0),
            "{selection:?}"
        );
        for view in &report.views {
            let oracle = view.casters_oracle.expect("the oracle per view");
            assert!(
                view.casters_rendered >= oracle,
                "{selection:?} {}: {view:?}",
                view.name
            );
        }
        // Selecting by map, a point whose footprint a cascade holds is marked in no later
        // cascade, but still in every light's view.
        assert!(
            rendered_in(&outcomes, SEEN).contains(&cascades),
            "{selection:?}: the spot's view (after the cascades) draws the first box"
        );
    }
}
