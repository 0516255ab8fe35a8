//! Everything in shadowlab that computes or draws: scenes, geometry, GPU passes and metrics.
//! No egui and no winit here; the UI reads the plain data types this crate reports.

pub mod culling;
pub mod frame;
pub mod geom;
pub mod gpu;
pub mod metrics;
pub mod scene;
pub mod shadow_map;

#[cfg(test)]
mod shader_validation;
