//! GPU plumbing shared by every pass: the context, readback, and pass timing.

mod async_readback;
mod context;
mod counters;
mod fullscreen;
mod readback;
mod timing;

pub use async_readback::AsyncReadback;
pub use context::{GpuContext, GpuError, OPTIONAL_FEATURES, SharedGpu};
pub use counters::GpuCounters;
pub use fullscreen::{buffer_entry, fullscreen_pipeline, view_entry};
pub use readback::{TexelRows, map_and_copy, read_buffer, read_flags, read_texel, read_texture};
pub use timing::{FrameTimer, PassTiming};
