//! What a frame reports: counts, stages, timings. The stats JSON and the panels read this.

use serde::Serialize;

use crate::gpu::PassTiming;
use crate::metrics::ShadowError;

/// Object and triangle counts of one frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameCounts {
    /// Objects that cast shadows in the scene.
    pub casters_total: u32,
    /// Objects drawn into the shadow map.
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

/// What happened to an object in a frame's shadow pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CasterOutcome {
    NotACaster,
    Rendered,
    /// Culled by the stage with this index in [`FrameReport::stages`].
    Culled {
        stage: usize,
    },
    /// Left out on request (`FrameRenderer::exclude_casters`).
    Excluded,
}

impl CasterOutcome {
    /// `rendered`, the culling stage's name, `excluded` or `not a caster`, as reports write it.
    pub fn describe(self, stages: &[Stage]) -> String {
        match self {
            Self::NotACaster => "not a caster".into(),
            Self::Rendered => "rendered".into(),
            Self::Culled { stage } => stages
                .get(stage)
                .map_or_else(|| format!("stage {stage}"), |s| s.name.clone()),
            Self::Excluded => "excluded".into(),
        }
    }
}

/// One caster-culling stage and how many casters remain after it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stage {
    pub name: String,
    pub remaining: u32,
}

/// CPU time of the frame's parts, milliseconds.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CpuTimings {
    pub culling_ms: f64,
    pub encode_submit_ms: f64,
}

/// Facts about the fitted light frustum.
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
    pub counts: FrameCounts,
    pub stages: Vec<Stage>,
    pub cpu: CpuTimings,
    /// GPU time per pass of frame `gpu_frame_index` (timestamps arrive late in the window).
    pub gpu: Vec<PassTiming>,
    pub gpu_frame_index: Option<u64>,
    pub light: LightFacts,
    /// Shadow error against the reference map (when measuring), of frame `measured_frame_index`.
    pub error: Option<ShadowError>,
    pub measured_frame_index: Option<u64>,
    /// For the GPU culling methods: the frame whose counts and stages these are.
    pub culled_frame_index: Option<u64>,
}

/// Pass labels, shared by the renderer and readers of [`FrameReport::gpu`].
pub mod pass_label {
    pub const CAMERA_PREPASS: &str = "camera depth+id";
    pub const VISIBILITY: &str = "visible objects";
    pub const SHADOW_MAP: &str = "shadow map";
    /// Measurement only: the reference map of every caster. Not part of a method's cost.
    pub const REFERENCE_MAP: &str = "reference map (measure)";
    /// The GPU culling methods: receiver mask, pyramids and caster tests (both phases).
    pub const CULLING: &str = "mask + culling";
    pub const SHADING: &str = "shading";
    pub const OVERLAYS: &str = "overlays";
}

impl FrameReport {
    /// GPU time of the passes called `label` (summed where a frame has several, like the
    /// culling methods' two shadow passes), if measured.
    pub fn gpu_ms(&self, label: &str) -> Option<f64> {
        let mut passes = self.gpu.iter().filter(|t| t.label == label).peekable();
        passes.peek()?;
        Some(passes.map(|t| t.gpu_ms).sum())
    }

    /// Sum of the GPU pass times of the frame itself, leaving out measurement passes.
    pub fn gpu_total_ms(&self) -> Option<f64> {
        let passes = || {
            self.gpu
                .iter()
                .filter(|t| t.label != pass_label::REFERENCE_MAP)
        };
        (passes().count() > 0).then(|| passes().map(|t| t.gpu_ms).sum())
    }

    /// Casters drawn per oracle caster (1 is the floor for a method without error).
    pub fn tightness(&self) -> Option<f64> {
        let oracle = self.counts.casters_oracle?;
        (oracle > 0).then(|| f64::from(self.counts.casters_rendered) / f64::from(oracle))
    }
}
