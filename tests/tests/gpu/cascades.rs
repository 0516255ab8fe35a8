//! Cascaded shadow maps through the whole frame: the exact shadow of a box under each
//! cascade, every method culling each cascade on its own without error, and the hard views
//! (everything within 20 m, sky only).

use glam::Vec3;
use render_core::cascades::{
    CascadeDepths, CascadeSelection, CascadeSettings, SplitScheme, Splits,
};
use render_core::frame::SceneGpu;
use render_core::frame::{FrameInput, FrameRenderer, FrameSettings, Method, ShadowSetup};
use render_core::geom::Camera;
use render_core::scene::{Scene, Sun, load_builtin};
use render_core::shadow_view::DepthMeasure;
use shadowlab_tests::{
    box_on_plane, city_small_street_camera, expected_shadow, gpu, last_of_frames, pixels_of, render,
};

const GROUND: u32 = 1;

fn cascades(count: u32) -> FrameSettings {
    FrameSettings {
        setup: ShadowSetup::Cascades,
        cascades: CascadeSettings {
            count,
            ..CascadeSettings::default()
        },
        ..FrameSettings::default()
    }
}

/// A 2 x 3 x 2 m box 0.5 m above a 120 m ground, and a camera low over the ground, so the view
/// holds near and far ground and the box's shadow in the near cascades.
fn box_seen_low() -> (Sun, Scene, Camera) {
    let sun = Sun::from_azimuth_elevation_deg(30.0, 50.0);
    let scene = box_on_plane(60.0, Vec3::new(2.0, 3.0, 2.0), 0.5, sun);
    let camera = Camera::look_at(
        Vec3::new(-6.0, 2.0, 9.0),
        Vec3::new(20.0, 0.0, -25.0),
        60f32.to_radians(),
        0.05,
        200.0,
    );
    (sun, scene, camera)
}

#[test]
fn each_cascade_shadows_the_ground_exactly_where_the_box_does() {
    let (sun, scene, camera) = box_seen_low();
    let settings = FrameSettings { sun, ..cascades(4) };
    let (report, capture) = render(&scene, &camera, &settings, 320, 200);
    assert_eq!(report.technique, "cascades");
    assert_eq!(report.views.len(), 4, "{:?}", report.views);
    let texels: Vec<f32> = report.views.iter().map(|v| v.texel_size_m[0]).collect();
    assert!(
        texels.windows(2).all(|w| w[0] < w[1]),
        "each cascade's texels are coarser than the one before: {texels:?}"
    );
    // The PCF border of the coarsest cascade that shades a ground pixel.
    let border = texels[3] * (settings.shadow.pcf.width() as f32 * 0.5 + 1.0);
    // The box: 2 x 3 x 2 m, its bottom 0.5 m above the ground.
    let (min, max) = (Vec3::new(-1.0, 0.5, -1.0), Vec3::new(1.0, 3.5, 1.0));
    let (mut shadowed, mut lit, mut wrong) = (0, 0, Vec::new());
    for (i, p) in pixels_of(&capture, &camera, GROUND) {
        let Some(expected) = expected_shadow(p, sun.direction_to_sun, min, max, border) else {
            continue;
        };
        let dark = capture.shadow[i] == 0;
        let bright = capture.shadow[i] == 255;
        if expected {
            shadowed += 1;
        } else {
            lit += 1;
        }
        if (expected && !dark) || (!expected && !bright) {
            wrong.push((p, capture.shadow[i]));
        }
    }
    assert!(shadowed > 200, "{shadowed} shadowed ground pixels seen");
    assert!(lit > 10_000, "{lit} lit ground pixels seen");
    assert!(
        wrong.is_empty(),
        "{} wrong, first {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(5)]
    );
}

