//! Stencil shadow volumes of the sun (Crow 1977; Lloyd et al., "CC Shadow Volumes", 2004):
//! exact per-pixel hard shadows, a technique with no map. Per frame:
//!
//! ```text
//! silhouettes (compute)  per caster and edge of its mesh (edges.rs), the quad's
//!                        multiplicity from its triangles' facing; per triangle, whether it
//!                        caps the volume; records appended for six indirect draws
//!                        (records.wgsl)
//! volume depth           the camera's visible surface again, into a depth-stencil target
//!                        (the camera's vertex stage, so the depths are the prepass's)
//! shadow volumes         quads and caps extruded past the scene, two-sided stencil, depth
//!                        clamped where the adapter can (nothing clipped at the far plane);
//!                        z-pass where the camera's near rectangle cannot lie in a caster's
//!                        volume (DOOM 3's test; caps only where the volume ends
//!                        short of infinity, and an open mesh's), else z-fail with caps
//! light term             lit where the stencil at the point's pixel is 0 (light.wgsl)
//! ```
//!
//! Every caster's volume is drawn; Lloyd's culling and clamping build on this.

mod box_clamp;
mod calibrate;
pub mod edges;
mod exact;
mod fill;
mod find_passes;
mod frame;
mod pipelines;
mod receivers;
mod scene;
mod sweep_prune;

use crate::culling::{CasterOutcome, Method, Stage};
use crate::gpu::{
    AsyncReadback, GpuContext, bind_group_layout, pass_label, pipeline_layout, shader_module,
    storage, texture, uniform, view_entry,
};
use crate::scene::Scene;
use crate::scene_gpu::SceneGpu;
use crate::shadow_view::ShadowView;
pub use crate::shadow_view::{VolumeClamp, VolumePassChoice, VolumeSettings};
use crate::technique::{
    DrawInput, InsetSources, ShadowPasses, ShadowReport, ShadowTechnique, TechniqueInput,
    TechniqueOverlays,
};
pub use crate::technique::{VolumeFill, VolumePasses};
pub use calibrate::measured_pixels_per_vertex;
use fill::{Fill, FillDraw};
use find_passes::{FindInput, FindPasses};
#[cfg(test)]
pub(crate) use pipelines::shader_sources;
use pipelines::{
    DrawModules, StripPipelines, VolumeFrameGpu, VolumePass, depth_pipeline, depth_stencil_pass,
    shader_source,
};
#[cfg(test)]
pub(crate) use scene::CAP_RECORDS;
use scene::{SceneLayouts, SceneVolumes};

/// The light term's file (group 1 of the shading pass).
pub const LIGHT_WGSL: &str = "volumes/light.wgsl";

/// The depth-stencil target at the view's size and the light group that reads its stencil.
struct StencilTarget {
    size: (u32, u32),
    depth_stencil: wgpu::TextureView,
    light_group: wgpu::BindGroup,
    points: receivers::ReceiverPoints,
}

/// Stencil shadow volumes of the sun: long-lived pipelines, the scene's edges and the
/// stencil target.
pub struct VolumeTechnique {
    format: wgpu::TextureFormat,
    depth_clamped: bool,
    /// The adapter's kind, which sets the grid test's budget of loop iterations.
    device_type: wgpu::DeviceType,
    scene_layout: wgpu::BindGroupLayout,
    find_layout: wgpu::BindGroupLayout,
    draw_layout: wgpu::BindGroupLayout,
    light_layout: wgpu::BindGroupLayout,
    fill: Fill,
    /// The receiver grid, the cull and the silhouettes in compute.
    find: FindPasses,
    depth: wgpu::RenderPipeline,
    volumes: StripPipelines,
    /// The `volumes` overlay's, and the frame group it draws with (the last frame's).
    overlay: StripPipelines,
    frame_group: Option<wgpu::BindGroup>,
    uniforms: wgpu::Buffer,
    scene: Option<SceneVolumes>,
    target: Option<StencilTarget>,
    excluded: Vec<u32>,
    method: Method,
    /// The slices of the view this frame's receivers are told apart by.
    slices: u32,
    /// Exact clamping's trees, clamping by boxes' order, and this frame's light frame.
    exact: exact::ExactClamp,
    boxes: box_clamp::BoxClamp,
    light_frame: box_clamp::LightFrame,
    /// The CPU time of the last frame's clamping (exact or by boxes), milliseconds.
    clamp_cpu_ms: f64,
    /// Whether the draws clip intervals to their strips (`CLIP_DISTANCES`), and whether
    /// this frame's do: cut into more than one strip.
    clip_distances: bool,
    cut: bool,

