//! glTF 2.0 import: `.gltf` with external or base64 buffers, and `.glb`, into a [`Scene`].
//!
//! The node tree of the default scene is flattened: every (node with a mesh, primitive) pair
//! becomes one [`Instance`] whose transform is the product of its ancestors' transforms.
//! A glTF mesh primitive used by several nodes becomes one shared [`Mesh`].
//!
//! Naming: an instance is named after its node (`node<index>` when the node has no name), a mesh
//! after its glTF mesh (`mesh<index>`). Primitive 0 of a mesh keeps that name; primitive `k > 0`
//! adds `/p<k>`, e.g. `car`, `car/p1`, `car/p2`. Split large objects then get `#<chunk>` (see
//! [`split_large_instances`]).
//!
//! Only triangles are imported (strips and fans are converted); other primitives, and primitives
//! whose data is broken, are skipped with a warning. Images are never decoded: a shadow lab does
//! not need textures, and a missing texture should not stop a scene from loading.

use std::collections::HashMap;
use std::io;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::{Mode, Semantic};

use super::chunking::compact_vertices;
use super::{ChunkSettings, Instance, Mesh, MeshId, Scene, Sun, split_large_instances};

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
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice(bytes).map_err(|e| not_gltf(e.to_string()))?;
    let buffers = load_buffers(&document, blob, path, base_dir)?;

    let (mut meshes, instances, warnings) = flatten_node_trees(&document, &buffers, path);
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
    Ok(Scene::new(
        path.display().to_string(),
        meshes,
        instances,
        Sun::default(),
    ))
}

/// `gltf` subtracts the header size from the declared GLB length before checking it, which
/// panics on a length below 12; reject that here.
fn check_glb_header(bytes: &[u8]) -> Result<(), String> {
    if bytes.starts_with(b"glTF")
        && let Some(&[a, b, c, d]) = bytes.get(8..12)
    {
        let declared_length = u32::from_le_bytes([a, b, c, d]);
        if declared_length < 12 {
            return Err(format!(
                "the GLB header declares a length of {declared_length} bytes"
            ));
        }
    }
    Ok(())
}

/// The bytes of every buffer, in document order.
fn load_buffers(
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    path: &Path,
    base_dir: Option<&Path>,
) -> Result<Vec<Vec<u8>>, ImportError> {
    let bad_buffer = |index: usize, reason: String| ImportError::BadBuffer {
        path: path.to_owned(),
        index,
        reason,
    };
    document
        .buffers()
        .map(|buffer| {
            let index = buffer.index();
            let data = match buffer.source() {
                gltf::buffer::Source::Bin => blob
                    .take()
                    .ok_or_else(|| bad_buffer(index, "the GLB file has no binary chunk".into()))?,
                gltf::buffer::Source::Uri(uri) => read_buffer_uri(uri, index, path, base_dir)?,
            };
            if data.len() < buffer.length() {
                let reason = format!(
                    "it holds {} bytes but should hold {}",
                    data.len(),
                    buffer.length()
                );
                return Err(bad_buffer(index, reason));
            }
            Ok(data)
        })
        .collect()
}

/// Reads a buffer given by a `data:` URI, a `file:` URI or a path relative to `base_dir`.
fn read_buffer_uri(
    uri: &str,
    index: usize,
    path: &Path,
    base_dir: Option<&Path>,
) -> Result<Vec<u8>, ImportError> {
    let bad_buffer = |reason: String| ImportError::BadBuffer {
        path: path.to_owned(),
        index,
        reason,
    };
    if uri.starts_with("data:") {
        let source = gltf::buffer::Source::Uri(uri);
        return gltf::buffer::Data::from_source(source, None)
            .map(|data| data.0)
            .map_err(|e| bad_buffer(format!("its data URI is not valid base64: {e}")));
    }
    let file_path = if let Some(absolute) = uri
        .strip_prefix("file://")
        .or_else(|| uri.strip_prefix("file:"))
    {
        PathBuf::from(absolute)
    } else if uri.contains(':') {
        return Err(bad_buffer(format!(
            "the URI '{uri}' uses a scheme that is not supported"
        )));
    } else {
        let relative = percent_decode(uri)
            .ok_or_else(|| bad_buffer(format!("the URI '{uri}' is malformed")))?;
        let base_dir = base_dir.ok_or_else(|| {
            bad_buffer(format!(
                "it refers to the external file '{uri}', which cannot be loaded from memory"
            ))
        })?;
        base_dir.join(relative)
    };
    std::fs::read(&file_path).map_err(|error| ImportError::MissingBuffer {
        path: path.to_owned(),
        uri: uri.to_owned(),
        resolved: file_path,
        error,
    })
}

