//! Cascaded shadow maps (Engel, "Cascaded Shadow Maps", `ShaderX5` 4.1): the view frustum cut
//! along its depth into slices ([`splits`]), each slice a view of the sun fitted to it in its
//! own layer of the map array. The map technique (`shadow_map/`) renders, culls and shades
//! them as it does any views: every method runs per cascade, masks included, and the light
//! term takes each point from the cascade whose depths hold it, or from the first whose map
//! does ([`CascadeSelection`], `view_selected`).

pub mod splits;

use serde::{Deserialize, Serialize};

use crate::culling::Method;
use crate::geom::{SliceFit, fit_focused_slice, stable_depth_range, view_depth_range};
use crate::shadow_map::ViewLayout;
use crate::shadow_view::{DepthMeasure, ShadowView, ViewTarget};
use crate::technique::TechniqueInput;

pub use splits::{SplitScheme, Splits};

/// The most cascades a frame renders.
pub const MAX_CASCADES: u32 = 8;

/// How each cascade's light box is fitted to its slice.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CascadeFit {
    /// The light-space box of the slice's corners: the most texels on the slice, but the box
    /// changes size as the camera turns, so shadow edges crawl.
    Tight,
    /// A square around the slice's bounding sphere, moved in whole texels: its size never
    /// changes and its texel grid stays put when the camera moves or turns (stabilised).
    #[default]
    Sphere,
}

impl CascadeFit {
    pub const ALL: [Self; 2] = [Self::Tight, Self::Sphere];

    pub fn name(self) -> &'static str {
        match self {
            Self::Tight => "tight",
            Self::Sphere => "sphere",
        }
    }
}

impl std::str::FromStr for CascadeFit {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|fit| fit.name() == s)
            .ok_or_else(|| format!("unknown cascade fit '{s}' (available: tight, sphere)"))
    }
}

/// Which cascade shades a point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CascadeSelection {
    /// The cascade whose slice holds the point's view depth: the boundary is a plane that
    /// turns with the camera.
    #[default]
    Depth,
    /// The first cascade whose map holds every PCF tap of the point: boundaries are map
    /// edges, which stabilised cascades move only in whole texels, and each point gets the
    /// finest map that has it.
    Map,
}

impl CascadeSelection {
    pub const ALL: [Self; 2] = [Self::Depth, Self::Map];

    pub fn name(self) -> &'static str {
        match self {
            Self::Depth => "depth",
            Self::Map => "map",
        }
    }

    /// The code the light term reads (`frame.views.z`, `view_selected` in
    /// `shadow_view/lookup.wgsl`).
    pub fn code(self) -> u32 {
        match self {
            Self::Depth => 0,
            Self::Map => 1,
        }
    }
}

impl std::str::FromStr for CascadeSelection {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|selection| selection.name() == s)
            .ok_or_else(|| format!("unknown cascade selection '{s}' (available: depth, map)"))
    }
}

/// Which view depths the splits cover.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CascadeDepths {
    /// Where the view frustum meets the scene's box; cascades whose slice holds no visible
    /// receiver (by the newest visible depths) are skipped.
    #[default]
    Scene,
    /// From the nearest to the furthest visible receiver pixel (Lauritzen's sample
    /// distribution shadow maps: a min/max reduction of the camera's depth, one frame late in
    /// the window), so every cascade shades depths that exist.
    Visible,
}

impl CascadeDepths {
    pub const ALL: [Self; 2] = [Self::Scene, Self::Visible];

    pub fn name(self) -> &'static str {
        match self {
            Self::Scene => "scene",
            Self::Visible => "visible",
        }
    }
}

impl std::str::FromStr for CascadeDepths {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|d| d.name() == s)
            .ok_or_else(|| format!("unknown cascade depths '{s}' (available: scene, visible)"))
    }
}

/// How far beyond the newest visible depths a cascade still counts them, as a share: the
/// depths are a frame old in the window.
const VISIBLE_MARGIN: f64 = 0.02;

/// The cascades a user sets.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CascadeSettings {
    /// 1 to [`MAX_CASCADES`].
    pub count: u32,
    pub splits: Splits,
    pub fit: CascadeFit,
    pub selection: CascadeSelection,
    pub depths: CascadeDepths,
    /// With selection by depth: the share of each cascade's depths, at its far end, over
    /// which it blends into the next (0 to 0.5; 0 switches at once), and over which the last
    /// one fades out to no shadow.
    pub blend: f32,
}

impl Default for CascadeSettings {
    fn default() -> Self {
        Self {
            count: 4,
            splits: Splits::default(),
            fit: CascadeFit::default(),
            selection: CascadeSelection::default(),
            depths: CascadeDepths::default(),
            blend: 0.0,
        }
    }
}

/// The cascades as the map technique's views.
#[derive(Clone, Debug, Default)]
pub struct Cascades {
    pub settings: CascadeSettings,
}

impl Cascades {
    pub fn new(settings: CascadeSettings) -> Self {
        Self { settings }
    }

