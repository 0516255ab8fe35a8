//! The observer camera: the frozen view's shadows seen from elsewhere, with its frustum and
//! light boxes drawn as lines, and the technique untouched by observing.

use glam::Vec3;
use render_core::frame::{
    FrameCapture, FrameInput, FrameRenderer, FrameSettings, Method, SceneGpu, ShadowSetup,
};
use render_core::geom::Camera;
use render_core::scene::Sun;
use shadowlab_tests::{box_on_plane, gpu};

#[test]
fn the_observer_sees_the_frozen_views_frustum_and_shadows_and_leaves_the_technique_alone() {
    let ctx = gpu();
    let sun = Sun::from_azimuth_elevation_deg(30.0, 50.0);
    let scene = box_on_plane(60.0, Vec3::new(2.0, 3.0, 2.0), 0.0, sun);
    let scene_gpu = SceneGpu::new(ctx, &scene);
    let view = Camera::look_at(
        Vec3::new(-6.0, 2.0, 9.0),
        Vec3::new(20.0, 0.0, -25.0),
        60f32.to_radians(),
        0.5,
        200.0,
    );
    let observer = Camera::look_at(
        Vec3::new(-40.0, 45.0, 50.0),
        Vec3::new(0.0, 0.0, -10.0),
        60f32.to_radians(),
        0.5,
        500.0,
    );
    let settings = FrameSettings {
        sun,
        method: Method::Frag,
        setup: ShadowSetup::Cascades,
        measure: true,
        ..FrameSettings::default()
    };
    let mut renderer = FrameRenderer::new(ctx);
    let (width, height) = (320, 240);
    let input = FrameInput {
        camera: &view,
        width,
        height,
        settings: &settings,
    };
    let before = renderer
        .render_and_wait(ctx, &scene, &scene_gpu, &input)
        .expect("frame");
    let observed_settings = FrameSettings {
        observer: Some(observer),
        ..settings
    };
    let observed = renderer
        .render_and_wait(
            ctx,
            &scene,
            &scene_gpu,
            &FrameInput {
                settings: &observed_settings,
                ..input
            },
        )
        .expect("observer frame");
    let names = |r: &render_core::frame::FrameReport| -> Vec<(String, [f32; 2])> {
        r.views
            .iter()
            .map(|v| (v.name.clone(), v.texel_size_m))
            .collect()
    };
    assert_eq!(names(&observed), names(&before), "the frozen views");
    assert_eq!(
        observed.error, None,
        "nothing is measured from the observer"
    );
    let capture = FrameCapture::read(ctx, renderer.targets().unwrap()).expect("readback");

    // The frozen camera's eye: its frustum's near corners meet there, in white.
    let clip = observer.clip_from_world(width as f32 / height as f32) * view.eye.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    let (px, py) = (
        ((ndc.x * 0.5 + 0.5) * width as f32) as i32,
        ((0.5 - ndc.y * 0.5) * height as f32) as i32,
    );
    let white_near = (-2..=2).any(|dy| {
        (-2..=2).any(|dx| {
            let (x, y) = (px + dx, py + dy);
            (0..width as i32).contains(&x)
                && (0..height as i32).contains(&y)
                && capture.color.get_pixel(x as u32, y as u32).0[..3] == [255, 255, 255]
        })
    });
    assert!(white_near, "the frustum's apex at pixel ({px}, {py})");
    // And the lines are thin: only a small share of the picture.
    let white = capture
        .color
        .pixels()
        .filter(|p| p.0[..3] == [255, 255, 255])
        .count();
    assert!(
        white > 50 && white < (width * height / 10) as usize,
        "{white} white pixels"
    );
    // The box's shadow is still there, seen from above: some ground pixels are shadowed.
    let ground_shadowed = capture
        .ids
        .iter()
        .zip(&capture.shadow)
        .filter(|(id, s)| **id == 1 && **s < 128)
        .count();
    assert!(
        ground_shadowed > 20,
        "{ground_shadowed} shadowed ground pixels"
    );

    // Back to the view: the technique goes on as if nothing happened.
    let after = renderer
        .render_and_wait(ctx, &scene, &scene_gpu, &input)
        .expect("frame");
    assert_eq!(names(&after), names(&before));
    assert_eq!(
        after.counts.casters_rendered,
        before.counts.casters_rendered
    );
    let e = after.error.expect("measured");
    assert_eq!((e.missing_shadow_px, e.extra_shadow_px), (0, 0));
}
