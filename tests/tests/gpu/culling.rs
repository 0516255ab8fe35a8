//! Known answers for the caster-culling methods on small scenes built here: which objects each
//! method culls, DigitalRune's progressive failure, FOCUS's fit, an empty view.

use glam::{Mat4, Vec3};
use render_core::frame::{FrameInput, FrameRenderer, FrameReport, FrameSettings, Method, SceneGpu};
use render_core::geom::Camera;
use render_core::scene::{Instance, Scene, Sun, load_builtin};
use shadowlab_tests::{box_mesh, city_small_street_camera, gpu};

/// `frames` measured frames of one view; per frame the report and the drawn casters.
fn frames(
    scene: &Scene,
    camera: &Camera,
    settings: &FrameSettings,
    frames: usize,
) -> Vec<(FrameReport, Vec<u32>)> {
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, scene);
    let mut renderer = FrameRenderer::new(ctx);
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
    (0..frames)
        .map(|_| {
            let report = renderer
                .render_and_wait(ctx, scene, &scene_gpu, &input)
                .expect("frame");
            (report, renderer.drawn_casters())
        })
        .collect()
}

fn error_px(report: &FrameReport) -> (u32, u32) {
    let e = report.error.expect("measured");
    (e.missing_shadow_px, e.extra_shadow_px)
}

/// A wall hides a box and the ground around it; the sun from +X throws the box's shadow onto
/// that hidden ground only. A second box stands in front of the wall, its shadow in view.
fn hidden_box_scene() -> (Scene, Camera) {
    let sun = Sun::from_direction(Vec3::new(1.0, 1.0, 0.0));
    let ground = box_mesh("ground", Vec3::new(100.0, 0.5, 100.0));
    let cube = box_mesh("box", Vec3::splat(1.0));
    let wall = box_mesh("wall", Vec3::new(20.0, 5.0, 0.5));
    let at = |x, y, z| Mat4::from_translation(Vec3::new(x, y, z));
    let instances = vec![
        Instance::new("ground", 0, &ground, at(0.0, -0.5, 0.0)),
        Instance::new("seen", 1, &cube, at(5.0, 1.0, -20.0)),
        Instance::new("hidden", 1, &cube, at(0.0, 1.0, 0.0)),
        Instance::new("wall", 2, &wall, at(0.0, 5.0, -10.0)),
    ];
    let scene = Scene::new("test:hidden-box", vec![ground, cube, wall], instances, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 2.0, -30.0),
        Vec3::new(0.0, 2.0, 0.0),
        60f32.to_radians(),
        0.1,
        300.0,
    );
    (scene, camera)
}

#[test]
fn each_method_culls_exactly_the_expected_objects() {
    let (scene, camera) = hidden_box_scene();
    let (seen, hidden) = (1u32, 2u32);
    // The ground is one huge visible receiver: its box (BVOL) and its geometry (GEOM) cover
    // the hidden box's shadow, so they keep it; the fragment mask and the oracle cull it, and
    // so do DigitalRune's shadow volumes, which the wall hides from the camera.
    let expected_hidden_drawn = |m: Method| {
        !matches!(
            m,
            Method::Frag | Method::Oracle | Method::DrConservative | Method::DrProgressive
        )
    };
    for method in Method::ALL {
        let settings = FrameSettings {
            sun: scene.sun,
            method,
            ..FrameSettings::default()
        };
        let runs = frames(&scene, &camera, &settings, 3);
        // INCR draws its whole map once, then nothing while nothing moves.
        let incremental = method == Method::Incr;
        for (frame, (report, drawn)) in runs.iter().enumerate() {
            assert_eq!(error_px(report), (0, 0), "{} frame {frame}", method.name());
            if incremental && frame > 0 {
                assert!(drawn.is_empty(), "incr redrew {drawn:?} in a still scene");
                continue;
            }
            assert!(
                drawn.contains(&seen),
                "{} frame {frame}: the box in view was culled",
                method.name()
            );
        }
        let (report, drawn) = if incremental {
            &runs[0]
        } else {
            runs.last().expect("frames")
        };
        assert_eq!(
            drawn.contains(&hidden),
            expected_hidden_drawn(method),
            "{}: the hidden box (drawn {drawn:?}, stages {:?})",
            method.name(),
            report.stages
        );
    }
}

