//! glTF 2.0 import. STUB.

use std::path::{Path, PathBuf};

use super::{ChunkSettings, Scene};

/// Why a glTF file could not be loaded; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    #[error("{path}: {reason}")]
    Invalid { path: PathBuf, reason: String },
}

/// Loads a `.gltf` (with external or embedded buffers) or `.glb` file into a scene.
pub fn import_gltf(path: &Path, _chunking: &ChunkSettings) -> Result<Scene, ImportError> {
    Err(ImportError::Invalid { path: path.to_owned(), reason: "not implemented".into() })
}