/// Decodes `%XX` escapes in a relative URI; `None` when an escape or the result is malformed.
fn percent_decode(uri: &str) -> Option<String> {
    let mut bytes = Vec::with_capacity(uri.len());
    let mut rest = uri.as_bytes();
    while let Some((&first, tail)) = rest.split_first() {
        if first == b'%' {
            let hex = std::str::from_utf8(tail.get(..2)?).ok()?;
            bytes.push(u8::from_str_radix(hex, 16).ok()?);
            rest = &tail[2..];
        } else {
            bytes.push(first);
            rest = tail;
        }
    }
    String::from_utf8(bytes).ok()
}

/// The meshes and instances of the document's node trees, and a warning for each part skipped.
fn flatten_node_trees(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    path: &Path,
) -> (Vec<Mesh>, Vec<Instance>, Vec<String>) {
    let mut builder = SceneBuilder::new(path, buffers);
    builder.add_node_trees(document);
    (builder.meshes, builder.instances, builder.warnings)
}

/// Turns the node trees of a document into meshes and instances.
struct SceneBuilder<'a> {
    path: &'a Path,
    buffers: &'a [Vec<u8>],
    meshes: Vec<Mesh>,
    /// The mesh made from each (glTF mesh, primitive), or `None` when the primitive was rejected.
    mesh_ids: HashMap<(usize, usize), Option<MeshId>>,
    instances: Vec<Instance>,
    /// What was skipped or repaired, each naming the file.
    warnings: Vec<String>,
}

impl<'a> SceneBuilder<'a> {
    fn new(path: &'a Path, buffers: &'a [Vec<u8>]) -> Self {
        Self {
            path,
            buffers,
            meshes: Vec::new(),
            mesh_ids: HashMap::new(),
            instances: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// Walks the node trees depth first, in document order. A node reached twice (the file
    /// has a cycle or shares a child) is only imported the first time.
    fn add_node_trees(&mut self, document: &gltf::Document) {
        let mut visited = vec![false; document.nodes().len()];
        let mut stack: Vec<(gltf::Node, Mat4)> = root_nodes(document)
            .into_iter()
            .rev()
            .map(|node| (node, Mat4::IDENTITY))
            .collect();
        while let Some((node, world_from_parent)) = stack.pop() {
            match visited.get_mut(node.index()) {
                Some(seen) if !*seen => *seen = true,
                _ => {
                    let file = self.path.display();
                    self.warnings.push(format!(
                        "{file}: node {} appears twice in the node tree; imported once",
                        node.index()
                    ));
                    continue;
                }
            }
            let world_from_local =
                world_from_parent * Mat4::from_cols_array_2d(&node.transform().matrix());
            if !world_from_local.is_finite() {
                let file = self.path.display();
                self.warnings.push(format!(
                    "{file}: node '{}' and its children skipped: transform overflows",
                    node_name(&node)
                ));
                continue;
            }
            self.add_node(&node, world_from_local);
            let children: Vec<gltf::Node> = node.children().collect();
            stack.extend(
                children
                    .into_iter()
                    .rev()
                    .map(|child| (child, world_from_local)),
            );
        }
    }

    /// One instance per triangle primitive of the node's mesh.
    fn add_node(&mut self, node: &gltf::Node, world_from_local: Mat4) {
        let Some(mesh) = node.mesh() else { return };
        let node_name = node_name(node);
        for primitive in mesh.primitives() {
            let instance_name = with_primitive_suffix(&node_name, primitive.index());
            if !matches!(
                primitive.mode(),
                Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
            ) {
                let (file, mode) = (self.path.display(), primitive.mode());
                self.warnings.push(format!(
                    "{file}: node '{node_name}', primitive {} skipped: it draws {mode:?}, not triangles",
                    primitive.index()
                ));
                continue;
            }
            let Some(mesh_id) = self.mesh_for(&mesh, &primitive, &instance_name) else {
                continue;
            };
            let base_color = primitive
                .material()
                .pbr_metallic_roughness()
                .base_color_factor();
            let instance = Instance::new(
                instance_name,
                mesh_id,
                &self.meshes[mesh_id as usize],
                world_from_local,
            )
            .with_color(base_color);
            self.instances.push(instance);
        }
    }

    /// The scene mesh of a primitive, read the first time a node uses it.
    fn mesh_for(
        &mut self,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
        instance_name: &str,
    ) -> Option<MeshId> {
        let key = (mesh.index(), primitive.index());
        if let Some(&mesh_id) = self.mesh_ids.get(&key) {
            return mesh_id;
        }
        let base_name = mesh
            .name()
            .map_or_else(|| format!("mesh{}", mesh.index()), str::to_owned);
        let mesh_name = with_primitive_suffix(&base_name, primitive.index());
        let context = format!(
            "{}: node '{instance_name}', mesh '{mesh_name}'",
            self.path.display()
        );
        let read = read_triangle_mesh(
            primitive,
            self.buffers,
            mesh_name,
            &context,
            &mut self.warnings,
        );
        let mesh_id = match read {
            Ok(mesh) => {
                self.meshes.push(mesh);
                Some((self.meshes.len() - 1) as MeshId)
            }
            Err(reason) => {
                self.warnings.push(format!("{context} skipped: {reason}"));
                None
            }
        };
        self.mesh_ids.insert(key, mesh_id);
        mesh_id
    }
}

/// The nodes the default scene (or else the first scene) lists; without scenes, every node
/// that is nobody's child.
fn root_nodes(document: &gltf::Document) -> Vec<gltf::Node<'_>> {
    if let Some(scene) = document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        return scene.nodes().collect();
    }
    let mut is_child = vec![false; document.nodes().len()];
    for child in document.nodes().flat_map(|node| node.children()) {
        if let Some(flag) = is_child.get_mut(child.index()) {
            *flag = true;
        }
    }
    document
        .nodes()
        .filter(|node| !is_child.get(node.index()).copied().unwrap_or(true))
        .collect()
}

