//! The seam between the frame and its shadows. A **shadow technique** (the single map today;
//! cascades, shadow volumes, many lights and virtual maps to come, a folder each) is what the
//! frame asks for "how much light reaches this point":
//!
//! ```text
//! prepare   its shadow views for this frame (shadow_view/), long-lived resources following
//!           the scene and the settings
//! draw      its passes for those views: masks, caster culling per view, maps (or stencil
//!           volumes); returns the bind group its light term reads
//! light     the WGSL of "light reaching this point" (`technique/light.wgsl` as the shading
//!           pass composes it) for the method and the reference, and its bind-group layout
//! report    per view and in total: stages, casters, outcomes; the light view inset's sources
//! ```
//!
//! The frame knows techniques only through [`ShadowTechnique`]; how a technique culls, which
//! maps it keeps between frames and what it falls back to are its own.

use glam::Mat4;
use serde::Serialize;

use crate::culling::{CasterOutcome, Method, Stage};
use crate::geom::{Aabb, Camera};
use crate::gpu::{FrameTimer, GpuContext};
use crate::scene::Scene;
use crate::scene_gpu::{DrawList, SceneGpu};
use crate::shadow_view::{DepthMeasure, ShadowSettings, ShadowView, ViewBuffer};
use crate::view::ViewTargets;

/// The virtual file a technique's light term is composed as.
pub const LIGHT_WGSL_PATH: &str = "technique/light.wgsl";

/// The shader `root` (a file that imports [`LIGHT_WGSL_PATH`]) composed with the technique's
/// light term, the file `light_wgsl`, and the generated files every light term may read
/// (culling's codes, the palette). The shading pass and the truth's shadow-at-points pass
/// compose through this, so both read the same light.
pub(crate) fn compose_with_light_term(root: &str, light_wgsl: &str) -> String {
    let codes = crate::culling::codes::wgsl();
    let palette = crate::palette::wgsl();
    let light = format!("#import {light_wgsl}\n");
    crate::shaders::compose(
        root,
        &[
            (crate::culling::codes::WGSL_PATH, codes.as_str()),
            (crate::palette::WGSL_PATH, palette.as_str()),
            (LIGHT_WGSL_PATH, light.as_str()),
        ],
    )
}

/// What a technique knows of the frame when it prepares its views.
pub struct TechniqueInput<'a> {
    pub scene: &'a Scene,
    pub scene_gpu: &'a SceneGpu,
    pub camera: &'a Camera,
    /// Width over height of the view.
    pub aspect: f32,
    pub method: Method,
    pub shadow: &'a ShadowSettings,
    pub direction_to_sun: glam::Vec3,
    /// A point light casts the shadows instead of the sun (shadow volumes only).
    pub point_light: Option<crate::scene::PointShadow>,
    /// The frame measures error and the oracle against the reference.
    pub measure: bool,
    /// Shadow volumes count their fill (when measuring, or for the fill heat map).
    pub measure_fill: bool,
    pub volumes: crate::shadow_view::VolumeSettings,
    /// How the many-lights technique renders its maps.
    pub layered: &'a crate::shadow_view::LayeredSettings,
    /// The virtual maps' pool, levels and cache.
    pub virtual_maps: crate::shadow_view::VirtualSettings,
    pub frame_index: u64,
    /// The newest visible receivers' world bounds that have come back (for FOCUS).
    pub visible_receivers: Option<Aabb>,
    /// The newest view depths, metres, of the nearest and furthest visible receiver pixel
    /// (`None` before any came back, or when no receiver is visible).
    pub visible_depths_m: Option<[f32; 2]>,
}

/// What a technique draws with: the frame's bindings, the camera's passes so far, and this
/// frame's views (already in the view buffer).
pub struct DrawInput<'a> {
    pub ctx: &'a GpuContext,
    pub views: &'a [ShadowView],
    pub view_buffer: &'a ViewBuffer,
    /// Group 0 of every scene pass (frame uniforms, instances, views).
    pub frame_group: &'a wgpu::BindGroup,
    pub camera_clip_from_world: Mat4,
    pub camera_draws: &'a DrawList,
    pub targets: &'a ViewTargets,
    /// One word per instance, non-zero where a pixel shows it (`view::VisibilityPass`).
    pub visible_flags: &'a wgpu::Buffer,
    pub timer: &'a FrameTimer,
    pub indirect_first_instance: bool,
}