    /// The counters of the frames in flight, and the newest that came back with its frame.
    readback: AsyncReadback,
    latest: Option<(u64, VolumePasses)>,
    /// Whether the frames in flight count fill, and the newest fill that came back.
    fill_counted: bool,
    latest_fill: Option<VolumeFill>,
}

impl VolumeTechnique {
    /// `frame_layout`: group 0 of every scene pass.
    pub fn new(ctx: &GpuContext, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let device = &ctx.device;
        let features = ctx.features();
        let format = if features.contains(wgpu::Features::DEPTH32FLOAT_STENCIL8) {
            wgpu::TextureFormat::Depth32FloatStencil8
        } else {
            wgpu::TextureFormat::Depth24PlusStencil8
        };
        let depth_clamped = features.contains(wgpu::Features::DEPTH_CLIP_CONTROL);
        let cut = features.contains(wgpu::Features::CLIP_DISTANCES);
        // The fragment stages read the frame's uniforms (volumes/strips_clipped.wgsl).
        let stages =
            wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT;
        let scene_layout = bind_group_layout(
            device,
            "Volumes::scene_layout",
            stages,
            &[
                uniform(),
                storage(true),
                storage(true),
                storage(true),
                storage(true),
                storage(true),
            ],
        );
        let find_layout = receivers::find_layout(device);
        let draw_layout = bind_group_layout(
            device,
            "Volumes::draw_layout",
            wgpu::ShaderStages::VERTEX,
            &[storage(true); 7],
        );
        let light_layout = bind_group_layout(
            device,
            "Volumes::light_layout",
            wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
            &[texture(
                wgpu::TextureSampleType::Uint,
                wgpu::TextureViewDimension::D2,
            )],
        );
        let find_module =
            shader_module(device, "Volumes::find", shader_source("volumes/find.wgsl"));
        let find_pipeline_layout = pipeline_layout(
            device,
            "Volumes::find_pipeline_layout",
            &[frame_layout, &scene_layout, &find_layout],
        );
        let depth = depth_pipeline(device, frame_layout, format);
        let draw_modules = DrawModules::new(device, cut);
        let draw_pipeline_layout = pipeline_layout(
            device,
            "Volumes::draw_pipeline_layout",
            &[frame_layout, &scene_layout, &draw_layout],
        );
        let volumes = StripPipelines::new(
            device,
            (&draw_pipeline_layout, &draw_modules),
            (format, depth_clamped),
            VolumePass::Stencil,
        );
        let overlay = StripPipelines::new(
            device,
            (&draw_pipeline_layout, &draw_modules),
            (format, depth_clamped),
            VolumePass::Overlay,
        );
        let fill = Fill::new(
            device,
            [frame_layout, &scene_layout, &draw_layout],
            &draw_modules,
            (format, depth_clamped),
        );
        Self {
            fill,
            format,
            depth_clamped,
            device_type: ctx.adapter.get_info().device_type,
            find: FindPasses::new(ctx, &find_module, &find_pipeline_layout),
            depth,
            volumes,
            overlay,
            frame_group: None,
            uniforms: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("Volumes::uniforms"),
                size: size_of::<VolumeFrameGpu>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            scene_layout,
            find_layout,
            draw_layout,
            light_layout,
            scene: None,
            target: None,
            excluded: Vec::new(),
            method: Method::None,
            slices: 1,
            exact: exact::ExactClamp::default(),
            boxes: box_clamp::BoxClamp::default(),
            light_frame: [[0.0; 4]; 3],
            clamp_cpu_ms: 0.0,
            clip_distances: cut,
            cut: false,
            readback: AsyncReadback::new(
                device,
                "Volumes::counters_readback",
                scene::READBACK_BYTES,
                3,
            ),
            latest: None,
            fill_counted: false,
            latest_fill: None,
        }
    }

