//! What a frame reports: counts, stages, timings, per shadow view and in total. The stats
//! JSON and the panels read this.

use serde::Serialize;

use crate::culling::Stage;
use crate::gpu::{PassTiming, pass_label, summed_by_label};
use crate::metrics::{Measured, ShadowError};
use crate::technique::{ShadowReport, ViewReport};

/// Object and triangle counts of one frame; shadow counts are summed over the views.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameCounts {
    /// Objects that cast shadows in the scene.
    pub casters_total: u32,
    /// Objects drawn into shadow maps (an object drawn into two views counts twice).
    pub casters_rendered: u32,
    /// Casters a shadow map identical where it is read needs (when measuring).
    pub casters_oracle: Option<u32>,
    /// Visible objects that receive shadows; `None` until the GPU count has come back.
    pub receivers_visible: Option<u32>,
    /// Visible objects of any kind.
    pub objects_visible: Option<u32>,
    /// Objects drawn by the camera passes (after view-frustum culling).
    pub objects_drawn_camera: u32,
    pub triangles_shadow: u64,
    pub triangles_camera: u64,
}

/// CPU time of the frame's parts, milliseconds.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CpuTimings {
    pub culling_ms: f64,
    pub encode_submit_ms: f64,
}

/// Facts about the first shadow view's light frustum.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct LightFacts {
    pub texel_size_m: [f32; 2],
    pub depth_range_m: f32,
    pub covers_whole_scene: bool,
}

/// Everything one frame reports.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameReport {
    pub frame_index: u64,
    pub width: u32,
    pub height: u32,
    /// The shadow technique (`single`).
    pub technique: &'static str,
    pub counts: FrameCounts,
    /// Caster-culling stages summed over the views.
    pub stages: Vec<Stage>,
    /// Per shadow view: stages, casters, oracle, texel size.
    pub views: Vec<ViewReport>,
    pub cpu: CpuTimings,
    /// GPU time per pass of frame `gpu_frame_index` (timestamps arrive late in the window).
    pub gpu: Vec<PassTiming>,
    pub gpu_frame_index: Option<u64>,
    pub light: LightFacts,
    /// Shadow error against the reference map (when measuring), of frame `measured_frame_index`.
    pub error: Option<ShadowError>,
    /// Shadow error against the exact shadow (a ray cast per pixel, `truth/`), when the caller
    /// measured it ([`super::FrameRenderer::exact_error`]).
    pub exact_error: Option<ShadowError>,
    /// Pixels whose shadow changes when only the camera moves 1 cm or turns 0.1 degrees, when
    /// the caller measured it ([`super::FrameRenderer::flicker`]).
    pub flicker: Option<super::Flicker>,
    /// Undersampling over every view (when measuring), of frame `measured_frame_index`.
    pub undersampling: Option<crate::metrics::Undersampling>,
    pub measured_frame_index: Option<u64>,
    /// For the GPU culling methods: the frame whose counts and stages these are.
    pub culled_frame_index: Option<u64>,
    /// What the device changes about the method (a fallback), in words.
    pub notes: Vec<String>,
    /// Why this frame's shadow passes could not run as asked, and what was drawn instead.
    pub shadow_failure: Option<String>,
    /// The GPU fault that stopped this frame before it drew (memory, limits, a lost device).
    pub fault: Option<crate::gpu::GpuFault>,
    /// Shadow volumes: fragments rasterised and stencil writes (when counted).
    pub volume_fill: Option<crate::technique::VolumeFill>,
    /// Shadow volumes: how many were counted z-pass and z-fail.
    pub volume_passes: Option<crate::technique::VolumePasses>,
    /// Many lights: the path, its passes and draws, and the CPU time of recording them.
    pub layered: Option<crate::technique::LayeredFacts>,
    /// Virtual maps: pages marked, resident, drawn and refused, and the pool.
    pub virtual_pages: Option<crate::technique::VirtualPages>,
}

impl FrameReport {
    /// Takes the technique's newest report: per view, and summed into the totals.
    pub(super) fn set_shadows(&mut self, shadows: ShadowReport) {
        self.counts.casters_total = shadows.casters_total;
        self.counts.casters_rendered = shadows
            .casters_rendered
            .unwrap_or_else(|| shadows.views.iter().map(|v| v.casters_rendered).sum());
        self.counts.triangles_shadow = shadows.views.iter().map(|v| v.triangles_shadow).sum();
        self.stages = if shadows.views.is_empty() {
            shadows.stages
        } else {
            summed_stages(&shadows.views)
        };
        if let Some(first) = shadows.views.first() {
            self.light = LightFacts {
                texel_size_m: first.texel_size_m,
                depth_range_m: first.depth_range_m,
                covers_whole_scene: first.covers_whole_scene,
            };
        }
        self.views = shadows.views;
        self.culled_frame_index = shadows.culled_frame_index;
        self.notes = shadows.notes;
        self.shadow_failure = shadows.failure;
        self.volume_fill = shadows.volume_fill;
        self.volume_passes = shadows.volume_passes;
        if let Some(passes) = shadows.volume_passes {
            self.counts.triangles_shadow =
                u64::from(passes.quad_triangles) + u64::from(passes.cap_triangles);
        }
        self.layered = shadows.layered;
        self.virtual_pages = shadows.virtual_pages;
    }

