//! The error measure and the oracle: conservative methods give zero error and draw every oracle
//! caster; a missing caster shows up as missing shadow; the oracle leaves out casters whose
//! shadow nobody sees.

use glam::{Mat4, Vec3};
use render_core::frame::{
    FrameCapture, FrameInput, FrameRenderer, FrameReport, FrameSettings, Method, PcfKernel,
    SceneGpu, ShadowSetup,
};
use render_core::geom::Camera;
use render_core::scene::{Instance, Scene, Sun, load_builtin};
use shadowlab_tests::{biggest_building, box_mesh, box_on_plane, gpu};

/// Renders one measured frame and returns the report, the drawn casters and the oracle flags.
fn measured(
    scene: &Scene,
    camera: &Camera,
    settings: &FrameSettings,
    exclude: &[u32],
) -> (FrameReport, Vec<u32>, Vec<bool>) {
    let (report, drawn, oracle, _) = measured_with_capture(scene, camera, settings, exclude);
    (report, drawn, oracle)
}

/// As [`measured`], plus the frame's targets.
fn measured_with_capture(
    scene: &Scene,
    camera: &Camera,
    settings: &FrameSettings,
    exclude: &[u32],
) -> (FrameReport, Vec<u32>, Vec<bool>, FrameCapture) {
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, scene);
    let mut renderer = FrameRenderer::new(ctx);
    renderer.exclude_casters(exclude);
    let settings = FrameSettings {
        measure: true,
        ..*settings
    };
    let input = FrameInput {
        camera,
        width: 256,
        height: 192,
        settings: &settings,
    };
    // Methods that lean on last frame's visibility are checked on their first frame and once
    // settled (FOCUS needs a frame for the visible receivers to come back).
    // (INCR draws its whole map on the first frame, then only what moved: tests/culling.rs.)
    let frames = if settings.method.temporal() && !settings.method.static_light() {
        3
    } else {
        1
    };
    let mut report = FrameReport::default();
    for _ in 0..frames {
        report = renderer
            .render_and_wait(ctx, scene, &scene_gpu, &input)
            .expect("frame");
        if !settings.method.may_err() && exclude.is_empty() {
            assert_eq!(
                report
                    .error
                    .map(|e| (e.missing_shadow_px, e.extra_shadow_px)),
                Some((0, 0)),
                "{}: every frame, not only the settled one, has zero error",
                settings.method.name()
            );
        }
    }
    let oracle = renderer.read_oracle(ctx, &scene_gpu).expect("oracle flags");
    let capture = FrameCapture::read(ctx, renderer.targets().expect("targets")).expect("readback");
    (report, renderer.drawn_casters(), oracle, capture)
}

fn assert_conservative(name: &str, scene: &Scene, camera: &Camera, settings: &FrameSettings) {
    let mut rendered = Vec::new();
    for method in Method::ALL {
        let settings = FrameSettings {
            method,
            ..*settings
        };
        let (report, drawn, oracle, capture) = measured_with_capture(scene, camera, &settings, &[]);
        let error = report
            .error
            .unwrap_or_else(|| panic!("{name}/{}: no error reported: {report:?}", method.name()));
        // Exactly the visible receiver pixels are compared: hidden fragments must not count.
        let receiver_px = capture
            .ids
            .iter()
            .filter(|&&id| id != 0 && scene.instances[id as usize - 1].receives_shadow)
            .count() as u32;
        assert_eq!(
            error.visible_px,
            receiver_px,
            "{name}/{}: compared pixels",
            method.name()
        );
        for (i, _) in oracle.iter().enumerate().filter(|(_, o)| **o) {
            let shadows_something = capture
                .shadow
                .iter()
                .zip(&capture.ids)
                .any(|(f, &id)| *f < 255 && id != 0);
            assert!(
                shadows_something,
                "{name}: oracle caster {} but no shadowed pixel",
                scene.instances[i].name
            );
        }
        assert!(
            error.visible_px > 0,
            "{name}/{}: no visible receiver pixels",
            method.name()
        );
        rendered.push(report.counts.casters_rendered);
        if method.may_err() {
            continue;
        }
        assert_eq!(
            (error.missing_shadow_px, error.extra_shadow_px),
            (0, 0),
            "{name}/{}: error pixels",
            method.name()
        );
        let oracle_count = oracle.iter().filter(|&&o| o).count() as u32;
        assert_eq!(
            report.counts.casters_oracle,
            Some(oracle_count),
            "{name}: oracle count and flags agree"
        );
        for (i, _) in oracle.iter().enumerate().filter(|(_, o)| **o) {
            assert!(
                drawn.binary_search(&(i as u32)).is_ok(),
                "{name}/{}: oracle caster {} was not drawn",
                method.name(),
                scene.instances[i].name
            );
        }
    }
    // none draws every caster; vfc at most as many.
    assert_eq!(rendered[0], scene.caster_count() as u32, "{name}");
    assert!(
        rendered[1] <= rendered[0],
        "{name}: vfc drew more than none"
    );
}

