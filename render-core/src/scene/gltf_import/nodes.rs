//! The node trees of a glTF document flattened into instances: world transforms, names, and one
//! shared scene mesh per (glTF mesh, primitive), read the first time a node uses it.

use std::collections::HashMap;
use std::path::Path;

use glam::{Mat4, Vec3};
use gltf::mesh::Mode;

use super::super::{Instance, LightKind, Mesh, MeshId, PunctualLight, Sun};
use super::primitives::read_triangle_mesh;

/// Coordinates beyond this (in the file's units) are taken for an overflow: single precision
/// keeps no useful detail there, and the camera's and the light's arithmetic would overflow.
pub(super) const MAX_COORDINATE: f32 = 1e9;

/// A node the scene cannot hold, and why.
pub(super) struct BadNode {
    pub node: String,
    pub reason: String,
}

/// The meshes and instances of a document, the sun of its first directional light and its
/// point and spot lights (`KHR_lights_punctual`), and a warning for each part skipped.
pub(super) struct Flattened {
    pub meshes: Vec<Mesh>,
    pub instances: Vec<Instance>,
    pub sun: Option<Sun>,
    pub lights: Vec<PunctualLight>,
    pub warnings: Vec<String>,
}

/// The meshes and instances of the document's node trees, and a warning for each part skipped;
/// a node whose transform or bounds are not finite, or overflow, rejects the file.
pub(super) fn flatten_node_trees(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    path: &Path,
) -> Result<Flattened, BadNode> {
    let mut builder = SceneBuilder::new(path, buffers);
    builder.add_node_trees(document)?;
    Ok(Flattened {
        meshes: builder.meshes,
        instances: builder.instances,
        sun: builder.sun,
        lights: builder.lights,
        warnings: builder.warnings,
    })
}

/// Turns the node trees of a document into meshes and instances.
struct SceneBuilder<'a> {
    path: &'a Path,
    buffers: &'a [Vec<u8>],
    meshes: Vec<Mesh>,
    /// The mesh made from each (glTF mesh, primitive), or `None` when the primitive was rejected.
    mesh_ids: HashMap<(usize, usize), Option<MeshId>>,
    instances: Vec<Instance>,
    /// The first directional light that shines down.
    sun: Option<Sun>,
    lights: Vec<PunctualLight>,
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
            sun: None,
            lights: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// Walks the node trees depth first, in document order. A node reached twice (the file
    /// has a cycle or shares a child) is only imported the first time.
    fn add_node_trees(&mut self, document: &gltf::Document) -> Result<(), BadNode> {
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
                return Err(BadNode {
                    node: node_name(&node),
                    reason: "its transform (with its parents') is not finite".into(),
                });
            }
            self.add_light(&node, world_from_local);
            self.add_node(&node, world_from_local)?;
            let children: Vec<gltf::Node> = node.children().collect();
            stack.extend(
                children
                    .into_iter()
                    .rev()
                    .map(|child| (child, world_from_local)),
            );
        }
        Ok(())
    }

    /// The scene's sun from the first directional light (it shines along the node's -Z); one
    /// that shines upwards is left out with a warning. Point and spot lights are kept at the
    /// node's origin (spots shining along its -Z), with a warning that only the sun is shaded.
    fn add_light(&mut self, node: &gltf::Node, world_from_local: Mat4) {
        use gltf::khr_lights_punctual::Kind;
        let Some(light) = node.light() else { return };
        let file = self.path.display();
        let name = light.name().map_or_else(|| node_name(node), str::to_owned);
        let kind = match light.kind() {
            Kind::Directional => None,
            Kind::Point => Some(LightKind::Point),
            Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => Some(LightKind::Spot {
                direction: world_from_local
                    .transform_vector3(Vec3::NEG_Z)
                    .normalize_or(Vec3::NEG_Y),
                inner_cone_rad: inner_cone_angle,
                outer_cone_rad: outer_cone_angle,
            }),
        };
        if let Some(kind) = kind {
            self.warnings.push(format!(
                "{file}: light '{name}' is a point or spot light; it is kept, but only the sun \
                 lights and shadows the view yet"
            ));
            self.lights.push(PunctualLight {
                name,
                position: world_from_local.transform_point3(Vec3::ZERO),
                kind,
                color: light.color(),
                intensity: light.intensity(),
                range: light.range(),
            });
            return;
        }
        if self.sun.is_some() {
            self.warnings.push(format!(
                "{file}: directional light '{name}' ignored; the first one is the sun"
            ));
            return;
        }
        let shines = world_from_local.transform_vector3(Vec3::NEG_Z);
        match shines.try_normalize() {
            Some(d) if d.y < 0.0 => self.sun = Some(Sun::from_direction(-d)),
            _ => self.warnings.push(format!(
                "{file}: directional light '{name}' does not shine downwards; the default sun is used"
            )),
        }
    }

    /// One instance per triangle primitive of the node's mesh.
    fn add_node(&mut self, node: &gltf::Node, world_from_local: Mat4) -> Result<(), BadNode> {
        let Some(mesh) = node.mesh() else {
            return Ok(());
        };
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
            let bounds = instance.aabb_in_world;
            let reach = bounds.min.abs().max(bounds.max.abs()).max_element();
            let finite = bounds.min.is_finite() && bounds.max.is_finite() && reach.is_finite();
            if !finite || reach > MAX_COORDINATE {
                return Err(BadNode {
                    node: node_name,
                    reason: format!(
                        "its mesh reaches {reach:e} from the origin once transformed, beyond \
                         ±{MAX_COORDINATE:e} (a transform or position that overflows)"
                    ),
                });
            }
            self.instances.push(instance);
        }
        Ok(())
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
