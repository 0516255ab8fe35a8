//! Pure CPU geometry: boxes, planes, frusta, cameras and light-space fitting.

mod aabb;
mod camera;
mod clipmap;
mod frustum;
mod light_fit;
mod lispsm;
mod punctual;
mod slice_fit;

pub use aabb::Aabb;
pub use camera::{BOX_EDGES, Camera, basis_for_direction};
pub use clipmap::{ClipmapLevel, fit_clipmap_level};
pub use frustum::{Containment, Frustum, Plane};
pub use light_fit::{
    LightFrustum, TexelGrid, fit_directional_light, fit_focused_light, fit_whole_scene,
    stable_depth_range, view_depth_range,
};
pub use lispsm::{MIN_SIN_GAMMA, Warp, fit_lispsm};
pub use punctual::{
    CUBE_FACES, NEAR_M, Perspective, TILE_OVERLAP_TEXELS, cube_face_frustum, spot_frustum,
    tile_frustum,
};
pub use slice_fit::{SliceFit, fit_focused_slice, fit_view_slice};
