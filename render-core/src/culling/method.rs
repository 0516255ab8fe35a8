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

    /// What the method does and where it comes from, for tooltips and reports.
    pub fn summary(self) -> &'static str {
        match self {
            Self::None => {
                "Every caster is drawn; the rasteriser clips what lies outside the light's \
                frustum. The reference that error is measured against."
            }
            Self::Vfc => "Light frustum culling only, on the CPU through the scene's BVH.",
            Self::Ref => {
                "Occlusion culling in the light's view without a receiver mask: the \
                baseline of Bittner et al. 2011, sections 3 and 6."
            }
            Self::Focus => {
                "REF with the light frustum fitted to the visible receivers' bounds \
                (Bittner et al. 2011, section 5.2)."
            }
            Self::Bvol => {
                "Receiver mask from the visible receivers' bounding boxes (Bittner et al. \
                2011, section 4.1)."
            }
            Self::Geom => {
                "Receiver mask from the visible receivers' geometry, drawn into the map \
                first (Bittner et al. 2011, section 4.2)."
            }
            Self::GeomBvol => {
                "Geometry for the receivers the light saw last frame, boxes for the \
                rest (Bittner et al. 2011, section 4.3)."
            }
            Self::Frag => {
                "Fragment mask: only the texels that the filter taps of visible pixels' \
                footprints read, with the depth a caster must beat there (Bittner et al. \
                2011, section 4.4)."
            }
            Self::DrConservative => {
                "DigitalRune's caster tests: light frustum and occlusion, \
                then the shadow volume, extruded to the far plane, against the camera's frustum \
                and depth (steps 1 to 4). Never errs."
            }
            Self::DrProgressive => {
                "DigitalRune's progressive mode: the shadow volume ends at the \
                farthest depth behind the caster in last frame's map; it can be too short and \
                err."
            }
            Self::Incr => {
                "Incremental updates of a map over the whole scene: only where moving \
                objects were or are is cleared and drawn again (Bittner et al. 2011, section \
                5.1)."
            }
            Self::Oracle => {
                "Exactly the casters that shadow a visible pixel's filter tap, from a \
                reference map of every caster: the floor for every conservative method."
            }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_papers_method_cites_its_section() {
        let cited = [
            (Method::Ref, "Bittner et al. 2011, sections 3"),
            (Method::Focus, "section 5.2"),
            (Method::Bvol, "section 4.1"),
            (Method::Geom, "section 4.2"),
            (Method::GeomBvol, "section 4.3"),
            (Method::Frag, "section 4.4"),
            (Method::Incr, "section 5.1"),
            (Method::DrConservative, "DigitalRune"),
            (Method::DrProgressive, "DigitalRune"),
        ];
        for (method, source) in cited {
            assert!(
                method.summary().contains(source),
                "{}: {}",
                method.name(),
                method.summary()
            );
        }
        for method in Method::ALL {
            assert!(method.summary().len() > 40, "{}", method.name());
        }
    }
}
