//! Splitting very large objects into spatially coherent chunks, so that culling has more than one
//! all-or-nothing box for a ground plane or a terrain.
//!
//! An instance is split by bucketing its triangles, by world-space centroid, into a regular grid
//! over its world box. Naming: chunk `k` of instance `ground` is the instance `ground#k` with the
//! mesh `<mesh name>#k`; `k` counts the non-empty grid cells from 0 in cell order (x fastest,
//! then y, then z), so the output is the same on every run.

use std::collections::BTreeMap;

use glam::{UVec3, Vec3};

use super::{Instance, Mesh, MeshId};
use crate::geom::Aabb;

/// When an instance counts as very large, relative to the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChunkSettings {
    /// An instance whose largest world extent exceeds this fraction of the scene's largest
    /// extent is split into chunks no larger than that. `0` or less disables splitting.
    pub max_extent_fraction: f32,
}

impl Default for ChunkSettings {
    fn default() -> Self {
        Self {
            max_extent_fraction: 0.25,
        }
    }
}

/// At most this many grid cells along one axis, so that a tiny fraction cannot turn a mesh into
/// one chunk per triangle; chunks are then larger than the limit.
const MAX_CELLS_PER_AXIS: u32 = 64;

/// Splits every very large instance into chunks; returns the new instance list.
///
/// Instances keep their order; the chunks of a split instance take its place, in chunk order.
/// Chunk meshes are appended to `meshes`. Meshes that only split instances used are removed and
/// the remaining ids renumbered, so every id in the result is valid for `meshes`.
pub fn split_large_instances(
    meshes: &mut Vec<Mesh>,
    instances: Vec<Instance>,
    settings: &ChunkSettings,
) -> Vec<Instance> {
    let Some(max_extent_m) = max_chunk_extent_m(&instances, *settings) else {
        return instances;
    };
    let referenced_before = referenced_meshes(meshes.len(), &instances);
    let mut result = Vec::with_capacity(instances.len());
    for instance in instances {
        let chunks = match meshes.get(instance.mesh as usize) {
            Some(mesh) if instance.aabb_in_world.extent().max_element() > max_extent_m => {
                split_instance(mesh, &instance, max_extent_m)
            }
            _ => Vec::new(),
        };
        // A single chunk would be the same object again under a new name.
        if chunks.len() < 2 {
            result.push(instance);
            continue;
        }
        for (mesh, mut chunk) in chunks {
            chunk.mesh = meshes.len() as MeshId;
            meshes.push(mesh);
            result.push(chunk);
        }
    }
    remove_orphaned_meshes(meshes, &mut result, &referenced_before);
    result
}

/// The largest extent a chunk may have, or `None` when splitting is disabled or pointless.
fn max_chunk_extent_m(instances: &[Instance], settings: ChunkSettings) -> Option<f32> {
    let scene_bounds = instances
        .iter()
        .fold(Aabb::EMPTY, |acc, i| acc.union(i.aabb_in_world));
    let limit_m = settings.max_extent_fraction * scene_bounds.extent().max_element();
    // Also rejects a NaN fraction and a non-positive one.
    (limit_m.is_finite() && limit_m > 0.0).then_some(limit_m)
}

/// The chunks of `instance` (each a mesh and an instance whose mesh id is still to be set), or
/// nothing when the mesh has invalid indices.
fn split_instance(mesh: &Mesh, instance: &Instance, max_extent_m: f32) -> Vec<(Mesh, Instance)> {
    if mesh
        .indices
        .iter()
        .any(|&i| i as usize >= mesh.positions.len())
    {
        return Vec::new();
    }
    let world_from_local = instance.world_from_local;
    let positions_in_world: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|&p| world_from_local.transform_point3(p))
        .collect();
    // The tight box, not the instance's (possibly looser) transformed local box.
    let bounds_in_world = Aabb::from_points(positions_in_world.iter().copied());
    let grid = ChunkGrid::new(bounds_in_world, max_extent_m);

    let mut triangles_by_cell: BTreeMap<usize, Vec<u32>> = BTreeMap::new();
    for triangle in mesh.indices.chunks_exact(3) {
        let centroid_in_world = triangle
            .iter()
            .map(|&i| positions_in_world[i as usize])
            .sum::<Vec3>()
            / 3.0;
        triangles_by_cell
            .entry(grid.cell_of(centroid_in_world))
            .or_default()
            .extend(triangle);
    }

    triangles_by_cell
        .values()
        .enumerate()
        .map(|(k, triangle_indices)| {
            let (positions, normals, indices) =
                compact_vertices(&mesh.positions, &mesh.normals, triangle_indices);
            let chunk_mesh = Mesh::new(format!("{}#{k}", mesh.name), positions, normals, indices);
            let chunk = Instance {
                name: format!("{}#{k}", instance.name),
                aabb_in_world: chunk_mesh.aabb_in_local.transformed(&world_from_local),
                ..instance.clone()
            };
            (chunk_mesh, chunk)
        })
        .collect()
}

