//! LiSPSM through the whole frame: the shadow of a box where the truth has it, every method
//! culling the warped view without error, finer shadows than one uniform map at street level,
//! and the fall-back to a uniform map looking along the light.

use glam::Vec3;
use render_core::frame::{
    FrameInput, FrameRenderer, FrameSettings, Method, PcfKernel, SceneGpu, ShadowSetup,
};
use render_core::geom::Camera;
use render_core::scene::{Scene, Sun, load_builtin};
use render_core::truth::TruthCache;
use shadowlab_tests::{box_on_plane, city_small_street_camera, gpu, last_of_frames};

fn lispsm() -> FrameSettings {
    FrameSettings {
        setup: ShadowSetup::Lispsm,
        ..FrameSettings::default()
    }
}

/// `frames` frames of `settings`; the last report and its error against the exact shadow.
fn measured(
    scene: &Scene,
    camera: &Camera,
    settings: &FrameSettings,
    frames: usize,
) -> (
    render_core::frame::FrameReport,
    render_core::metrics::ShadowError,
) {
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, scene);
    let mut renderer = FrameRenderer::new(ctx);
    let input = FrameInput {
        camera,
        width: 320,
        height: 200,
        settings,
    };
    let report = last_of_frames(&mut renderer, (scene, &scene_gpu), &input, frames);
    let mut truth = TruthCache::default();
    let exact = truth.exact_and_rays(scene, camera, (320, 200), settings.sun.direction_to_sun);
    let error = renderer.exact_error(ctx, exact).expect("read back");
    (report, error)
}

#[test]
fn the_warped_map_shadows_a_box_where_the_exact_shadow_is() {
    let sun = Sun::from_azimuth_elevation_deg(30.0, 45.0);
    let scene = box_on_plane(30.0, Vec3::new(2.0, 3.0, 2.0), 0.0, sun);
    let camera = Camera::look_at(
        Vec3::new(-8.0, 2.0, 10.0),
        Vec3::new(10.0, 0.0, -15.0),
        60f32.to_radians(),
        0.1,
        200.0,
    );
    let mut settings = FrameSettings {
        sun,
        measure: true,
        ..lispsm()
    };
    settings.shadow.pcf = PcfKernel::Off;
    let (report, error) = measured(&scene, &camera, &settings, 1);
    assert_eq!(report.views.len(), 1);
    assert!(
        report.views[0].lispsm_n_m.is_some(),
        "{:?}",
        report.views[0]
    );
    assert!(report.notes.is_empty(), "{:?}", report.notes);
    let wrong = error.missing_shadow_px + error.extra_shadow_px;
    assert!(error.visible_px > 20_000, "{error:?}");
    assert!(
        wrong * 100 < error.visible_px,
        "the warped map differs from the exact shadow in {wrong} of {} pixels",
        error.visible_px
    );
}

#[test]
fn every_method_culls_the_warped_view_without_error_and_it_undersamples_less_than_one_map() {
    let scene = load_builtin("city-small", 0).expect("city-small");
    let camera = city_small_street_camera();
    let mut exact_errors = Vec::new();
    for method in [
        Method::Ref,
        Method::Bvol,
        Method::Frag,
        Method::DrConservative,
    ] {
        let settings = FrameSettings {
            sun: scene.sun,
            method,
            measure: true,
            ..lispsm()
        };
        let (report, exact) = measured(&scene, &camera, &settings, 3);
        let error = report.error.expect("measured");
        assert_eq!(
            (error.missing_shadow_px, error.extra_shadow_px),
            (0, 0),
            "{method:?} against the reference of the same warped view"
        );
        let view = &report.views[0];
        assert!(view.lispsm_n_m.is_some());
        assert!(view.casters_rendered >= view.casters_oracle.expect("oracle"));
        exact_errors.push(exact.missing_shadow_px + exact.extra_shadow_px);
    }
    // Every method draws the same shadow.
    assert!(
        exact_errors.windows(2).all(|w| w[0] == w[1]),
        "{exact_errors:?}"
    );
    let single = FrameSettings {
        sun: scene.sun,
        method: Method::Frag,
        measure: true,
        ..FrameSettings::default()
    };
    let (single_report, single_exact) = measured(&scene, &camera, &single, 3);
    let (warped_report, _) = measured(
        &scene,
        &camera,
        &FrameSettings {
            setup: ShadowSetup::Lispsm,
            ..single
        },
        3,
    );
    let (u_single, u_warped) = (
        single_report.undersampling.expect("measured"),
        warped_report.undersampling.expect("measured"),
    );
    assert!(
        u_warped.median_octaves < u_single.median_octaves,
        "LiSPSM {u_warped:?} against one map {u_single:?}"
    );
    // Which has fewer error pixels depends on the view (far texels are coarser): the bench
    // measures it. Both stay close to the truth.
    for (name, wrong, of) in [
        ("LiSPSM", exact_errors[0], single_exact.visible_px),
        (
            "one map",
            single_exact.missing_shadow_px + single_exact.extra_shadow_px,
            single_exact.visible_px,
        ),
    ] {
        assert!(
            wrong * 50 < of,
            "{name}: {wrong} of {of} pixels differ from the truth"
        );
    }
}

