//! Rays through the scene on the CPU: a two-level BVH (`obvhs` compressed wide BVHs), one per
//! mesh in its own space and one over the instances in world space. Meshes are shared by
//! instances, so the mesh trees are built once per scene; the instance tree is rebuilt when an
//! instance moves (a few thousand boxes).

use glam::{Mat4, Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb as BvhAabb;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::{build_cwbvh, build_cwbvh_from_tris};
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;

use crate::scene::{Instance, Scene};

/// A mesh's triangles in its own space and their tree.
struct MeshTree {
    triangles: Vec<Triangle>,
    bvh: CwBvh,
}

/// An instance as rays see it.
#[derive(Clone, Copy)]
struct Placed {
    instance: u32,
    mesh: u32,
    world_from_local: Mat4,
    local_from_world: Mat4,
    /// Turns a local triangle's winding normal into the world's (the cofactor matrix: it
    /// keeps the winding's sign under a mirroring transform, as the rasteriser sees it).
    normal_from_local: glam::Mat3,
    casts_shadow: bool,
    receives_shadow: bool,
}

/// What a camera ray hits first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    pub instance: u32,
    pub position: Vec3,
    /// The triangle's unit normal on the side the ray came from.
    pub normal: Vec3,
    pub receives_shadow: bool,
}

/// The scene's trees.
pub struct SceneRays {
    meshes: Vec<Option<MeshTree>>,
    placed: Vec<Placed>,
    instances: CwBvh,
    /// The transforms the instance tree was built from.
    transforms: Vec<Mat4>,
    /// Bumped each time the instance tree is rebuilt: part of a cached view's key.
    pub version: u64,
}

impl SceneRays {
    pub fn new(scene: &Scene) -> Self {
        let meshes = scene
            .meshes
            .iter()
            .map(|mesh| {
                let triangles: Vec<Triangle> = mesh
                    .indices
                    .chunks_exact(3)
                    .filter_map(|t| {
                        let v = |i: u32| mesh.positions.get(i as usize).map(|p| Vec3A::from(*p));
                        Some(Triangle {
                            v0: v(t[0])?,
                            v1: v(t[1])?,
                            v2: v(t[2])?,
                        })
                    })
                    .collect();
                (!triangles.is_empty()).then(|| MeshTree {
                    bvh: build_cwbvh_from_tris(
                        &triangles,
                        BvhBuildParams::fast_build(),
                        &mut std::time::Duration::default(),
                    ),
                    triangles,
                })
            })
            .collect();
        let mut rays = Self {
            meshes,
            placed: Vec::new(),
            instances: CwBvh::default(),
            transforms: Vec::new(),
            version: 0,
        };
        rays.rebuild_instances(&scene.instances);
        rays
    }

    /// Follows instances that moved since the trees were built (the scene's instances, with
    /// the same meshes).
    pub fn sync(&mut self, instances: &[Instance]) {
        let moved = self.transforms.len() != instances.len()
            || self
                .transforms
                .iter()
                .zip(instances)
                .any(|(t, i)| *t != i.world_from_local);
        if moved {
            self.rebuild_instances(instances);
        }
    }

    fn rebuild_instances(&mut self, instances: &[Instance]) {
        self.transforms = instances.iter().map(|i| i.world_from_local).collect();
        self.placed = (0..)
            .zip(instances)
            .filter(|(_, i)| {
                self.meshes
                    .get(i.mesh as usize)
                    .is_some_and(Option::is_some)
                    && i.world_from_local.determinant().abs() > f32::MIN_POSITIVE
            })
            .map(|(index, i)| {
                let linear = glam::Mat3::from_mat4(i.world_from_local);
                Placed {
                    instance: index,
                    mesh: i.mesh,
                    world_from_local: i.world_from_local,
                    local_from_world: i.world_from_local.inverse(),
                    normal_from_local: linear.inverse().transpose() * linear.determinant(),
                    casts_shadow: i.casts_shadow,
                    receives_shadow: i.receives_shadow,
                }
            })
            .collect();
        let boxes: Vec<BvhAabb> = self
            .placed
            .iter()
            .map(|p| {
                let b = instances[p.instance as usize].aabb_in_world;
                BvhAabb::new(b.min.into(), b.max.into())
            })
            .collect();
        self.instances = if boxes.is_empty() {
            CwBvh::default()
        } else {
            build_cwbvh(
                &boxes,
                BvhBuildParams::fast_build(),
                &mut std::time::Duration::default(),
            )
        };
        self.version += 1;
    }

