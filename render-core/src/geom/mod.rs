//! Pure CPU geometry: boxes, planes, frusta, cameras and light-space fitting.

mod aabb;
mod frustum;

pub use aabb::Aabb;
pub use frustum::{Containment, Frustum, Plane};