#[test]
fn conservative_methods_have_zero_error_and_draw_the_oracle() {
    let city = load_builtin("city-small", 0).expect("city-small");
    let street = Camera::look_at(
        Vec3::new(-40.0, 3.5, 2.0),
        Vec3::new(60.0, 8.0, 2.0),
        60f32.to_radians(),
        0.1,
        2000.0,
    );
    let above = Camera::look_at(
        Vec3::new(-150.0, 120.0, 150.0),
        Vec3::ZERO,
        60f32.to_radians(),
        0.1,
        2000.0,
    );
    for (name, camera, sun) in [
        ("street", street, city.sun),
        ("above", above, city.sun),
        (
            "grazing",
            street,
            Sun::from_azimuth_elevation_deg(20.0, 1.0),
        ),
        ("zenith", above, Sun::from_direction(Vec3::Y)),
    ] {
        let settings = FrameSettings {
            sun,
            ..FrameSettings::default()
        };
        assert_conservative(name, &city, &camera, &settings);
    }
    let boxes = load_builtin("boxes", 0).expect("boxes");
    let view = Camera::look_at(
        Vec3::new(-25.0, 18.0, 25.0),
        Vec3::ZERO,
        50f32.to_radians(),
        0.1,
        200.0,
    );
    for pcf in PcfKernel::ALL {
        let mut settings = FrameSettings {
            sun: boxes.sun,
            ..FrameSettings::default()
        };
        settings.shadow.pcf = pcf;
        assert_conservative(pcf.name(), &boxes, &view, &settings);
    }
}

#[test]
fn a_missing_caster_shows_as_missing_shadow() {
    let sun = Sun::from_direction(Vec3::Y);
    let scene = box_on_plane(20.0, Vec3::splat(2.0), 1.5, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 4.0, 12.0),
        Vec3::ZERO,
        50f32.to_radians(),
        0.1,
        100.0,
    );
    let settings = FrameSettings {
        sun,
        ..FrameSettings::default()
    };
    let (full, _, oracle) = measured(&scene, &camera, &settings, &[]);
    assert_eq!(full.error.map(|e| e.missing_shadow_px), Some(0));
    assert!(
        oracle[1],
        "the box shadows visible ground, so it is in the oracle"
    );
    let mut with_heat_map = settings;
    with_heat_map.overlays.error = true;
    let (without_box, drawn, _, capture) =
        measured_with_capture(&scene, &camera, &with_heat_map, &[1]);
    assert_eq!(drawn, vec![0]);
    let error = without_box.error.expect("measured");
    assert!(
        error.missing_shadow_px > 100,
        "the box's shadow is missing but only {} px counted",
        error.missing_shadow_px
    );
    assert_eq!(error.extra_shadow_px, 0);
    // The per-pixel factors agree with the counts, and the heat map paints those pixels red.
    let darker_in_reference = capture
        .shadow
        .iter()
        .zip(&capture.reference_shadow)
        .filter(|(m, r)| r < m)
        .count() as u32;
    assert_eq!(darker_in_reference, error.missing_shadow_px);
    let red = capture
        .color
        .pixels()
        .filter(|p| {
            i32::from(p.0[0]) > i32::from(p.0[1]) + 60 && i32::from(p.0[0]) > i32::from(p.0[2]) + 60
        })
        .count() as u32;
    assert!(
        red >= error.missing_shadow_px * 9 / 10,
        "{red} red pixels for {} missing",
        error.missing_shadow_px
    );
}