#[test]
fn every_method_culls_each_cascade_on_its_own_without_error() {
    let ctx = gpu();
    let scene = load_builtin("city-small", 0).expect("city-small");
    let scene_gpu = SceneGpu::new(ctx, &scene);
    let camera = city_small_street_camera();
    let methods = [
        Method::Ref,
        Method::Bvol,
        Method::Geom,
        Method::Frag,
        Method::DrConservative,
    ];
    // Selecting each point's cascade by its map: FRAG's masks follow the same choice.
    let by_map = [Method::Frag, Method::Ref].map(|m| (m, CascadeSelection::Map));
    for (method, selection) in methods
        .map(|m| (m, CascadeSelection::Depth))
        .into_iter()
        .chain(by_map)
    {
        let mut renderer = FrameRenderer::new(ctx);
        let mut settings = FrameSettings {
            sun: scene.sun,
            method,
            measure: true,
            ..cascades(3)
        };
        settings.cascades.selection = selection;
        let input = FrameInput {
            camera: &camera,
            width: 256,
            height: 192,
            settings: &settings,
        };
        let report = last_of_frames(&mut renderer, (&scene, &scene_gpu), &input, 3);
        assert_eq!(report.views.len(), 3, "{method:?}");
        let error = report.error.expect("measured");
        assert_eq!(
            (error.missing_shadow_px, error.extra_shadow_px),
            (0, 0),
            "{method:?} by {selection:?} against the reference of the same cascades"
        );
        for view in &report.views {
            let oracle = view.casters_oracle.expect("oracle per cascade");
            assert!(
                view.casters_rendered >= oracle,
                "{method:?} {}: {} drawn, the oracle needs {oracle}",
                view.name,
                view.casters_rendered
            );
            if method == Method::Frag {
                assert!(
                    view.casters_rendered as f32 <= 1.3 * oracle as f32 + 2.0,
                    "frag {}: {} drawn for an oracle of {oracle}",
                    view.name,
                    view.casters_rendered
                );
            }
        }
        let total: u32 = report.views.iter().map(|v| v.casters_rendered).sum();
        assert_eq!(
            report.counts.casters_rendered, total,
            "{method:?}: the total is the views' sum"
        );
    }
}

#[test]
fn a_view_within_twenty_metres_skips_the_far_cascades_and_sky_keeps_one_view() {
    let sun = Sun::from_azimuth_elevation_deg(60.0, 40.0);
    // A 10 m ground: seen from 3 m away, every depth is within 20 m.
    let scene = box_on_plane(5.0, Vec3::splat(1.0), 0.0, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 4.0, 8.0),
        Vec3::ZERO,
        60f32.to_radians(),
        0.1,
        1000.0,
    );
    let settings = FrameSettings {
        sun,
        cascades: CascadeSettings {
            count: 4,
            splits: Splits {
                scheme: SplitScheme::Geometric,
                first_m: 10.0,
                ratio: 3.0,
                ..Splits::default()
            },
            ..CascadeSettings::default()
        },
        ..cascades(4)
    };
    let (report, _) = render(&scene, &camera, &settings, 128, 96);
    // Depths up to about 15 m: the cascade to 10 m and the one to 30 m (cut to the scene).
    let names: Vec<&str> = report.views.iter().map(|v| v.name.as_str()).collect();
    assert_eq!(names, ["cascade 0", "cascade 1"]);

    // Looking up at the sky: no depth of the scene is in view, one view over it all.
    let sky = Camera::look_at(
        Vec3::new(0.0, 20.0, 0.0),
        Vec3::new(0.0, 40.0, 1.0),
        60f32.to_radians(),
        0.1,
        1000.0,
    );
    let (report, capture) = render(&scene, &sky, &settings, 128, 96);
    assert_eq!(report.views.len(), 1);
    assert!(report.views[0].covers_whole_scene);
    assert!(
        report.views[0]
            .texel_size_m
            .iter()
            .all(|t| t.is_finite() && *t > 0.0)
    );
    assert!(capture.depth.iter().all(|d| *d == 0.0), "only sky in view");
}

