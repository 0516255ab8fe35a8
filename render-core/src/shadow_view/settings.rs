//! The parameters of a shadow lookup (bias, normal offset, filter) and the map size. Plain
//! data: the UI edits it, the CLI parses it, reports echo it.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

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
#[serde(default)]
pub struct ShadowSettings {
    pub shadows_enabled: bool,
    /// Shadow map width and height in texels (512 to 8192).
    pub resolution: u32,
    /// Constant bias along the light direction, metres.
    pub depth_bias_m: f32,
    /// More bias along the light direction, in each view's texels: it grows with a cascade's
    /// texel size (0: the same bias in metres for every view).
    pub depth_bias_texels: f32,
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
            depth_bias_texels: 0.0,
            slope_bias: 0.3,
            normal_offset_texels: 0.5,
            pcf: PcfKernel::default(),
        }
    }
}