    /// Builds the scene's edges and casters when the scene (or the excluded set) changed.
    fn ensure_scene(&mut self, ctx: &GpuContext, scene: &Scene, scene_gpu: &SceneGpu) {
        if self
            .scene
            .as_ref()
            .is_some_and(|s| s.scene_id == scene_gpu.id && s.excluded == self.excluded)
        {
            return;
        }
        // Their buffers grow with the scene's edges: a large scene can pass what one binding
        // may hold, which the allocation's fault names.
        self.scene = Some(ctx.allocate(&SceneVolumes::asked(scene), 0, |device| {
            SceneVolumes::new(
                device,
                &SceneLayouts {
                    scene: &self.scene_layout,
                    draw: &self.draw_layout,
                },
                &self.uniforms,
                (scene, scene_gpu),
                &self.excluded,
            )
        }));
        if let Some(built) = &self.scene {
            log::info!(
                "shadow volumes: {} of {} meshes closed (the others cast from both sides of \
                 every triangle), {} casters",
                built.closed_meshes,
                built.meshes,
                built.casters
            );
        }
    }

    /// The depth-stencil target at the view's size.
    fn ensure_target(&mut self, device: &wgpu::Device, size: (u32, u32)) {
        if self.target.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("Volumes::depth_stencil"),
            size: wgpu::Extent3d {
                width: size.0.max(1),
                height: size.1.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let stencil = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("Volumes::stencil"),
            aspect: wgpu::TextureAspect::StencilOnly,
            ..Default::default()
        });
        let light_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("Volumes::light_group"),
            layout: &self.light_layout,
            entries: &[view_entry(0, &stencil)],
        });
        self.target = Some(StencilTarget {
            size,
            depth_stencil: texture.create_view(&wgpu::TextureViewDescriptor::default()),
            light_group,
            points: receivers::ReceiverPoints::new(device, size),
        });
    }
}

impl VolumeTechnique {
    /// The last frame's intervals of `instance`'s volume: where each starts and ends, metres
    /// along the light from the caster (empty: culled; `None`: not a caster, or no frame yet).
    /// Blocks: for a click in the window, tests and reports.
    pub fn read_intervals(
        &self,
        ctx: &GpuContext,
        instance: u32,
    ) -> Result<Option<Vec<[f32; 2]>>, crate::gpu::GpuError> {
        self.scene
            .as_ref()
            .map_or(Ok(None), |scene| scene.read_intervals(ctx, instance))
    }
}