/// sRGB byte to linear.
fn linear(byte: u8) -> f32 {
    let c = f32::from(byte) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[test]
fn the_cascade_tint_colours_each_point_by_the_cascade_whose_depths_hold_it() {
    let (sun, scene, camera) = box_seen_low();
    let plain = FrameSettings { sun, ..cascades(4) };
    let mut tinted = plain;
    tinted.overlays.cascades = true;
    let (report, before) = render(&scene, &camera, &plain, 200, 120);
    let (_, after) = render(&scene, &camera, &tinted, 200, 120);
    let mut seen = [0; 4];
    for (i, p) in pixels_of(&after, &camera, GROUND) {
        // Away from the boundaries, where rounding could pick the neighbour.
        let mut depth = 0.0;
        let Some(v) = report.views.iter().position(|view| {
            depth = match view.shades_by {
                DepthMeasure::ViewDepth => (p - camera.eye).dot(camera.forward),
                DepthMeasure::EyeDistance => (p - camera.eye).length(),
            };
            let [near, far] = view.shades_depth_m;
            near.is_none_or(|n| depth > n * 1.01) && far.is_some_and(|f| depth < f * 0.99)
        }) else {
            continue;
        };
        let (x, y) = (i as u32 % after.width, i as u32 / after.width);
        let (a, b) = (
            before.color.get_pixel(x, y).0,
            after.color.get_pixel(x, y).0,
        );
        let tint = render_core::palette::VIEWS[v].rgb;
        for c in 0..3 {
            let expected = linear(a[c]) * 0.65 + tint[c] * 0.35;
            let got = linear(b[c]);
            assert!(
                (got - expected).abs() < 0.02,
                "ground at depth {depth:.1} m (cascade {v}): channel {c} is {got:.3}, the tint gives {expected:.3}"
            );
        }
        seen[v] += 1;
    }
    assert!(
        seen.iter().all(|n| *n > 20),
        "ground pixels per cascade: {seen:?}"
    );
}

#[test]
fn cascades_stay_sound_looking_into_the_sun_away_from_it_and_100_km_out() {
    let sun = Sun::from_azimuth_elevation_deg(0.0, 15.0);
    let near_scene = box_on_plane(150.0, Vec3::new(4.0, 12.0, 4.0), 0.0, sun);
    let offset = Vec3::new(100_000.0, 0.0, -100_000.0);
    let far_scene = shadowlab_tests::translated(&near_scene, offset);
    // The sun lies towards +X and the box's shadow falls towards -X: looking at the shadow
    // into the sun, away from it (from beside the box), and the same 100 km out.
    let cases = [
        (
            "into the sun",
            &near_scene,
            Vec3::new(-60.0, 3.0, 5.0),
            Vec3::new(-20.0, 0.0, 0.0),
        ),
        (
            "away from the sun",
            &near_scene,
            Vec3::new(20.0, 4.0, 14.0),
            Vec3::new(-25.0, 0.0, 0.0),
        ),
        (
            "100 km out",
            &far_scene,
            offset + Vec3::new(20.0, 4.0, 14.0),
            offset + Vec3::new(-25.0, 0.0, 0.0),
        ),
    ];
    for (name, scene, eye, target) in cases {
        let camera = Camera::look_at(eye, target, 60f32.to_radians(), 0.01, 10_000.0);
        let settings = FrameSettings {
            sun,
            method: Method::Frag,
            measure: true,
            ..cascades(4)
        };
        let (report, capture) = render(scene, &camera, &settings, 192, 128);
        assert_eq!(report.views.len(), 4, "{name}");
        for view in &report.views {
            assert!(
                view.texel_size_m.iter().all(|t| t.is_finite() && *t > 0.0),
                "{name}: {} has texels {:?}",
                view.name,
                view.texel_size_m
            );
        }
        let error = report.error.expect("measured");
        assert_eq!(
            (error.missing_shadow_px, error.extra_shadow_px),
            (0, 0),
            "{name}"
        );
        assert!(
            error.visible_px > 1000,
            "{name}: {} receiver pixels",
            error.visible_px
        );
        // The box's shadow falls on the ground in view: some ground is dark, most is lit.
        let (mut dark, mut ground) = (0, 0);
        for (i, _) in pixels_of(&capture, &camera, GROUND) {
            ground += 1;
            dark += usize::from(capture.shadow[i] == 0);
        }
        assert!(
            dark > 20 && dark < ground / 2,
            "{name}: {dark} of {ground} ground pixels dark"
        );
    }
}

/// A 20 m ground with a box, and a tower 500 m off to the side, out of view but within the
/// view's depths: the scene reaches about 400 m deep, the visible receivers 20 m.
fn ground_and_far_tower(sun: Sun) -> (Scene, Camera) {
    let base = box_on_plane(10.0, Vec3::splat(1.0), 0.0, sun);
    let tower = shadowlab_tests::box_mesh("tower", Vec3::new(5.0, 40.0, 5.0));
    let mut meshes = base.meshes.clone();
    let mut instances = base.instances.clone();
    instances.push(render_core::scene::Instance::new(
        "tower",
        meshes.len() as u32,
        &tower,
        glam::Mat4::from_translation(Vec3::new(450.0, 40.0, -400.0)),
    ));
    meshes.push(tower);
    let scene = Scene::new("test:far-tower", meshes, instances, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 4.0, 8.0),
        Vec3::new(0.0, 0.0, -4.0),
        60f32.to_radians(),
        0.1,
        1000.0,
    );
    (scene, camera)
}

