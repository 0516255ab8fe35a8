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
mod tests {
    use std::sync::atomic::{AtomicUsize, Ordering};

    use glam::{Quat, Vec4};
    use serde_json::{Value, json};

    use super::*;
    use crate::geom::Aabb;

    const FLOAT: u32 = 5126;
    const UNSIGNED_SHORT: u32 = 5123;
    const UNSIGNED_INT: u32 = 5125;
    const LINES: u32 = 1;
    const TRIANGLE_STRIP: u32 = 5;

    /// A glTF document under construction, with one binary buffer.
    #[derive(Default)]
    struct TestGltf {
        bin: Vec<u8>,
        buffer_views: Vec<Value>,
        accessors: Vec<Value>,
        meshes: Vec<Value>,
        materials: Vec<Value>,
        nodes: Vec<Value>,
        scene_roots: Vec<usize>,
    }

    impl TestGltf {
        fn view(&mut self, bytes: &[u8]) -> usize {
            self.bin.resize(self.bin.len().next_multiple_of(4), 0);
            let offset = self.bin.len();
            self.bin.extend_from_slice(bytes);
            self.buffer_views
                .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}));
            self.buffer_views.len() - 1
        }

        fn accessor(&mut self, accessor: Value) -> usize {
            self.accessors.push(accessor);
            self.accessors.len() - 1
        }

        fn vec3s(&mut self, values: &[Vec3]) -> usize {
            let bytes: Vec<u8> = values
                .iter()
                .flat_map(Vec3::to_array)
                .flat_map(f32::to_le_bytes)
                .collect();
            let view = self.view(&bytes);
            self.accessor(json!({"bufferView": view, "componentType": FLOAT, "count": values.len(), "type": "VEC3"}))
        }

        /// Positions need min and max (glTF 2.0 requires them).
        fn positions(&mut self, points: &[Vec3]) -> usize {
            let accessor = self.vec3s(points);
            let bounds = Aabb::from_points(points.iter().copied().filter(|p| p.is_finite()));
            let (min, max) = if bounds.is_empty() {
                (Vec3::ZERO, Vec3::ZERO)
            } else {
                (bounds.min, bounds.max)
            };
            self.accessors[accessor]["min"] = json!(min.to_array());
            self.accessors[accessor]["max"] = json!(max.to_array());
            accessor
        }

        fn indices_u32(&mut self, indices: &[u32]) -> usize {
            let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
            let view = self.view(&bytes);
            self.accessor(json!({"bufferView": view, "componentType": UNSIGNED_INT, "count": indices.len(), "type": "SCALAR"}))
        }

        fn indices_u16(&mut self, indices: &[u16]) -> usize {
            let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
            let view = self.view(&bytes);
            self.accessor(json!({"bufferView": view, "componentType": UNSIGNED_SHORT, "count": indices.len(), "type": "SCALAR"}))
        }

        fn material(&mut self, base_color: [f32; 4]) -> usize {
            self.materials
                .push(json!({"pbrMetallicRoughness": {"baseColorFactor": base_color}}));
            self.materials.len() - 1
        }

        fn mesh(&mut self, name: &str, primitives: &[Value]) -> usize {
            self.meshes
                .push(json!({"name": name, "primitives": primitives}));
            self.meshes.len() - 1
        }

        /// A triangle mesh from positions and indices, with nothing else.
        fn simple_mesh(&mut self, name: &str, positions: &[Vec3], indices: &[u32]) -> usize {
            let positions = self.positions(positions);
            let indices = self.indices_u32(indices);
            self.mesh(
                name,
                &[json!({"attributes": {"POSITION": positions}, "indices": indices})],
            )
        }

        fn node(&mut self, node: Value) -> usize {
            self.nodes.push(node);
            self.nodes.len() - 1
        }

        fn root(&mut self, node: Value) -> usize {
            let index = self.node(node);
            self.scene_roots.push(index);
            index
        }

        fn json(&self, buffer_uri: Option<&str>) -> Value {
            let mut buffer = json!({"byteLength": self.bin.len()});
            if let Some(uri) = buffer_uri {
                buffer["uri"] = json!(uri);
            }
            json!({
                "asset": {"version": "2.0"},
                "scene": 0,
                "scenes": [{"nodes": self.scene_roots}],
                "nodes": self.nodes,
                "meshes": self.meshes,
                "materials": self.materials,
                "accessors": self.accessors,
                "bufferViews": self.buffer_views,
                "buffers": [buffer],
            })
        }

        /// Writes `<stem>.gltf` and `<stem>.bin` into `dir`; returns the `.gltf` path.
        fn write_with_bin(&self, dir: &Path, stem: &str) -> PathBuf {
            let bin_name = format!("{stem}.bin");
            std::fs::write(dir.join(&bin_name), &self.bin).unwrap();
            let gltf_path = dir.join(format!("{stem}.gltf"));
            std::fs::write(&gltf_path, self.json(Some(&bin_name)).to_string()).unwrap();
            gltf_path
        }

        fn embedded(&self) -> Vec<u8> {
            let uri = format!("data:application/octet-stream;base64,{}", base64(&self.bin));
            self.json(Some(&uri)).to_string().into_bytes()
        }

        /// Binary glTF: a 12-byte header, a JSON chunk padded with spaces, a BIN chunk padded
        /// with zeros.
        fn glb(&self) -> Vec<u8> {
            let mut json_chunk = self.json(None).to_string().into_bytes();
            json_chunk.resize(json_chunk.len().next_multiple_of(4), b' ');
            let mut bin_chunk = self.bin.clone();
            bin_chunk.resize(bin_chunk.len().next_multiple_of(4), 0);
            let total_length = 12 + 8 + json_chunk.len() + 8 + bin_chunk.len();
            let mut glb = Vec::with_capacity(total_length);
            glb.extend_from_slice(b"glTF");
            glb.extend_from_slice(&2u32.to_le_bytes());
            glb.extend_from_slice(&(total_length as u32).to_le_bytes());
            glb.extend_from_slice(&(json_chunk.len() as u32).to_le_bytes());
            glb.extend_from_slice(b"JSON");
            glb.extend_from_slice(&json_chunk);
            glb.extend_from_slice(&(bin_chunk.len() as u32).to_le_bytes());
            glb.extend_from_slice(b"BIN\0");
            glb.extend_from_slice(&bin_chunk);
            glb
        }
    }

    fn base64(bytes: &[u8]) -> String {
        const ALPHABET: &[u8; 64] =
            b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut encoded = String::new();
        for chunk in bytes.chunks(3) {
            let byte = |i: usize| u32::from(chunk.get(i).copied().unwrap_or(0));
            let group = (byte(0) << 16) | (byte(1) << 8) | byte(2);
            for i in 0..4 {
                let sextet = (group >> (18 - 6 * i)) & 63;
                encoded.push(if i <= chunk.len() {
                    char::from(ALPHABET[sextet as usize])
                } else {
                    '='
                });
            }
        }
        encoded
    }

    /// A folder under the system temp folder, removed when dropped.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(label: &str) -> Self {
            static COUNTER: AtomicUsize = AtomicUsize::new(0);
            let unique = COUNTER.fetch_add(1, Ordering::Relaxed);
            let path = std::env::temp_dir().join(format!(
                "shadowlab-gltf-{}-{unique}-{label}",
                std::process::id()
            ));
            std::fs::create_dir_all(&path).unwrap();
            Self(path)
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// A unit quad in the XY plane, facing +Z.
    fn quad() -> ([Vec3; 4], [u32; 6]) {
        (
            [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            [0, 1, 2, 0, 2, 3],
        )
    }

    /// `quads` x `quads` quads in the XZ plane, `size_m` wide, centred on the origin, facing +Y.
    fn ground(quads: u32, size_m: f32) -> (Vec<Vec3>, Vec<u32>) {
        let step_m = size_m / quads as f32;
        let mut positions = Vec::new();
        for iz in 0..=quads {
            for ix in 0..=quads {
                let (x, z) = (
                    ix as f32 * step_m - size_m / 2.0,
                    iz as f32 * step_m - size_m / 2.0,
                );
                positions.push(Vec3::new(x, 0.0, z));
            }
        }
        let vertex = |ix: u32, iz: u32| iz * (quads + 1) + ix;
        let mut indices = Vec::new();
        for iz in 0..quads {
            for ix in 0..quads {
                let (v00, v10, v01, v11) = (
                    vertex(ix, iz),
                    vertex(ix + 1, iz),
                    vertex(ix, iz + 1),
                    vertex(ix + 1, iz + 1),
                );
                indices.extend([v00, v01, v10, v10, v01, v11]);
            }
        }
        (positions, indices)
    }

    fn cube(size_m: f32) -> (Vec<Vec3>, Vec<u32>) {
        let corners = Aabb::new(Vec3::ZERO, Vec3::splat(size_m))
            .corners()
            .to_vec();
        let indices = vec![
            0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4,
            6, 1, 3, 5, 3, 7, 5,
        ];
        (corners, indices)
    }

    fn no_chunking() -> ChunkSettings {
        ChunkSettings {
            max_extent_fraction: 0.0,
        }
    }

    fn import_glb(gltf: &TestGltf) -> Scene {
        import_gltf_slice(&gltf.glb(), "test.glb", &no_chunking()).unwrap()
    }

    /// The instance names (before chunking) and the warnings of a GLB named `test.glb`.
    fn flatten_glb(gltf: &TestGltf) -> (Vec<String>, Vec<String>) {
        let gltf::Gltf { document, blob } = gltf::Gltf::from_slice(&gltf.glb()).unwrap();
        let path = Path::new("test.glb");
        let buffers = load_buffers(&document, blob, path, None).unwrap();
        let (_, instances, warnings) = flatten_node_trees(&document, &buffers, path);
        (instances.into_iter().map(|i| i.name).collect(), warnings)
    }

    fn names(scene: &Scene) -> Vec<&str> {
        scene.instances.iter().map(|i| i.name.as_str()).collect()
    }

    fn instance<'s>(scene: &'s Scene, name: &str) -> &'s Instance {
        scene.instances.iter().find(|i| i.name == name).unwrap()
    }

    #[test]
    fn hierarchy_flattens_into_world_transforms() {
        let mut gltf = TestGltf::default();
        let (positions, indices) = quad();
        let mesh = gltf.simple_mesh("quad", &positions, &indices);
        let rotation = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
        gltf.root(json!({"name": "parent", "translation": [1.0, 2.0, 3.0], "scale": [2.0, 2.0, 2.0], "children": [1]}));
        gltf.node(json!({"name": "child", "rotation": rotation.to_array(), "mesh": mesh}));
        gltf.root(json!({"mesh": mesh, "translation": [0.0, 0.0, -5.0]}));
        let scene = import_glb(&gltf);

        // The parent has no mesh and is no instance; the unnamed node is named by its index.
        assert_eq!(names(&scene), ["child", "node2"]);
        let expected = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0))
            * Mat4::from_scale(Vec3::splat(2.0))
            * Mat4::from_quat(rotation);
        let child = instance(&scene, "child");
        assert!(
            child.world_from_local.abs_diff_eq(expected, 1e-5),
            "{:?}",
            child.world_from_local
        );
        // The quad's corner (1, 0, 0) is rotated to (0, 0, -1), scaled by 2 and moved.
        let corner_in_world = child.world_from_local.transform_point3(Vec3::X);
        assert!(corner_in_world.abs_diff_eq(Vec3::new(1.0, 2.0, 1.0), 1e-5));
        // The quad spans y and z in world space: x = 1, y in [2, 4], z in [1, 3].
        assert!(
            child
                .aabb_in_world
                .min
                .abs_diff_eq(Vec3::new(1.0, 2.0, 1.0), 1e-5)
        );
        assert!(
            child
                .aabb_in_world
                .max
                .abs_diff_eq(Vec3::new(1.0, 4.0, 3.0), 1e-5)
        );
        let translation = instance(&scene, "node2").world_from_local.w_axis.truncate();
        assert!(translation.abs_diff_eq(Vec3::new(0.0, 0.0, -5.0), 1e-6));
        assert_eq!(scene.name, "test.glb");
    }

    #[test]
    fn nodes_sharing_a_mesh_share_one_scene_mesh() {
        let mut gltf = TestGltf::default();
        let (positions, indices) = cube(1.0);
        let mesh = gltf.simple_mesh("crate", &positions, &indices);
        gltf.root(json!({"name": "crate_a", "mesh": mesh}));
        gltf.root(json!({"name": "crate_b", "mesh": mesh, "translation": [4.0, 0.0, 0.0]}));
        let scene = import_glb(&gltf);
        assert_eq!(scene.meshes.len(), 1);
        assert_eq!(scene.meshes[0].name, "crate");
        assert_eq!(names(&scene), ["crate_a", "crate_b"]);
        assert!(scene.instances.iter().all(|i| i.mesh == 0));
        assert_eq!(scene.meshes[0].triangle_count(), 12);
        assert_eq!(scene.triangle_count(), 24);
    }

    #[test]
    fn primitives_get_suffixes_and_lines_are_skipped() {
        let mut gltf = TestGltf::default();
        let (positions, indices) = quad();
        let p = gltf.positions(&positions);
        let i32s = gltf.indices_u32(&indices);
        let i16s = gltf.indices_u16(&[0, 1, 2]);
        let lines = gltf.indices_u32(&[0, 1, 1, 2]);
        let mesh = gltf.mesh(
            "thing",
            &[
                json!({"attributes": {"POSITION": p}, "indices": i32s}),
                json!({"attributes": {"POSITION": p}, "indices": lines, "mode": LINES}),
                json!({"attributes": {"POSITION": p}, "indices": i16s}),
            ],
        );
        gltf.root(json!({"name": "thing_node", "mesh": mesh}));
        let scene = import_glb(&gltf);
        assert_eq!(names(&scene), ["thing_node", "thing_node/p2"]);
        let (_, warnings) = flatten_glb(&gltf);
        assert_eq!(
            warnings,
            ["test.glb: node 'thing_node', primitive 1 skipped: it draws Lines, not triangles"]
        );
        let mesh_names: Vec<&str> = scene.meshes.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(mesh_names, ["thing", "thing/p2"]);
        assert_eq!(scene.mesh_of(&scene.instances[0]).triangle_count(), 2);
        assert_eq!(scene.mesh_of(&scene.instances[1]).triangle_count(), 1);
    }

    #[test]
    fn normals_are_computed_when_missing_and_kept_when_present() {
        let mut gltf = TestGltf::default();
        let (positions, indices) = quad();
        let bare = gltf.simple_mesh("bare", &positions, &indices);
        let p = gltf.positions(&positions);
        let i = gltf.indices_u32(&indices);
        // Deliberately not the geometric normal (+Z), and not unit length.
        let n = gltf.vec3s(&[Vec3::new(0.0, 3.0, 0.0); 4]);
        let with_normals = gltf.mesh(
            "with_normals",
            &[json!({"attributes": {"POSITION": p, "NORMAL": n}, "indices": i})],
        );
        gltf.root(json!({"name": "bare", "mesh": bare}));
        gltf.root(json!({"name": "with_normals", "mesh": with_normals}));
        let scene = import_glb(&gltf);

        let computed = &scene.mesh_of(instance(&scene, "bare")).normals;
        assert_eq!(computed.len(), 4);
        assert!(
            computed.iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)),
            "{computed:?}"
        );
        let from_file = &scene.mesh_of(instance(&scene, "with_normals")).normals;
        assert_eq!(from_file.len(), 4);
        assert!(
            from_file.iter().all(|n| n.abs_diff_eq(Vec3::Y, 1e-6)),
            "{from_file:?}"
        );
    }

    #[test]
    fn unindexed_triangles_and_strips_become_triangle_lists() {
        let mut gltf = TestGltf::default();
        let (corners, indices) = quad();
        let unrolled: Vec<Vec3> = indices.iter().map(|&i| corners[i as usize]).collect();
        let p = gltf.positions(&unrolled);
        let soup = gltf.mesh("soup", &[json!({"attributes": {"POSITION": p}})]);
        // Strip order 0, 1, 3, 2 covers the quad with two triangles of the same winding.
        let strip_positions = [corners[0], corners[1], corners[3], corners[2]];
        let sp = gltf.positions(&strip_positions);
        let strip = gltf.mesh(
            "strip",
            &[json!({"attributes": {"POSITION": sp}, "mode": TRIANGLE_STRIP})],
        );
        gltf.root(json!({"name": "soup", "mesh": soup}));
        gltf.root(json!({"name": "strip", "mesh": strip}));
        let scene = import_glb(&gltf);

        let soup = scene.mesh_of(instance(&scene, "soup"));
        assert_eq!(soup.triangle_count(), 2);
        let strip = scene.mesh_of(instance(&scene, "strip"));
        assert_eq!(strip.triangle_count(), 2);
        for mesh in [soup, strip] {
            for triangle in mesh.indices.chunks_exact(3) {
                let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[triangle[k] as usize]);
                let face_normal = (b - a).cross(c - a).normalize();
                assert!(
                    face_normal.abs_diff_eq(Vec3::Z, 1e-6),
                    "{} {triangle:?}",
                    mesh.name
                );
            }
        }
    }

    #[test]
    fn base_color_comes_from_the_material() {
        let mut gltf = TestGltf::default();
        let (positions, indices) = quad();
        let p = gltf.positions(&positions);
        let i = gltf.indices_u32(&indices);
        let red = gltf.material([0.9, 0.1, 0.2, 0.5]);
        let painted = gltf.mesh(
            "painted",
            &[json!({"attributes": {"POSITION": p}, "indices": i, "material": red})],
        );
        let plain = gltf.mesh(
            "plain",
            &[json!({"attributes": {"POSITION": p}, "indices": i})],
        );
        gltf.root(json!({"name": "painted", "mesh": painted}));
        gltf.root(json!({"name": "plain", "mesh": plain}));
        let scene = import_glb(&gltf);
        let painted = Vec4::from(instance(&scene, "painted").base_color);
        assert!(
            painted.abs_diff_eq(Vec4::new(0.9, 0.1, 0.2, 0.5), 1e-6),
            "{painted}"
        );
        // glTF's default material is white.
        let plain = Vec4::from(instance(&scene, "plain").base_color);
        assert!(plain.abs_diff_eq(Vec4::ONE, 1e-6), "{plain}");
    }

    fn two_boxes() -> TestGltf {
        let mut gltf = TestGltf::default();
        let (positions, indices) = cube(1.0);
        let mesh = gltf.simple_mesh("box", &positions, &indices);
        gltf.root(json!({"name": "left", "mesh": mesh, "translation": [-2.0, 0.0, 0.0]}));
        gltf.root(json!({"name": "right", "mesh": mesh, "translation": [2.0, 0.0, 0.0]}));
        gltf
    }

    #[test]
    fn external_embedded_and_binary_files_load_alike() {
        let gltf = two_boxes();
        let dir = TempDir::new("formats");
        let external = gltf.write_with_bin(&dir.0, "boxes");
        let embedded = dir.0.join("embedded.gltf");
        std::fs::write(&embedded, gltf.embedded()).unwrap();
        let binary = dir.0.join("boxes.glb");
        std::fs::write(&binary, gltf.glb()).unwrap();

        for path in [&external, &embedded, &binary] {
            let scene = import_gltf(path, &ChunkSettings::default()).unwrap();
            assert_eq!(scene.name, path.display().to_string());
            assert_eq!(names(&scene), ["left", "right"], "{}", path.display());
            assert_eq!(scene.meshes.len(), 1);
            assert_eq!(scene.triangle_count(), 24);
            assert!(
                scene
                    .bounds()
                    .min
                    .abs_diff_eq(Vec3::new(-2.0, 0.0, 0.0), 1e-6)
            );
            assert!(
                scene
                    .bounds()
                    .max
                    .abs_diff_eq(Vec3::new(3.0, 1.0, 1.0), 1e-6)
            );
        }
        let in_memory = import_gltf_slice(&gltf.embedded(), "embedded", &no_chunking()).unwrap();
        assert_eq!(in_memory.triangle_count(), 24);
    }

    #[test]
    fn a_missing_file_is_named_in_the_error() {
        let dir = TempDir::new("missing");
        let path = dir.0.join("nowhere_to_be_found.gltf");
        let error = import_gltf(&path, &ChunkSettings::default()).unwrap_err();
        assert!(matches!(error, ImportError::NotFound { .. }), "{error:?}");
        let message = error.to_string();
        assert!(
            message.contains("nowhere_to_be_found.gltf") && message.contains("not found"),
            "{message}"
        );
    }

    #[test]
    fn a_corrupt_or_empty_file_is_named_in_the_error() {
        let dir = TempDir::new("corrupt");
        let mut state = 0x2545_f491_u32;
        let noise: Vec<u8> = (0..512)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                state.to_le_bytes()[1]
            })
            .collect();
        let corrupt = dir.0.join("corrupt_scene.glb");
        std::fs::write(&corrupt, &noise).unwrap();
        let message = import_gltf(&corrupt, &ChunkSettings::default())
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("corrupt_scene.glb") && message.contains("not a valid glTF"),
            "{message}"
        );

        let empty = dir.0.join("empty_scene.gltf");
        std::fs::write(&empty, b"").unwrap();
        let message = import_gltf(&empty, &ChunkSettings::default())
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("empty_scene.gltf") && message.contains("empty"),
            "{message}"
        );
    }

    #[test]
    fn a_missing_bin_is_named_in_the_error() {
        let dir = TempDir::new("missing-bin");
        let path = two_boxes().write_with_bin(&dir.0, "orphan");
        std::fs::remove_file(dir.0.join("orphan.bin")).unwrap();
        let error = import_gltf(&path, &ChunkSettings::default()).unwrap_err();
        assert!(
            matches!(error, ImportError::MissingBuffer { .. }),
            "{error:?}"
        );
        let message = error.to_string();
        assert!(
            message.contains("orphan.gltf") && message.contains("'orphan.bin'"),
            "{message}"
        );

        // In memory, an external buffer cannot be resolved at all.
        let json = two_boxes().json(Some("orphan.bin")).to_string();
        let message = import_gltf_slice(json.as_bytes(), "memory.gltf", &no_chunking())
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("memory.gltf") && message.contains("orphan.bin"),
            "{message}"
        );
    }

    #[test]
    fn a_file_without_triangles_is_an_error() {
        let mut gltf = TestGltf::default();
        let p = gltf.positions(&[Vec3::ZERO, Vec3::X]);
        let mesh = gltf.mesh(
            "wire",
            &[json!({"attributes": {"POSITION": p}, "mode": LINES})],
        );
        gltf.root(json!({"name": "wire", "mesh": mesh}));
        let error = import_gltf_slice(&gltf.glb(), "wires.glb", &no_chunking()).unwrap_err();
        assert_eq!(error.to_string(), "wires.glb contains no triangle meshes");
    }

    #[test]
    fn broken_primitives_are_skipped_without_panicking() {
        let mut gltf = TestGltf::default();
        let (positions, indices) = quad();
        let good = gltf.simple_mesh("good", &positions, &indices);
        let out_of_range = gltf.simple_mesh("out_of_range", &positions, &[0, 1, 99]);
        let p = gltf.positions(&positions);
        let overlong = gltf.indices_u32(&indices);
        gltf.accessors[overlong]["count"] = json!(1_000_000);
        let overlong = gltf.mesh(
            "overlong",
            &[json!({"attributes": {"POSITION": p}, "indices": overlong})],
        );
        let empty_positions = gltf.positions(&[]);
        let empty = gltf.mesh(
            "empty",
            &[json!({"attributes": {"POSITION": empty_positions}})],
        );
        let flat = gltf.positions(&positions);
        gltf.accessors[flat]["type"] = json!("VEC2");
        let wrong_type = gltf.mesh("wrong_type", &[json!({"attributes": {"POSITION": flat}})]);
        for (name, mesh) in [
            ("good", good),
            ("a", out_of_range),
            ("b", overlong),
            ("c", empty),
            ("d", wrong_type),
        ] {
            gltf.root(json!({"name": name, "mesh": mesh}));
        }
        let scene = import_glb(&gltf);
        assert_eq!(names(&scene), ["good"]);
        assert_eq!(scene.meshes.len(), 1);
        // Each broken primitive is skipped for its own reason, naming the node.
        let (_, warnings) = flatten_glb(&gltf);
        let expected = [
            ("node 'a'", "vertex index 99 is out of range (4 vertices)"),
            ("node 'b'", "runs past the end of buffer view"),
            ("node 'c'", "is empty"),
            ("node 'd'", "has type (F32, Vec2)"),
        ];
        assert_eq!(warnings.len(), expected.len(), "{warnings:#?}");
        for (warning, (node, reason)) in warnings.iter().zip(expected) {
            assert!(
                warning.contains(node) && warning.contains(reason),
                "{warning}"
            );
        }

        // A GLB header whose length is shorter than the header itself.
        let mut glb = gltf.glb();
        glb[8..12].copy_from_slice(&4u32.to_le_bytes());
        let message = import_gltf_slice(&glb, "short.glb", &no_chunking())
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("short.glb") && message.contains("not a valid glTF"),
            "{message}"
        );
        // A truncated GLB.
        let glb = gltf.glb();
        let message = import_gltf_slice(&glb[..glb.len() / 2], "cut.glb", &no_chunking())
            .unwrap_err()
            .to_string();
        assert!(message.contains("cut.glb"), "{message}");
    }

    #[test]
    fn triangles_with_non_finite_positions_are_dropped() {
        let mut gltf = TestGltf::default();
        let (mut positions, indices) = quad();
        positions[3] = Vec3::new(f32::NAN, 1.0, 0.0);
        let mesh = gltf.simple_mesh("torn", &positions, &indices);
        gltf.root(json!({"name": "torn", "mesh": mesh}));
        let scene = import_glb(&gltf);
        let torn = &scene.meshes[0];
        assert_eq!(torn.triangle_count(), 1);
        assert_eq!(torn.positions.len(), 3);
        assert!(torn.positions.iter().all(|p| p.is_finite()));
        assert!(scene.bounds().min.is_finite() && scene.bounds().max.is_finite());
        let (_, warnings) = flatten_glb(&gltf);
        assert_eq!(warnings.len(), 1);
        assert!(
            warnings[0].contains("1 of 2 triangles dropped"),
            "{}",
            warnings[0]
        );
    }

    #[test]
    fn a_cycle_in_the_node_tree_terminates() {
        let mut gltf = TestGltf::default();
        let (positions, indices) = quad();
        let mesh = gltf.simple_mesh("quad", &positions, &indices);
        gltf.root(json!({"name": "a", "mesh": mesh, "children": [1]}));
        gltf.node(json!({"name": "b", "mesh": mesh, "children": [0]}));
        let scene = import_glb(&gltf);
        assert_eq!(names(&scene), ["a", "b"]);
        let (_, warnings) = flatten_glb(&gltf);
        assert_eq!(
            warnings,
            ["test.glb: node 0 appears twice in the node tree; imported once"]
        );
    }

    #[test]
    fn a_large_ground_is_chunked_on_import() {
        let mut gltf = TestGltf::default();
        let (ground_positions, ground_indices) = ground(100, 200.0);
        let ground = gltf.simple_mesh("ground", &ground_positions, &ground_indices);
        let (box_positions, box_indices) = cube(2.0);
        let small_box = gltf.simple_mesh("box", &box_positions, &box_indices);
        gltf.root(json!({"name": "ground", "mesh": ground}));
        gltf.root(json!({"name": "box", "mesh": small_box, "translation": [5.0, 0.0, 5.0]}));
        let glb = gltf.glb();

        let chunked = import_gltf_slice(&glb, "yard.glb", &ChunkSettings::default()).unwrap();
        let whole = import_gltf_slice(&glb, "yard.glb", &no_chunking()).unwrap();
        assert_eq!(names(&whole), ["ground", "box"]);
        // 200 m scene, chunks of at most 50 m: 4 x 4 over the ground.
        let mut expected: Vec<String> = (0..16).map(|k| format!("ground#{k}")).collect();
        expected.push("box".into());
        assert_eq!(names(&chunked), expected);
        assert_eq!(chunked.triangle_count(), whole.triangle_count());
        assert_eq!(chunked.triangle_count(), 100 * 100 * 2 + 12);
        let chunk_union = chunked.instances[..16]
            .iter()
            .fold(Aabb::EMPTY, |acc, i| acc.union(i.aabb_in_world));
        let ground_box = whole.instances[0].aabb_in_world;
        assert!(
            chunk_union.min.abs_diff_eq(ground_box.min, 1e-4)
                && chunk_union.max.abs_diff_eq(ground_box.max, 1e-4)
        );
        assert!(
            chunked
                .instances
                .iter()
                .all(|i| (i.mesh as usize) < chunked.meshes.len())
        );
    }

    #[test]
    fn percent_escapes_in_buffer_uris_are_decoded() {
        assert_eq!(
            percent_decode("my%20scene.bin").as_deref(),
            Some("my scene.bin")
        );
        assert_eq!(percent_decode("plain.bin").as_deref(), Some("plain.bin"));
        assert_eq!(percent_decode("bad%2"), None);
        assert_eq!(percent_decode("%FF.bin"), None);
    }
}
