//! Everything in shadowlab that computes or draws: scenes, geometry, GPU passes and metrics.
//! No egui and no winit here; the UI reads the plain data types this crate reports.

pub mod geom;
pub mod scene;