fn node_name(node: &gltf::Node) -> String {
    node.name()
        .map_or_else(|| format!("node{}", node.index()), str::to_owned)
}

/// `name` for a mesh's first primitive, `name/p<k>` for primitive `k > 0`.
fn with_primitive_suffix(name: &str, primitive_index: usize) -> String {
    if primitive_index == 0 {
        name.to_owned()
    } else {
        format!("{name}/p{primitive_index}")
    }
}

/// The primitive as a triangle mesh named `name`, without unused vertices and without triangles
/// that touch non-finite positions. Repairs add to `warnings`, prefixed by `context`.
fn read_triangle_mesh(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    name: String,
    context: &str,
    warnings: &mut Vec<String>,
) -> Result<Mesh, String> {
    let positions = read_positions(primitive, buffers)?;
    let vertex_order = read_vertex_order(primitive, buffers, positions.len())?;
    if primitive.mode() == Mode::Triangles && vertex_order.len() % 3 != 0 {
        warnings.push(format!(
            "{context}: {} trailing indices do not make a triangle; ignored",
            vertex_order.len() % 3
        ));
    }
    let indices = triangle_list(primitive.mode(), &vertex_order);
    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(format!(
            "vertex index {bad} is out of range ({} vertices)",
            positions.len()
        ));
    }
    let normals = match read_normals(primitive, buffers, positions.len()) {
        Ok(normals) => normals,
        Err(reason) => {
            warnings.push(format!("{context}: normals recomputed: {reason}"));
            None
        }
    };

    let triangle_count = indices.len() / 3;
    let finite_indices: Vec<u32> = indices
        .chunks_exact(3)
        .filter(|triangle| triangle.iter().all(|&i| positions[i as usize].is_finite()))
        .flatten()
        .copied()
        .collect();
    let dropped = triangle_count - finite_indices.len() / 3;
    if finite_indices.is_empty() {
        return Err(if triangle_count == 0 {
            "it has no triangles".to_owned()
        } else {
            "every triangle has a non-finite vertex position".to_owned()
        });
    }
    if dropped > 0 {
        warnings.push(format!(
            "{context}: {dropped} of {triangle_count} triangles dropped: they touch non-finite \
             vertex positions"
        ));
    }
    let (positions, normals, indices) = compact_vertices(
        &positions,
        normals.as_deref().unwrap_or_default(),
        &finite_indices,
    );
    Ok(Mesh::new(name, positions, normals, indices))
}

fn read_positions(primitive: &gltf::Primitive, buffers: &[Vec<u8>]) -> Result<Vec<Vec3>, String> {
    let accessor = primitive
        .get(&Semantic::Positions)
        .ok_or("it has no POSITION attribute")?;
    check_accessor(&accessor, &[DataType::F32], Dimensions::Vec3, buffers)
        .map_err(|reason| format!("its POSITION accessor {reason}"))?;
    let reader = primitive.reader(|buffer| buffers.get(buffer.index()).map(Vec::as_slice));
    let positions: Vec<Vec3> = reader
        .read_positions()
        .ok_or("its positions cannot be read")?
        .map(Vec3::from)
        .collect();
    if u32::try_from(positions.len()).is_err() {
        return Err(format!(
            "it has {} vertices, more than 32-bit indices can address",
            positions.len()
        ));
    }
    Ok(positions)
}

