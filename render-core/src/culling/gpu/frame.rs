//! One frame's inputs and outputs of GPU culling: what the long-lived resources follow, the
//! per-frame parameters, what passes from the first phase to the later steps, and errors.

use glam::Mat4;

use crate::culling::Method;
use crate::gpu::FrameTimer;
use crate::scene_gpu::DrawList;
use crate::shadow_view::{ShadowSettings, ShadowView, ViewBuffer};

/// Why GPU culling could not run a frame.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CullError {
    #[error("GPU culling has no {what} for this frame (prepare was not called)")]
    NotPrepared { what: &'static str },
    #[error("'{method}' does not cull on the GPU")]
    CpuMethod { method: &'static str },
    #[error("{views} shadow views, but culling was prepared for {capacity}")]
    TooManyViews { views: u32, capacity: u32 },
    #[error(
        "its {what} for {views} views of {resolution}² texels would take {} MiB, past this \
         adapter's limit of {} MiB for one binding (smaller maps or fewer views fit)",
        .bytes.div_ceil(1 << 20),
        .limit >> 20
    )]
    TooLarge {
        what: &'static str,
        views: u32,
        resolution: u32,
        bytes: u64,
        limit: u64,
    },
}

/// What the long-lived resources follow: the technique's depth array and the camera.
pub struct CullTargets<'a> {
    /// Side of every view's square, texels.
    pub resolution: u32,
    /// Views the buffers hold (the depth array's layers).
    pub capacity: u32,
    /// Changes whenever the technique replaces its depth array.
    pub maps_generation: u64,
    /// The method's depth array, every layer (the occlusion pyramids' base).
    pub shadow_maps: &'a wgpu::TextureView,
    pub views: &'a ViewBuffer,
    pub camera_size: (u32, u32),
    pub camera_depth: &'a wgpu::TextureView,
}

/// One frame's inputs.
pub struct CullFrame<'a> {
    pub method: Method,
    pub frame_index: u64,
    pub views: &'a [ShadowView],
    pub view_buffer: &'a ViewBuffer,
    pub camera_clip_from_world: Mat4,
    pub shadow: &'a ShadowSettings,
    pub casters_total: u32,
    /// For incremental updates: the maps hold nothing usable (first frame, new light, scene
    /// or exclusions): cleared, every caster drawn.
    pub full_redraw: bool,
    pub visible_flags: &'a wgpu::Buffer,
    pub frame_bind_group: &'a wgpu::BindGroup,
    /// The camera's depth (for the EQUAL-tested receiver passes) and its draws.
    pub camera_depth: &'a wgpu::TextureView,
    pub camera_draws: &'a DrawList,
    pub indirect_first_instance: bool,
    /// The prepass's object ids, surface positions and normals (FRAG's mask from the surface).
    pub surface: (
        &'a wgpu::TextureView,
        &'a wgpu::TextureView,
        &'a wgpu::TextureView,
    ),
    /// The reference maps' depth and caster ids (arrays); drawn already for `oracle`.
    pub reference: (&'a wgpu::TextureView, &'a wgpu::TextureView),
    /// One view of each layer of the method's maps (incremental updates clear there).
    pub shadow_layers: &'a [wgpu::TextureView],
    /// Times culling as [`crate::gpu::pass_label::CULLING`], its steps inside it.
    pub timer: &'a FrameTimer,
}

/// What passes from the first phase to the later steps of one frame.
pub struct CullPass {
    pub(super) bits: u32,
    pub(super) views: u32,
    pub(super) cull_group: wgpu::BindGroup,
    /// The footprint passes' group, for methods with the footprint test.
    pub(super) footprint_group: Option<wgpu::BindGroup>,
}

/// The mask of one view, as the light's view inset shows it.
pub struct MaskForInset<'a> {
    pub raster: &'a wgpu::TextureView,
    pub bits: &'a wgpu::Buffer,
    /// The view's first word in `bits`, and the mask's side in texels.
    pub bits_offset: u32,
    pub mask_size: u32,
    /// Shadow texels per mask texel.
    pub scale: u32,
    /// Which masks the method has: raster, fragment depths.
    pub raster_shown: bool,
    pub fragment_shown: bool,
}

/// Where FRAG's mask comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FragmentMaskSource {
    /// A compute pass over the prepass's surface targets (one thread per pixel).
    #[default]
    Surface,
    /// A second pass over the visible geometry, depth EQUAL (the camera's fragments).
    CameraPass,
}