#[test]
fn the_oracle_leaves_out_a_caster_whose_shadow_falls_on_hidden_ground() {
    // A wall hides a box and the ground around it; the sun from +X throws the box's shadow onto
    // that hidden ground. A second box stands in front of the wall, its shadow in view.
    let sun = Sun::from_direction(Vec3::new(1.0, 1.0, 0.0));
    let ground = box_mesh("ground", Vec3::new(100.0, 0.5, 100.0));
    let cube = box_mesh("box", Vec3::splat(1.0));
    let wall = box_mesh("wall", Vec3::new(20.0, 5.0, 0.5));
    let instances = vec![
        Instance::new(
            "ground",
            0,
            &ground,
            Mat4::from_translation(Vec3::new(0.0, -0.5, 0.0)),
        ),
        Instance::new(
            "seen",
            1,
            &cube,
            Mat4::from_translation(Vec3::new(5.0, 1.0, -20.0)),
        ),
        Instance::new(
            "hidden",
            1,
            &cube,
            Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)),
        ),
        Instance::new(
            "wall",
            2,
            &wall,
            Mat4::from_translation(Vec3::new(0.0, 5.0, -10.0)),
        ),
    ];
    let scene = Scene::new("test:oracle", vec![ground, cube, wall], instances, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 2.0, -30.0),
        Vec3::new(0.0, 2.0, 0.0),
        60f32.to_radians(),
        0.1,
        300.0,
    );
    let settings = FrameSettings {
        sun,
        method: Method::Vfc,
        ..FrameSettings::default()
    };
    let (report, drawn, oracle) = measured(&scene, &camera, &settings, &[]);
    assert!(
        oracle[1],
        "the box in front of the wall shadows visible ground"
    );
    assert!(
        !oracle[2],
        "the hidden box's shadow falls only on hidden ground"
    );
    assert!(
        drawn.contains(&2),
        "vfc keeps the hidden box: it is inside the light frustum"
    );
    let oracle_count = report.counts.casters_oracle.expect("measured");
    assert!(
        oracle_count < report.counts.casters_rendered,
        "{oracle_count} oracle casters"
    );
    assert!(report.tightness().expect("tightness") > 1.0);
    assert_eq!(
        report
            .error
            .map(|e| (e.missing_shadow_px, e.extra_shadow_px)),
        Some((0, 0))
    );
}