/// The view depths, metres, of the nearest and furthest pixel that shows something.
fn visible_depths(capture: &render_core::frame::FrameCapture, camera: &Camera) -> [f64; 2] {
    let (near, far) = (f64::from(camera.near_m), f64::from(camera.far_m));
    let depths: Vec<f64> = capture
        .depth
        .iter()
        .filter(|d| **d > 0.0)
        .map(|d| far * near / (near + f64::from(*d) * (far - near)))
        .collect();
    [
        depths.iter().copied().fold(f64::INFINITY, f64::min),
        depths.iter().copied().fold(0.0, f64::max),
    ]
}

#[test]
fn cascades_skip_slices_without_visible_receivers_and_can_split_only_visible_depths() {
    let sun = Sun::from_azimuth_elevation_deg(60.0, 40.0);
    let (scene, camera) = ground_and_far_tower(sun);
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, &scene);
    let (near, scene_far) =
        render_core::geom::view_depth_range(&camera, &scene.bounds()).expect("in view");
    assert!(
        scene_far > 300.0,
        "the tower makes the scene deep: {scene_far}"
    );
    for depths in CascadeDepths::ALL {
        let mut settings = FrameSettings { sun, ..cascades(4) };
        settings.cascades.fit = render_core::cascades::CascadeFit::Tight;
        settings.cascades.depths = depths;
        let mut renderer = FrameRenderer::new(ctx);
        let input = FrameInput {
            camera: &camera,
            width: 160,
            height: 120,
            settings: &settings,
        };
        // The first frame knows no visible depths yet: four slices of the scene's depths.
        let first = renderer
            .render_and_wait(ctx, &scene, &scene_gpu, &input)
            .expect("frame");
        assert_eq!(first.views.len(), 4, "{depths:?}");
        let capture = render_core::frame::FrameCapture::read(ctx, renderer.targets().unwrap())
            .expect("readback");
        let [lo, hi] = visible_depths(&capture, &camera);
        assert!(hi < 25.0, "only the ground is visible: {lo}..{hi}");
        let report = renderer
            .render_and_wait(ctx, &scene, &scene_gpu, &input)
            .expect("frame");
        // What the renderer was told, with its 2 % margin for a moving camera.
        let (lo_m, hi_m) = (lo * 0.98, hi * 1.02);
        let splits = &settings.cascades.splits;
        let ends: Vec<[f64; 2]> = match depths {
            CascadeDepths::Scene => splits
                .distances(4, near, scene_far)
                .windows(2)
                .map(|w| [w[0], w[1]])
                .filter(|[a, b]| *a <= hi_m && *b >= lo_m)
                .collect(),
            CascadeDepths::Visible => splits
                .distances(4, near.max(lo_m), scene_far.min(hi_m))
                .windows(2)
                .map(|w| [w[0], w[1]])
                .collect(),
        };
        assert_eq!(
            report.views.len(),
            ends.len(),
            "{depths:?}: {:?}",
            report.views
        );
        assert!(
            depths == CascadeDepths::Visible || ends.len() < 4,
            "the slices beyond the ground are skipped"
        );
        for (view, [a, b]) in report.views.iter().zip(&ends) {
            let [from, to] = view.shades_depth_m;
            if let Some(from) = from {
                assert!(
                    (f64::from(from) - a).abs() < 1e-3 * a.max(1.0),
                    "{depths:?} {view:?} vs {a}"
                );
            }
            let to = f64::from(to.expect("a far end"));
            assert!(
                (to - b).abs() < 2e-3 * b.max(1.0),
                "{depths:?} {view:?} vs {b}"
            );
        }
    }
}