impl ShadowTechnique for VolumeTechnique {
    fn name(&self) -> &'static str {
        "volumes"
    }

    fn light_term(&self) -> (&'static str, &wgpu::BindGroupLayout) {
        (LIGHT_WGSL, &self.light_layout)
    }

    /// `none` draws every caster's volume (standard shadow volumes); every other method culls
    /// them by the visible receivers' boxes (BVOL's test on the volumes, Lloyd's 3.1).
    fn effective_method(&self, requested: Method) -> Method {
        if requested == Method::None {
            Method::None
        } else {
            Method::Bvol
        }
    }

    fn prepare(&mut self, ctx: &GpuContext, input: &TechniqueInput<'_>) -> Vec<ShadowView> {
        self.ensure_scene(ctx, input.scene, input.scene_gpu);
        self.method = self.effective_method(input.method);
        let scene = self.scene.as_ref().expect("ensured above");
        self.slices = input.volumes.clamp.slices(&input.volumes);
        self.cut = self.slices > 1 && input.volumes.strips;
        // What a vertex costs in pixels matters only to clamping; it is measured the first
        // time a frame clamps without a user's figure (once per process, `calibrate.rs`).
        let pixels_per_vertex = match (input.volumes.clamp, input.volumes.vertex_pixels) {
            (_, Some(pixels)) => pixels as f32,
            (VolumeClamp::None, None) => 0.0,
            (_, None) => calibrate::pixels_per_vertex(ctx, self.format),
        };
        let uniforms = frame::uniforms(
            input,
            scene,
            self.method,
            (self.slices, pixels_per_vertex),
            self.device_type,
        );
        self.light_frame = [uniforms.right, uniforms.up, uniforms.travel];
        ctx.queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        Vec::new()
    }

    fn draw(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: &TechniqueInput<'_>,
        draw: &DrawInput<'_>,
    ) -> ShadowPasses {
        self.ensure_target(&draw.ctx.device, (draw.targets.width, draw.targets.height));
        let (offset, picture) =
            VolumeFrameGpu::picture_bytes((draw.targets.width, draw.targets.height));
        draw.ctx
            .queue
            .write_buffer(&self.uniforms, offset, bytemuck::bytes_of(&picture));
        let (Some(scene), Some(target)) = (self.scene.as_ref(), self.target.as_ref()) else {
            unreachable!("ensured in prepare and above");
        };
        let find_group =
            target
                .points
                .find_group(&draw.ctx.device, &self.find_layout, scene, draw.targets);
        encoder.clear_buffer(&scene.grid, 0, Some(scene::grid_bytes(self.slices)));
        encoder.clear_buffer(&scene.cells, 0, None);
        let clamp_started = std::time::Instant::now();
        if input.volumes.clamp == VolumeClamp::Exact {
            let size = (draw.targets.width, draw.targets.height);
            self.exact
                .write(draw.ctx, input, scene, (size, self.light_frame[2]));
        }
        self.boxes.last = None;
        self.boxes.under_point = false;
        if input.volumes.clamp == VolumeClamp::Boxes {
            self.boxes.under_point = input.point_light.is_some();
            if !self.boxes.under_point {
                self.boxes.write(draw.ctx, input, scene, self.light_frame);
            }
        }
        self.clamp_cpu_ms = clamp_started.elapsed().as_secs_f64() * 1e3;
        let scope = draw
            .timer
            .open_scope(pass_label::VOLUME_SILHOUETTES, encoder);
        self.find.encode(
            encoder,
            &scope,
            &FindInput {
                scene,
                frame_group: draw.frame_group,
                find_group: &find_group,
                size: (draw.targets.width, draw.targets.height),
            },
        );
        scope.close(encoder);
        let query = draw.timer.begin_pass(pass_label::VOLUME_DEPTH, encoder);
        {
            let mut pass = depth_stencil_pass(
                encoder,
                ("Volumes::depth", &target.depth_stencil),
                Some((0.0, 0)),
                query.as_ref(),
            );
            pass.set_pipeline(&self.depth);
            pass.set_bind_group(0, draw.frame_group, &[]);
            draw.camera_draws
                .draw(&mut pass, input.scene_gpu, draw.indirect_first_instance);
        }
        draw.timer.end_pass(encoder, query);
        let query = draw.timer.begin_pass(pass_label::SHADOW_VOLUMES, encoder);
        {
            let mut pass = depth_stencil_pass(
                encoder,
                ("Volumes::stencil", &target.depth_stencil),
                None,
                query.as_ref(),
            );
            pass.set_bind_group(0, draw.frame_group, &[]);
            pass.set_bind_group(1, &scene.scene_group, &[]);
            pass.set_bind_group(2, &scene.draw_group, &[]);
            self.volumes.draw(&mut pass, &scene.draws, self.cut);
        }
        draw.timer.end_pass(encoder, query);
        self.frame_group = Some(draw.frame_group.clone());
        self.fill_counted = input.measure_fill;
        if input.measure_fill {
            self.fill.draw(
                (&draw.ctx.device, &draw.ctx.queue),
                encoder,
                (draw.targets, &target.depth_stencil),
                &FillDraw {
                    frame: draw.frame_group,
                    scene: &scene.scene_group,
                    records: &scene.draw_group,
                    draws: &scene.draws,
                    cut: self.cut,
                    counters: &scene.counters,
                },
            );
        }
        encoder.copy_buffer_to_buffer(
            &scene.draws,
            0,
            &scene.counters,
            scene::DRAWS_OFFSET,
            scene::DRAWS_BYTES,
        );
        self.readback
            .copy(encoder, &scene.counters, input.frame_index);
        ShadowPasses {
            light_group: target.light_group.clone(),
            outcomes: scene.outcomes.clone(),
        }
    }

    fn after_submit(&mut self) {
        self.readback.map_copied();
    }

    fn collect(&mut self) -> ShadowReport {
        if let Some((frame, bytes)) = self.readback.take_latest() {
            let (passes, fill) = scene::read_counters(bytemuck::cast_slice(&bytes));
            self.latest = Some((frame, passes));
            self.latest_fill = self.fill_counted.then_some(fill);
        }
        let Some(scene) = self.scene.as_ref() else {
            return ShadowReport::default();
        };
        let kept = self.latest.map(|(_, passes)| passes.z_pass + passes.z_fail);
        let mut stages = vec![Stage::new("scene casters", scene.casters)];
        if self.method != Method::None {
            stages.push(Stage::new(
                "visible receiver points (volume)",
                kept.unwrap_or(scene.casters),
            ));
        }
        let mut notes = Vec::new();
        if let Some((_, passes)) = self.latest.filter(|(_, p)| p.whole_past_budget > 0) {
            notes.push(format!(
                "{} casters kept their whole volume: gathering their receivers ran past the \
                 cull's budget of loop iterations",
                passes.whole_past_budget
            ));
        }
        if let Some(b) = self.boxes.last {
            notes.push(format!(
                "clamping by boxes on the CPU: {:.2} ms, {} potential receivers, {} overlapping \
                 pairs, {} swaps to sort",
                self.clamp_cpu_ms, b.receivers, b.pairs, b.swaps
            ));
        }
        if self.boxes.under_point {
            notes.push(
                "clamping by boxes is the sun's: under a point light the volumes are clamped by \
                 the visible receiver points (continuous)"
                    .into(),
            );
        }
        if !self.clip_distances && self.slices > 1 {
            notes.push(
                "this adapter has no CLIP_DISTANCES: clamped volumes are drawn across the whole \
                 picture, not only across their strips"
                    .into(),
            );
        }
        if !self.depth_clamped {
            notes.push(
                "this adapter has no DEPTH_CLIP_CONTROL: volumes past the far plane are clipped"
                    .into(),
            );
        }
        ShadowReport {
            casters_total: scene.casters,
            casters_rendered: Some(match self.method {
                Method::None => scene.casters,
                _ => kept.unwrap_or(scene.casters),
            }),
            stages,
            culled_frame_index: self.latest.map(|(frame, ..)| frame),
            volume_fill: self.latest_fill,
            volume_passes: self.latest.map(|(_, passes)| passes),
            notes,
            cpu_culling_ms: self.clamp_cpu_ms,
            ..ShadowReport::default()
        }
    }

    fn has_results_of(&self, frame_index: u64) -> bool {
        self.latest.is_some_and(|(frame, _)| frame >= frame_index)
    }

    fn draw_overlay(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        targets: &crate::view::ViewTargets,
        overlays: TechniqueOverlays,
    ) {
        if overlays.fill {
            self.fill.draw_heat(device, encoder, targets);
        }
        let (Some(scene), Some(target), Some(frame_group)) =
            (&self.scene, &self.target, &self.frame_group)
        else {
            return;
        };
        if !overlays.volumes || target.size != (targets.width, targets.height) {
            return;
        }
        let mut pass = pipelines::read_only_pass(
            encoder,
            "Volumes::overlay",
            Some(&targets.color_view),
            &target.depth_stencil,
        );
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(1, &scene.scene_group, &[]);
        pass.set_bind_group(2, &scene.draw_group, &[]);
        self.overlay.draw(&mut pass, &scene.draws, self.cut);
    }

    fn inset(&self, _view: u32) -> Option<InsetSources<'_>> {
        None
    }

    fn view_outcomes(&self) -> Vec<&[CasterOutcome]> {
        Vec::new()
    }

    fn exclude(&mut self, instances: &[u32]) {
        self.excluded = instances.to_vec();
        self.excluded.sort_unstable();
    }
}
