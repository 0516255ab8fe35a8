//! The caster-culling methods of DESIGN.md, with the stages each reports and the parts of the
//! GPU pipeline each uses.

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::codes::method_bits;
use super::stage::StageKind;

/// How shadow casters are chosen (DESIGN.md, "Methods and their names").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// No caster culling: every caster is drawn and the rasteriser clips what lies outside the
    /// light frustum. The reference for error.
    #[default]
    None,
    /// Light frustum culling only (on the CPU, through the scene's BVH).
    Vfc,
    /// Occlusion culling in the camera and light views, no receiver mask (Bittner's REF).
    Ref,
    /// REF with the light frustum fitted to the visible receivers' bounds (Bittner 5.2), from
    /// the newest visible set that has come back: it follows the view a frame or two late.
    Focus,
    /// Receiver mask from visible receivers' bounding boxes (Bittner 4.1).
    Bvol,
    /// Receiver mask from visible receivers' geometry, drawn into the shadow map at once (4.2).
    Geom,
    /// Geometry for receivers that were visible in the light's view, boxes for the rest (4.3).
    GeomBvol,
    /// Fragment mask: only the texels visible receiver pixels read (4.4).
    Frag,
    /// DigitalRune: light frustum, light occlusion, and the caster's shadow volume, extruded
    /// to the light's far plane, against the camera's frustum and depth. Never errs.
    DrConservative,
    /// DigitalRune's progressive mode: the shadow volume ends at the farthest depth behind the
    /// caster in the light's view (last frame's), which can be too short: may err, and says so.
    DrProgressive,
    /// Incremental updates of a statically focused map (Bittner 5.1, INCR): the map covers the
    /// whole scene and persists; each frame only the old and new boxes of moving objects are
    /// cleared and the casters touching them drawn again.
    Incr,
    /// Exactly the casters that shadow a visible pixel's filter tap: the floor for every
    /// conservative method, taken from a reference map of every caster.
    Oracle,
}

impl Method {
    pub const ALL: [Self; 12] = [
        Self::None,
        Self::Vfc,
        Self::Ref,
        Self::Focus,
        Self::Bvol,
        Self::Geom,
        Self::GeomBvol,
        Self::Frag,
        Self::DrConservative,
        Self::DrProgressive,
        Self::Incr,
        Self::Oracle,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Vfc => "vfc",
            Self::Ref => "ref",
            Self::Focus => "focus",
            Self::Bvol => "bvol",
            Self::Geom => "geom",
            Self::GeomBvol => "geom-bvol",
            Self::Frag => "frag",
            Self::DrConservative => "dr-conservative",
            Self::DrProgressive => "dr-progressive",
            Self::Incr => "incr",
            Self::Oracle => "oracle",
        }
    }

    /// Culls on the GPU (`culling::GpuCulling`); `none` and `vfc` choose on the CPU.
    pub fn gpu_driven(self) -> bool {
        !matches!(self, Self::None | Self::Vfc)
    }

    /// Uses last frame's visibility in the light's view, so a new view needs a few frames to
    /// reach its steady state (every frame is conservative on the way).
    pub fn temporal(self) -> bool {
        self.gpu_driven() && self != Self::Oracle
    }

    /// The light frustum covers the whole scene and does not follow the camera.
    pub fn static_light(self) -> bool {
        self == Self::Incr
    }

    /// May cull a caster whose shadow is seen (DigitalRune's progressive mode); every other
    /// method is conservative.
    pub fn may_err(self) -> bool {
        self == Self::DrProgressive
    }

    /// The stages the method reports after "scene casters", in order.
    pub fn stages(self) -> &'static [StageKind] {
        use StageKind::{
            CameraFrustum, CameraOcclusion, ChangedRegion, Footprint, LightFrustum, LightOcclusion,
            Oracle, ReceiverMask,
        };
        match self {
            Self::None => &[],
            Self::Vfc => &[LightFrustum],
            Self::Ref | Self::Focus => &[LightFrustum, LightOcclusion, Footprint],
            Self::Bvol | Self::Geom | Self::GeomBvol | Self::Frag => {
                &[LightFrustum, LightOcclusion, ReceiverMask, Footprint]
            }
            Self::DrConservative | Self::DrProgressive => &[
                LightFrustum,
                LightOcclusion,
                CameraFrustum,
                CameraOcclusion,
                Footprint,
            ],
            Self::Incr => &[LightFrustum, LightOcclusion, ChangedRegion, Footprint],
            Self::Oracle => &[Oracle],
        }
    }

    /// Which parts of the GPU pipeline the method uses (`METHOD_*` bits); `None` for the CPU
    /// methods.
    pub(crate) fn gpu_bits(self) -> Option<u32> {
        use method_bits::{
            BVOL, DRAW_RECEIVERS, FOOTPRINT, FRAG, GEOM, GEOMETRY_FOOTPRINT, INCREMENTAL, MASK,
            OCCLUSION, ORACLE, PROGRESSIVE, TEMPORAL, VOLUME,
        };
        let occlusion = OCCLUSION | TEMPORAL | FOOTPRINT;
        Some(match self {
            Self::None | Self::Vfc => return None,
            // FOCUS culls like REF; its light frustum is fitted to the visible receivers.
            Self::Ref | Self::Focus => occlusion,
            Self::DrConservative => occlusion | VOLUME,
            Self::DrProgressive => occlusion | VOLUME | PROGRESSIVE,
            Self::Bvol => occlusion | MASK | BVOL,
            Self::Geom => occlusion | MASK | GEOM | DRAW_RECEIVERS,
            Self::GeomBvol => occlusion | MASK | GEOM | BVOL | DRAW_RECEIVERS,
            Self::Frag => occlusion | MASK | FRAG | DRAW_RECEIVERS | GEOMETRY_FOOTPRINT,
            // The changed region is redrawn front to back: last frame's casters that were
            // front-most in it first, then the others against them.
            Self::Incr => occlusion | MASK | INCREMENTAL | GEOMETRY_FOOTPRINT,
            Self::Oracle => ORACLE,
        })
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = Self::ALL.iter().map(|m| m.name()).collect();
                format!("unknown method '{s}' (available: {})", names.join(", "))
            })
    }
}
