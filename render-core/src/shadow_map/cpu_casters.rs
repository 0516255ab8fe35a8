//! The CPU side of a map technique's casters: per view, the CPU methods' choice and draw list,
//! the reference list of every caster, and the outcome codes the overlays read. Long-lived
//! buffers, refilled per frame.

use crate::culling::codes::outcome_code;
use crate::culling::{CasterOutcome, CasterSelection, Method, Stage};
use crate::geom::LightFrustum;
use crate::gpu::GpuContext;
use crate::scene::Scene;
use crate::scene_gpu::{DrawList, SceneGpu};

/// Per view: what the CPU chose, and its draws.
struct ViewCasters {
    selection: CasterSelection,
    draws: DrawList,
    stages: Vec<Stage>,
}

/// The CPU methods' casters for every view, and every caster for the reference maps.
pub struct CpuCasters {
    views: Vec<ViewCasters>,
    reference: DrawList,
    /// Per view and instance, outcome codes (the overlays' buffer for CPU methods).
    outcome_buffer: wgpu::Buffer,
    outcome_codes: Vec<u32>,
    excluded: Vec<u32>,
}

impl CpuCasters {
    pub fn new(ctx: &GpuContext) -> Self {
        Self {
            views: Vec::new(),
            reference: DrawList::new(ctx, "ShadowMap::reference_draws"),
            outcome_buffer: create_outcome_buffer(&ctx.device, 4),
            outcome_codes: Vec::new(),
            excluded: Vec::new(),
        }
    }

    /// Leaves these instances out of the chosen casters from the next frame on.
    pub fn exclude(&mut self, instances: &[u32]) {
        self.excluded = instances.to_vec();
        for v in &mut self.views {
            v.selection.exclude(instances);
        }
    }

    /// Chooses each view's casters for `method` (GPU methods: only the scene's casters, for
    /// the counts) and, where `upload` says, their draw lists and outcome codes.
    pub fn select(
        &mut self,
        ctx: &GpuContext,
        (scene, scene_gpu): (&Scene, &SceneGpu),
        method: Method,
        lights: &[&LightFrustum],
        upload: bool,
    ) {
        while self.views.len() < lights.len() {
            let mut selection = CasterSelection::default();
            selection.exclude(&self.excluded);
            self.views.push(ViewCasters {
                selection,
                draws: DrawList::new(ctx, "ShadowMap::caster_draws"),
                stages: Vec::new(),
            });
        }
        self.outcome_codes.clear();
        for (view, light) in self.views.iter_mut().zip(lights) {
            view.stages = view.selection.select(scene, scene_gpu.id, method, light);
            if upload {
                view.draws.upload(ctx, scene_gpu, view.selection.chosen());
                self.outcome_codes.extend(
                    view.selection
                        .outcomes()
                        .iter()
                        .map(|o| outcome_code(*o, method)),
                );
            }
        }
        if upload {
            self.upload_outcomes(ctx);
        }
    }

    /// Fills the reference list with every caster of the scene.
    pub fn upload_reference(&mut self, ctx: &GpuContext, scene_gpu: &SceneGpu) {
        if let Some(view) = self.views.first() {
            self.reference.upload(ctx, scene_gpu, view.selection.all());
        }
    }

    fn upload_outcomes(&mut self, ctx: &GpuContext) {
        let bytes = (self.outcome_codes.len().max(1) * 4) as u64;
        if self.outcome_buffer.size() < bytes {
            self.outcome_buffer = create_outcome_buffer(&ctx.device, bytes.next_power_of_two());
        }
        if !self.outcome_codes.is_empty() {
            ctx.queue.write_buffer(
                &self.outcome_buffer,
                0,
                bytemuck::cast_slice(&self.outcome_codes),
            );
        }
    }

    /// Every caster of the scene.
    pub fn casters_total(&self) -> u32 {
        self.views
            .first()
            .map_or(0, |v| v.selection.all().len() as u32)
    }

    /// View `view`'s draws, stages and outcomes this frame.
    pub fn draws(&self, view: usize) -> Option<&DrawList> {
        self.views.get(view).map(|v| &v.draws)
    }

    /// View `view`'s chosen casters, sorted.
    pub fn chosen(&self, view: usize) -> &[u32] {
        self.views.get(view).map_or(&[], |v| v.selection.chosen())
    }

    pub fn stages(&self, view: usize) -> &[Stage] {
        self.views.get(view).map_or(&[], |v| v.stages.as_slice())
    }

    pub fn outcomes(&self, view: usize) -> &[CasterOutcome] {
        self.views.get(view).map_or(&[], |v| v.selection.outcomes())
    }

    pub fn reference(&self) -> &DrawList {
        &self.reference
    }

    pub fn outcome_buffer(&self) -> &wgpu::Buffer {
        &self.outcome_buffer
    }
}

fn create_outcome_buffer(device: &wgpu::Device, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("ShadowMap::outcomes"),
        size: size.max(4),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