#[test]
fn the_last_cascade_fades_out_over_its_blend_band_and_frag_still_culls_exactly() {
    // A 280 m roof 10 m over the ground and the sun straight above: the ground under it is
    // all in shadow, so the fade is the only thing that lightens it.
    let sun = Sun::from_direction(Vec3::Y);
    let scene = box_on_plane(150.0, Vec3::new(280.0, 1.0, 280.0), 10.0, sun);
    let camera = Camera::look_at(
        Vec3::new(-60.0, 2.0, 0.0),
        Vec3::new(40.0, 0.0, 0.0),
        60f32.to_radians(),
        0.1,
        1000.0,
    );
    let mut settings = FrameSettings {
        sun,
        method: Method::Frag,
        measure: true,
        ..cascades(2)
    };
    settings.shadow.pcf = render_core::frame::PcfKernel::Off;
    settings.cascades.fit = render_core::cascades::CascadeFit::Tight;
    settings.cascades.splits = Splits {
        scheme: SplitScheme::Manual,
        manual_m: [20.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        ..Splits::default()
    };
    settings.cascades.blend = 0.5;
    let (report, capture) = render(&scene, &camera, &settings, 320, 200);
    let error = report.error.expect("measured");
    assert_eq!((error.missing_shadow_px, error.extra_shadow_px), (0, 0));
    assert_eq!(report.views.len(), 2, "{:?}", report.views);
    let [near, far] = report.views[1].shades_depth_m;
    let (near, far) = (near.expect("a near end"), far.expect("a far end"));
    assert!((near - 20.0).abs() < 1e-3);
    let width = 0.5 * (far - near);
    let (mut checked, mut fading) = (0, 0);
    for (i, p) in pixels_of(&capture, &camera, GROUND) {
        // Under the roof, away from its edge.
        if p.x.abs() > 130.0 || p.z.abs() > 130.0 {
            continue;
        }
        let depth = (p - camera.eye).dot(camera.forward);
        let kept = ((far - depth) / width).clamp(0.0, 1.0);
        let expected = 1.0 - kept;
        let got = f32::from(capture.shadow[i]) / 255.0;
        assert!(
            (got - expected).abs() < 0.02,
            "ground at depth {depth} m: light {got}, expected {expected} (band {}..{far} m)",
            far - width
        );
        checked += 1;
        if expected > 0.05 && expected < 0.95 {
            fading += 1;
        }
    }
    assert!(
        checked > 5000 && fading > 100,
        "{checked} pixels, {fading} in the fade"
    );
}

#[test]
fn focus_fits_each_tight_cascade_to_the_visible_receivers_without_error() {
    let ctx = gpu();
    let scene = load_builtin("city-small", 0).expect("city-small");
    let scene_gpu = SceneGpu::new(ctx, &scene);
    let camera = city_small_street_camera();
    let texels = |method: Method| {
        let mut settings = FrameSettings {
            sun: scene.sun,
            method,
            measure: true,
            ..cascades(3)
        };
        settings.cascades.fit = render_core::cascades::CascadeFit::Tight;
        let mut renderer = FrameRenderer::new(ctx);
        let input = FrameInput {
            camera: &camera,
            width: 256,
            height: 192,
            settings: &settings,
        };
        let report = last_of_frames(&mut renderer, (&scene, &scene_gpu), &input, 3);
        let e = report.error.expect("measured");
        assert_eq!(
            (e.missing_shadow_px, e.extra_shadow_px),
            (0, 0),
            "{method:?}"
        );
        report
            .views
            .iter()
            .map(|v| (v.name.clone(), v.texel_size_m[0] * v.texel_size_m[1]))
            .collect::<Vec<_>>()
    };
    let plain = texels(Method::Ref);
    let focused = texels(Method::Focus);
    assert_eq!(
        plain.iter().map(|v| &v.0).collect::<Vec<_>>(),
        focused.iter().map(|v| &v.0).collect::<Vec<_>>()
    );
    for ((name, a), (_, b)) in plain.iter().zip(&focused) {
        assert!(
            b <= &(a * 1.0001),
            "{name}: focused texel area {b} over {a}"
        );
    }
    assert!(
        plain
            .iter()
            .zip(&focused)
            .any(|((_, a), (_, b))| *b < a * 0.9),
        "some cascade shrinks to its receivers: {plain:?} {focused:?}"
    );
}

#[test]
fn the_texel_bias_grows_with_the_texel_and_lifts_the_shadow_of_a_floating_box_when_it_passes_the_gap()
 {
    // The sun straight above a 2 m slab 0.2 m thick floating 0.5 m over the ground: the map
    // holds its top, 0.7 m above the ground, which stays shadowed unless the bias moves the
    // receiver more than 0.7 m towards the light.
    let sun = Sun::from_direction(Vec3::Y);
    let scene = box_on_plane(20.0, Vec3::new(2.0, 0.2, 2.0), 0.5, sun);
    // Low, looking through the gap at the ground under the box.
    let camera = Camera::look_at(
        Vec3::new(0.0, 0.3, 4.0),
        Vec3::new(0.0, 0.0, 0.0),
        60f32.to_radians(),
        0.05,
        100.0,
    );
    let mut settings = FrameSettings {
        sun,
        ..FrameSettings::default()
    };
    settings.shadow.pcf = render_core::frame::PcfKernel::Off;
    settings.shadow.depth_bias_m = 0.0;
    settings.shadow.slope_bias = 0.0;
    settings.shadow.normal_offset_texels = 0.0;
    let (report, _) = render(&scene, &camera, &settings, 160, 120);
    let texel = report.views[0].texel_size_m[0].max(report.views[0].texel_size_m[1]);
    let under_the_box = |bias_m: f32| {
        let mut s = settings;
        s.shadow.depth_bias_texels = bias_m / texel;
        let (report, capture) = render(&scene, &camera, &s, 160, 120);
        assert!((report.views[0].depth_bias_m - bias_m).abs() < 1e-4 * bias_m.max(1.0));
        // Ground pixels within 0.5 m of the point under the box's centre.
        let light: Vec<u8> = pixels_of(&capture, &camera, GROUND)
            .filter(|(_, p)| p.x.abs() < 0.5 && p.z.abs() < 0.5)
            .map(|(i, _)| capture.shadow[i])
            .collect();
        assert!(
            light.len() > 10,
            "{} ground pixels under the box",
            light.len()
        );
        light
    };
    assert!(
        under_the_box(0.35).iter().all(|l| *l == 0),
        "a bias below the gap keeps the shadow"
    );
    assert!(
        under_the_box(1.0).iter().all(|l| *l == 255),
        "a bias past the gap loses it"
    );
}