#[test]
fn looking_into_the_sun_or_away_falls_back_to_a_uniform_map_and_says_so() {
    let sun = Sun::from_azimuth_elevation_deg(0.0, 30.0);
    let scene = box_on_plane(30.0, Vec3::new(2.0, 3.0, 2.0), 0.0, sun);
    for towards in [sun.direction_to_sun, -sun.direction_to_sun] {
        let eye = Vec3::new(0.0, 20.0, 0.0) - towards * 25.0;
        let camera = Camera::look_at(eye, eye + towards, 60f32.to_radians(), 0.1, 200.0);
        let settings = FrameSettings {
            sun,
            measure: true,
            ..lispsm()
        };
        let (report, error) = measured(&scene, &camera, &settings, 1);
        assert_eq!(report.views[0].lispsm_n_m, None, "{towards}");
        assert_eq!(report.views[0].name, "sun (uniform)");
        assert!(
            report.notes.iter().any(|n| n.contains("LiSPSM")),
            "{:?}",
            report.notes
        );
        assert!(report.views[0].texel_size_m.iter().all(|t| t.is_finite()));
        let e = report.error.expect("measured");
        assert_eq!((e.missing_shadow_px, e.extra_shadow_px), (0, 0));
        assert!(error.visible_px > 0 || towards.y > 0.0);
    }
}

#[test]
fn a_wall_facing_the_sun_is_lit_everywhere_in_the_warped_map() {
    // A lit wall at a slant to the light: the bias and the receiver plane of a warped lookup
    // keep it free of acne.
    let sun = Sun::from_azimuth_elevation_deg(0.0, 30.0);
    let scene = box_on_plane(40.0, Vec3::new(10.0, 10.0, 10.0), 0.0, sun);
    let camera = Camera::look_at(
        Vec3::new(25.0, 3.0, 18.0),
        Vec3::new(5.0, 5.0, 0.0),
        60f32.to_radians(),
        0.1,
        300.0,
    );
    let settings = lispsm_with(sun);
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, &scene);
    let mut renderer = FrameRenderer::new(ctx);
    let report = renderer
        .render_and_wait(
            ctx,
            &scene,
            &scene_gpu,
            &FrameInput {
                camera: &camera,
                width: 320,
                height: 200,
                settings: &settings,
            },
        )
        .expect("frame");
    assert!(report.views[0].lispsm_n_m.is_some());
    let capture =
        render_core::frame::FrameCapture::read(ctx, renderer.targets().unwrap()).expect("readback");
    // The box is instance 1 (id 2); its +x face is the one facing the sun.
    let face: Vec<(u8, Vec3)> = shadowlab_tests::pixels_of(&capture, &camera, 2)
        // Away from its edges, where the taps reach round the corner.
        .filter(|(_, p)| (p.x - 5.0).abs() < 0.01 && p.y > 0.2 && p.z.abs() < 4.8)
        .map(|(i, p)| (capture.shadow[i], p))
        .collect();
    let shadowed: Vec<Vec3> = face
        .iter()
        .filter(|(l, _)| *l < 255)
        .map(|(_, p)| *p)
        .collect();
    assert!(face.len() > 2000, "{} pixels of the wall", face.len());
    assert!(
        shadowed.is_empty(),
        "{} of {} wall pixels get shadow: {shadowed:?}",
        shadowed.len(),
        face.len()
    );
}

fn lispsm_with(sun: Sun) -> FrameSettings {
    FrameSettings { sun, ..lispsm() }
}