/// What the shading pass binds after a technique has drawn.
#[derive(Clone)]
pub struct ShadowPasses {
    /// Group 1 of the shading pass, read by the technique's light term.
    pub light_group: wgpu::BindGroup,
    /// Per view and instance, the outcome code in the low byte (`culling/codes.wgsl`), for the
    /// `casters` overlay.
    pub outcomes: wgpu::Buffer,
}

/// One view's part of the report.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ViewReport {
    pub name: String,
    pub stages: Vec<Stage>,
    pub casters_rendered: u32,
    /// Casters in this view's oracle set (when measuring).
    pub casters_oracle: Option<u32>,
    pub triangles_shadow: u64,
    pub texel_size_m: [f32; 2],
    pub depth_range_m: f32,
    pub covers_whole_scene: bool,
    /// The camera depths it shades, metres (`null` in JSON for an open end), measured as
    /// `shades_by` says.
    pub shades_depth_m: [Option<f32>; 2],
    pub shades_by: DepthMeasure,
    /// How much it undersamples the pixels it shades (when measuring).
    pub undersampling: Option<Undersampling>,
    /// For a LiSPSM view, the warp's `n` in metres (`None` when the map is uniform).
    pub lispsm_n_m: Option<f32>,
    /// The constant depth bias this view applies, metres (the settings' metres plus their
    /// texels of this view; at the far end of a warped view).
    pub depth_bias_m: f32,
    /// How wide its PCF kernel reaches on the ground across the light, metres.
    pub pcf_m: f32,
}

/// How many octaves the shadow map undersamples the visible pixels: max(0, log2 of a texel's
/// footprint over a pixel's, as areas on the surface), to a quarter octave.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Undersampling {
    pub median_octaves: f32,
    pub p95_octaves: f32,
    /// Pixels counted.
    pub pixels: u32,
}

/// A technique's part of the report, the newest it has.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadowReport {
    pub casters_total: u32,
    /// For a technique with no views (shadow volumes), the casters it drew and its culling
    /// stages.
    pub casters_rendered: Option<u32>,
    pub stages: Vec<Stage>,
    /// Shadow volumes: the fill of the newest frame that counted it.
    pub volume_fill: Option<VolumeFill>,
    /// Shadow volumes: how the newest frame's drawn volumes were counted.
    pub volume_passes: Option<VolumePasses>,
    pub views: Vec<ViewReport>,
    /// For counts that come back from the GPU: the frame they belong to.
    pub culled_frame_index: Option<u64>,
    /// What the device changes about the method (a fallback), in words.
    pub notes: Vec<String>,
    /// Why this frame's shadow passes could not run as asked, and what was drawn instead.
    pub failure: Option<String>,
    /// CPU time of choosing casters this frame, milliseconds.
    pub cpu_culling_ms: f64,
    /// Many lights: how the maps were rendered.
    pub layered: Option<LayeredFacts>,
    /// Virtual shadow maps: the newest frame's pages.
    pub virtual_pages: Option<VirtualPages>,
}

/// The pages of one frame of the virtual shadow maps (`virtual_maps/`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct VirtualPages {
    /// Pages that visible pixels' taps read (and the coarsest level's under them).
    pub pages_marked: u32,
    /// Pages holding a physical page after allocation (cached ones included).
    pub pages_resident: u32,
    /// Pages drawn this frame, every layer: new, or invalidated.
    pub pages_rendered: u32,
    /// Cached pages whose movable casters' layer alone was drawn this frame (static casters
    /// kept apart, [`crate::shadow_view::VirtualSettings::separate_static`]).
    pub pages_refreshed: u32,
    /// Marked pages the pool had no room for; their pixels read a coarser level.
    pub pages_refused: u32,
    /// The share of marked pages the cache served whole ([`VirtualPages::pages_served`]; none
    /// marked: `None`).
    pub cache_hit_rate: Option<f64>,
    /// Cached pages no pixel marked, evicted where the pool ran out.
    pub pages_evicted: u32,
    /// Cached pages released at the frame's start: moved through, left their level's
    /// square, or everything was invalid.
    pub pages_invalidated: u32,
    /// Boxes (old and new bounds of moved objects) that invalidated pages.
    pub moved_boxes: u32,
    /// Every page was invalid (the cache off, the light or the scene changed).
    pub all_invalidated: bool,
    /// (caster, page) pairs drawn.
    pub caster_pages: u32,
    /// (caster, page) pairs the receiver mask left out: the caster covers none of the
    /// page's blocks that pixels read.
    pub caster_pages_masked: u32,
    /// Static occlusion (`static_occlusion`): (moved box, page) pairs that left the page's
    /// movable layer fresh, the box wholly behind its static depths, and (movable caster,
    /// refreshed page) pairs left out so.
    pub moved_pages_occluded: u32,
    pub caster_pages_occluded: u32,
    pub static_occlusion: bool,
    /// The cull's work: the page flags under the casters' boxes (within each level's drawn
    /// pages), which a walk page by page reads, and the page flags and cells of the hierarchy
    /// of page flags it read walking through that hierarchy.
    pub cull_pages_spanned: u32,
    pub cull_flag_reads: u32,
    pub receiver_mask: bool,
    pub pool_pages: u32,
    pub pool_mib: f64,
    pub levels: u32,
    pub finest_texel_m: f32,
    pub cache: bool,
    pub separate_static: bool,
    /// Texels of the pages drawn, each layer's.
    pub texels_rendered: u64,
    /// Texels of resident pages that visible pixels' taps read (when the frame measured).
    pub texels_sampled: Option<u64>,
}

