//! Rays through the scene on the CPU: a two-level BVH (`obvhs` compressed wide BVHs), one per
//! mesh in its own space and one over the instances in world space. Meshes are shared by
//! instances, so the mesh trees are built once per scene; the instance tree is rebuilt when an
//! instance moves (a few thousand boxes).

use glam::{DMat4, DVec3, Mat4, Vec3, Vec3A};
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
    /// In f64: a point's own coordinates in its mesh are small wherever the instance stands,
    /// so rays are moved into a mesh's space without the rounding of world coordinates far
    /// from the origin.
    world_from_local: DMat4,
    local_from_world: DMat4,
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
    /// The point on the triangle, from its barycentrics (see [`SceneRays::first_hit`]).
    pub position: Vec3,
    /// The triangle's unit normal on the side the ray came from.
    pub normal: Vec3,
    /// Where a ray leaving the surface on that side starts: the point moved off its triangle in
    /// the mesh's own space ([`offset_from_surface`]), in world space in f64.
    pub leaving: DVec3,
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
                let world_from_local = i.world_from_local.as_dmat4();
                Placed {
                    instance: index,
                    mesh: i.mesh,
                    world_from_local,
                    local_from_world: world_from_local.inverse(),
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
                // Widened by a few units in the last place: the traversal's world rays are
                // rounded to f32, the triangles' tests are not.
                let b = instances[p.instance as usize].aabb_in_world;
                let pad = b.min.abs().max(b.max.abs()) * (8.0 * f32::EPSILON) + 1e-6;
                BvhAabb::new((b.min - pad).into(), (b.max + pad).into())
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
    ///
    /// The point is computed from the triangle's barycentrics in its mesh's space, in f64, not
    /// along the ray: a point along the ray carries an error that grows with the eye's
    /// coordinates and with `t` (tens of micrometres seen from 60 m), enough to land it
    /// behind its own triangle, whose ray towards the light then hits that triangle. The
    /// barycentric point lies on the triangle's plane to the rounding of the mesh's own
    /// coordinates, which is what [`offset_from_surface`] steps over.
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
        let origin_f64 = origin.as_dvec3();
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
                let local = local_ray(placed, origin_f64, world_ray);
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
        let triangle = &self.meshes[placed.mesh as usize].as_ref()?.triangles[tri as usize];
        let local = local_ray(placed, origin_f64, &ray);
        let local_point = point_on(triangle, &local);
        let local_winding = winding(triangle);
        // The triangle's normal in its mesh's space on the side the ray came from.
        let local_normal = Vec3::from(if local_winding.dot(local.direction) > 0.0 {
            -local_winding
        } else {
            local_winding
        })
        .try_normalize()?;
        let n = (placed.normal_from_local * Vec3::from(local_winding)).try_normalize()?;
        let normal = if n.dot(direction) > 0.0 { -n } else { n };
        let leaving = offset_from_surface(local_point.as_vec3(), local_normal).as_dvec3();
        Some(SurfaceHit {
            instance: placed.instance,
            position: placed
                .world_from_local
                .transform_point3(local_point)
                .as_vec3(),
            normal,
            leaving: placed.world_from_local.transform_point3(leaving),
            receives_shadow: placed.receives_shadow,
        })
    }

    /// Whether any caster's triangle (either side) lies on the ray from `origin` towards
    /// `direction` between `t_min` and `t_max`. The origin is in f64 (a
    /// [`SurfaceHit::leaving`]): each mesh sees it in its own space, rounded there.
    pub fn blocked(&self, origin: DVec3, direction: Vec3, (t_min, t_max): (f32, f32)) -> bool {
        if self.placed.is_empty() {
            return false;
        }
        let ray = Ray::new(origin.as_vec3().into(), direction.into(), t_min, t_max);
        !self.instances.ray_traverse_miss(ray, |world_ray, slot| {
            let placed = &self.placed[self.instances.primitive_indices[slot] as usize];
            if !placed.casts_shadow {
                return f32::INFINITY;
            }
            let Some(tree) = &self.meshes[placed.mesh as usize] else {
                return f32::INFINITY;
            };
            let local = local_ray(placed, origin, world_ray);
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
        origin: DVec3,
        direction: Vec3,
        (t_min, t_max): (f32, f32),
        mut found: impl FnMut(u32),
    ) {
        if self.placed.is_empty() {
            return;
        }
        let ray = Ray::new(origin.as_vec3().into(), direction.into(), t_min, t_max);
        self.instances.ray_traverse_anyhit(ray, |world_ray, slot| {
            let placed = &self.placed[self.instances.primitive_indices[slot] as usize];
            let Some(tree) = self.meshes[placed.mesh as usize]
                .as_ref()
                .filter(|_| placed.casts_shadow)
            else {
                return;
            };
            let local = local_ray(placed, origin, world_ray);
            let missed = tree.bvh.ray_traverse_miss(local, |r, id| {
                tree.triangles[tree.bvh.primitive_indices[id] as usize].intersect(r)
            });
            if !missed {
                found(placed.instance);
            }
        });
    }
}

/// The ray from `origin` (world, f64) along `ray`'s direction in the instance's own space,
/// moved there in f64 and rounded only then; its parameter `t` is the same point in both.
fn local_ray(placed: &Placed, origin: DVec3, ray: &Ray) -> Ray {
    let origin = placed.local_from_world.transform_point3(origin).as_vec3();
    let direction = placed
        .local_from_world
        .transform_vector3(Vec3::from(ray.direction).as_dvec3())
        .as_vec3();
    Ray::new(origin.into(), direction.into(), ray.tmin, ray.tmax)
}

/// The point of `tri` that `ray` meets (Möller and Trumbore's barycentrics, in f64), kept on
/// the triangle: its coordinates are the vertices' combination, so a face in a coordinate
/// plane gives points exactly in it.
fn point_on(tri: &Triangle, ray: &Ray) -> DVec3 {
    let v0 = Vec3::from(tri.v0).as_dvec3();
    let e1 = Vec3::from(tri.v1).as_dvec3() - v0;
    let e2 = Vec3::from(tri.v2).as_dvec3() - v0;
    let d = Vec3::from(ray.direction).as_dvec3();
    let s = Vec3::from(ray.origin).as_dvec3() - v0;
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return v0;
    }
    let q = s.cross(e1);
    let u = (s.dot(p) / det).clamp(0.0, 1.0);
    let v = (d.dot(q) / det).clamp(0.0, 1.0 - u);
    v0 + e1 * u + e2 * v
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
