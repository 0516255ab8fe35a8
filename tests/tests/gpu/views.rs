//! The shadow-view seam: a frame whose single map's view is rendered twice culls and counts
//! each view on its own, per-view counts sum to the totals, and the picture and the maps are
//! the one-view frame's, for every method.

use render_core::frame::{FrameCapture, FrameReport, Method};
use render_core::geom::Camera;
use render_core::gpu::read_texture_layer;
use render_core::scene::{Scene, load_builtin};
use shadowlab_tests::{city_small_street_camera, gpu, measured_frames};

/// What one frame of a view count gave.
struct Frame {
    report: FrameReport,
    capture: FrameCapture,
    /// Per view, what happened to each instance.
    outcomes: Vec<Vec<render_core::frame::CasterOutcome>>,
    /// Per view, the method's shadow map.
    maps: Vec<Vec<f32>>,
    oracle: Vec<bool>,
}

/// `frames` measured frames of `method` with the view rendered `views` times; the last one.
fn last_frame(scene: &Scene, camera: &Camera, method: Method, views: u32, frames: usize) -> Frame {
    let (renderer, scene_gpu, reports) =
        measured_frames((scene, camera), (method, scene.sun), frames, |r| {
            r.set_repeated_views(views);
        });
    let report = reports.last().expect("a frame").clone();
    let ctx = gpu();
    let maps = (0..views)
        .map(|layer| {
            read_texture_layer(
                ctx,
                renderer.shadow_depth_texture(),
                wgpu::TextureAspect::DepthOnly,
                layer,
            )
            .expect("shadow map layer")
            .to_f32()
        })
        .collect();
    Frame {
        capture: FrameCapture::read(ctx, renderer.targets().expect("targets")).expect("readback"),
        outcomes: renderer.view_caster_outcomes(),
        maps,
        oracle: renderer.read_oracle(ctx, &scene_gpu).expect("oracle"),
        report,
    }
}

fn street() -> (Scene, Camera) {
    let city = load_builtin("city-small", 0).expect("city-small");
    let camera = city_small_street_camera();
    (city, camera)
}

#[test]
fn two_views_of_one_light_cull_and_count_apart_and_shade_as_one() {
    let (scene, camera) = street();
    for method in Method::ALL {
        let name = method.name();
        // Temporal methods lean on last frame's light visibility: give both the same frames.
        let frames = if method.temporal() { 3 } else { 1 };
        let one = last_frame(&scene, &camera, method, 1, frames);
        let two = last_frame(&scene, &camera, method, 2, frames);

        assert_eq!(one.report.views.len(), 1, "{name}");
        assert_eq!(two.report.views.len(), 2, "{name}");
        for view in &two.report.views {
            assert_eq!(
                view.stages, one.report.views[0].stages,
                "{name}: {}",
                view.name
            );
            assert_eq!(
                view.casters_rendered, one.report.views[0].casters_rendered,
                "{name}: {}",
                view.name
            );
            assert_eq!(
                view.casters_oracle, one.report.views[0].casters_oracle,
                "{name}: {}",
                view.name
            );
        }
        assert_eq!(
            two.report.counts.casters_rendered,
            2 * one.report.counts.casters_rendered,
            "{name}: each view draws its own casters"
        );
        assert!(
            one.report.counts.casters_rendered > 0 || method == Method::Incr,
            "{name}: the street view has shadows to draw"
        );
        assert_eq!(two.outcomes.len(), 2, "{name}");
        assert_eq!(
            two.outcomes[0], one.outcomes[0],
            "{name}: view 0's outcomes"
        );
        assert_eq!(
            two.outcomes[1], one.outcomes[0],
            "{name}: view 1's outcomes"
        );
        assert_eq!(two.oracle, one.oracle, "{name}: oracle flags");

        // Each view's map is the one-view frame's map, texel for texel.
        assert_eq!(two.maps.len(), 2);
        for (layer, map) in two.maps.iter().enumerate() {
            assert!(
                map == &one.maps[0],
                "{name}: layer {layer} differs from the one-view map"
            );
        }
        // And the picture is the same, pixel for pixel.
        assert_eq!(
            two.capture.shadow, one.capture.shadow,
            "{name}: method shadow"
        );
        assert_eq!(
            two.capture.reference_shadow, one.capture.reference_shadow,
            "{name}: reference shadow"
        );
        assert!(two.capture.color == one.capture.color, "{name}: colour");
        if !method.may_err() {
            let e = two.report.error.expect("measured");
            assert_eq!((e.missing_shadow_px, e.extra_shadow_px), (0, 0), "{name}");
        }
    }
}

#[test]
fn per_view_counts_sum_to_the_totals() {
    let (scene, camera) = street();
    for method in [
        Method::Vfc,
        Method::Ref,
        Method::Frag,
        Method::DrConservative,
        Method::Oracle,
    ] {
        let name = method.name();
        let frame = last_frame(&scene, &camera, method, 3, 2);
        let report = &frame.report;
        let views = &report.views;
        assert_eq!(views.len(), 3, "{name}");
        assert_eq!(
            views.iter().map(|v| v.casters_rendered).sum::<u32>(),
            report.counts.casters_rendered,
            "{name}: casters drawn"
        );
        assert_eq!(
            views.iter().map(|v| v.triangles_shadow).sum::<u64>(),
            report.counts.triangles_shadow,
            "{name}: triangles"
        );
        assert_eq!(
            views
                .iter()
                .map(|v| v.casters_oracle.unwrap_or(0))
                .sum::<u32>(),
            report.counts.casters_oracle.expect("measured"),
            "{name}: oracle"
        );
        assert_eq!(report.stages.len(), method.stages().len() + 1, "{name}");
        for (k, stage) in report.stages.iter().enumerate() {
            let per_view: u32 = views.iter().map(|v| v.stages[k].remaining).sum();
            assert_eq!(per_view, stage.remaining, "{name}: stage {}", stage.name);
        }
        assert!(
            report.shadow_failure.is_none(),
            "{name}: {:?}",
            report.shadow_failure
        );
    }
}