/// A regular grid over a world box, split only along axes longer than the chunk limit.
struct ChunkGrid {
    bounds_in_world: Aabb,
    cells: UVec3,
}

impl ChunkGrid {
    fn new(bounds_in_world: Aabb, max_extent_m: f32) -> Self {
        let cells = bounds_in_world.extent().to_array().map(|extent_m| {
            if extent_m > max_extent_m {
                ((extent_m / max_extent_m).ceil() as u32).clamp(1, MAX_CELLS_PER_AXIS)
            } else {
                1
            }
        });
        Self {
            bounds_in_world,
            cells: UVec3::from_array(cells),
        }
    }

    /// The linear index (x fastest) of the cell holding `p`; points outside are clamped in.
    fn cell_of(&self, p_in_world: Vec3) -> usize {
        // The floor keeps a zero extent (an unsplit flat axis) from dividing by zero.
        let extent = self
            .bounds_in_world
            .extent()
            .max(Vec3::splat(f32::MIN_POSITIVE));
        let t = (p_in_world - self.bounds_in_world.min) / extent;
        // The float-to-int cast saturates, so NaN and negative values land in cell 0.
        let cell = (t * self.cells.as_vec3())
            .floor()
            .as_uvec3()
            .min(self.cells - 1);
        (cell.x + self.cells.x * (cell.y + self.cells.y * cell.z)) as usize
    }
}

/// The vertices that `indices` use, renumbered in order of first use, and the renumbered
/// indices. Normals come along when there is one per position; otherwise `None`.
///
/// Every index must be less than `positions.len()`.
pub(super) fn compact_vertices(
    positions: &[Vec3],
    normals: &[Vec3],
    indices: &[u32],
) -> (Vec<Vec3>, Option<Vec<Vec3>>, Vec<u32>) {
    const UNUSED: u32 = u32::MAX;
    let carry_normals = normals.len() == positions.len();
    let mut new_index = vec![UNUSED; positions.len()];
    let mut new_positions = Vec::new();
    let mut new_normals = Vec::new();
    let new_indices = indices
        .iter()
        .map(|&old| {
            let old = old as usize;
            if new_index[old] == UNUSED {
                new_index[old] = new_positions.len() as u32;
                new_positions.push(positions[old]);
                if carry_normals {
                    new_normals.push(normals[old]);
                }
            }
            new_index[old]
        })
        .collect();
    (
        new_positions,
        carry_normals.then_some(new_normals),
        new_indices,
    )
}

/// For each mesh id below `mesh_count`, whether an instance refers to it.
fn referenced_meshes(mesh_count: usize, instances: &[Instance]) -> Vec<bool> {
    let mut referenced = vec![false; mesh_count];
    for instance in instances {
        if let Some(flag) = referenced.get_mut(instance.mesh as usize) {
            *flag = true;
        }
    }
    referenced
}

