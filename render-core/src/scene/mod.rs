//! Scenes: the model, glTF import, built-in generators and the instance hierarchy (a BVH).

mod builtin;
mod bvh;
mod camera_path;
mod chunking;
mod city;
mod corridor;
mod gltf_import;
mod hall;
mod model;
mod motion;
mod robots;
mod units;

#[cfg(test)]
pub(crate) use builtin::closed_box;
pub use builtin::{BUILTIN_SCENES, BuiltinScene, CITY_BLOCKS, load_builtin, sized_city};
pub use bvh::Bvh;
pub use camera_path::{CameraPath, PathError, PathKey};
pub use chunking::{ChunkSettings, split_large_instances};
pub use city::{CityParams, RectXz, build_city};
pub use gltf_import::{ImportError, import_gltf, import_gltf_slice};
pub use model::{
    Instance, LightKind, Mesh, MeshId, Mobility, PointShadow, PunctualLight, Scene, SceneFacts,
    ShadowLight, SpotCone, Sun, compute_vertex_normals,
};
pub use motion::Motion;
pub use units::{Units, in_metres, unit_note};
