//! One frame, in a fixed order:
//!
//! ```text
//! prepare_targets / prepare_scene_bindings      long-lived objects follow size and scene
//! fit light, prepare_draw_lists (CPU culling)   light frustum and camera frustum via the BVH
//! draw_camera_prepass                           depth + object id
//! mark_visible                                  visible objects and receivers from the ids
//! draw_shadow_map                               casters into the shadow map: the CPU's list,
//!                                               or GPU culling's two phases (culling/gpu.rs)
//! draw_shading                                  diffuse + ambient with PCF shadows
//! draw_overlays                                 light's view inset, error heat map
//! ```
//!
//! The window and the headless CLI both call [`FrameRenderer::render`]; the window only
//! presents the colour target.

mod capture;
pub mod compare;
pub(crate) mod gpu_data;
pub(crate) mod light_inset;
mod report;
pub mod scene_gpu;
mod settings;
pub mod targets;
mod visibility;

use std::time::Instant;

use glam::Vec3;

pub use capture::FrameCapture;
pub use report::{
    CasterOutcome, CpuTimings, FrameCounts, FrameReport, LightFacts, Stage, pass_label,
};
pub use scene_gpu::SceneGpu;
pub use settings::{FrameSettings, Method, Overlays, PcfKernel, ShadowSettings};
pub use targets::ViewTargets;
pub use visibility::VisibilityCounts;

use crate::culling::{CasterSelection, CullFrame, GpuCulling};
use crate::geom::{Camera, Frustum, LightFrustum, fit_focused_light, fit_whole_scene};
use crate::gpu::{FrameTimer, GpuContext, PassTiming};
use crate::metrics::{HeatMapOverlay, MeasureResources, Measured};
use crate::scene::Scene;
use crate::shadow_map::{LIGHT_VIEW_SIZE, MapKind, ShadowMapPass};
use gpu_data::FrameUniforms;
use scene_gpu::{DrawList, VERTEX_LAYOUT};
use targets::{COLOR_FORMAT, DEPTH_FORMAT, ID_FORMAT, SHADOW_FACTOR_FORMAT};
use visibility::VisibilityPass;

pub(crate) const INSTANCE_WGSL: &str = include_str!("instance.wgsl");
pub(crate) const COMMON_WGSL: &str = include_str!("common.wgsl");

/// The camera passes' shader; without forced early depth tests the shading pass cannot
/// measure, so the attribute is dropped there (and measurement is switched off).
fn camera_shader_source(early_depth_test: bool) -> String {
    let body = if early_depth_test {
        CAMERA_WGSL.to_owned()
    } else {
        CAMERA_WGSL.replace("@early_depth_test(force)", "")
    };
    format!("{}\n{body}", camera_prelude())
}

/// The scene prelude plus the camera's vertex stage and shadow lookup.
pub(crate) fn camera_prelude() -> String {
    format!("{}\n{SHADOW_LOOKUP_WGSL}", scene_prelude())
}

/// The declarations every scene pass starts with: the instance layout, then frame uniforms and
/// scene bindings.
pub(crate) fn scene_prelude() -> String {
    format!("{INSTANCE_WGSL}\n{COMMON_WGSL}")
}
pub(crate) const CAMERA_WGSL: &str = include_str!("camera.wgsl");
pub(crate) const SHADOW_LOOKUP_WGSL: &str = include_str!("shadow_lookup.wgsl");

/// Linear sky colour behind the scene.
const SKY: wgpu::Color = wgpu::Color {
    r: 0.42,
    g: 0.58,
    b: 0.80,
    a: 1.0,
};

/// What a frame looks at.
#[derive(Clone, Copy, Debug)]
pub struct FrameInput<'a> {
    pub camera: &'a Camera,
    pub width: u32,
    pub height: u32,
    pub settings: &'a FrameSettings,
}

