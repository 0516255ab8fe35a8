//! Caster-culling stages and what happened to each object: the report's vocabulary, and its
//! GPU encoding (counter slots and outcome codes), written once here. `codes.rs` turns it
//! into the WGSL constants the shaders use.

use serde::Serialize;

/// A test a caster goes through. Each kind has its own counter slot and outcome code on the
/// GPU (`SLOT_*`, `OUTCOME_CULLED_*` in `culling/codes.wgsl`); which kinds a method reports,
/// in order, is [`crate::culling::Method::stages`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StageKind {
    LightFrustum,
    LightOcclusion,
    /// Bittner's receiver masks (BVOL, GEOM, GEOM+BVOL, FRAG).
    ReceiverMask,
    /// Incremental updates: the moving objects' old and new boxes.
    ChangedRegion,
    /// DigitalRune: the shadow volume against the camera's frustum.
    CameraFrustum,
    /// DigitalRune: the shadow volume against the camera's depth.
    CameraOcclusion,
    /// The texel-exact test of the casters the cheap tests kept: their boxes rasterised in the
    /// light's view against the map's depth and the mask (Bittner's occlusion queries).
    Footprint,
    /// The oracle method's set: the casters that win a shadowed tap of a visible pixel.
    Oracle,
}

impl StageKind {
    pub const ALL: [Self; 8] = [
        Self::LightFrustum,
        Self::LightOcclusion,
        Self::ReceiverMask,
        Self::ChangedRegion,
        Self::CameraFrustum,
        Self::CameraOcclusion,
        Self::Footprint,
        Self::Oracle,
    ];

    /// The name reports give the stage.
    pub fn name(self) -> &'static str {
        match self {
            Self::LightFrustum => "light frustum",
            Self::LightOcclusion => "light occlusion",
            Self::ReceiverMask => "receiver mask",
            Self::ChangedRegion => "changed region",
            Self::CameraFrustum => "camera frustum (shadow volume)",
            Self::CameraOcclusion => "camera occlusion (shadow volume)",
            Self::Footprint => "footprint (texel-exact)",
            Self::Oracle => "oracle",
        }
    }

    /// Its name in WGSL constants (`SLOT_LIGHT_FRUSTUM`, `OUTCOME_CULLED_LIGHT_FRUSTUM`).
    pub(crate) fn wgsl_name(self) -> &'static str {
        match self {
            Self::LightFrustum => "LIGHT_FRUSTUM",
            Self::LightOcclusion => "LIGHT_OCCLUSION",
            Self::ReceiverMask => "RECEIVER_MASK",
            Self::ChangedRegion => "CHANGED_REGION",
            Self::CameraFrustum => "CAMERA_FRUSTUM",
            Self::CameraOcclusion => "CAMERA_OCCLUSION",
            Self::Footprint => "FOOTPRINT",
            Self::Oracle => "ORACLE",
        }
    }

    /// Its counter slot: how many casters remain after it (per view on the GPU).
    pub(crate) fn slot(self) -> u32 {
        Self::ALL
            .iter()
            .position(|k| *k == self)
            .map_or(0, |p| p as u32)
    }
}

/// One caster-culling stage and how many casters remain after it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stage {
    pub name: String,
    pub remaining: u32,
}

impl Stage {
    pub fn new(name: &str, remaining: u32) -> Self {
        Self {
            name: name.to_owned(),
            remaining,
        }
    }
}

/// What happened to an object in a frame's shadow pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CasterOutcome {
    NotACaster,
    Rendered,
    /// Culled by the stage with this index in the report's stages (`FrameReport::stages`).
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

    /// How far the object got: rendered beats every culling stage, a later stage an earlier
    /// one. An object's outcome over several views is the furthest of its views'.
    #[must_use]
    pub fn furthest(self, other: Self) -> Self {
        let rank = |o: Self| match o {
            Self::NotACaster => 0,
            Self::Excluded => 1,
            Self::Culled { stage } => 2 + stage,
            Self::Rendered => usize::MAX,
        };
        if rank(other) > rank(self) {
            other
        } else {
            self
        }
    }
}
