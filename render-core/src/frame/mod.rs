//! One frame, in a fixed order (DESIGN.md, "One frame"):
//!
//! ```text
//! begin_frame                 settings, targets, the camera's draws (BVH)
//! technique.prepare           the shadow views, into the view buffer and frame uniforms
//! camera prepass              depth + object id
//! mark_visible                visible objects and receivers from the ids
//! technique.draw              per view: masks, caster culling, maps (shadow_map/, culling/)
//! shading                     diffuse + ambient with the technique's light reaching each point
//! overlays                    light's view inset, error heat map
//! ```
//!
//! The window and the headless CLI both call [`FrameRenderer::render`]; the window only
//! presents the colour target. The frame knows its shadows only through
//! [`crate::technique::ShadowTechnique`].

mod camera;
mod capture;
pub mod compare;
mod flicker;
mod legend;
mod observer;
mod report;
mod results;
mod settings;
mod techniques;

use std::time::Instant;

pub use capture::FrameCapture;
pub use flicker::{FLICKER_MOVE_M, FLICKER_TURN_DEG, Flicker, moved, turned};
pub use legend::{LegendEntry, LegendGroup, legend};
pub use report::{CpuTimings, FrameCounts, FrameReport, LightFacts};
pub use settings::{FrameSettings, LispsmSettings, Overlays, ShadowSetup};

pub use crate::culling::{CasterOutcome, Method, Stage};
pub use crate::gpu::pass_label;
pub use crate::scene_gpu::SceneGpu;
pub use crate::shadow_view::{PcfKernel, ShadowSettings};
pub use crate::technique::ViewReport;
pub use crate::view::{ViewTargets, VisibilityCounts};

use camera::ShadingGroups;
#[cfg(test)]
pub(crate) use camera::shader_source as camera_shader_source;
use results::Latest;

use crate::geom::{Camera, Frustum};
use crate::gpu::{FrameTimer, GpuContext};
use crate::metrics::{HeatMapOverlay, MeasureResources, ShadowError};
use crate::overlays::{LightInset, ObserverLines};
use crate::scene::Scene;
use crate::scene_gpu::DrawList;
use crate::shadow_view::{ShadowView, ViewBuffer};
use crate::technique::{DrawInput, ShadowPasses, TechniqueInput};
use crate::truth::{ExactShadow, FrameGroups, PendingLight, SurfacePoint};
use crate::view::gpu_data::{FrameUniforms, OVERLAY_CASTERS, OVERLAY_VIEWS, punctual_light_fields};
use crate::view::{FrameBindings, VisibilityPass};
use observer::Frozen;
use techniques::{Family, SingleViews, Techniques};

/// What a frame looks at.
#[derive(Clone, Copy, Debug)]
pub struct FrameInput<'a> {
    pub camera: &'a Camera,
    pub width: u32,
    pub height: u32,
    pub settings: &'a FrameSettings,
}

/// This frame's settings (after fallbacks), its camera and what the camera passes draw.
struct FrameSetup {
    settings: FrameSettings,
    aspect: f32,
    /// The view's height in pixels.
    height: u32,
    clip_from_world: glam::Mat4,
    started: Instant,
    camera_culling_ms: f64,
}

/// Long-lived: pipelines, layouts, the technique and per-size targets. Per frame: uniforms,
/// views, draw lists and the bind groups that depend on them.
pub struct FrameRenderer {
    bindings: FrameBindings,
    views: ViewBuffer,
    /// The shadow techniques (maps of the sun: one view or one per cascade; stencil volumes)
    /// and the passes that read their light, one active per frame.
    techniques: Techniques,
    /// What the single map renders (its fitted view but in tests).
    single_views: SingleViews,
    visibility: VisibilityPass,
    /// Objects in the view frustum (camera passes), refilled per frame.
    camera_list: DrawList,
    scratch: Vec<u32>,
    measure: MeasureResources,
    heat_map: HeatMapOverlay,
    light_inset: LightInset,
    /// The last frame of the frame's own camera: its views and passes, which an observer
    /// frame shades with, and the camera and aspect its lines show.
    frozen: Option<Frozen>,
    observer_lines: ObserverLines,
    /// The last frame was seen from the observer (the technique did not draw).
    observing: bool,
    last_groups: Option<[wgpu::BindGroup; 3]>,
    timer: FrameTimer,
    /// Whether the device can measure error and oracle exactly (see `camera.wgsl`).
    measurement_available: bool,
    indirect_first_instance: bool,
    targets: Option<ViewTargets>,
    frame_index: u64,
    /// What has come back from the GPU, and what the last frame was.
    latest: Latest,
    /// Why the frame's technique cannot cast its point light's shadows.
    refused: Option<&'static str>,
}