/// Long-lived: pipelines, layouts, the shadow map and per-size targets. Per frame: uniforms,
/// draw lists and bind groups that depend on them.
pub struct FrameRenderer {
    frame_layout: wgpu::BindGroupLayout,
    prepass_pipeline: wgpu::RenderPipeline,
    shade_pipeline: wgpu::RenderPipeline,
    uniform_buffer: wgpu::Buffer,
    frame_bind_group: Option<(u64, wgpu::BindGroup)>,
    pub shadow_map: ShadowMapPass,
    visibility: VisibilityPass,
    camera_list: DrawList,
    caster_list: DrawList,
    /// Every caster, for the reference map when measuring.
    reference_list: DrawList,
    measure: MeasureResources,
    heat_map: HeatMapOverlay,
    light_inset: light_inset::LightInset,
    /// Incremental updates: what last frame's map was drawn for (scene, exclusions, light).
    static_map_key: Option<(u64, u64, [u32; 16])>,
    exclusions_version: u64,
    latest_measured: Option<Measured>,
    /// Whether the last frame measured; older measurements are not reported after a switch.
    measuring: bool,
    /// Per-instance outcome codes for the `casters` overlay, and their group (shading group 2).
    outcome_layout: wgpu::BindGroupLayout,
    outcome_buffer: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    outcome_codes: Vec<u32>,
    /// The GPU methods' state buffer in the outcome layout, and its scene.
    gpu_outcome_group: Option<(u64, wgpu::BindGroup)>,
    /// Whether the device can measure error and oracle exactly (see `camera.wgsl`).
    measurement_available: bool,
    targets: Option<ViewTargets>,
    timer: FrameTimer,
    frame_index: u64,
    latest_gpu: Option<(u64, Vec<PassTiming>)>,
    latest_visibility: Option<VisibilityCounts>,
    gpu_frames_in_flight: std::collections::VecDeque<u64>,
    indirect_first_instance: bool,
    /// Objects in the view frustum (camera passes), refilled per frame.
    scratch: Vec<u32>,
    /// The CPU methods' casters and each object's outcome.
    selection: CasterSelection,
    /// The GPU methods' masks, pyramids and caster tests.
    culling: GpuCulling,
    /// The method of the last frame (after fallbacks).
    method: Method,
    warned_no_indirect: bool,
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
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("Frame::frame_layout"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: true },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        let measure = MeasureResources::new(device);
        let outcome_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("Frame::outcome_layout"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let shadow_map = ShadowMapPass::new(
            device,
            &frame_layout,
            &scene_prelude(),
            ShadowSettings::default().resolution,
        );
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("Frame::camera_shader"),
            source: wgpu::ShaderSource::Wgsl(camera_shader_source(measurement_available).into()),
        });
        let prepass_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("Frame::prepass_layout"),
            bind_group_layouts: &[Some(&frame_layout)],
            immediate_size: 0,
        });
        let shade_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("Frame::shade_layout"),
                bind_group_layouts: &[
                    Some(&frame_layout),
                    Some(&measure.layout),
                    Some(&outcome_layout),
                ],
                immediate_size: 0,
            });
        let prepass_pipeline = camera_pipeline(
            device,
            "Frame::prepass_pipeline",
            &prepass_layout,
            &module,
            "fs_prepass",
            &[Some(ID_FORMAT.into())],
            (true, wgpu::CompareFunction::Greater),
        );
        let shade_pipeline = camera_pipeline(
            device,
            "Frame::shade_pipeline",
            &shade_pipeline_layout,
            &module,
            "fs_shade",
            &[Some(COLOR_FORMAT.into()), Some(SHADOW_FACTOR_FORMAT.into())],
            (false, wgpu::CompareFunction::Equal),
        );
        let uniform_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("Frame::uniforms"),
            size: size_of::<FrameUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let culling = GpuCulling::new(ctx, &frame_layout, &scene_prelude(), &camera_prelude());
        Self {
            frame_layout,
            prepass_pipeline,
            shade_pipeline,
            uniform_buffer,
            frame_bind_group: None,
            shadow_map,
            visibility: VisibilityPass::new(ctx),
            camera_list: DrawList::new(ctx, "Frame::camera_draws"),
            caster_list: DrawList::new(ctx, "Frame::caster_draws"),
            reference_list: DrawList::new(ctx, "Frame::reference_draws"),
            measure,
            heat_map: HeatMapOverlay::new(device),
            light_inset: light_inset::LightInset::new(device),
            static_map_key: None,
            exclusions_version: 0,
            latest_measured: None,
            measuring: false,
            outcome_layout,
            outcome_buffer: None,
            outcome_codes: Vec::new(),
            gpu_outcome_group: None,
            measurement_available,
            targets: None,
            timer: FrameTimer::new(ctx),
            frame_index: 0,
            latest_gpu: None,
            latest_visibility: None,
            gpu_frames_in_flight: std::collections::VecDeque::new(),
            indirect_first_instance: ctx
                .features()
                .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE),
            scratch: Vec::new(),
            selection: CasterSelection::default(),
            culling,
            method: Method::None,
            warned_no_indirect: false,
        }
    }

    /// The camera targets of the last frame (colour, ids, depth, shadow factor).
    pub fn targets(&self) -> Option<&ViewTargets> {
        self.targets.as_ref()
    }

    pub fn has_gpu_timestamps(&self) -> bool {
        self.timer.has_gpu_timestamps()
    }

    /// Renders one frame and submits it. Returns at once; GPU times and visible counts in the
    /// report are the newest that have come back (see [`FrameRenderer::collect_finished`]).
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        scene: &Scene,
        scene_gpu: &SceneGpu,
        input: &FrameInput<'_>,
    ) -> FrameReport {
        let started = Instant::now();
        self.frame_index += 1;
        let (width, height) = (input.width.max(1), input.height.max(1));
        let settings = &self.effective_settings(input.settings);
        self.method = settings.method;
        self.prepare_targets(ctx, width, height);
        self.prepare_scene_bindings(ctx, scene_gpu, settings.shadow.resolution);

        if let Some(targets) = &self.targets {
            self.culling
                .prepare_camera(ctx, (targets.width, targets.height), &targets.depth_view);
        }
        let aspect = width as f32 / height as f32;
        // FOCUS fits to the newest visible receivers that have come back.
        let focus = self
            .latest_visibility
            .filter(|_| settings.method == Method::Focus)
            .map(|v| v.receiver_bounds);
        let light = if settings.method.static_light() {
            fit_whole_scene(
                settings.sun.direction_to_sun,
                &scene.bounds(),
                self.shadow_map.resolution,
            )
        } else {
            fit_focused_light(
                input.camera,
                aspect,
                settings.sun.direction_to_sun,
                &scene.bounds(),
                focus.as_ref(),
                self.shadow_map.resolution,
            )
        };
        // An incremental update needs last frame's map under the same light, scene and
        // exclusions; anything else redraws it whole.
        let static_key = (settings.method == Method::Incr).then(|| {
            (
                scene_gpu.id,
                self.exclusions_version,
                light
                    .light_clip_from_world
                    .to_cols_array()
                    .map(f32::to_bits),
            )
        });
        let full_redraw = static_key.is_none() || static_key != self.static_map_key;
        self.static_map_key = static_key;
        let culling_started = Instant::now();
        let (counts, stages) = self.prepare_draw_lists(
            ctx,
            scene,
            scene_gpu,
            input.camera,
            aspect,
            &light,
            settings,
        );
        let culling_ms = culling_started.elapsed().as_secs_f64() * 1000.0;
        self.write_uniforms(ctx, input.camera, aspect, settings, &light);

        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("Frame::encoder"),
            });
        self.draw_camera_prepass(&mut encoder, scene_gpu);
        self.mark_visible(ctx, &mut encoder, scene_gpu);
        // The oracle method reads the reference map before its own map is drawn.
        let reference_first = settings.method == Method::Oracle;
        if reference_first {
            self.draw_reference_map(&mut encoder, scene_gpu);
        }
        if settings.method.gpu_driven() {
            self.draw_culled_shadow_map(
                ctx,
                &mut encoder,
                scene_gpu,
                (&light, input.camera.clip_from_world(aspect)),
                settings,
                (counts.casters_total, full_redraw),
            );
        } else {
            self.draw_shadow_map(&mut encoder, scene_gpu);
        }
        if settings.measure && !reference_first {
            self.draw_reference_map(&mut encoder, scene_gpu);
        }
        self.draw_shading(ctx, &mut encoder, scene_gpu);
        if settings.measure {
            self.measure.copy_counts(&mut encoder, self.frame_index);
        }
        self.measuring = settings.measure;
        self.draw_overlays(ctx, &mut encoder, settings);
        self.timer.resolve(&mut encoder);
        ctx.queue.submit([encoder.finish()]);
        self.timer.end_frame();
        self.visibility.after_submit();
        self.measure.after_submit();
        self.culling.after_submit();
        self.gpu_frames_in_flight.push_back(self.frame_index);

        let mut report = FrameReport {
            frame_index: self.frame_index,
            width,
            height,
            counts,
            stages,
            cpu: CpuTimings {
                culling_ms,
                encode_submit_ms: 0.0,
            },
            light: LightFacts {
                texel_size_m: light.texel_size_m,
                depth_range_m: light.depth_range_m,
                covers_whole_scene: light.covers_whole_scene,
            },
            ..FrameReport::default()
        };
        report.cpu.encode_submit_ms = started.elapsed().as_secs_f64() * 1000.0 - culling_ms;
        self.collect_finished(ctx, &mut report);
        report
    }

    /// Takes GPU times and visible counts that have come back, without waiting, and puts the
    /// newest into `report`. After [`GpuContext::wait_idle`] they belong to the last frame.
    pub fn collect_finished(&mut self, ctx: &GpuContext, report: &mut FrameReport) {
        // A non-blocking poll runs the map callbacks of finished work.
        if let Err(e) = ctx.device.poll(wgpu::PollType::Poll) {
            log::warn!("device poll failed: {e}");
        }
        while let Some(timings) = self.timer.take_finished() {
            let frame = self
                .gpu_frames_in_flight
                .pop_front()
                .unwrap_or(self.frame_index);
            self.latest_gpu = Some((frame, timings));
        }
        if let Some(counts) = self.visibility.take_latest() {
            self.latest_visibility = Some(counts);
        }
        if let Some((frame, timings)) = &self.latest_gpu {
            report.gpu.clone_from(timings);
            report.gpu_frame_index = Some(*frame);
        }
        if let Some(m) = self.measure.take_latest() {
            self.latest_measured = Some(m);
        }
        if let Some(m) = self.latest_measured.filter(|_| self.measuring) {
            report.counts.casters_oracle = Some(m.casters_oracle);
            report.error = Some(m.error);
            report.measured_frame_index = Some(m.frame_index);
        }
        if let Some(v) = self.latest_visibility {
            report.counts.receivers_visible = Some(v.receivers_visible);
            report.counts.objects_visible = Some(v.objects_visible);
        }
        self.culling.collect();
        if self.method.gpu_driven()
            && let Some(culled) = self.culling.latest().filter(|c| c.method == self.method)
        {
            report.counts.casters_rendered = culled.casters_rendered;
            report.counts.triangles_shadow = culled.triangles;
            report.stages.clone_from(&culled.stages);
            report.culled_frame_index = Some(culled.frame_index);
        }
    }

    /// The settings a frame runs with: measurement needs forced early depth tests, and the
    /// GPU methods indirect draws with a first instance (else `vfc`, with a warning).
    fn effective_settings(&mut self, requested: &FrameSettings) -> FrameSettings {
        let mut settings = *requested;
        settings.measure &= self.measurement_available;
        if settings.method.gpu_driven() && !self.indirect_first_instance {
            if !self.warned_no_indirect {
                log::warn!(
                    "this adapter has no INDIRECT_FIRST_INSTANCE: '{}' runs as 'vfc'",
                    settings.method.name()
                );
                self.warned_no_indirect = true;
            }
            settings.method = Method::Vfc;
        }
        settings
    }

    fn prepare_targets(&mut self, ctx: &GpuContext, width: u32, height: u32) {
        if self
            .targets
            .as_ref()
            .is_none_or(|t| t.width != width || t.height != height)
        {
            self.targets = Some(ViewTargets::new(&ctx.device, width, height));
        }
    }

    fn prepare_scene_bindings(&mut self, ctx: &GpuContext, scene_gpu: &SceneGpu, resolution: u32) {
        let resolution = resolution.clamp(
            ShadowSettings::MIN_RESOLUTION,
            ShadowSettings::MAX_RESOLUTION.min(ctx.device.limits().max_texture_dimension_2d),
        );
        self.shadow_map.ensure_resolution(&ctx.device, resolution);
        self.culling
            .prepare(ctx, scene_gpu, resolution, &self.shadow_map.depth_view);
        if self
            .frame_bind_group
            .as_ref()
            .is_none_or(|(id, _)| *id != scene_gpu.id)
        {
            let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("Frame::frame_bind_group"),
                layout: &self.frame_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: self.uniform_buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: scene_gpu.instance_buffer.as_entire_binding(),
                    },
                ],
            });
            self.frame_bind_group = Some((scene_gpu.id, group));
        }
    }

    /// The casters the method draws (on the CPU through the scene's BVH for now), every
    /// caster for the reference map when measuring, and view-frustum culling of the camera
    /// passes. Returns the counts and the caster stages in order.
    #[expect(
        clippy::too_many_arguments,
        reason = "one preparation step, all of its inputs"
    )]
    fn prepare_draw_lists(
        &mut self,
        ctx: &GpuContext,
        scene: &Scene,
        scene_gpu: &SceneGpu,
        camera: &Camera,
        aspect: f32,
        light: &LightFrustum,
        settings: &FrameSettings,
    ) -> (FrameCounts, Vec<Stage>) {
        let stages = self
            .selection
            .select(scene, scene_gpu.id, settings.method, light);
        if !settings.method.gpu_driven() {
            self.caster_list
                .upload(ctx, scene_gpu, self.selection.chosen());
        }
        if settings.measure || settings.method == Method::Oracle {
            self.reference_list
                .upload(ctx, scene_gpu, self.selection.all());
        }
        let casters_total = self.selection.all().len() as u32;
        // The casters overlay and the light's view inset colour objects by outcome.
        if !settings.method.gpu_driven() {
            self.upload_outcomes(ctx);
        }

        let camera_frustum = Frustum::from_clip_from_world(&camera.clip_from_world(aspect));
        self.scratch.clear();
        scene
            .bvh()
            .query_frustum(&camera_frustum, &mut self.scratch);
        self.scratch.sort_unstable();
        self.camera_list.upload(ctx, scene_gpu, &self.scratch);
        let counts = FrameCounts {
            casters_total,
            casters_rendered: self.caster_list.len(),
            objects_drawn_camera: self.camera_list.len(),
            triangles_shadow: self.caster_list.triangles,
            triangles_camera: self.camera_list.triangles,
            ..FrameCounts::default()
        };
        (counts, stages)
    }

    /// Leaves these instances out of the method's shadow map from the next frame on, while the
    /// reference map keeps them: shows what a caster contributes, and lets tests check that the
    /// error measure sees a missing caster.
    pub fn exclude_casters(&mut self, instances: &[u32]) {
        self.exclusions_version += 1;
        self.selection.exclude(instances);
        self.culling.exclude(instances);
    }

    /// Writes the outcome codes for the `casters` overlay, growing the buffer when needed.
    fn upload_outcomes(&mut self, ctx: &GpuContext) {
        self.outcome_codes.clear();
        self.outcome_codes.extend(
            self.selection
                .outcomes()
                .iter()
                .map(|&o| gpu_data::outcome_code(o)),
        );
        self.outcome_codes
            .resize(self.outcome_codes.len().max(1), 0);
        let bytes = (self.outcome_codes.len() * 4) as u64;
        if self
            .outcome_buffer
            .as_ref()
            .is_none_or(|(b, _)| b.size() < bytes)
        {
            self.outcome_buffer =
                Some(self.create_outcome_buffer(&ctx.device, bytes.next_power_of_two()));
        }
        if let Some((buffer, _)) = &self.outcome_buffer {
            ctx.queue
                .write_buffer(buffer, 0, bytemuck::cast_slice(&self.outcome_codes));
        }
    }

    fn create_outcome_buffer(
        &self,
        device: &wgpu::Device,
        size: u64,
    ) -> (wgpu::Buffer, wgpu::BindGroup) {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("Frame::outcomes"),
            size: size.max(4),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Frame::outcome_bind_group"),
            layout: &self.outcome_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: buffer.as_entire_binding(),
            }],
        });
        (buffer, group)
    }

    /// What happened to each instance in the shadow pass: the last frame's for the CPU
    /// methods, the newest that came back for the GPU methods.
    pub fn caster_outcomes(&self) -> &[CasterOutcome] {
        if self.method.gpu_driven() {
            self.culling.latest_outcomes().map_or(&[], |(_, o)| o)
        } else {
            self.selection.outcomes()
        }
    }

    /// Which instances some pixel of the last frame shows. Blocks: for tests and reports.
    pub fn read_visible(
        &self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
    ) -> Result<Vec<bool>, crate::gpu::GpuError> {
        crate::gpu::read_flags(
            ctx,
            &self.visibility.visible_flags,
            scene_gpu.instance_count,
            "visible flags",
        )
    }

    /// The instances drawn into the method's shadow map (as [`FrameRenderer::caster_outcomes`]),
    /// sorted.
    pub fn drawn_casters(&self) -> Vec<u32> {
        if self.method.gpu_driven() {
            (0..)
                .zip(self.caster_outcomes())
                .filter(|(_, o)| **o == CasterOutcome::Rendered)
                .map(|(i, _)| i)
                .collect()
        } else {
            self.selection.chosen().to_vec()
        }
    }

    /// The oracle flag of every instance from the last measured frame. Blocks: for tests and
    /// reports, never the window loop.
    pub fn read_oracle(
        &self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
    ) -> Result<Vec<bool>, crate::gpu::GpuError> {
        self.measure.read_oracle(ctx, scene_gpu.instance_count)
    }

    fn write_uniforms(
        &self,
        ctx: &GpuContext,
        camera: &Camera,
        aspect: f32,
        settings: &FrameSettings,
        light: &LightFrustum,
    ) {
        let rows = light.light_from_world.transpose();
        let (right, up) = (rows.x_axis.truncate(), rows.y_axis.truncate());
        let shadow = &settings.shadow;
        let uniforms = FrameUniforms {
            clip_from_world: camera.clip_from_world(aspect).to_cols_array_2d(),
            light_clip_from_world: light.light_clip_from_world.to_cols_array_2d(),
            eye_world: camera.eye.extend(1.0).to_array(),
            direction_to_sun: settings.sun.direction_to_sun.extend(1.0).to_array(),
            light_right: right.extend(light.texel_size_m[0]).to_array(),
            light_up: up.extend(light.texel_size_m[1]).to_array(),
            light_dir: light.light_direction.extend(light.depth_range_m).to_array(),
            shadow: [
                shadow.depth_bias_m,
                shadow.slope_bias,
                shadow.normal_offset_texels,
                self.shadow_map.resolution as f32,
            ],
            params: [
                shadow.pcf.width(),
                u32::from(shadow.shadows_enabled),
                u32::from(settings.measure),
                if settings.overlays.casters {
                    gpu_data::OVERLAY_CASTERS
                } else {
                    0
                },
            ],
        };
        debug_assert!(
            Vec3::from(uniforms.light_dir[..3].try_into().unwrap_or([0.0; 3])).is_finite()
        );
        ctx.queue
            .write_buffer(&self.uniform_buffer, 0, bytemuck::bytes_of(&uniforms));
    }

    fn frame_bind_group(&self) -> &wgpu::BindGroup {
        &self
            .frame_bind_group
            .as_ref()
            .expect("prepare_scene_bindings runs first")
            .1
    }

    fn targets_ref(&self) -> &ViewTargets {
        self.targets.as_ref().expect("prepare_targets runs first")
    }

    fn draw_camera_prepass(&self, encoder: &mut wgpu::CommandEncoder, scene_gpu: &SceneGpu) {
        let targets = self.targets_ref();
        let query = self.timer.begin_pass(pass_label::CAMERA_PREPASS, encoder);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("Frame::draw_camera_prepass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &targets.ids_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &targets.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: query
                    .as_ref()
                    .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.prepass_pipeline);
            pass.set_bind_group(0, self.frame_bind_group(), &[]);
            self.camera_list
                .draw(&mut pass, scene_gpu, self.indirect_first_instance);
        }
        self.timer.end_pass(encoder, query);
    }

    fn mark_visible(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
    ) {
        let query = self.timer.begin_pass(pass_label::VISIBILITY, encoder);
        let targets = self.targets.as_ref().expect("prepare_targets runs first");
        self.visibility.mark_visible(
            ctx,
            encoder,
            query
                .as_ref()
                .and_then(wgpu_profiler::GpuProfilerQuery::compute_pass_timestamp_writes),
            targets,
            scene_gpu,
            self.frame_index,
        );
        self.timer.end_pass(encoder, query);
    }

    fn draw_shadow_map(&self, encoder: &mut wgpu::CommandEncoder, scene_gpu: &SceneGpu) {
        self.draw_casters(encoder, scene_gpu, MapKind::Method);
    }

    /// The GPU methods: mask and first phase, its casters, the occlusion pyramid and second
    /// phase, the survivors (culling/gpu.rs).
    fn draw_culled_shadow_map(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
        (light, camera_clip_from_world): (&LightFrustum, glam::Mat4),
        settings: &FrameSettings,
        (casters_total, full_redraw): (u32, bool),
    ) {
        let shadow = &settings.shadow;
        let pcf_radius = shadow.pcf.width().div_ceil(2);
        let frame_bind_group = self.frame_bind_group().clone();
        let targets = self.targets.as_ref().expect("prepare_targets runs first");
        let frame = CullFrame {
            method: settings.method,
            frame_index: self.frame_index,
            light_clip_from_world: light.light_clip_from_world,
            camera_clip_from_world,
            volume_depth_pad: (shadow.normal_offset_texels.max(0.0) + 1.0)
                * light.texel_size_m[0].max(light.texel_size_m[1])
                / light.depth_range_m.max(1e-6),
            casters_total,
            full_redraw,
            mask_pad_texels: pcf_radius + shadow.normal_offset_texels.max(0.0).ceil() as u32 + 1,
            visible_flags: &self.visibility.visible_flags,
            frame_bind_group: &frame_bind_group,
            camera_depth: &targets.depth_view,
        };
        let reference = (
            &self.shadow_map.reference.depth_view,
            &self.shadow_map.reference.ids_view,
        );
        for phase in 0..2 {
            let query = self.timer.begin_scope(pass_label::CULLING, encoder);
            let encoded = if phase == 0 {
                self.culling.encode_first_phase(
                    ctx,
                    encoder,
                    scene_gpu,
                    &self.camera_list,
                    self.indirect_first_instance,
                    reference,
                    &frame,
                )
            } else {
                self.culling.encode_second_phase(encoder, scene_gpu, &frame)
            };
            self.timer.end_pass(encoder, query);
            let (Some(()), Some((draws, count))) = (encoded, self.culling.draws()) else {
                return;
            };
            let query = self.timer.begin_pass(pass_label::SHADOW_MAP, encoder);
            self.shadow_map.draw_culled(
                encoder,
                query
                    .as_ref()
                    .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
                &frame_bind_group,
                scene_gpu,
                draws,
                count,
                // Incremental updates keep last frame's map (every other method redraws it).
                phase == 0 && full_redraw,
            );
            self.timer.end_pass(encoder, query);
        }
        let query = self.timer.begin_scope(pass_label::CULLING, encoder);
        self.culling.encode_far_ends(encoder, settings.method);
        self.timer.end_pass(encoder, query);
    }

    /// The reference map for measuring: every caster, with ids. Timed as its own pass so
    /// reports can leave it out of the method's cost.
    fn draw_reference_map(&self, encoder: &mut wgpu::CommandEncoder, scene_gpu: &SceneGpu) {
        self.draw_casters(encoder, scene_gpu, MapKind::Reference);
    }

    fn draw_casters(&self, encoder: &mut wgpu::CommandEncoder, scene_gpu: &SceneGpu, map: MapKind) {
        let (label, casters) = match map {
            MapKind::Method => (pass_label::SHADOW_MAP, &self.caster_list),
            MapKind::Reference => (pass_label::REFERENCE_MAP, &self.reference_list),
        };
        let query = self.timer.begin_pass(label, encoder);
        self.shadow_map.draw_casters(
            encoder,
            query
                .as_ref()
                .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
            self.frame_bind_group(),
            scene_gpu,
            casters,
            self.indirect_first_instance,
            map,
        );
        self.timer.end_pass(encoder, query);
    }

    fn draw_shading(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        scene_gpu: &SceneGpu,
    ) {
        let measure_group = self
            .measure
            .prepare(ctx, encoder, &self.shadow_map, scene_gpu)
            .clone();
        if self.outcome_buffer.is_none() {
            // The overlay has not been used: bind a small zeroed buffer.
            self.outcome_buffer = Some(self.create_outcome_buffer(&ctx.device, 4));
        }
        let outcome_group = if self.method.gpu_driven()
            && let Some(group) = self.gpu_outcome_group(ctx, scene_gpu)
        {
            group
        } else {
            self.outcome_buffer
                .as_ref()
                .map(|(_, g)| g.clone())
                .expect("created above")
        };
        let targets = self.targets_ref();
        let query = self.timer.begin_pass(pass_label::SHADING, encoder);
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("Frame::draw_shading"),
                color_attachments: &[
                    Some(wgpu::RenderPassColorAttachment {
                        view: &targets.color_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(SKY),
                            store: wgpu::StoreOp::Store,
                        },
                    }),
                    Some(wgpu::RenderPassColorAttachment {
                        view: &targets.shadow_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                            store: wgpu::StoreOp::Store,
                        },
                    }),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &targets.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: query
                    .as_ref()
                    .and_then(wgpu_profiler::GpuProfilerQuery::render_pass_timestamp_writes),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.shade_pipeline);
            pass.set_bind_group(0, self.frame_bind_group(), &[]);
            pass.set_bind_group(1, &measure_group, &[]);
            pass.set_bind_group(2, &outcome_group, &[]);
            self.camera_list
                .draw(&mut pass, scene_gpu, self.indirect_first_instance);
        }
        self.timer.end_pass(encoder, query);
    }

    /// The GPU methods' per-object states as the `casters` overlay's outcome codes, bound once
    /// per scene.
    fn gpu_outcome_group(
        &mut self,
        ctx: &GpuContext,
        scene_gpu: &SceneGpu,
    ) -> Option<wgpu::BindGroup> {
        if self
            .gpu_outcome_group
            .as_ref()
            .is_none_or(|(id, _)| *id != scene_gpu.id)
        {
            let state = self.culling.state_buffer()?;
            let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("Frame::gpu_outcome_bind_group"),
                layout: &self.outcome_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: state.as_entire_binding(),
                }],
            });
            self.gpu_outcome_group = Some((scene_gpu.id, group));
        }
        self.gpu_outcome_group.as_ref().map(|(_, g)| g.clone())
    }

    /// The light's view inset is always rendered (the panel shows it); the `light-view`
    /// overlay also draws it into the top-left corner of the colour target, and the `error`
    /// overlay tints pixels whose shadow differs from the reference.
    fn draw_overlays(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        settings: &FrameSettings,
    ) {
        let inset = self.light_inset_group(ctx, settings);
        if let Some(inset) = &inset {
            self.light_inset.draw(
                encoder,
                inset,
                &self.shadow_map.light_view_view,
                None,
                wgpu::LoadOp::Clear(wgpu::Color::BLACK),
            );
        }
        if settings.overlays.error && settings.measure {
            self.heat_map.draw(&ctx.device, encoder, self.targets_ref());
        }
        if settings.overlays.light_view
            && let Some(inset) = &inset
        {
            let targets = self.targets_ref();
            let side = (LIGHT_VIEW_SIZE as f32)
                .min(targets.width.min(targets.height) as f32 * 0.4)
                .max(1.0);
            let margin = (side * 0.05).round();
            self.light_inset.draw(
                encoder,
                inset,
                &targets.color_view,
                Some([margin, margin, side, side]),
                wgpu::LoadOp::Load,
            );
        }
    }

    /// The light's view inset's inputs this frame: the method's map and mask, and where the
    /// reference map was drawn, the casters the method culled.
    fn light_inset_group(
        &self,
        ctx: &GpuContext,
        settings: &FrameSettings,
    ) -> Option<wgpu::BindGroup> {
        let (mask_raster, mask_bits, mask_scale, mask_shown) =
            self.culling.mask_for_inset(settings.method)?;
        let outcomes = if settings.method.gpu_driven() {
            self.culling.state_buffer()?
        } else {
            &self.outcome_buffer.as_ref()?.0
        };
        let reference_drawn = settings.measure || settings.method == Method::Oracle;
        let show = mask_shown
            | if reference_drawn {
                light_inset::show::OUTCOMES
            } else {
                0
            };
        Some(self.light_inset.bind(
            &ctx.device,
            &ctx.queue,
            &light_inset::InsetSources {
                shadow_depth: &self.shadow_map.depth_view,
                reference_ids: &self.shadow_map.reference.ids_view,
                outcomes,
                mask_raster,
                mask_bits,
                show,
                mask_scale,
            },
        ))
    }
}

/// A pipeline over the camera's view of the scene (`vs_main`, back faces culled, the camera's
/// reversed depth): the prepass, shading, and the receiver passes of GPU culling.
pub(crate) fn camera_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    fragment_entry: &str,
    targets: &[Option<wgpu::ColorTargetState>],
    (depth_write, depth_compare): (bool, wgpu::CompareFunction),
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[Some(VERTEX_LAYOUT)],
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(depth_write),
            depth_compare: Some(depth_compare),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fragment_entry),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}
