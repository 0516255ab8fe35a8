//! How the many-lights technique (`layered/`) renders its shadow maps, as the user sets it.
//! Plain data: the UI edits it, the CLI parses it, reports echo it.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// The ways to render N shadow maps (Rákos, GPU Pro 4, chapter 19).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LayeredPath {
    /// One render pass per map, as engines do: the baseline.
    #[default]
    Traditional,
    /// One pass per group of maps through multiview: the view index picks the map, each a
    /// layer of the depth array; groups as large as the adapter allows.
    Multiview,
    /// One instanced draw per mesh for every map: each instance places its triangles in its
    /// map's tile of a depth atlas, clip distances keeping them inside the tile.
    Atlas,
}

impl LayeredPath {
    pub const ALL: [Self; 3] = [Self::Traditional, Self::Multiview, Self::Atlas];

    pub fn name(self) -> &'static str {
        match self {
            Self::Traditional => "traditional",
            Self::Multiview => "multiview",
            Self::Atlas => "atlas",
        }
    }
}

impl fmt::Display for LayeredPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for LayeredPath {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| {
                format!("unknown layered path '{s}' (expected traditional, multiview or atlas)")
            })
    }
}

/// Per-layer culling in compute before the maps are drawn (Rákos 19.5, 19.6): each
/// triangle against each view's frustum, and a closed mesh's triangles that face away from
/// the light.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LayerCulling {
    /// Every triangle of every caster a view draws.
    None,
    Frustum,
    BackFaces,
    #[default]
    Both,
}

impl LayerCulling {
    pub const ALL: [Self; 4] = [Self::None, Self::Frustum, Self::BackFaces, Self::Both];

    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Frustum => "frustum",
            Self::BackFaces => "back-faces",
            Self::Both => "both",
        }
    }

    pub fn frustum(self) -> bool {
        matches!(self, Self::Frustum | Self::Both)
    }

    pub fn back_faces(self) -> bool {
        matches!(self, Self::BackFaces | Self::Both)
    }
}

impl fmt::Display for LayerCulling {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for LayerCulling {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| {
                format!("unknown layer culling '{s}' (expected none, frustum, back-faces or both)")
            })
    }
}

/// The many-lights technique's settings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct LayeredSettings {
    pub path: LayeredPath,
    /// The scene's first this many lights cast shadows and light the frame (0: all of them).
    pub lights: u32,
    /// Per-layer culling of triangles in compute before the draw.
    pub culling: LayerCulling,
    /// The sun shines too, shadowed by the frame's cascades (`FrameSettings::cascades`),
    /// which the same path renders as the first views.
    pub sun: bool,
    /// Extra load on the maps' geometry stage, to measure it (`bench`). Not remembered: a
    /// window must not reopen with maps left empty by `--no-raster`.
    #[serde(skip)]
    pub load: super::GeometryLoad,
}

impl LayeredSettings {
    /// The side of each map follows `ShadowSettings::resolution`, within these (a cube
    /// face's for a point light).
    pub const MIN_RESOLUTION: u32 = 64;
    pub const MAX_RESOLUTION: u32 = 4096;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_path_parses_from_its_name_and_a_wrong_one_names_itself() {
        for p in LayeredPath::ALL {
            assert_eq!(p.name().parse::<LayeredPath>(), Ok(p));
        }
        let e = "layers".parse::<LayeredPath>().unwrap_err();
        assert!(e.contains("'layers'") && e.contains("atlas"), "{e}");
        for c in LayerCulling::ALL {
            assert_eq!(c.name().parse::<LayerCulling>(), Ok(c));
        }
        assert!(
            "faces"
                .parse::<LayerCulling>()
                .unwrap_err()
                .contains("back-faces")
        );
    }
}
