//! "Compare all": every method's counts, tightness, error and shadow-pass time for the current
//! view, side by side, while the selected method drives the picture. A second renderer of its
//! own steps through the methods, one measured frame per call, each method until it has
//! settled; when the view or the settings change the table starts over (old rows stay, marked
//! stale, until their method's turn comes).

use super::{FrameInput, FrameRenderer, FrameReport, FrameSettings, Method, SceneGpu};
use crate::gpu::GpuContext;
use crate::gpu::pass_label;
use crate::scene::Scene;

/// Frames a method that relies on last frame's visibility may take to settle.
pub const MAX_SETTLE_FRAMES: usize = 6;

/// Whether a temporal method has settled: its drawn count repeated, or it ran out of frames.
pub fn settled(method: Method, previous: Option<u32>, drawn: u32, frames: usize) -> bool {
    !method.temporal() || previous == Some(drawn) || frames >= MAX_SETTLE_FRAMES
}

/// One method's row.
#[derive(Clone, Debug, PartialEq)]
pub struct CompareRow {
    pub method: Method,
    pub casters_rendered: u32,
    pub triangles: u64,
    pub casters_oracle: Option<u32>,
    /// Visible pixels that lost or gained shadow against `none` with the same light frustum.
    pub error_px: Option<u32>,
    /// GPU time of the shadow-map passes and of mask + culling, when timestamps exist.
    pub shadow_ms: Option<f64>,
    pub culling_ms: Option<f64>,
    /// Computed for an earlier view or settings.
    pub stale: bool,
}

impl CompareRow {
    fn from_report(method: Method, report: &FrameReport) -> Self {
        Self {
            method,
            casters_rendered: report.counts.casters_rendered,
            triangles: report.counts.triangles_shadow,
            casters_oracle: report.counts.casters_oracle,
            error_px: report
                .error
                .map(|e| e.missing_shadow_px + e.extra_shadow_px),
            shadow_ms: report.shadow_pass_ms(),
            culling_ms: report.gpu_ms(pass_label::CULLING),
            stale: false,
        }
    }

    /// Casters drawn per oracle caster.
    pub fn tightness(&self) -> Option<f64> {
        let oracle = self.casters_oracle.filter(|&o| o > 0)?;
        Some(f64::from(self.casters_rendered) / f64::from(oracle))
    }
}

/// The comparison's own renderer and where it is in its round.
pub struct CompareAll {
    renderer: FrameRenderer,
    /// In [`Method::ALL`] order, those computed so far.
    rows: Vec<CompareRow>,
    next: usize,
    frames: usize,
    last_drawn: Option<u32>,
    /// The view and settings the rows are for (camera, size, settings but the method).
    key: String,
    scene_id: u64,
}

impl CompareAll {
    pub fn new(ctx: &GpuContext) -> Self {
        Self {
            renderer: FrameRenderer::new(ctx),
            rows: Vec::new(),
            next: 0,
            frames: 0,
            last_drawn: None,
            key: String::new(),
            scene_id: u64::MAX,
        }
    }

    /// Renders one measured frame of the method whose turn it is (blocking) and updates its
    /// row once it has settled.
    pub fn step(
        &mut self,
        ctx: &GpuContext,
        scene: &Scene,
        scene_gpu: &SceneGpu,
        input: &FrameInput<'_>,
    ) -> Result<(), crate::gpu::GpuError> {
        let base = FrameSettings {
            method: Method::None,
            overlays: super::Overlays::default(),
            measure: true,
            ..*input.settings
        };
        let key = format!(
            "{:?} {}x{} {:?}",
            input.camera, input.width, input.height, base
        );
        if key != self.key || scene_gpu.id != self.scene_id {
            if scene_gpu.id != self.scene_id {
                self.rows.clear();
            }
            for row in &mut self.rows {
                row.stale = true;
            }
            self.key = key;
            self.scene_id = scene_gpu.id;
            (self.next, self.frames, self.last_drawn) = (0, 0, None);
        }
        let method = Method::ALL[self.next];
        let settings = FrameSettings { method, ..base };
        let report = self.renderer.render_and_wait(
            ctx,
            scene,
            scene_gpu,
            &FrameInput {
                settings: &settings,
                ..*input
            },
        )?;
        self.frames += 1;
        let drawn = report.counts.casters_rendered;
        if settled(method, self.last_drawn, drawn, self.frames) {
            let row = CompareRow::from_report(method, &report);
            if let Some(old) = self.rows.iter_mut().find(|r| r.method == method) {
                *old = row;
            } else {
                self.rows.push(row);
                let order = |r: &CompareRow| Method::ALL.iter().position(|m| *m == r.method);
                self.rows.sort_by_key(order);
            }
            self.next = (self.next + 1) % Method::ALL.len();
            (self.frames, self.last_drawn) = (0, None);
        } else {
            self.last_drawn = Some(drawn);
        }
        Ok(())
    }

    /// The rows computed so far, in [`Method::ALL`] order.
    pub fn rows(&self) -> &[CompareRow] {
        &self.rows
    }

    /// Every method has its row for the current view and settings.
    pub fn complete(&self) -> bool {
        self.rows.len() == Method::ALL.len() && self.rows.iter().all(|r| !r.stale)
    }
}