/// Sun at the zenith. A canopy at 5 m roofs a 4 m room whose walls rise to 8 m, so from the
/// light the canopy is framed by nearer wall tops and hides everything behind it. The camera
/// stands in the room under the canopy, looking at the shadowed floor.
fn canopy_room() -> (Scene, Camera) {
    let sun = Sun::from_direction(Vec3::Y);
    let ground = box_mesh("ground", Vec3::new(12.0, 0.5, 12.0));
    let canopy = box_mesh("canopy", Vec3::new(2.0, 0.1, 2.0));
    let wall_x = box_mesh("wall", Vec3::new(1.5, 4.0, 5.0));
    let wall_z = box_mesh("wall", Vec3::new(2.0, 4.0, 1.5));
    let at = |x, y, z| Mat4::from_translation(Vec3::new(x, y, z));
    let instances = vec![
        Instance::new("ground", 0, &ground, at(0.0, -0.5, 0.0)),
        Instance::new("canopy", 1, &canopy, at(0.0, 5.0, 0.0)),
        Instance::new("east", 2, &wall_x, at(3.5, 4.0, 0.0)),
        Instance::new("west", 2, &wall_x, at(-3.5, 4.0, 0.0)),
        Instance::new("north", 3, &wall_z, at(0.0, 4.0, 3.5)),
        Instance::new("south", 3, &wall_z, at(0.0, 4.0, -3.5)),
    ];
    let scene = Scene::new(
        "test:canopy-room",
        vec![ground, canopy, wall_x, wall_z],
        instances,
        sun,
    );
    let camera = Camera::look_at(
        Vec3::new(0.0, 2.0, -1.2),
        Vec3::new(0.2, 0.0, 0.8),
        60f32.to_radians(),
        0.05,
        100.0,
    );
    (scene, camera)
}

#[test]
fn progressive_volumes_lose_a_shadow_that_conservative_ones_keep() {
    let (scene, camera) = canopy_room();
    let canopy = 1u32;
    let run = |method| {
        let settings = FrameSettings {
            sun: scene.sun,
            method,
            ..FrameSettings::default()
        };
        frames(&scene, &camera, &settings, 4)
    };
    for (frame, (report, drawn)) in run(Method::DrConservative).iter().enumerate() {
        assert_eq!(error_px(report), (0, 0), "conservative, frame {frame}");
        assert!(drawn.contains(&canopy), "conservative, frame {frame}");
    }
    // The canopy is its own occluder: with it in last frame's map, the farthest depth over
    // its box is its own top, its volume ends there, above the camera, and it is culled; the
    // next frame's map shows the floor again and it comes back. The shadow flickers, and the
    // measure reports the lost floor pixels.
    let progressive = run(Method::DrProgressive);
    let lost: Vec<u32> = progressive.iter().map(|(r, _)| error_px(r).0).collect();
    let drawn: Vec<bool> = progressive
        .iter()
        .map(|(_, d)| d.contains(&canopy))
        .collect();
    assert!(
        lost.iter().any(|&px| px > 1000),
        "progressive lost no shadow: {lost:?}, canopy drawn {drawn:?}"
    );
    assert!(
        drawn.iter().any(|&d| d),
        "the canopy never came back: {drawn:?}"
    );
    for (((report, _), d), px) in progressive.iter().zip(&drawn).zip(&lost) {
        assert_eq!(
            *d,
            *px == 0,
            "a frame loses shadow exactly when the canopy is culled: {:?}",
            report.stages
        );
    }
}

#[test]
fn an_empty_view_needs_no_casters_from_the_receiver_methods() {
    let city = load_builtin("city-small", 0).expect("city-small");
    // Looking straight up from above the rooftops: sky only.
    let camera = Camera::look_at(
        Vec3::new(-40.0, 400.0, 2.0),
        Vec3::new(-40.0, 500.0, 2.5),
        40f32.to_radians(),
        0.1,
        2000.0,
    );
    for method in Method::ALL {
        let settings = FrameSettings {
            sun: city.sun,
            method,
            ..FrameSettings::default()
        };
        let runs = frames(&city, &camera, &settings, 2);
        let (report, drawn) = runs.last().expect("frames");
        assert_eq!(report.error.map(|e| e.visible_px), Some(0), "sky only");
        assert_eq!(error_px(report), (0, 0));
        assert_eq!(report.counts.casters_oracle, Some(0));
        if matches!(
            method,
            Method::Bvol | Method::Geom | Method::GeomBvol | Method::Frag | Method::Oracle
        ) {
            assert!(
                drawn.is_empty(),
                "{}: no visible receiver, yet {} casters drawn",
                method.name(),
                drawn.len()
            );
        }
    }
}

