//! What the user sets for a frame: shadow parameters, the sun, the method and overlays.
//! Plain data: the UI edits it, the CLI parses it, reports echo it.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::scene::Sun;

/// Percentage-closer filtering kernel: taps on whole texels around the lookup.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum PcfKernel {
    /// One tap: hard shadows.
    Off,
    #[serde(rename = "2x2")]
    K2x2,
    #[default]
    #[serde(rename = "3x3")]
    K3x3,
    #[serde(rename = "5x5")]
    K5x5,
}

impl PcfKernel {
    pub const ALL: [Self; 4] = [Self::Off, Self::K2x2, Self::K3x3, Self::K5x5];

    /// Kernel width in texels.
    pub fn width(self) -> u32 {
        match self {
            Self::Off => 1,
            Self::K2x2 => 2,
            Self::K3x3 => 3,
            Self::K5x5 => 5,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Off => "off",
            Self::K2x2 => "2x2",
            Self::K3x3 => "3x3",
            Self::K5x5 => "5x5",
        }
    }
}

impl fmt::Display for PcfKernel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for PcfKernel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("unknown PCF kernel '{s}' (expected off, 2x2, 3x3 or 5x5)"))
    }
}

/// Shadow-map parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShadowSettings {
    pub shadows_enabled: bool,
    /// Shadow map width and height in texels (512 to 8192).
    pub resolution: u32,
    /// Constant bias along the light direction, metres.
    pub depth_bias_m: f32,
    /// Bias proportional to the receiver's depth slope, in texels of slope.
    pub slope_bias: f32,
    /// Lookup moved along the surface normal, in shadow texels.
    pub normal_offset_texels: f32,
    pub pcf: PcfKernel,
}

impl ShadowSettings {
    pub const MIN_RESOLUTION: u32 = 512;
    pub const MAX_RESOLUTION: u32 = 8192;
}

impl Default for ShadowSettings {
    fn default() -> Self {
        Self {
            shadows_enabled: true,
            resolution: 2048,
            depth_bias_m: 0.02,
            slope_bias: 0.3,
            normal_offset_texels: 0.5,
            pcf: PcfKernel::default(),
        }
    }
}

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

/// Overlays drawn on top of the shaded view.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Overlays {
    /// The light's view (shadow-map depth) in the top-left corner.
    pub light_view: bool,
    /// Pixels whose shadow differs from the reference: red missing, blue extra. Needs
    /// [`FrameSettings::measure`].
    pub error: bool,
    /// Objects in the camera view tinted by what happened to them in the shadow pass: green
    /// rendered; culled orange by the light frustum, yellow by light occlusion, magenta by the
    /// mask or shadow volume; purple excluded; non-casters untinted.
    pub casters: bool,
}

impl Overlays {
    pub const NAMES: [&'static str; 3] = ["light-view", "error", "casters"];

    /// Turns on the overlay called `name`.
    pub fn enable(&mut self, name: &str) -> Result<(), String> {
        match name {
            "light-view" => self.light_view = true,
            "error" => self.error = true,
            "casters" => self.casters = true,
            _ => {
                return Err(format!(
                    "unknown overlay '{name}' (available: {})",
                    Self::NAMES.join(", ")
                ));
            }
        }
        Ok(())
    }
}

/// Everything the user sets that shapes a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FrameSettings {
    pub shadow: ShadowSettings,
    #[serde(skip)]
    pub sun: Sun,
    pub method: Method,
    pub overlays: Overlays,
    /// Also render the reference shadow map (every caster, with ids) and measure the shadow
    /// error against it and the oracle caster set. Costs a second shadow pass.
    pub measure: bool,
    /// Dynamic objects follow their scripted motion (cars drive) as time passes.
    pub animate: bool,
    /// The window also runs every method on the current view for the panel's comparison
    /// table (`frame::compare`); the frame itself does not change.
    #[serde(skip)]
    pub compare_all: bool,
}
