//! Which views of the sun the map technique renders each frame: one fitted to the view (the
//! single map, [`SunView`]), one warped by LiSPSM ([`WarpedSunView`]) or one per cascade
//! (`cascades/`). The layout chooses the views;
//! everything after (maps, culling per view, reference, report, light term) is the
//! technique's and the same for every layout.

use crate::culling::Method;
use crate::geom::{fit_focused_light, fit_lispsm, fit_whole_scene};
use crate::shadow_view::{ShadowView, ViewTarget};
use crate::technique::TechniqueInput;

/// The views of one frame, each in its own layer of the map arrays.
pub trait ViewLayout {
    /// Its name in reports (`single`, `cascades`).
    fn name(&self) -> &'static str;

    /// The most layers its views use.
    fn layers(&self) -> u32;

    /// This frame's views, in layers `0..layers()`, for maps `resolution` texels square.
    fn views(&self, input: &TechniqueInput<'_>, method: Method, resolution: u32)
    -> Vec<ShadowView>;
}

/// The sun's light frustum: the whole scene's for methods with a static light, else `fit`'s
/// over the scene's bounds.
fn sun_light(
    input: &TechniqueInput<'_>,
    method: Method,
    resolution: u32,
    fit: impl FnOnce(&crate::geom::Aabb) -> crate::geom::LightFrustum,
) -> crate::geom::LightFrustum {
    let bounds = input.scene.bounds();
    if method.static_light() {
        fit_whole_scene(input.direction_to_sun, &bounds, resolution)
    } else {
        fit(&bounds)
    }
}

/// One view of the sun fitted to the camera's view (FOCUS: to the visible receivers; methods
/// with a static light: the whole scene), rendered `copies` times, each into its own layer and
/// culled and counted on its own. More than one copy is a test of the per-view path, not a
/// shadow setup: the shading takes the least light of them, so the picture is one view's.
#[derive(Clone, Copy, Debug)]
pub struct SunView {
    pub copies: u32,
}

impl Default for SunView {
    fn default() -> Self {
        Self { copies: 1 }
    }
}

impl ViewLayout for SunView {
    fn name(&self) -> &'static str {
        "single"
    }

    fn layers(&self) -> u32 {
        self.copies.max(1)
    }

    fn views(
        &self,
        input: &TechniqueInput<'_>,
        method: Method,
        resolution: u32,
    ) -> Vec<ShadowView> {
        let light = sun_light(input, method, resolution, |bounds| {
            // FOCUS fits to the newest visible receivers that have come back.
            let focus = input.visible_receivers.filter(|_| method == Method::Focus);
            fit_focused_light(
                input.camera,
                input.aspect,
                input.direction_to_sun,
                bounds,
                focus.as_ref(),
                resolution,
            )
        });
        (0..self.layers())
            .map(|layer| {
                let name = if layer == 0 {
                    "sun".to_owned()
                } else {
                    format!("sun (copy {layer})")
                };
                ShadowView::covering_all_depths(&name, light, ViewTarget::layer(layer, resolution))
            })
            .collect()
    }
}

/// One view of the sun warped by a perspective in light space (LiSPSM, `geom::fit_lispsm`):
/// finer texels near the viewer. Methods with a static light keep the whole scene's uniform
/// map, and a view along the light falls back to the uniform focused map (dueling frusta).
#[derive(Clone, Copy, Debug)]
pub struct WarpedSunView {
    /// Multiplies the paper's optimal `n` (1: the optimum; larger is more uniform).
    pub n_scale: f32,
}

impl ViewLayout for WarpedSunView {
    fn name(&self) -> &'static str {
        "lispsm"
    }

    fn layers(&self) -> u32 {
        1
    }

    fn views(
        &self,
        input: &TechniqueInput<'_>,
        method: Method,
        resolution: u32,
    ) -> Vec<ShadowView> {
        let light = sun_light(input, method, resolution, |bounds| {
            fit_lispsm(
                (input.camera, input.aspect),
                input.direction_to_sun,
                bounds,
                resolution,
                self.n_scale,
            )
        });
        let name = if light.warp.is_some() {
            "sun (lispsm)"
        } else {
            "sun (uniform)"
        };
        vec![ShadowView::covering_all_depths(
            name,
            light,
            ViewTarget::layer(0, resolution),
        )]
    }
}

/// Views another technique chose (many lights: its lamps' views and the sun's cascades, a
/// layer each), rendered and culled here like any layout's.
#[derive(Clone, Debug, Default)]
pub struct GivenViews(pub Vec<ShadowView>);

impl ViewLayout for GivenViews {
    fn name(&self) -> &'static str {
        "given"
    }

    fn layers(&self) -> u32 {
        self.0.len().max(1) as u32
    }

    fn views(&self, _: &TechniqueInput<'_>, _: Method, _: u32) -> Vec<ShadowView> {
        self.0.clone()
    }
}
