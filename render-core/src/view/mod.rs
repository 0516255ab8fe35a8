//! The camera's side of a frame: its targets (colour, object ids, depth, shadow factor), the
//! frame uniforms and scene bindings every scene pass starts with (group 0: uniforms,
//! instances, shadow views), the camera pipelines' shape, and which objects the camera sees.
//! Long-lived layouts and pipelines; targets follow the view size, uniforms are per frame.

mod bindings;
pub(crate) mod gpu_data;
mod pipeline;
pub mod targets;
mod visibility;

pub use bindings::FrameBindings;
pub use pipeline::camera_pipeline;
pub use targets::ViewTargets;
#[cfg(test)]
pub(crate) use visibility::shader_source as visibility_shader_source;
pub use visibility::{VisibilityCounts, VisibilityPass};
