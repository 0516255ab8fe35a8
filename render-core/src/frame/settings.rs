//! What the user sets for a frame: shadow parameters, the sun, the method and overlays.
//! Plain data: the UI edits it, the CLI parses it, reports echo it.

use serde::{Deserialize, Serialize};

use crate::cascades::CascadeSettings;
use crate::culling::Method;
use crate::scene::{ShadowLight, Sun};
use crate::shadow_view::ShadowSettings;

/// Overlays drawn on top of the shaded view.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct Overlays {
    /// The light's view (shadow-map depth) in the top-left corner.
    pub light_view: bool,
    /// Pixels whose shadow differs from the reference: red missing, blue extra. Needs
    /// [`FrameSettings::measure`].
    pub error: bool,
    /// Objects in the camera view tinted by what happened to them in the shadow pass: green
    /// rendered; culled orange by the light frustum, yellow by light occlusion, magenta by the
    /// mask, the texel-exact footprint or the shadow volume; purple excluded; non-casters
    /// untinted.
    pub casters: bool,
    /// Each point tinted by the shadow view that shades it: a colour per cascade.
    pub cascades: bool,
    /// Shadow volumes: how many volume fragments each pixel took (the fill heat map).
    pub fill: bool,
    /// Shadow volumes: the volumes themselves, translucent yellow in front of the surface.
    pub volumes: bool,
    /// Which shadow view (cascade) the light-view inset shows; the last one when there are
    /// fewer.
    pub inset_view: u32,
}

impl Overlays {
    pub const NAMES: [&'static str; 6] = [
        "light-view",
        "error",
        "casters",
        "cascades",
        "fill",
        "volumes",
    ];

    /// Turns on the overlay called `name`.
    pub fn enable(&mut self, name: &str) -> Result<(), String> {
        match name {
            "light-view" => self.light_view = true,
            "error" => self.error = true,
            "casters" => self.casters = true,
            "cascades" => self.cascades = true,
            "fill" => self.fill = true,
            "volumes" => self.volumes = true,
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

/// How the sun's shadow is mapped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowSetup {
    /// One map fitted to the view (or the whole scene for `incr`).
    #[default]
    Single,
    /// One map warped by a perspective in light space (LiSPSM, [`FrameSettings::lispsm`]).
    Lispsm,
    /// One map per slice of the view frustum ([`FrameSettings::cascades`]).
    Cascades,
    /// Stencil shadow volumes: exact hard shadows, no map (`volumes/`).
    Volumes,
    /// The scene's spot and point lights, a map each (six for a point light), rendered by
    /// the path of [`FrameSettings::layered`] (`layered/`).
    Lights,
    /// Virtual shadow maps: a clipmap of 128-texel pages, only the pages visible pixels read
    /// drawn, cached across frames ([`FrameSettings::virtual_maps`], `virtual_maps/`).
    Virtual,
}

impl ShadowSetup {
    pub const ALL: [Self; 6] = [
        Self::Single,
        Self::Lispsm,
        Self::Cascades,
        Self::Volumes,
        Self::Lights,
        Self::Virtual,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::Single => "single",
            Self::Lispsm => "lispsm",
            Self::Cascades => "cascades",
            Self::Volumes => "volumes",
            Self::Lights => "lights",
            Self::Virtual => "virtual",
        }
    }
}

/// The LiSPSM warp a user sets.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct LispsmSettings {
    /// Multiplies the paper's optimal `n` (Wimmer et al. 2004): below 1 warps harder (finer
    /// near, coarser far), above 1 tends to a uniform map.
    pub n_scale: f32,
}

impl Default for LispsmSettings {
    fn default() -> Self {
        Self { n_scale: 1.0 }
    }
}

impl std::str::FromStr for ShadowSetup {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|setup| setup.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = Self::ALL.iter().map(|s| s.name()).collect();
                format!(
                    "unknown shadow setup '{s}' (available: {})",
                    names.join(", ")
                )
            })
    }
}

impl FrameSettings {
    /// Whether the exact shadow (`truth/`: a ray per pixel towards the sun or the point light)
    /// is this frame's truth. Many lights alone have none yet: their error against it would
    /// measure the sun's shadow, so none is reported; with the sun, the sun's shadow is what
    /// their error measures.
    pub fn exact_truth_applies(&self) -> bool {
        self.setup != ShadowSetup::Lights || self.layered.sun
    }

    /// Whether the sun is shadowed by cascades: the cascades setup, or many lights with the
    /// sun (their first views).
    pub fn cascaded_sun(&self) -> bool {
        self.setup == ShadowSetup::Cascades
            || (self.setup == ShadowSetup::Lights && self.layered.sun)
    }

    /// Where this frame's shadows come from.
    pub fn shadow_light(&self) -> ShadowLight {
        match self.point_light {
            Some(point) => point.shadow_light(),
            None => ShadowLight::Sun(self.sun.direction_to_sun),
        }
    }
}

/// Everything the user sets that shapes a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct FrameSettings {
    pub shadow: ShadowSettings,
    /// One map or cascades, and the cascades' count, splits and fit.
    pub setup: ShadowSetup,
    pub cascades: CascadeSettings,
    pub lispsm: LispsmSettings,
    pub volumes: crate::shadow_view::VolumeSettings,
    /// Many lights: how their maps are rendered.
    pub layered: crate::shadow_view::LayeredSettings,
    /// Virtual maps: the pool, the levels and the cache.
    pub virtual_maps: crate::shadow_view::VirtualSettings,
    #[serde(skip)]
    pub sun: Sun,
    /// A point or spot light casts the shadows and lights the scene instead of the sun
    /// (shadow volumes and virtual maps; other techniques report that they cannot and draw
    /// no shadows).
    #[serde(skip)]
    pub point_light: Option<crate::scene::PointShadow>,
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
    /// Observer camera: the shadows stay as the last frame of the frame's own camera made
    /// them (frozen), and the picture is seen from here, with the frozen view's frustum, its
    /// cascades' ends and every shadow view's light box drawn as lines. Nothing is measured.
    #[serde(skip)]
    pub observer: Option<crate::geom::Camera>,
}