    /// The first front face along the ray from `origin` in `direction` between `t_min` and
    /// `t_max` (in units of `direction`), as the camera's rasteriser, which culls back faces,
    /// sees it.
    pub fn first_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<SurfaceHit> {
        if self.placed.is_empty() {
            return None;
        }
        let ray = Ray::new(origin.into(), direction.into(), t_min, t_max);
        let mut best: Option<(u32, u32)> = None;
        let mut hit = RayHit::none();
        self.instances
            .ray_traverse(ray, &mut hit, |world_ray, slot| {
                let placed_at = self.instances.primitive_indices[slot];
                let placed = &self.placed[placed_at as usize];
                let Some(tree) = &self.meshes[placed.mesh as usize] else {
                    return f32::INFINITY;
                };
                let local = local_ray(placed, world_ray);
                let mirrored = placed.normal_from_local.determinant() < 0.0;
                let mut local_hit = RayHit::none();
                let found = tree.bvh.ray_traverse(local, &mut local_hit, |r, id| {
                    let tri = &tree.triangles[tree.bvh.primitive_indices[id] as usize];
                    let t = tri.intersect(r);
                    // Front faces only: the winding normal faces against the ray (flipped for a
                    // mirroring transform).
                    let facing = winding(tri).dot(r.direction);
                    if t.is_finite() && ((facing < 0.0) != mirrored) {
                        t
                    } else {
                        f32::INFINITY
                    }
                });
                if found {
                    let tri = tree.bvh.primitive_indices[local_hit.primitive_id as usize];
                    best = Some((placed_at, tri));
                    local_hit.t
                } else {
                    f32::INFINITY
                }
            });
        let (placed_at, tri) = best?;
        let placed = &self.placed[placed_at as usize];
        let tree = self.meshes[placed.mesh as usize].as_ref()?;
        let local = local_ray(placed, &ray);
        let local_point = local.origin + local.direction * hit.t;
        let position = placed.world_from_local.transform_point3(local_point.into());
        let n = (placed.normal_from_local * Vec3::from(winding(&tree.triangles[tri as usize])))
            .try_normalize()?;
        let normal = if n.dot(direction) > 0.0 { -n } else { n };
        Some(SurfaceHit {
            instance: placed.instance,
            position,
            normal,
            receives_shadow: placed.receives_shadow,
        })
    }

    /// Whether any caster's triangle (either side) lies on the ray from `origin` towards
    /// `direction` between `t_min` and `t_max`.
    pub fn blocked(&self, origin: Vec3, direction: Vec3, (t_min, t_max): (f32, f32)) -> bool {
        if self.placed.is_empty() {
            return false;
        }
        let ray = Ray::new(origin.into(), direction.into(), t_min, t_max);
        !self.instances.ray_traverse_miss(ray, |world_ray, slot| {
            let placed = &self.placed[self.instances.primitive_indices[slot] as usize];
            if !placed.casts_shadow {
                return f32::INFINITY;
            }
            let Some(tree) = &self.meshes[placed.mesh as usize] else {
                return f32::INFINITY;
            };
            let local = local_ray(placed, world_ray);
            let missed = tree.bvh.ray_traverse_miss(local, |r, id| {
                tree.triangles[tree.bvh.primitive_indices[id] as usize].intersect(r)
            });
            if missed { f32::INFINITY } else { t_min }
        })
    }
}

impl SceneRays {
    /// Calls `found` once with every casting instance that has a triangle (either side) on
    /// the ray from `origin` towards `direction` between `t_min` and `t_max`.
    pub fn blockers(
        &self,
        origin: Vec3,
        direction: Vec3,
        (t_min, t_max): (f32, f32),
        mut found: impl FnMut(u32),
    ) {
        if self.placed.is_empty() {
            return;
        }
        let ray = Ray::new(origin.into(), direction.into(), t_min, t_max);
        self.instances.ray_traverse_anyhit(ray, |world_ray, slot| {
            let placed = &self.placed[self.instances.primitive_indices[slot] as usize];
            let Some(tree) = self.meshes[placed.mesh as usize]
                .as_ref()
                .filter(|_| placed.casts_shadow)
            else {
                return;
            };
            let local = local_ray(placed, world_ray);
            let missed = tree.bvh.ray_traverse_miss(local, |r, id| {
                tree.triangles[tree.bvh.primitive_indices[id] as usize].intersect(r)
            });
            if !missed {
                found(placed.instance);
            }
        });
    }
}

/// The ray in the instance's own space; its parameter `t` is the same point in both.
fn local_ray(placed: &Placed, ray: &Ray) -> Ray {
    let origin = placed
        .local_from_world
        .transform_point3(Vec3::from(ray.origin));
    let direction = placed
        .local_from_world
        .transform_vector3(Vec3::from(ray.direction));
    Ray::new(origin.into(), direction.into(), ray.tmin, ray.tmax)
}

/// The triangle's winding normal (not normalised): counter-clockwise faces towards it.
fn winding(tri: &Triangle) -> Vec3A {
    (tri.v1 - tri.v0).cross(tri.v2 - tri.v0)
}

/// Moves a ray's origin off the surface it starts on, by a few units in the last place of
/// each coordinate (Wächter and Binder, "A Fast and Robust Method for Avoiding
/// Self-Intersection", Ray Tracing Gems, chapter 6): robust at 1 m and at 100 km alike.
pub fn offset_from_surface(p: Vec3, n: Vec3) -> Vec3 {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let step = |p: f32, n: f32| {
        let of = (INT_SCALE * n) as i32;
        let moved = f32::from_bits((p.to_bits() as i32 + if p < 0.0 { -of } else { of }) as u32);
        if p.abs() < ORIGIN {
            p + FLOAT_SCALE * n
        } else {
            moved
        }
    };
    Vec3::new(step(p.x, n.x), step(p.y, n.y), step(p.z, n.z))
}