#[test]
fn focus_fits_the_map_to_the_visible_receivers() {
    let city = load_builtin("city-small", 0).expect("city-small");
    // Close to a wall at street level: few receivers in view, the city behind the camera.
    let camera = Camera::look_at(
        Vec3::new(-40.0, 1.7, 2.0),
        Vec3::new(-40.0, 0.0, 6.0),
        50f32.to_radians(),
        0.1,
        2000.0,
    );
    let run = |method| {
        let settings = FrameSettings {
            sun: city.sun,
            method,
            ..FrameSettings::default()
        };
        frames(&city, &camera, &settings, 3)
    };
    let reference = run(Method::Ref);
    let focused = run(Method::Focus);
    let (r, f) = (&reference[2].0, &focused[2].0);
    assert_eq!(error_px(f), (0, 0));
    // The first frame has no visible receivers back yet: it is REF's map.
    assert_eq!(
        focused[0].0.light.texel_size_m.map(f32::to_bits),
        r.light.texel_size_m.map(f32::to_bits)
    );
    // The visible receivers (a ground chunk and a few facades) cover less than the view
    // frustum does: smaller texels on both axes.
    assert!(
        (0..2).all(|k| f.light.texel_size_m[k] < r.light.texel_size_m[k] * 0.95),
        "focused texels {:?}, unfocused {:?}",
        f.light.texel_size_m,
        r.light.texel_size_m
    );
    let in_frustum = |report: &FrameReport| {
        report
            .stages
            .iter()
            .find(|s| s.name == "light frustum")
            .map(|s| s.remaining)
    };
    assert!(
        in_frustum(f) < in_frustum(r),
        "focus {:?} vs ref {:?}",
        f.stages,
        r.stages
    );
}

#[test]
fn incremental_updates_match_a_full_redraw_while_cars_drive() {
    let ctx = gpu();
    let mut city = load_builtin("city-small", 0).expect("city-small");
    assert!(!city.motions.is_empty(), "the city has moving cars");
    let scene_gpu = SceneGpu::new(ctx, &city);
    let mut renderer = FrameRenderer::new(ctx);
    let camera = city_small_street_camera();
    let settings = FrameSettings {
        sun: city.sun,
        method: Method::Incr,
        measure: true,
        ..FrameSettings::default()
    };
    let input = FrameInput {
        camera: &camera,
        width: 256,
        height: 192,
        settings: &settings,
    };
    let mut drawn = Vec::new();
    for frame in 0..5 {
        let moved = city.animate(f64::from(frame) * 0.2);
        scene_gpu.update_instances(ctx, &city, &moved);
        let report = renderer
            .render_and_wait(ctx, &city, &scene_gpu, &input)
            .expect("frame");
        // The reference map is a full redraw of every caster under the same static light.
        assert_eq!(error_px(&report), (0, 0), "frame {frame}");
        assert!(report.light.covers_whole_scene, "a statically focused map");
        drawn.push(report.counts.casters_rendered);
    }
    // The first frame draws the whole map; later ones only the casters whose light-space
    // rectangles touch the cars' old and new boxes (the ground, the cars, the trees and the
    // buildings along the streets, whose rectangles reach over the road).
    assert_eq!(drawn[0] as usize, city.caster_count(), "{drawn:?}");
    for &d in &drawn[1..] {
        assert!(d > 0 && d * 10 < drawn[0] * 8, "{drawn:?}");
    }
    // With nothing moving, nothing is drawn and the map stays right.
    let report = renderer
        .render_and_wait(ctx, &city, &scene_gpu, &input)
        .expect("frame");
    assert_eq!(report.counts.casters_rendered, 0);
    assert_eq!(error_px(&report), (0, 0));
}
