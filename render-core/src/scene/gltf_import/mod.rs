//! glTF 2.0 import: `.gltf` with external or base64 buffers, and `.glb`, into a [`Scene`],
//! including files packed by `gltfpack` (`EXT_meshopt_compression`, `KHR_mesh_quantization`).
//!
//! The node tree of the default scene is flattened: every (node with a mesh, primitive) pair
//! becomes one [`Instance`](crate::scene::Instance) whose transform is the product of its ancestors' transforms.
//! A glTF mesh primitive used by several nodes becomes one shared [`Mesh`](crate::scene::Mesh).
//!
//! Naming: an instance is named after its node (`node<index>` when the node has no name), a mesh
//! after its glTF mesh (`mesh<index>`). Primitive 0 of a mesh keeps that name; primitive `k > 0`
//! adds `/p<k>`, e.g. `car`, `car/p1`, `car/p2`. Split large objects then get `#<chunk>` (see
//! [`split_large_instances`]).
//!
//! Only triangles are imported (strips and fans are converted); other primitives, and primitives
//! whose data is broken, are skipped with a warning. Images are never decoded: a shadow lab does
//! not need textures, and a missing texture should not stop a scene from loading.
//!
//! This file holds the entry points and their error; `buffers` reads the file's buffers,
//! `compression` decodes meshopt-compressed views into them,
//! `nodes` flattens the node trees into instances and `primitives` turns a primitive's
//! accessors into a [`Mesh`](crate::scene::Mesh).

mod buffers;
mod compression;
mod nodes;
mod primitives;

use std::io;
use std::path::{Path, PathBuf};

use super::{ChunkSettings, Scene, split_large_instances};
use buffers::{check_glb_header, load_buffers};
use nodes::flatten_node_trees;

// `tests.rs` reaches these through `super::*`.
#[cfg(test)]
use super::Instance;
#[cfg(test)]
use buffers::percent_decode;
#[cfg(test)]
use glam::{Mat4, Vec3};

/// Why a glTF file could not be loaded; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    #[error("{}: file not found", .path.display())]
    NotFound { path: PathBuf },
    #[error("{}: the file could not be read ({error})", .path.display())]
    Unreadable { path: PathBuf, error: io::Error },
    #[error("{}: the file is empty", .path.display())]
    Empty { path: PathBuf },
    #[error("{}: not a valid glTF 2.0 file ({reason})", .path.display())]
    NotGltf { path: PathBuf, reason: String },
    #[error(
        "{}: its buffer file '{uri}' is missing or unreadable ({error}); looked for it at {}",
        .path.display(),
        .resolved.display()
    )]
    MissingBuffer {
        path: PathBuf,
        uri: String,
        resolved: PathBuf,
        error: io::Error,
    },
    #[error("{}: buffer {index} could not be loaded ({reason})", .path.display())]
    BadBuffer {
        path: PathBuf,
        index: usize,
        reason: String,
    },
    #[error("{}: its compressed data could not be decoded: {reason}", .path.display())]
    Compressed { path: PathBuf, reason: String },
    #[error("{}: node '{node}' rejected: {reason}", .path.display())]
    BadNode {
        path: PathBuf,
        node: String,
        reason: String,
    },
    #[error("{} contains no triangle meshes", .path.display())]
    NoTriangleMeshes { path: PathBuf },
}

/// Loads a `.gltf` (with external or embedded buffers) or `.glb` file into a scene.
///
/// The scene is named after `path` as given; very large objects are split per `chunking`.
pub fn import_gltf(path: &Path, chunking: &ChunkSettings) -> Result<Scene, ImportError> {
    let bytes = std::fs::read(path).map_err(|error| match error.kind() {
        io::ErrorKind::NotFound => ImportError::NotFound {
            path: path.to_owned(),
        },
        _ => ImportError::Unreadable {
            path: path.to_owned(),
            error,
        },
    })?;
    // External buffers are relative to the file's folder ("" for a bare file name: the cwd).
    let base_dir = path.parent().unwrap_or_else(|| Path::new(""));
    import_bytes(&bytes, path, Some(base_dir), *chunking)
}

/// Loads a `.glb`, or a `.gltf` whose buffers are all embedded, from memory. `name` names the
/// scene and appears in errors. A reference to an external file is an error.
pub fn import_gltf_slice(
    bytes: &[u8],
    name: &str,
    chunking: &ChunkSettings,
) -> Result<Scene, ImportError> {
    import_bytes(bytes, Path::new(name), None, *chunking)
}

fn import_bytes(
    bytes: &[u8],
    path: &Path,
    base_dir: Option<&Path>,
    chunking: ChunkSettings,
) -> Result<Scene, ImportError> {
    let not_gltf = |reason: String| ImportError::NotGltf {
        path: path.to_owned(),
        reason,
    };
    if bytes.is_empty() {
        return Err(ImportError::Empty {
            path: path.to_owned(),
        });
    }
    check_glb_header(bytes).map_err(not_gltf)?;
    let (document, blob) = compression::parse(bytes).map_err(not_gltf)?;
    let mut buffers = load_buffers(&document, blob, path, base_dir)?;
    compression::decode_views(&document, &mut buffers).map_err(|reason| {
        ImportError::Compressed {
            path: path.to_owned(),
            reason,
        }
    })?;

    let nodes::Flattened {
        mut meshes,
        instances,
        sun,
        lights,
        warnings,
    } = flatten_node_trees(&document, &buffers, path).map_err(|bad| ImportError::BadNode {
        path: path.to_owned(),
        node: bad.node,
        reason: bad.reason,
    })?;
    // Each names the file and the part left out; the rest of the scene still loads.
    for warning in &warnings {
        log::warn!("{warning}");
    }
    if instances.is_empty() {
        return Err(ImportError::NoTriangleMeshes {
            path: path.to_owned(),
        });
    }
    let instances = split_large_instances(&mut meshes, instances, &chunking);
    let mut scene = Scene::new(
        path.display().to_string(),
        meshes,
        instances,
        sun.unwrap_or_default(),
    );
    scene.lights = lights;
    Ok(scene)
}

#[cfg(test)]
mod lights_tests;
#[cfg(test)]
mod safety_tests;
#[cfg(test)]
mod tests;