#[test]
fn hard_views_have_zero_error_and_draw_the_oracle() {
    // The camera inside a building's box: the biggest building of the small city.
    let city = load_builtin("city-small", 0).expect("city-small");
    let building = biggest_building(&city).expect("a building");
    let inside = building.aabb_in_world.center();
    let camera = Camera::look_at(
        inside,
        inside + Vec3::new(30.0, -5.0, 10.0),
        60f32.to_radians(),
        0.1,
        2000.0,
    );
    let settings = FrameSettings {
        sun: city.sun,
        ..FrameSettings::default()
    };
    assert_conservative("inside a building", &city, &camera, &settings);

    // A tower behind the camera throws its shadow into view; its top is the scene's highest
    // point and, with the sun 1 degree up, its sunward face is the scene's nearest point to the
    // sun: it touches the light's near plane (the fit pulls the plane back to the scene's
    // extent, so no caster crosses it).
    for elevation in [25.0, 1.0] {
        let sun = Sun::from_azimuth_elevation_deg(180.0, elevation);
        let ground = box_mesh("ground", Vec3::new(60.0, 0.5, 60.0));
        let tower = box_mesh("tower", Vec3::new(3.0, 40.0, 3.0));
        let at = |x, y, z| Mat4::from_translation(Vec3::new(x, y, z));
        let to_sun = sun.direction_to_sun;
        let sunward = Vec3::new(to_sun.x, 0.0, to_sun.z).normalize();
        let behind = sunward * 30.0;
        let instances = vec![
            Instance::new("ground", 0, &ground, at(0.0, -0.5, 0.0)),
            Instance::new("tower", 1, &tower, at(behind.x, 40.0, behind.z)),
        ];
        let scene = Scene::new("test:tower-behind", vec![ground, tower], instances, sun);
        // The camera stands between the tower and its shadow, looking away from the tower.
        let eye = Vec3::new(0.0, 2.0, 0.0);
        let camera = Camera::look_at(
            eye,
            eye - sunward * 20.0 - Vec3::Y * 2.0,
            50f32.to_radians(),
            0.1,
            500.0,
        );
        let settings = FrameSettings {
            sun,
            ..FrameSettings::default()
        };
        let (_, _, oracle) = measured(
            &scene,
            &camera,
            &FrameSettings {
                method: Method::None,
                ..settings
            },
            &[],
        );
        assert!(oracle[1], "{elevation}°: the tower's shadow is in view");
        let name = format!("tower behind the camera, sun {elevation}°");
        assert_conservative(&name, &scene, &camera, &settings);
    }
}

#[test]
fn a_technique_is_built_on_first_use_and_leaves_out_the_casters_excluded_before() {
    // The box is left out before the first frame, while only the shadow maps exist; the
    // volumes and the virtual maps, built when a frame first asks for them, leave it out too:
    // not one pixel of the ground is in shadow, where a renderer that keeps the box shadows
    // hundreds. The many lights' maps are never asked for, so never built.
    let sun = Sun::from_direction(Vec3::new(0.3, 1.0, 0.2));
    let scene = box_on_plane(20.0, Vec3::splat(2.0), 1.5, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 6.0, 12.0),
        Vec3::ZERO,
        50f32.to_radians(),
        0.1,
        100.0,
    );
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, &scene);
    let mut without_box = FrameRenderer::new(ctx);
    without_box.exclude_casters(&[1]);
    let mut with_box = FrameRenderer::new(ctx);
    let shadowed_ground = |renderer: &mut FrameRenderer, setup| {
        let settings = FrameSettings {
            sun,
            setup,
            ..FrameSettings::default()
        };
        let input = FrameInput {
            camera: &camera,
            width: 256,
            height: 192,
            settings: &settings,
        };
        renderer
            .render_and_wait(ctx, &scene, &scene_gpu, &input)
            .expect("frame");
        let capture =
            FrameCapture::read(ctx, renderer.targets().expect("targets")).expect("readback");
        capture
            .shadow
            .iter()
            .zip(&capture.ids)
            .filter(|&(&f, &id)| id == 1 && f < 128)
            .count()
    };
    for setup in [
        ShadowSetup::Single,
        ShadowSetup::Volumes,
        ShadowSetup::Virtual,
    ] {
        assert_eq!(shadowed_ground(&mut without_box, setup), 0, "{setup:?}");
        let kept = shadowed_ground(&mut with_box, setup);
        assert!(
            kept > 500,
            "{setup:?}: {kept} ground pixels in the box's shadow"
        );
    }
    assert!(
        without_box.lights_depth_texture().is_none(),
        "no frame asked for many lights"
    );
}
