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

/// What a user sets about shadow volumes.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(default)]
pub struct VolumeSettings {
    pub clamp: VolumeClamp,
}