/// Removes meshes that were referenced before splitting and are not any more, and renumbers the
/// instances' mesh ids. Meshes that nothing referenced to begin with are the caller's business.
fn remove_orphaned_meshes(
    meshes: &mut Vec<Mesh>,
    instances: &mut [Instance],
    referenced_before: &[bool],
) {
    let referenced_after = referenced_meshes(meshes.len(), instances);
    let keep: Vec<bool> = referenced_after
        .iter()
        .enumerate()
        .map(|(id, &after)| after || !referenced_before.get(id).copied().unwrap_or(false))
        .collect();
    if keep.iter().all(|&k| k) {
        return;
    }
    let mut new_id = Vec::with_capacity(keep.len());
    let mut next_id: MeshId = 0;
    for &kept in &keep {
        new_id.push(next_id);
        next_id += MeshId::from(kept);
    }
    let mut kept = keep.iter();
    meshes.retain(|_| kept.next().copied().unwrap_or(true));
    for instance in instances {
        if let Some(&id) = new_id.get(instance.mesh as usize) {
            instance.mesh = id;
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Quat, Vec4};

    use super::super::Mobility;
    use super::*;

    /// A flat grid of `quads` x `quads` quads in the XZ plane, `size_m` wide, centred on the
    /// origin, facing +Y.
    fn ground_mesh(quads: u32, size_m: f32) -> Mesh {
        let step_m = size_m / quads as f32;
        let mut positions = Vec::new();
        for iz in 0..=quads {
            for ix in 0..=quads {
                positions.push(Vec3::new(
                    ix as f32 * step_m - size_m / 2.0,
                    0.0,
                    iz as f32 * step_m - size_m / 2.0,
                ));
            }
        }
        let vertex = |ix: u32, iz: u32| iz * (quads + 1) + ix;
        let mut indices = Vec::new();
        for iz in 0..quads {
            for ix in 0..quads {
                let (v00, v10) = (vertex(ix, iz), vertex(ix + 1, iz));
                let (v01, v11) = (vertex(ix, iz + 1), vertex(ix + 1, iz + 1));
                indices.extend([v00, v01, v10, v10, v01, v11]);
            }
        }
        Mesh::new("ground_mesh", positions, None, indices)
    }

    fn box_mesh(size_m: f32) -> Mesh {
        let corners = Aabb::new(Vec3::ZERO, Vec3::splat(size_m))
            .corners()
            .to_vec();
        let indices = vec![
            0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4,
            6, 1, 3, 5, 3, 7, 5,
        ];
        Mesh::new("box_mesh", corners, None, indices)
    }

    /// A 200 m ground (mesh 0) and a 2 m box standing on it (mesh 1).
    fn ground_and_box() -> (Vec<Mesh>, Vec<Instance>) {
        let meshes = vec![ground_mesh(100, 200.0), box_mesh(2.0)];
        let instances = vec![
            Instance::new("ground", 0, &meshes[0], Mat4::IDENTITY).with_color([0.2, 0.5, 0.1, 1.0]),
            Instance::new(
                "box",
                1,
                &meshes[1],
                Mat4::from_translation(Vec3::new(3.0, 0.0, 4.0)),
            )
            .with_mobility(Mobility::Dynamic),
        ];
        (meshes, instances)
    }

    fn approx_eq(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-3
    }

    #[test]
    fn ground_plane_is_split_into_chunks_that_cover_it() {
        let (mut meshes, instances) = ground_and_box();
        let ground_before = instances[0].clone();
        let triangles_before = meshes[0].triangle_count();
        let result = split_large_instances(&mut meshes, instances, &ChunkSettings::default());

        // Scene extent 200 m, limit 50 m: a 4 x 4 grid over the ground, never along y.
        let chunks: Vec<&Instance> = result
            .iter()
            .filter(|i| i.name.starts_with("ground#"))
            .collect();
        assert_eq!(chunks.len(), 16);
        let names: Vec<&str> = chunks.iter().map(|c| c.name.as_str()).collect();
        let expected: Vec<String> = (0..16).map(|k| format!("ground#{k}")).collect();
        assert_eq!(names, expected);
        assert_eq!(result.len(), 17);
        assert_eq!(result.last().map(|i| i.name.as_str()), Some("box"));

        let union = chunks
            .iter()
            .fold(Aabb::EMPTY, |acc, c| acc.union(c.aabb_in_world));
        assert!(approx_eq(union.min, ground_before.aabb_in_world.min));
        assert!(approx_eq(union.max, ground_before.aabb_in_world.max));
        let triangles_after: usize = chunks
            .iter()
            .map(|c| meshes[c.mesh as usize].triangle_count())
            .sum();
        assert_eq!(triangles_after, triangles_before);

        for chunk in &chunks {
            let mesh = &meshes[chunk.mesh as usize];
            assert_eq!(mesh.triangle_count(), 25 * 25 * 2, "{}", chunk.name);
            assert!(chunk.aabb_in_world.extent().max_element() <= 50.0 + 1e-3);
            let color = Vec4::from(chunk.base_color);
            assert!(color.abs_diff_eq(Vec4::from(ground_before.base_color), 1e-6));
            assert_eq!(chunk.world_from_local, ground_before.world_from_local);
            assert_eq!(chunk.mobility, Mobility::Static);
            // Compact: every vertex is used, and normals came along (the ground faces +Y).
            assert_eq!(mesh.positions.len(), 26 * 26);
            assert!(mesh.normals.iter().all(|n| approx_eq(*n, Vec3::Y)));
        }
        // The original ground mesh is gone; the ids of the rest are valid and distinct.
        assert_eq!(meshes.len(), 17);
        assert!(meshes.iter().all(|m| m.name != "ground_mesh"));
        assert!(result.iter().all(|i| (i.mesh as usize) < meshes.len()));
        let box_instance = &result[16];
        assert_eq!(meshes[box_instance.mesh as usize].name, "box_mesh");
        assert_eq!(box_instance.mobility, Mobility::Dynamic);
    }

    #[test]
    fn splitting_is_disabled_by_a_fraction_that_is_not_positive() {
        for fraction in [0.0, -1.0, f32::NAN] {
            let (mut meshes, instances) = ground_and_box();
            let settings = ChunkSettings {
                max_extent_fraction: fraction,
            };
            let result = split_large_instances(&mut meshes, instances, &settings);
            let names: Vec<&str> = result.iter().map(|i| i.name.as_str()).collect();
            assert_eq!(names, ["ground", "box"], "fraction {fraction}");
            assert_eq!(meshes.len(), 2);
        }
    }

    #[test]
    fn a_long_strip_is_split_only_along_its_long_axis() {
        // 200 m along x, 2 m along z: a 100 x 1 strip of quads scaled in z.
        let mut meshes = vec![ground_mesh(100, 200.0)];
        let strip_from_ground = Mat4::from_scale(Vec3::new(1.0, 1.0, 0.01));
        let instances = vec![Instance::new("strip", 0, &meshes[0], strip_from_ground)];
        let result = split_large_instances(&mut meshes, instances, &ChunkSettings::default());
        assert_eq!(result.len(), 4);
        for chunk in &result {
            assert!(chunk.aabb_in_world.extent().x <= 50.0 + 1e-3);
            assert!((chunk.aabb_in_world.extent().z - 2.0).abs() < 1e-3);
        }
    }

    #[test]
    fn chunks_keep_local_space_under_a_rotated_transform() {
        let (mut meshes, mut instances) = ground_and_box();
        let world_from_local =
            Mat4::from_rotation_translation(Quat::from_rotation_y(0.3), Vec3::new(10.0, -1.0, 5.0));
        instances[0] = Instance::new("ground", 0, &meshes[0], world_from_local);
        let original = meshes[0].clone();
        let ground_box = instances[0].aabb_in_world;
        let result = split_large_instances(&mut meshes, instances, &ChunkSettings::default());
        let chunks: Vec<&Instance> = result
            .iter()
            .filter(|i| i.name.starts_with("ground#"))
            .collect();
        assert!(chunks.len() > 1);
        for chunk in chunks {
            assert_eq!(chunk.world_from_local, world_from_local);
            let mesh = &meshes[chunk.mesh as usize];
            // Chunk vertices are the original local-space vertices, not world-space copies.
            assert!(
                mesh.positions
                    .iter()
                    .all(|p| original.positions.contains(p))
            );
            let expected_box = mesh.aabb_in_local.transformed(&world_from_local);
            assert_eq!(chunk.aabb_in_world, expected_box);
            assert!(ground_box.contains_point(expected_box.center()));
        }
    }

    #[test]
    fn a_mesh_shared_with_a_small_instance_is_kept() {
        // Mesh 0 is used by a huge scaled instance (split) and a small one (not split).
        let mut meshes = vec![box_mesh(1.0), ground_mesh(10, 2.0)];
        let instances = vec![
            Instance::new("small", 1, &meshes[1], Mat4::IDENTITY),
            Instance::new("huge", 1, &meshes[1], Mat4::from_scale(Vec3::splat(100.0))),
            Instance::new("unit_box", 0, &meshes[0], Mat4::IDENTITY),
        ];
        let result = split_large_instances(&mut meshes, instances, &ChunkSettings::default());
        assert_eq!(result[0].name, "small");
        assert_eq!(meshes[result[0].mesh as usize].triangle_count(), 200);
        assert_eq!(result.last().map(|i| i.name.as_str()), Some("unit_box"));
        assert!(result.iter().any(|i| i.name == "huge#0"));
        assert!(!result.iter().any(|i| i.name == "huge"));
        // 16 chunks of "huge" replace it; both original meshes are still in use.
        assert_eq!(result.len(), 1 + 16 + 1);
        assert_eq!(meshes.len(), 2 + 16);
        assert!(result.iter().all(|i| (i.mesh as usize) < meshes.len()));
    }

    #[test]
    fn output_is_deterministic() {
        let run = || {
            let (mut meshes, instances) = ground_and_box();
            let result = split_large_instances(
                &mut meshes,
                instances,
                &ChunkSettings {
                    max_extent_fraction: 0.1,
                },
            );
            result
                .iter()
                .map(|i| {
                    (
                        i.name.clone(),
                        i.mesh,
                        meshes[i.mesh as usize].indices.clone(),
                    )
                })
                .collect::<Vec<_>>()
        };
        let first = run();
        assert!(first.len() > 17);
        assert_eq!(first, run());
    }

    #[test]
    fn compact_vertices_renumbers_in_order_of_first_use() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let normals = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::NEG_X];
        let (p, n, i) = compact_vertices(&positions, &normals, &[3, 1, 3]);
        assert_eq!(p, [Vec3::Z, Vec3::X]);
        assert_eq!(n, Some(vec![Vec3::NEG_X, Vec3::Y]));
        assert_eq!(i, [0, 1, 0]);
        let (_, n, _) = compact_vertices(&positions, &[], &[0, 1, 2]);
        assert_eq!(n, None);
    }
}
