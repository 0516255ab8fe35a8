//! Splitting very large objects into spatially coherent chunks. STUB.

use super::{Instance, Mesh};

/// When an instance counts as very large, relative to the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChunkSettings {
    /// An instance whose largest world extent exceeds this fraction of the scene's largest
    /// extent is split into chunks no larger than that. `0` or less disables splitting.
    pub max_extent_fraction: f32,
}

impl Default for ChunkSettings {
    fn default() -> Self {
        Self { max_extent_fraction: 0.25 }
    }
}

/// Splits every very large instance into chunks; returns the new instance list.
pub fn split_large_instances(_meshes: &mut Vec<Mesh>, instances: Vec<Instance>, _settings: &ChunkSettings) -> Vec<Instance> {
    instances
}