    /// Takes a measured frame: error, and the oracle per view and in total (the virtual
    /// maps' own per-page oracle, `virtual_maps/oracle.rs`).
    pub(super) fn set_measured(&mut self, measured: &Measured) {
        self.error = Some(measured.error);
        self.measured_frame_index = Some(measured.frame_index);
        if self.virtual_pages.is_some() {
            // The virtual maps' per-page oracle, where the frame drew every page it reads.
            self.counts.casters_oracle = self.views.iter().map(|v| v.casters_oracle).sum();
        } else {
            self.counts.casters_oracle = Some(measured.casters_oracle);
            for (view, oracle) in self.views.iter_mut().zip(&measured.oracle_per_view) {
                view.casters_oracle = Some(*oracle);
            }
        }
        for (view, histogram) in self.views.iter_mut().zip(&measured.undersampling_per_view) {
            view.undersampling = crate::metrics::Undersampling::from_histogram(histogram);
        }
        self.undersampling = measured.undersampling();
    }

    /// GPU time of the passes called `label` (summed where a frame has several, like the
    /// culling methods' two shadow passes), if measured.
    pub fn gpu_ms(&self, label: &str) -> Option<f64> {
        let mut passes = self.gpu.iter().filter(|t| t.label == label).peekable();
        passes.peek()?;
        Some(passes.map(|t| t.gpu_ms).sum())
    }

    /// The GPU time of drawing the shadows themselves: the shadow maps, or the shadow
    /// volumes' silhouettes, depth and stencil passes (culling is timed apart).
    pub fn shadow_pass_ms(&self) -> Option<f64> {
        self.gpu_ms(pass_label::SHADOW_MAP).or_else(|| {
            let volumes = [
                pass_label::VOLUME_SILHOUETTES,
                pass_label::VOLUME_DEPTH,
                pass_label::SHADOW_VOLUMES,
            ]
            .map(|label| self.gpu_ms(label));
            volumes
                .iter()
                .any(Option::is_some)
                .then(|| volumes.iter().flatten().sum())
        })
    }

    /// Sum of the GPU pass times of the frame itself, leaving out measurement passes (and the
    /// steps timed inside a pass).
    pub fn gpu_total_ms(&self) -> Option<f64> {
        let passes = || {
            self.gpu
                .iter()
                .filter(|t| t.depth == 0 && t.label != pass_label::REFERENCE_MAP)
        };
        (passes().count() > 0).then(|| passes().map(|t| t.gpu_ms).sum())
    }

    /// GPU time per pass label, summed over the frame, in order of first appearance; a step
    /// timed inside a pass follows it one level deeper.
    pub fn gpu_passes(&self) -> Vec<PassTiming> {
        summed_by_label(&self.gpu)
    }

    /// Casters drawn per oracle caster (1 is the floor for a method without error).
    pub fn tightness(&self) -> Option<f64> {
        let oracle = self.counts.casters_oracle?;
        (oracle > 0).then(|| f64::from(self.counts.casters_rendered) / f64::from(oracle))
    }
}

/// The views' stages, remaining counts summed stage by stage (every view of a frame runs the
/// same method, so the same stages).
fn summed_stages(views: &[ViewReport]) -> Vec<Stage> {
    let mut stages: Vec<Stage> = views.first().map(|v| v.stages.clone()).unwrap_or_default();
    for view in views.iter().skip(1) {
        for (total, stage) in stages.iter_mut().zip(&view.stages) {
            total.remaining += stage.remaining;
        }
    }
    stages
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view(rendered: u32, stages: &[(&str, u32)]) -> ViewReport {
        ViewReport {
            stages: stages.iter().map(|(n, r)| Stage::new(n, *r)).collect(),
            casters_rendered: rendered,
            triangles_shadow: u64::from(rendered) * 12,
            ..ViewReport::default()
        }
    }

    #[test]
    fn totals_are_the_sums_of_the_views() {
        let mut report = FrameReport::default();
        report.set_shadows(ShadowReport {
            casters_total: 10,
            views: vec![
                view(
                    3,
                    &[
                        ("scene casters", 10),
                        ("light frustum", 6),
                        ("light occlusion", 3),
                    ],
                ),
                view(
                    4,
                    &[
                        ("scene casters", 10),
                        ("light frustum", 7),
                        ("light occlusion", 4),
                    ],
                ),
            ],
            ..ShadowReport::default()
        });
        assert_eq!(report.counts.casters_rendered, 7);
        assert_eq!(report.counts.triangles_shadow, 84);
        let remaining: Vec<u32> = report.stages.iter().map(|s| s.remaining).collect();
        assert_eq!(remaining, [20, 13, 7]);
        report.set_measured(&Measured {
            frame_index: 1,
            casters_oracle: 5,
            oracle_per_view: vec![2, 3],
            ..Measured::default()
        });
        assert_eq!(report.views[1].casters_oracle, Some(3));
        assert_eq!(report.counts.casters_oracle, Some(5));
    }
}