impl VirtualPages {
    /// Marked pages the cache served whole: neither drawn, refreshed nor refused.
    pub fn pages_served(&self) -> u32 {
        self.pages_marked
            .saturating_sub(self.pages_rendered + self.pages_refreshed + self.pages_refused)
    }
}

/// How the many-lights technique rendered a frame's maps.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LayeredFacts {
    /// The path that drew, after the adapter's fallbacks.
    pub path: crate::shadow_view::LayeredPath,
    pub lights: u32,
    pub maps: u32,
    /// Render passes and draw calls recorded (a multi-draw counts its draws).
    pub passes: u32,
    pub draws: u32,
    /// Triangles submitted, once per view they were drawn for (an instanced or multiview
    /// draw counts once per pass).
    pub triangles: u64,
    /// CPU time of recording the passes and draws, milliseconds.
    pub cpu_submit_ms: f64,
    /// The most maps one multiview pass renders on this adapter (0: no multiview).
    pub multiview_group: u32,
    /// Per-layer culling as it ran (none where it could not), and the triangles it tested:
    /// each caster's, once per view (per multiview group) that draws it.
    pub culling: crate::shadow_view::LayerCulling,
    pub triangles_tested: u64,
}

/// The overlays a technique draws itself.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TechniqueOverlays {
    /// Shadow volumes' fill heat map.
    pub fill: bool,
    /// The shadow volumes, translucent.
    pub volumes: bool,
    /// The light's view, for a technique that draws its own (the virtual maps' pages).
    pub light_view: bool,
}

/// Fragments and stencil writes of one frame's volumes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct VolumeFill {
    /// Fragments the volume faces rasterise, depth test off.
    pub fragments: u64,
    /// Of those, the ones that write the stencil: behind the visible surface for a z-fail
    /// volume, in front of it for a z-pass one.
    pub stencil_writes: u64,
}

/// How many of one frame's drawn volumes the stencil counted each way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct VolumePasses {
    /// Volumes the camera's near rectangle cannot lie in: no near caps needed.
    pub z_pass: u32,
    /// Volumes drawn z-fail with both caps.
    pub z_fail: u32,
    /// Intervals drawn over all volumes (clamping draws a volume in up to four).
    pub intervals: u32,
    /// Casters whose receivers took a lane of the cull past its budget of loop iterations,
    /// so workgroups of their own gathered them (`volumes/big_casters.wgsl`).
    pub big_casters: u32,
    /// Casters that kept their whole volume, unculled and unclamped, because gathering
    /// their receivers ran past every budget (more big casters than the frame takes, or a
    /// lane past its own). Clamping's savings are lost there, not its correctness.
    pub whole_past_budget: u32,
    /// Triangles the stencil pass drew: the silhouettes' quads, two each, and the caps, one
    /// each (where an interval starts at its caster or further on, and where it ends).
    pub quad_triangles: u32,
    pub cap_triangles: u32,
}