/// The primitive's indices, or `0..vertex_count` when it has none.
fn read_vertex_order(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    vertex_count: usize,
) -> Result<Vec<u32>, String> {
    let Some(accessor) = primitive.indices() else {
        return Ok((0..vertex_count as u32).collect());
    };
    check_accessor(
        &accessor,
        &[DataType::U8, DataType::U16, DataType::U32],
        Dimensions::Scalar,
        buffers,
    )
    .map_err(|reason| format!("its index accessor {reason}"))?;
    let reader = primitive.reader(|buffer| buffers.get(buffer.index()).map(Vec::as_slice));
    Ok(reader
        .read_indices()
        .ok_or("its indices cannot be read")?
        .into_u32()
        .collect())
}

/// Unit normals from the file; `Ok(None)` when it has none, `Err` when they are unusable.
fn read_normals(
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    vertex_count: usize,
) -> Result<Option<Vec<Vec3>>, String> {
    let Some(accessor) = primitive.get(&Semantic::Normals) else {
        return Ok(None);
    };
    check_accessor(&accessor, &[DataType::F32], Dimensions::Vec3, buffers)
        .map_err(|reason| format!("the NORMAL accessor {reason}"))?;
    if accessor.count() != vertex_count {
        return Err(format!(
            "there are {} normals for {vertex_count} vertices",
            accessor.count()
        ));
    }
    let reader = primitive.reader(|buffer| buffers.get(buffer.index()).map(Vec::as_slice));
    let normals = reader.read_normals().ok_or("the normals cannot be read")?;
    let unit_normals: Option<Vec<Vec3>> = normals.map(|n| Vec3::from(n).try_normalize()).collect();
    unit_normals
        .map(Some)
        .ok_or_else(|| "some normals are zero or not finite".to_owned())
}

/// Checks what `gltf`'s reader assumes (and would panic or silently truncate on otherwise): the
/// element type, a non-empty dense accessor, and every element inside its view and buffer.
fn check_accessor(
    accessor: &gltf::Accessor,
    data_types: &[DataType],
    dimensions: Dimensions,
    buffers: &[Vec<u8>],
) -> Result<(), String> {
    let index = accessor.index();
    if !data_types.contains(&accessor.data_type()) || accessor.dimensions() != dimensions {
        let found = (accessor.data_type(), accessor.dimensions());
        return Err(format!(
            "{index} has type {found:?}, expected {dimensions:?} of {data_types:?}"
        ));
    }
    if accessor.sparse().is_some() {
        return Err(format!(
            "{index} uses sparse storage, which is not supported"
        ));
    }
    let view = accessor
        .view()
        .ok_or_else(|| format!("{index} has no buffer view"))?;
    if accessor.count() == 0 {
        return Err(format!("{index} is empty"));
    }
    let element_size = accessor.size();
    let stride = view.stride().unwrap_or(element_size);
    if stride < element_size {
        return Err(format!(
            "{index} has a stride of {stride} bytes for {element_size}-byte elements"
        ));
    }
    let buffer_length = buffers.get(view.buffer().index()).map_or(0, Vec::len);
    if view
        .offset()
        .checked_add(view.length())
        .is_none_or(|end| end > buffer_length)
    {
        return Err(format!(
            "{index} uses buffer view {}, which runs past the end of its buffer",
            view.index()
        ));
    }
    let accessor_end = (accessor.count() - 1)
        .checked_mul(stride)
        .and_then(|last_start| last_start.checked_add(accessor.offset()))
        .and_then(|last_start| last_start.checked_add(element_size));
    if accessor_end.is_none_or(|end| end > view.length()) {
        return Err(format!(
            "{index} runs past the end of buffer view {}",
            view.index()
        ));
    }
    Ok(())
}

/// Three indices per triangle from a triangle list, strip or fan (glTF 2.0 spec, section 3.7.2.1
/// "Topology Types"); other modes give nothing.
fn triangle_list(mode: Mode, order: &[u32]) -> Vec<u32> {
    let n = order.len();
    match mode {
        Mode::Triangles => order[..n / 3 * 3].to_vec(),
        // Every other strip triangle swaps two vertices to keep the winding.
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .flat_map(|i| {
                let odd = i % 2;
                [order[i], order[i + 1 + odd], order[i + 2 - odd]]
            })
            .collect(),
        Mode::TriangleFan => (0..n.saturating_sub(2))
            .flat_map(|i| [order[i + 1], order[i + 2], order[0]])
            .collect(),
        _ => Vec::new(),
    }
}

#[cfg(test)]
mod tests;
