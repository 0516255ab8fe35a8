//! GPU plumbing shared by every pass: the context, readback, and pass timing.

mod async_readback;
mod context;
mod counters;
mod faults;
mod fullscreen;
mod layout;
mod log_once;
mod readback;
mod timing;

pub use async_readback::AsyncReadback;
pub use context::{GpuContext, GpuError, OPTIONAL_FEATURES, SharedGpu};
pub use counters::GpuCounters;
pub use faults::{Asked, GpuFault, bytes_text};
pub use fullscreen::{draw_fullscreen, fullscreen_pipeline};
pub use layout::{
    bind_group_layout, buffer, buffer_entry, color_attachment, compute_pipeline, depth_attachment,
    depth_pass, depth_texture, layout_entry, pipeline_layout, shader_module, storage, texture,
    uniform, view_entry,
};
pub use log_once::LogOnce;
pub use readback::{
    TexelRows, map_and_copy, read_buffer, read_flags, read_texel, read_texture, read_texture_layer,
};
pub use timing::{FrameTimer, PassTiming, Scope, pass_label, summed_by_label};