impl FrameRenderer {
    pub fn new(ctx: &GpuContext) -> Self {
        let device = &ctx.device;
        let measurement_available = ctx
            .features()
            .contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST);
        if !measurement_available {
            log::warn!(
                "this adapter cannot force early depth tests (SHADER_EARLY_DEPTH_TEST), so shadow error \
                 and oracle are not measured"
            );
        }
        let bindings = FrameBindings::new(device);
        let views = ViewBuffer::new(device);
        let measure = MeasureResources::new(device);
        let techniques = Techniques::new(
            ctx,
            [&bindings.layout, views.pass_layout(), &measure.layout],
            measurement_available,
        );
        Self {
            bindings,
            views,
            techniques,
            single_views: SingleViews::Fitted { copies: 1 },
            visibility: VisibilityPass::new(ctx),
            camera_list: DrawList::new(ctx, "Frame::camera_draws"),
            scratch: Vec::new(),
            measure,
            heat_map: HeatMapOverlay::new(device),
            light_inset: LightInset::new(device),
            frozen: None,
            observer_lines: ObserverLines::new(device),
            observing: false,
            last_groups: None,
            timer: FrameTimer::new(ctx),
            measurement_available,
            indirect_first_instance: ctx
                .features()
                .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE),
            targets: None,
            frame_index: 0,
            latest: Latest::default(),
            refused: None,
        }
    }

    /// Renders one frame and submits it. Returns at once; GPU times, visible counts and GPU
    /// culling's counts in the report are the newest that have come back (see
    /// [`FrameRenderer::collect_finished`]).
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        scene: &Scene,
        scene_gpu: &SceneGpu,
        input: &FrameInput<'_>,
    ) -> FrameReport {
        if let Some(observer) = input.settings.observer
            && self.frozen.is_some()
        {
            return self.render_observed(ctx, scene, scene_gpu, input, &observer);
        }
        // A lost device, or an allocation that failed since the last frame (a scene's).
        if let Some(fault) = ctx.take_fault() {
            return self.faulted(fault);
        }
        self.observing = false;
        self.techniques
            .activate(ctx, Family::of(input.settings.setup));
        let setup = self.begin_frame(ctx, scene, scene_gpu, input);
        let technique_input = self.technique_input(&setup, scene, scene_gpu, input.camera);
        self.techniques.arrange(&setup.settings, &self.single_views);
        let views = self.techniques.active_mut().prepare(ctx, &technique_input);
        if let Some(fault) = ctx.take_fault() {
            // What the technique allocated is invalid: built again when next asked for.
            self.techniques.discard_active(ctx);
            return self.faulted(fault);
        }
        let frame_group = self.write_frame(ctx, &setup, input.camera, scene_gpu, &views);
        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("Frame::encoder"),
            });
        let Some(targets) = self.targets.as_ref() else {
            return FrameReport::default();
        };
        let draws = (scene_gpu, &self.camera_list, self.indirect_first_instance);
        self.techniques.shading().camera.draw_prepass(
            &mut encoder,
            &self.timer,
            targets,
            draws,
            &frame_group,
        );
        self.visibility.mark_visible(
            ctx,
            (&mut encoder, &self.timer),
            targets,
            scene_gpu,
            self.frame_index,
        );
        let shadows = self.techniques.active_mut().draw(
            &mut encoder,
            &technique_input,
            &DrawInput {
                ctx,
                views: &views,
                view_buffer: &self.views,
                frame_group: &frame_group,
                camera_clip_from_world: setup.clip_from_world,
                camera_draws: &self.camera_list,
                targets,
                visible_flags: &self.visibility.visible_flags,
                timer: &self.timer,
                indirect_first_instance: self.indirect_first_instance,
            },
        );
        self.draw_shading(ctx, &mut encoder, scene_gpu, &frame_group, &shadows);
        self.draw_overlays(ctx, &mut encoder, &setup.settings);
        self.submit(ctx, encoder, &setup);
        self.frozen = Some(Frozen {
            views,
            passes: shadows,
            camera: *input.camera,
            aspect: setup.aspect,
        });
        self.report(ctx, &setup)
    }

    /// Settings after the device's fallbacks, targets at the view's size, and the objects in
    /// the view frustum for the camera passes.
    fn begin_frame(
        &mut self,
        ctx: &GpuContext,
        scene: &Scene,
        scene_gpu: &SceneGpu,
        input: &FrameInput<'_>,
    ) -> FrameSetup {
        let started = Instant::now();
        self.frame_index += 1;
        let (width, height) = (input.width.max(1), input.height.max(1));
        let mut settings = *input.settings;
        settings.measure &= self.measurement_available;
        settings.method = self.techniques.active().effective_method(settings.method);
        self.refused = self.techniques.refuse_point_light(&mut settings);
        if self
            .targets
            .as_ref()
            .is_none_or(|t| t.width != width || t.height != height)
        {
            self.targets = Some(ViewTargets::new(&ctx.device, width, height));
        }
        let aspect = width as f32 / height as f32;
        let clip_from_world = input.camera.clip_from_world(aspect);
        let camera_started = Instant::now();
        self.scratch.clear();
        scene.bvh().query_frustum(
            &Frustum::from_clip_from_world(&clip_from_world),
            &mut self.scratch,
        );
        self.scratch.sort_unstable();
        self.camera_list.upload(ctx, scene_gpu, &self.scratch);
        FrameSetup {
            height,
            settings,
            aspect,
            clip_from_world,
            started,
            camera_culling_ms: camera_started.elapsed().as_secs_f64() * 1000.0,
        }
    }

    /// What the technique is told of this frame.
    fn technique_input<'a>(
        &self,
        setup: &'a FrameSetup,
        scene: &'a Scene,
        scene_gpu: &'a SceneGpu,
        camera: &'a Camera,
    ) -> TechniqueInput<'a> {
        let settings = &setup.settings;
        TechniqueInput {
            scene,
            scene_gpu,
            camera,
            aspect: setup.aspect,
            method: settings.method,
            shadow: &settings.shadow,
            direction_to_sun: settings.sun.direction_to_sun,
            point_light: settings.point_light,
            measure: settings.measure,
            measure_fill: settings.measure || settings.overlays.fill,
            volumes: settings.volumes,
            layered: &settings.layered,
            virtual_maps: settings.virtual_maps,
            frame_index: self.frame_index,
            visible_receivers: self.latest.visibility.map(|v| v.receiver_bounds),
            visible_depths_m: self
                .latest
                .visibility
                .and_then(|v| v.receiver_depths_m(camera.near_m, camera.far_m)),
        }
    }

    /// The frame's views into the view buffer, its uniforms, and group 0 of scene passes.
    fn write_frame(
        &mut self,
        ctx: &GpuContext,
        setup: &FrameSetup,
        camera: &Camera,
        scene_gpu: &SceneGpu,
        views: &[ShadowView],
    ) -> wgpu::BindGroup {
        self.views.write(ctx, views);
        let settings = &setup.settings;
        let shadow = &settings.shadow;
        let [point_light, spot, spot_inner] = punctual_light_fields(settings.point_light);
        let uniforms = FrameUniforms {
            clip_from_world: setup.clip_from_world.to_cols_array_2d(),
            eye_world: camera.eye.extend(1.0).to_array(),
            camera_forward: camera
                .forward
                .extend(2.0 * (camera.fov_y_rad * 0.5).tan() / setup.height as f32)
                .to_array(),
            direction_to_sun: (settings.sun.direction_to_sun)
                .extend(self.techniques.active().sun_scale())
                .to_array(),
            point_light,
            spot,
            spot_inner,
            shadow: [
                shadow.depth_bias_m,
                shadow.slope_bias,
                shadow.normal_offset_texels,
                if settings.cascaded_sun() {
                    settings.cascades.blend.clamp(0.0, 0.5)
                } else {
                    0.0
                },
            ],
            params: [
                shadow.pcf.width(),
                u32::from(shadow.shadows_enabled),
                u32::from(settings.measure),
                (u32::from(settings.overlays.casters) * OVERLAY_CASTERS)
                    | (u32::from(settings.overlays.cascades) * OVERLAY_VIEWS),
            ],
            views: [
                views.len() as u32,
                scene_gpu.instance_count,
                if settings.cascaded_sun() {
                    settings.cascades.selection.code()
                } else {
                    0
                },
                shadow.depth_bias_texels.max(0.0).to_bits(),
            ],
        };
        self.bindings
            .prepare(ctx, &uniforms, scene_gpu, &self.views)
    }

    fn draw_shading(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        frame_group: &wgpu::BindGroup,
        shadows: &ShadowPasses,
    ) {
        let measure_group = self.measure.prepare(
            ctx,
            encoder,
            scene_gpu,
            self.views.count(),
            &shadows.outcomes,
        );
        let Some(targets) = self.targets.as_ref() else {
            return;
        };
        self.techniques.shading().camera.draw_shading(
            encoder,
            &self.timer,
            targets,
            (scene_gpu, &self.camera_list, self.indirect_first_instance),
            &ShadingGroups {
                frame: frame_group,
                light: &shadows.light_group,
                measure: &measure_group,
            },
        );
        self.last_groups = Some([
            frame_group.clone(),
            shadows.light_group.clone(),
            measure_group,
        ]);
    }

    /// The light's view inset (of the view `overlays.inset_view`) is always rendered (the panel
    /// shows it); the `light-view`
    /// overlay also draws it into the top-left corner of the colour target, and the `error`
    /// overlay tints pixels whose shadow differs from the reference.
    fn draw_overlays(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        settings: &FrameSettings,
    ) {
        let Some(targets) = self.targets.as_ref() else {
            return;
        };
        if settings.overlays.error && settings.measure {
            self.heat_map.draw(&ctx.device, encoder, targets);
        }
        let own = crate::technique::TechniqueOverlays {
            fill: settings.overlays.fill,
            volumes: settings.overlays.volumes,
            light_view: settings.overlays.light_view,
        };
        if own.fill || own.volumes || own.light_view {
            self.techniques
                .active()
                .draw_overlay(&ctx.device, encoder, targets, own);
        }
        let last_view = self.views.count().saturating_sub(1);
        if let Some(sources) = self
            .techniques
            .active()
            .inset(settings.overlays.inset_view.min(last_view))
        {
            let group = self.light_inset.bind(&ctx.device, &ctx.queue, &sources);
            let onto = settings.overlays.light_view.then_some((
                &targets.color_view,
                targets.width,
                targets.height,
            ));
            self.light_inset.draw(encoder, &group, onto);
        }
    }

    fn submit(&mut self, ctx: &GpuContext, mut encoder: wgpu::CommandEncoder, setup: &FrameSetup) {
        if setup.settings.measure {
            self.measure
                .copy_counts(&mut encoder, self.frame_index, self.views.count());
        }
        self.timer.resolve(&mut encoder);
        ctx.queue.submit([encoder.finish()]);
        self.timer.end_frame();
        self.visibility.after_submit();
        self.measure.after_submit();
        self.techniques.active_mut().after_submit();
        self.latest
            .submitted(self.frame_index, &setup.settings, setup.camera_culling_ms);
    }

    fn report(&mut self, ctx: &GpuContext, setup: &FrameSetup) -> FrameReport {
        let (width, height) = self
            .targets
            .as_ref()
            .map_or((1, 1), |t| (t.width, t.height));
        let mut report = FrameReport {
            frame_index: self.frame_index,
            width,
            height,
            technique: self.techniques.active().name(),
            counts: FrameCounts {
                objects_drawn_camera: self.camera_list.len(),
                triangles_camera: self.camera_list.triangles,
                ..FrameCounts::default()
            },
            ..FrameReport::default()
        };
        self.collect_finished(ctx, &mut report);
        report.cpu.encode_submit_ms =
            setup.started.elapsed().as_secs_f64() * 1000.0 - report.cpu.culling_ms;
        report
    }

    /// The fraction of light the last frame's technique lets reach each point, read with the
    /// frame's own views and maps at points it need not have rasterised (the truth's). Blocks:
    /// for measuring, never the window loop's every frame.
    pub fn light_at(
        &self,
        ctx: &GpuContext,
        points: &[SurfacePoint],
    ) -> Result<Vec<f32>, crate::gpu::GpuError> {
        let Some([frame, light, measure]) = &self.last_groups else {
            return Ok(vec![1.0; points.len()]);
        };
        self.techniques.shading().at_points.evaluate(
            ctx,
            &FrameGroups {
                frame,
                light,
                measure,
            },
            points,
        )
    }

    /// As [`FrameRenderer::light_at`], without waiting: the light arrives once a later
    /// [`FrameRenderer::collect_finished`] (or any device poll) has run after the GPU is done.
    /// `None` before the first frame.
    pub fn request_light_at(
        &self,
        ctx: &GpuContext,
        points: &[SurfacePoint],
    ) -> Option<PendingLight> {
        let [frame, light, measure] = self.last_groups.as_ref()?;
        Some(self.techniques.shading().at_points.submit(
            ctx,
            &FrameGroups {
                frame,
                light,
                measure,
            },
            points,
        ))
    }

    /// The last frame's shadow against the exact shadow of its view: counted pixels whose
    /// shadow differs, missing or extra, and those of them off the truth's edges (looked for
    /// inside the pixel through `rays`, the trees `exact` was cast through). Blocks.
    pub fn exact_error(
        &self,
        ctx: &GpuContext,
        (exact, rays): (&ExactShadow, &crate::truth::SceneRays),
    ) -> Result<ShadowError, crate::gpu::GpuError> {
        Ok(exact.error_within(rays, &self.light_at(ctx, &exact.points)?))
    }

    /// The camera targets of the last frame (colour, ids, depth, shadow factor).
    pub fn targets(&self) -> Option<&ViewTargets> {
        self.targets.as_ref()
    }

    pub fn has_gpu_timestamps(&self) -> bool {
        self.timer.has_gpu_timestamps()
    }

    /// The light's view inset as egui displays it (sRGB bytes read as `Rgba8Unorm`).
    pub fn light_view_texture(&self) -> &wgpu::TextureView {
        self.light_inset.texture_unorm()
    }

    /// Renders the single map's view `count` times, each into its own layer, culled and
    /// counted on its own ([`SunView`]): a test of the per-view path.
    pub fn set_repeated_views(&mut self, count: u32) {
        self.single_views = SingleViews::Fitted {
            copies: count.max(1),
        };
    }

    /// Renders the single map (`ShadowSetup::Single`) on these views instead of fitting one,
    /// each into the layer its target names: a test renders a virtual level's texel grid as
    /// one map. No views: back to the fitted view.
    pub fn set_single_map_views(&mut self, views: Vec<ShadowView>) {
        self.single_views = if views.is_empty() {
            SingleViews::Fitted { copies: 1 }
        } else {
            SingleViews::Given(views)
        };
    }

    /// Where FRAG's mask comes from: the prepass's surface targets (the default) or a second
    /// pass over the visible geometry, to compare the two.
    pub fn set_fragment_mask_source(&mut self, source: crate::culling::FragmentMaskSource) {
        self.techniques.maps.set_fragment_mask_source(source);
    }

    /// The method's shadow maps (a depth array, one layer per view), for tests.
    pub fn shadow_depth_texture(&self) -> &wgpu::Texture {
        self.techniques.maps.depth_texture()
    }

    /// Leaves these instances out of the method's shadow maps from the next frame on, while
    /// the reference keeps them: shows what a caster contributes, and lets tests check that
    /// the error measure sees a missing caster.
    pub fn exclude_casters(&mut self, instances: &[u32]) {
        self.techniques.exclude(instances);
    }
}
