//! The observer camera's frame: the shadows of the last frame of the view, frozen, seen from
//! elsewhere, with the frozen view's frustum and light boxes as lines (`overlays/observer.rs`).

use super::{FrameInput, FrameRenderer, FrameReport, SceneGpu};
use crate::geom::Camera;
use crate::gpu::GpuContext;
use crate::overlays::observer_segments;
use crate::scene::Scene;
use crate::shadow_view::ShadowView;
use crate::technique::ShadowPasses;

/// What an observer frame keeps of the last frame of the frame's own camera.
pub(super) struct Frozen {
    pub views: Vec<ShadowView>,
    pub passes: ShadowPasses,
    pub camera: Camera,
    pub aspect: f32,
}

impl FrameRenderer {
    /// A frame seen from `observer` with the shadows of the last frame of `input.camera`:
    /// the technique neither prepares nor draws; the camera passes and the light term read the
    /// frozen views (selected by the frozen camera's depths), and lines show the frozen view.
    pub(super) fn render_observed(
        &mut self,
        ctx: &GpuContext,
        scene: &Scene,
        scene_gpu: &SceneGpu,
        input: &FrameInput<'_>,
        observer: &Camera,
    ) -> FrameReport {
        self.observing = true;
        let mut setup = self.begin_frame(
            ctx,
            scene,
            scene_gpu,
            &FrameInput {
                camera: observer,
                ..*input
            },
        );
        setup.settings.measure = false;
        let Some(frozen) = self.frozen.take() else {
            return FrameReport::default();
        };
        let frame_group = self.write_frame(ctx, &setup, &frozen.camera, scene_gpu, &frozen.views);
        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("Frame::observer_encoder"),
            });
        // No visibility pass: the next frame of the view culls and splits by the view's own
        // visible receivers, not the observer's.
        if let Some(targets) = self.targets.as_ref() {
            let draws = (scene_gpu, &self.camera_list, self.indirect_first_instance);
            self.techniques.shading().camera.draw_prepass(
                &mut encoder,
                &self.timer,
                targets,
                draws,
                &frame_group,
            );
        }
        self.draw_shading(ctx, &mut encoder, scene_gpu, &frame_group, &frozen.passes);
        self.draw_overlays(ctx, &mut encoder, &setup.settings);
        if let Some(targets) = self.targets.as_ref() {
            let far = crate::geom::view_depth_range(&frozen.camera, &scene.bounds())
                .map_or(frozen.camera.far_m, |(_, far)| far as f32);
            let segments = observer_segments(&frozen.camera, frozen.aspect, far, &frozen.views);
            self.observer_lines.draw(
                (&ctx.device, &ctx.queue),
                &mut encoder,
                targets,
                setup.clip_from_world,
                &segments,
            );
        }
        self.submit(ctx, encoder, &setup);
        self.frozen = Some(frozen);
        self.report(ctx, &setup)
    }
}