/// One view of the light's view inset: its map, mask and outcomes.
pub struct InsetSources<'a> {
    /// The view's layer of the method's and the reference's maps (2D views).
    pub shadow_depth: &'a wgpu::TextureView,
    pub reference_ids: &'a wgpu::TextureView,
    /// The view's square in the layer: first texel and side.
    pub origin: [u32; 2],
    pub size: u32,
    /// Per view and instance, outcome codes; the view's first word.
    pub outcomes: &'a wgpu::Buffer,
    pub outcomes_offset: u32,
    /// The view's mask layer and FRAG's depths with the view's first word and the mask side.
    pub mask_raster: &'a wgpu::TextureView,
    pub mask_bits: &'a wgpu::Buffer,
    pub mask_offset: u32,
    pub mask_size: u32,
    /// Shadow texels per mask texel.
    pub mask_scale: u32,
    pub show_raster_mask: bool,
    pub show_fragment_mask: bool,
    /// The reference map holds caster ids this frame, so culled casters can be striped.
    pub show_outcomes: bool,
}

/// A way of rendering shadows. Long-lived (pipelines, textures, culling state); per frame it
/// prepares views, draws, and reports.
pub trait ShadowTechnique {
    /// Its name in reports (`single`).
    fn name(&self) -> &'static str;

    /// The WGSL file that defines `light_reaching` (the shading pass imports it as
    /// [`LIGHT_WGSL_PATH`]) and the layout of the group it reads (group 1 of the shading pass).
    fn light_term(&self) -> (&'static str, &wgpu::BindGroupLayout);

    /// The method this frame runs with, after the technique's fallbacks.
    fn effective_method(&self, requested: Method) -> Method;

    /// This frame's views; long-lived resources follow the scene and the settings.
    fn prepare(&mut self, ctx: &GpuContext, input: &TechniqueInput<'_>) -> Vec<ShadowView>;

    /// Records the technique's passes for this frame's views. A pass that cannot run does
    /// not fail the frame: the technique draws what it can, and [`ShadowReport::failure`]
    /// says what happened.
    fn draw(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: &TechniqueInput<'_>,
        draw: &DrawInput<'_>,
    ) -> ShadowPasses;

    /// How much of the sun's light the shading adds: 1, or 0 for a technique lit by the
    /// scene's own lights.
    fn sun_scale(&self) -> f32 {
        1.0
    }

    /// Call after the frame is submitted.
    fn after_submit(&mut self);

    /// Takes what has come back from the GPU (after a device poll) and returns the newest
    /// report.
    fn collect(&mut self) -> ShadowReport;

    /// Whether frame `frame_index`'s counts and outcomes have come back (or need not).
    fn has_results_of(&self, frame_index: u64) -> bool;

    /// Draws the technique's own overlays that are on over the colour target (shadow volumes:
    /// the fill heat map, when the frame counted fill, and the volumes themselves).
    fn draw_overlay(
        &self,
        _device: &wgpu::Device,
        _encoder: &mut wgpu::CommandEncoder,
        _targets: &ViewTargets,
        _overlays: TechniqueOverlays,
    ) {
    }

    /// View `view`'s part of the light's view inset, as the last frame drew it.
    fn inset(&self, view: u32) -> Option<InsetSources<'_>>;

    /// What happened to each instance in each view (the newest known).
    fn view_outcomes(&self) -> Vec<&[CasterOutcome]>;

    /// Leaves these instances out of the method's shadows from the next frame on.
    fn exclude(&mut self, instances: &[u32]);
}

/// The outcome of each instance over all views: the furthest it got in any view.
pub fn combined_outcomes(per_view: &[&[CasterOutcome]]) -> Vec<CasterOutcome> {
    let mut out: Vec<CasterOutcome> = per_view.first().map(|v| v.to_vec()).unwrap_or_default();
    for view in per_view.iter().skip(1) {
        for (o, v) in out.iter_mut().zip(view.iter()) {
            *o = o.furthest(*v);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_object_rendered_in_any_view_is_rendered() {
        let a = [
            CasterOutcome::Culled { stage: 1 },
            CasterOutcome::Rendered,
            CasterOutcome::NotACaster,
            CasterOutcome::Culled { stage: 1 },
        ];
        let b = [
            CasterOutcome::Rendered,
            CasterOutcome::Culled { stage: 2 },
            CasterOutcome::NotACaster,
            CasterOutcome::Culled { stage: 3 },
        ];
        assert_eq!(
            combined_outcomes(&[&a, &b]),
            [
                CasterOutcome::Rendered,
                CasterOutcome::Rendered,
                CasterOutcome::NotACaster,
                CasterOutcome::Culled { stage: 3 }
            ]
        );
        assert_eq!(combined_outcomes(&[&a]), a);
    }
}
