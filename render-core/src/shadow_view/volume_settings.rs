//! What a user sets about shadow volumes (`volumes/`), beside the shadow-map settings so the
//! frame and every technique can carry them.

/// How far each caster's volume reaches along the light.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum VolumeClamp {
    /// Past the scene's far side: the standard volume.
    None,
    /// Only to the far side of the furthest visible receiver box it overlaps in the light's
    /// view (Lloyd's continuous clamping, with one interval per caster): no volume crosses
    /// the empty space below the receivers.
    #[default]
    Continuous,
}

impl VolumeClamp {
    pub const ALL: [Self; 2] = [Self::None, Self::Continuous];

    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Continuous => "continuous",
        }
    }
}

impl std::str::FromStr for VolumeClamp {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| format!("unknown volume clamping '{s}' (available: none, continuous)"))
    }
}

/// How the stencil counts each caster's volume.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum VolumePassChoice {
    /// Per caster, as DOOM 3 chooses: z-pass where the camera's near rectangle cannot lie
    /// inside the volume, z-fail with caps where it can.
    #[default]
    Auto,
    /// Every volume z-pass (Heidmann): wrong where the near plane cuts a volume.
    ZPass,
    /// Every volume z-fail with caps (Carmack; Everitt and Kilgard).
    ZFail,
}

impl VolumePassChoice {
    pub const ALL: [Self; 3] = [Self::Auto, Self::ZPass, Self::ZFail];

    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::ZPass => "z-pass",
            Self::ZFail => "z-fail",
        }
    }
}

impl std::str::FromStr for VolumePassChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| format!("unknown volume pass '{s}' (available: auto, z-pass, z-fail)"))
    }
}

/// What a user sets about shadow volumes.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(default)]
pub struct VolumeSettings {
    pub clamp: VolumeClamp,
    pub pass: VolumePassChoice,
}
