//! Shadow views, the unit every shadow technique multiplies: one light projection, its texel
//! size and depth range, and where it renders (a square of a layer of a depth array; a whole
//! layer, or a tile of an atlas). A single map is one view, a cascade one view each, a spot
//! light one, a point light six. Caster culling runs per view (`culling/`).
//!
//! [`ShadowView`] is per-frame data; [`ViewBuffer`] is the long-lived GPU buffer the frame
//! writes them into each frame, read by every scene pass (group 0) and, one slice per view,
//! by the passes that render one view.

mod buffer;
mod gpu_data;
mod layered_settings;
mod settings;
mod virtual_settings;
mod volume_settings;

pub use buffer::ViewBuffer;
pub use gpu_data::ShadowViewGpu;
pub use layered_settings::{LayerCulling, LayeredPath, LayeredSettings};
pub use settings::{PcfKernel, ShadowSettings};
pub use virtual_settings::{
    LEVEL_PAGES, PAGE_BYTES, PAGE_TEXELS, SPOT_CHAIN_MAX_CONE_RAD, VirtualSettings, spot_chain,
};
pub use volume_settings::{VolumeClamp, VolumePassChoice, VolumeSettings};

use crate::geom::LightFrustum;

/// Depth of every shadow view: 0 towards the light, 1 at the far plane.
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Where a view renders: the square of `size` texels from `origin` in layer `layer`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ViewTarget {
    pub layer: u32,
    pub origin: [u32; 2],
    pub size: u32,
}

impl ViewTarget {
    /// All of layer `layer` of a depth array `size` texels square.
    pub fn layer(layer: u32, size: u32) -> Self {
        Self {
            layer,
            origin: [0, 0],
            size,
        }
    }

    /// Restricts `pass` (on the target's layer) to the target's square.
    pub fn set_viewport(&self, pass: &mut wgpu::RenderPass<'_>) {
        let [x, y] = self.origin.map(|o| o as f32);
        let side = self.size as f32;
        pass.set_viewport(x, y, side, side, 0.0, 1.0);
    }
}

/// One shadow view of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowView {
    /// What reports call it ("sun"; later "cascade 2", "spot 3", "point 1 +X").
    pub name: String,
    /// The light's projection and facts about it.
    pub light: LightFrustum,
    pub target: ViewTarget,
    /// The camera depths `[near, far)` in metres whose points this view shades, measured as
    /// `shades_by` says.
    pub shades_depth_m: [f32; 2],
    pub shades_by: DepthMeasure,
    /// What the passes that render it add to their geometry stage, to measure it (the
    /// many-lights technique's bench options; none otherwise).
    pub load: GeometryLoad,
}

/// Extra load on the geometry stage of the passes that render a view, as Rákos measures it
/// (GPU Pro 4, ch. 19, Figures 19.4 and 19.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct GeometryLoad {
    /// Every vertex lands outside the view after its work: nothing is rasterised.
    pub no_raster: bool,
    /// Rounds of skinning-like work per vertex (a chain of matrix products).
    pub vertex_work: u32,
}

/// How a point's camera depth is measured when views choose which of them shades it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DepthMeasure {
    /// Along the camera's view direction: slices end at planes, which turn with the camera.
    #[default]
    ViewDepth,
    /// The distance from the eye: slices end at spheres, so turning the camera moves no
    /// point into another view (Unity's "stable fit" selects cascades so).
    EyeDistance,
}

impl DepthMeasure {
    pub fn name(self) -> &'static str {
        match self {
            Self::ViewDepth => "view depth",
            Self::EyeDistance => "eye distance",
        }
    }
}

impl ShadowView {
    /// A view that shades every point it covers.
    pub fn covering_all_depths(name: &str, light: LightFrustum, target: ViewTarget) -> Self {
        Self {
            name: name.to_owned(),
            light,
            target,
            shades_depth_m: [f32::MIN, f32::MAX],
            shades_by: DepthMeasure::ViewDepth,
            load: GeometryLoad::default(),
        }
    }
}

/// Casters' depth only into shadow views' targets, both faces as the shadow-map technique
/// draws them: from the scene's vertex buffer, or (`pulled`) fetching the vertices in the
/// shader; `compare` is `Less` for casters, `Always` to write whatever is there (a clear).
pub(crate) fn depth_pipeline(
    device: &wgpu::Device,
    (layout, module, entry): (&wgpu::PipelineLayout, &wgpu::ShaderModule, &str),
    multiview_mask: Option<std::num::NonZeroU32>,
    (pulled, compare): (bool, wgpu::CompareFunction),
) -> wgpu::RenderPipeline {
    let buffers = [Some(crate::scene_gpu::VERTEX_LAYOUT)];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(entry),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: if pulled { &[] } else { &buffers },
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: SHADOW_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(compare),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: None,
        multiview_mask,
        cache: None,
    })
}
