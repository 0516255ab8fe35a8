//! Whole-frame consistency: GPU counts against the read-back targets, and hard placements.

use std::collections::HashSet;

use glam::Vec3;
use render_core::frame::FrameSettings;
use render_core::geom::Camera;
use render_core::scene::{Sun, load_builtin};
use shadowlab_tests::{box_on_plane, pixels_of, render, translated};

#[test]
fn visible_counts_match_the_object_id_target() {
    let scene = load_builtin("boxes", 0).expect("boxes exists");
    let camera = Camera::look_at(
        Vec3::new(-25.0, 18.0, 25.0),
        Vec3::ZERO,
        50f32.to_radians(),
        0.1,
        200.0,
    );
    let settings = FrameSettings {
        sun: scene.sun,
        ..FrameSettings::default()
    };
    let (report, capture) = render(&scene, &camera, &settings, 301, 203);
    let ids: HashSet<u32> = capture.ids.iter().copied().filter(|&id| id != 0).collect();
    let receivers = ids
        .iter()
        .filter(|&&id| scene.instances[id as usize - 1].receives_shadow)
        .count();
    assert!(ids.len() >= 4, "the boxes should be visible: {ids:?}");
    assert_eq!(report.counts.objects_visible, Some(ids.len() as u32));
    assert_eq!(report.counts.receivers_visible, Some(receivers as u32));
    assert_eq!(report.counts.casters_total, scene.caster_count() as u32);
    assert_eq!(
        report.counts.casters_rendered,
        scene.caster_count() as u32,
        "every caster of this small scene is in the light frustum"
    );
    // Sky and geometry are both present and the depth of geometry is inside (0, 1].
    assert!(capture.ids.contains(&0));
    for (id, depth) in capture.ids.iter().zip(&capture.depth) {
        if *id != 0 {
            assert!(
                *depth > 0.0 && *depth <= 1.0,
                "depth {depth} of object {id}"
            );
        }
    }
}

#[test]
fn shadows_hold_100_km_from_the_origin() {
    let sun = Sun::from_azimuth_elevation_deg(30.0, 50.0);
    let offset = Vec3::new(100_000.0, 0.0, -60_000.0);
    let scene = translated(&box_on_plane(30.0, Vec3::splat(4.0), 0.0, sun), offset);
    let camera = Camera::look_at(
        offset + Vec3::new(0.0, 25.0, 30.0),
        offset,
        55f32.to_radians(),
        0.1,
        500.0,
    );
    let settings = FrameSettings {
        sun,
        ..FrameSettings::default()
    };
    let (report, capture) = render(&scene, &camera, &settings, 256, 256);
    assert!(!report.light.covers_whole_scene);
    let texel = report.light.texel_size_m[0].max(report.light.texel_size_m[1]);
    let (min, max) = (
        offset + Vec3::new(-2.0, 0.0, -2.0),
        offset + Vec3::new(2.0, 4.0, 2.0),
    );
    let (mut shadowed, mut wrong, mut checked) = (0, 0, 0);
    for (i, p) in pixels_of(&capture, &camera, 1) {
        let Some(expected) =
            shadowlab_tests::expected_shadow(p, sun.direction_to_sun, min, max, texel * 3.0)
        else {
            continue;
        };
        checked += 1;
        let dark = capture.shadow[i] == 0;
        let lit = capture.shadow[i] == 255;
        shadowed += usize::from(expected && dark);
        wrong += usize::from(if expected { !dark } else { !lit });
    }
    assert!(checked > 20_000, "{checked} ground pixels checked");
    assert!(
        shadowed > 200,
        "the box's shadow is missing 100 km out ({shadowed} px)"
    );
    assert_eq!(
        wrong, 0,
        "{wrong} of {checked} ground pixels have the wrong shadow 100 km out"
    );
}

#[test]
fn casters_overlay_tints_objects_by_their_shadow_pass_outcome() {
    use render_core::frame::{FrameCapture, FrameInput, FrameRenderer, SceneGpu};
    let sun = Sun::from_azimuth_elevation_deg(30.0, 60.0);
    let scene = box_on_plane(20.0, Vec3::splat(4.0), 0.0, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 8.0, 14.0),
        Vec3::ZERO,
        50f32.to_radians(),
        0.1,
        100.0,
    );
    let mut settings = FrameSettings {
        sun,
        ..FrameSettings::default()
    };
    settings.overlays.casters = true;
    let ctx = shadowlab_tests::gpu();
    let scene_gpu = SceneGpu::new(ctx, &scene);
    let mut renderer = FrameRenderer::new(ctx);
    renderer.exclude_casters(&[1]);
    let input = FrameInput {
        camera: &camera,
        width: 200,
        height: 150,
        settings: &settings,
    };
    renderer
        .render_and_wait(ctx, &scene, &scene_gpu, &input)
        .expect("frame");
    let capture = FrameCapture::read(ctx, renderer.targets().expect("targets")).expect("readback");
    let dominant = |id: u32, test: &dyn Fn([i32; 3]) -> bool| {
        let pixels: Vec<[i32; 3]> = capture
            .ids
            .iter()
            .zip(capture.color.pixels())
            .filter(|(i, _)| **i == id)
            .map(|(_, p)| [p.0[0].into(), p.0[1].into(), p.0[2].into()])
            .collect();
        assert!(
            pixels.len() > 200,
            "object {id} covers {} pixels",
            pixels.len()
        );
        pixels.iter().filter(|c| test(**c)).count() * 10 >= pixels.len() * 9
    };
    // The ground was rendered into the shadow map: green. The box was excluded: purple.
    assert!(
        dominant(1, &|[r, g, b]| g > r + 20 && g > b + 20),
        "ground is not tinted green"
    );
    assert!(
        dominant(2, &|[r, g, b]| b > g + 20 && r > g),
        "the excluded box is not tinted purple"
    );
}

#[test]
fn one_texel_readback_matches_the_full_target() {
    use render_core::frame::{FrameCapture, FrameInput, FrameRenderer, SceneGpu};
    use render_core::gpu::read_texel;
    let scene = load_builtin("boxes", 0).expect("boxes");
    let camera = Camera::look_at(
        Vec3::new(-25.0, 18.0, 25.0),
        Vec3::ZERO,
        50f32.to_radians(),
        0.1,
        200.0,
    );
    let settings = FrameSettings {
        sun: scene.sun,
        ..FrameSettings::default()
    };
    let ctx = shadowlab_tests::gpu();
    let scene_gpu = SceneGpu::new(ctx, &scene);
    let mut renderer = FrameRenderer::new(ctx);
    let input = FrameInput {
        camera: &camera,
        width: 163,
        height: 97,
        settings: &settings,
    };
    renderer
        .render_and_wait(ctx, &scene, &scene_gpu, &input)
        .expect("frame");
    let targets = renderer.targets().expect("targets");
    let capture = FrameCapture::read(ctx, targets).expect("readback");
    for (x, y) in [(0, 0), (81, 48), (162, 96), (100, 10), (17, 90)] {
        let bytes = read_texel(ctx, &targets.ids, x, y)
            .expect("read")
            .expect("inside");
        let id = u32::from_le_bytes(bytes.try_into().expect("4 bytes"));
        assert_eq!(
            id,
            capture.ids[(y * capture.width + x) as usize],
            "texel ({x}, {y})"
        );
    }
    assert!(
        read_texel(ctx, &targets.ids, 163, 0)
            .expect("read")
            .is_none()
    );
}