    /// The depths that bound this frame's cascades (`count + 1`, increasing; measured as
    /// [`Self::measure`] says) and the far end of the scene's depths, or `None` when the view
    /// frustum does not meet the scene.
    pub fn split_distances(&self, input: &TechniqueInput<'_>) -> Option<(Vec<f64>, f64)> {
        let bounds = input.scene.bounds();
        let (near, scene_far) = view_depth_range(input.camera, &bounds)?;
        // Stabilised cascades split a range that does not follow the camera's turns, so each
        // slice, and its sphere, keeps its size.
        let (near, far) = match self.settings.fit {
            CascadeFit::Tight => (near, scene_far),
            CascadeFit::Sphere => {
                stable_depth_range(input.camera, f64::from(input.aspect), &bounds)?
            }
        };
        // Where the last cascade may reach a little beyond its end (rounding).
        let scene_far = match self.measure() {
            DepthMeasure::ViewDepth => scene_far,
            DepthMeasure::EyeDistance => far,
        };
        let (near, far) = match (self.settings.depths, self.visible_depths(input)) {
            (CascadeDepths::Visible, Some([lo, hi])) if lo.max(near) < hi.min(far) => {
                (lo.max(near), hi.min(far))
            }
            _ => (near, far),
        };
        let count = self.settings.count.clamp(1, MAX_CASCADES);
        Some((self.settings.splits.distances(count, near, far), scene_far))
    }

    /// How the cascades measure the depths they split: tight ones along the view direction,
    /// stabilised ones from the eye, so that turning the camera moves no point into another
    /// cascade (the spheres' sizes do not change, and the texel grids stay put).
    pub fn measure(&self) -> DepthMeasure {
        match self.settings.fit {
            CascadeFit::Tight => DepthMeasure::ViewDepth,
            CascadeFit::Sphere => DepthMeasure::EyeDistance,
        }
    }

    /// The newest visible receivers' depths as the cascades measure them, widened by
    /// [`VISIBLE_MARGIN`]; `None` before any came back, or when they are not a finite range.
    /// The receivers' view depths `[lo, hi]` lie `[lo, hi / c]` from the eye (`c` the
    /// frustum's corner cosine).
    fn visible_depths(&self, input: &TechniqueInput<'_>) -> Option<[f64; 2]> {
        let [lo, hi] = input.visible_depths_m?;
        let hi = match self.measure() {
            DepthMeasure::ViewDepth => f64::from(hi),
            DepthMeasure::EyeDistance => {
                f64::from(hi) / input.camera.corner_cosine(f64::from(input.aspect))
            }
        };
        let (lo, hi) = (
            f64::from(lo) * (1.0 - VISIBLE_MARGIN),
            hi * (1.0 + VISIBLE_MARGIN),
        );
        (lo.is_finite() && hi.is_finite() && lo < hi).then_some([lo, hi])
    }
}

impl ViewLayout for Cascades {
    fn name(&self) -> &'static str {
        "cascades"
    }

    fn layers(&self) -> u32 {
        self.settings.count.clamp(1, MAX_CASCADES)
    }

    /// One view per slice that holds depths; a slice of no depth (a geometric split beyond
    /// the scene) is not rendered. Without a view of the scene, one view of the whole scene
    /// keeps the frame sound.
    fn views(
        &self,
        input: &TechniqueInput<'_>,
        method: Method,
        resolution: u32,
    ) -> Vec<ShadowView> {
        let bounds = input.scene.bounds();
        let visible = self.visible_depths(input);
        let measure = self.measure();
        let Some((distances, scene_far)) = self.split_distances(input) else {
            let light = crate::geom::fit_whole_scene(input.direction_to_sun, &bounds, resolution);
            return vec![ShadowView::covering_all_depths(
                "cascade 0 (whole scene)",
                light,
                ViewTarget::layer(0, resolution),
            )];
        };
        let fit = match self.settings.fit {
            CascadeFit::Tight => SliceFit::Tight,
            CascadeFit::Sphere => SliceFit::Sphere,
        };
        // FOCUS fits each cascade to the newest visible receivers that came back too.
        let focus = input.visible_receivers.filter(|_| method == Method::Focus);
        let mut views = Vec::new();
        for (i, pair) in distances.windows(2).enumerate() {
            let [near, far] = [pair[0], pair[1]];
            // A slice of no depth, or (by the newest visible depths) of no visible receiver,
            // is not rendered (Engel: a culling system can tell how many maps are needed).
            let receives = visible.is_none_or(|[lo, hi]| near <= hi && far >= lo);
            if far <= near || !receives {
                continue;
            }
            // Measured from the eye, the slice also holds points nearer than `near` in view
            // depth (down to `near` times the corner cosine), but the sphere around the
            // slice's corners holds them already (`geom::slice_fit`'s test says why).
            let light = fit_focused_slice(
                (input.camera, input.aspect),
                input.direction_to_sun,
                &bounds,
                ([near, far], focus.as_ref()),
                (resolution, fit),
            );
            let layer = views.len() as u32;
            views.push(ShadowView {
                name: format!("cascade {i}"),
                light,
                target: ViewTarget::layer(layer, resolution),
                // Neighbours share their boundary, so each depth has one cascade. The first
                // also shades anything nearer, and one that reaches the scene's far end a
                // little beyond it (rounding); depths past a geometric split that ends short
                // have none (Engel's shadow distance).
                shades_depth_m: [
                    if i == 0 { f32::MIN } else { near as f32 },
                    if far >= scene_far {
                        (far * (1.0 + 1e-4)) as f32
                    } else {
                        far as f32
                    },
                ],
                shades_by: measure,
                load: crate::shadow_view::GeometryLoad::default(),
            });
        }
        views
    }
}
