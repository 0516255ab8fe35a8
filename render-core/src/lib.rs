//! Everything in shadowlab that computes or draws: scenes, geometry, GPU passes and metrics.
//! No egui and no winit here; the UI reads the plain data types this crate reports.
//!
//! Modules, from the bottom up (each imports only those before it): `geom`, `scene`, `gpu`,
//! `shaders`, `palette`, `scene_gpu`, `shadow_view`, `view`, `culling`, `technique`,
//! `shadow_map`, `cascades`, `volumes`, `layered`, `virtual_maps`, `metrics`, `truth`, `overlays`, `frame`.

pub mod cascades;
pub mod culling;
pub mod frame;
pub mod geom;
pub mod gpu;
pub mod layered;
pub mod metrics;
pub mod overlays;
pub mod palette;
pub mod scene;
pub mod scene_gpu;
pub mod shadow_map;
pub mod shadow_view;
pub mod technique;
pub mod truth;
pub mod view;
pub mod virtual_maps;
pub mod volumes;

mod shaders;

#[cfg(test)]
mod shader_validation;
