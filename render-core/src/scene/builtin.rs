//! The built-in scenes, deterministic from a seed, and the flat-shaded primitives they are made
//! of. Every face gets its own vertices, so a vertex normal is its face normal, and is wound
//! counter-clockwise seen from outside (the front face with right-handed coordinates).

use std::f32::consts::TAU;

use glam::{Mat4, Vec2, Vec3};

use super::city::{CityParams, build_city};
use super::{Instance, Mesh, Scene, Sun};

/// A built-in scene's name (as in `builtin:NAME`) and what it is.
#[derive(Clone, Copy, Debug)]
pub struct BuiltinScene {
    pub name: &'static str,
    pub description: &'static str,
}

pub const BUILTIN_SCENES: &[BuiltinScene] = &[
    BuiltinScene {
        name: "city",
        description: "Manhattan-like city: about 9,500 objects and 1.1M triangles, cars that move",
    },
    BuiltinScene {
        name: "city-night",
        description: "the city with 48 sodium street lamps over the crossings of its middle, \
                      spot lights shining down (`--shadow lights`)",
    },
    BuiltinScene {
        name: "city-small",
        description: "the city generator on 4 x 4 blocks: a few hundred objects, for tests",
    },
    BuiltinScene {
        name: "robots",
        description: "a walled hall crowded with 384 walking robots under a low sun (Lloyd et al.'s \
                      robot scene): about 106K triangles, high occlusion; each robot's six parts \
                      are casters of their own",
    },
    BuiltinScene {
        name: "corridor",
        description: "a long corridor under 40 roof trusses, 3,840 struts, lit by a point light \
                      over them and a low sun (Lloyd et al.'s trusses scene): about 108K \
                      triangles, thin casters",
    },
    BuiltinScene {
        name: "hall",
        description: "a dense bumpy statue (about 49K triangles) on a plinth among 8 columns, lit \
                      by 32 shadow-casting spot and point lights on a ring (Rákos's many-lights \
                      scene, GPU Pro 4)",
    },
    BuiltinScene {
        name: "boxes",
        description: "a 40 m ground plane and five boxes of known sizes (the same for every seed)",
    },
];

/// Blocks per side `builtin:city:N` may have: from a few hundred objects to over 100,000.
pub const CITY_BLOCKS: std::ops::RangeInclusive<u32> = 2..=64;

/// The city of `builtin:city:N`: N x N blocks, else none (not that name, or N outside
/// [`CITY_BLOCKS`]).
pub fn sized_city(name: &str, seed: u64) -> Option<CityParams> {
    let blocks: u32 = name.strip_prefix("city:")?.parse().ok()?;
    CITY_BLOCKS.contains(&blocks).then(|| CityParams {
        blocks_x: blocks,
        blocks_z: blocks,
        ..CityParams::full(seed)
    })
}

/// The built-in scene `name`, generated from `seed`; `None` for an unknown name.
/// `city:N` is the city on N x N blocks (the object-count sweeps).
pub fn load_builtin(name: &str, seed: u64) -> Option<Scene> {
    let scene_name = format!("builtin:{name}");
    if let Some(params) = sized_city(name, seed) {
        return Some(build_city(scene_name, &params));
    }
    match name {
        "city" => Some(build_city(scene_name, &CityParams::full(seed))),
        "city-small" => Some(build_city(scene_name, &CityParams::small(seed))),
        "city-night" => {
            let params = CityParams::full(seed);
            let mut scene = build_city(scene_name, &params);
            scene.lights = super::city::street_lamps(&params);
            Some(scene)
        }
        "boxes" => Some(boxes_scene(scene_name)),
        "robots" => Some(super::robots::robots_scene(scene_name, seed)),
        "corridor" => Some(super::corridor::corridor_scene(scene_name, seed)),
        "hall" => Some(super::hall::hall_scene(scene_name, seed)),
        _ => None,
    }
}

/// Side of the square ground of the `boxes` scene, metres.
const BOXES_GROUND_SIZE_M: f32 = 40.0;

/// The boxes of the `boxes` scene: centre x, centre z, size x, height, size z, in metres.
const BOXES_M: [[f32; 5]; 5] = [
    [-10.0, -10.0, 4.0, 2.0, 4.0],
    [8.0, -8.0, 3.0, 6.0, 3.0],
    [0.0, 0.0, 2.0, 10.0, 2.0],
    [-9.0, 8.0, 6.0, 1.0, 3.0],
    [10.0, 9.0, 2.0, 4.0, 6.0],
];

const BOX_COLORS: [[f32; 4]; 5] = [
    [0.60, 0.20, 0.15, 1.0],
    [0.20, 0.40, 0.60, 1.0],
    [0.70, 0.65, 0.30, 1.0],
    [0.25, 0.50, 0.25, 1.0],
    [0.50, 0.30, 0.55, 1.0],
];

/// `boxes`: a ground plane (`ground`, one object at y = 0) and boxes `box_0`.. standing on it.
/// The seed is ignored so tests can rely on the layout.
fn boxes_scene(name: String) -> Scene {
    let meshes = vec![unit_ground_quad("ground_quad"), unit_box("box")];
    let ground_size = Vec3::new(BOXES_GROUND_SIZE_M, 1.0, BOXES_GROUND_SIZE_M);
    let mut instances = vec![
        Instance::new("ground", 0, &meshes[0], Mat4::from_scale(ground_size))
            .with_color([0.55, 0.55, 0.52, 1.0]),
    ];
    for (k, ([x, z, size_x, height, size_z], color)) in BOXES_M.iter().zip(BOX_COLORS).enumerate() {
        let world_from_local = Mat4::from_translation(Vec3::new(*x, 0.0, *z))
            * Mat4::from_scale(Vec3::new(*size_x, *height, *size_z));
        instances.push(
            Instance::new(format!("box_{k}"), 1, &meshes[1], world_from_local).with_color(color),
        );
    }
    Scene::new(
        name,
        meshes,
        instances,
        Sun::from_azimuth_elevation_deg(35.0, 40.0),
    )
}

/// A 1 m square at y = 0 facing up, centred on the origin.
pub(super) fn unit_ground_quad(name: &str) -> Mesh {
    let mut builder = MeshBuilder::default();
    let corners =
        [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)].map(|(x, z)| Vec3::new(x, 0.0, z));
    builder.polygon(&corners, Vec3::Y);
    builder.build(name)
}

/// A closed box between `min` and `max`.
pub(crate) fn closed_box(name: &str, min: Vec3, max: Vec3) -> Mesh {
    let mut builder = MeshBuilder::default();
    builder.cuboid(min, max, true);
    builder.build(name)
}

/// Four closed walls `thickness` thick and `height` high standing round the floor from
/// `-half.x` to `half.x` and `-half.y` to `half.y` (x and z), appended to `meshes` and
/// `instances` as `wall_north` (+z), `wall_south`, `wall_east` (+x) and `wall_west`.
pub(super) fn walls_around(
    (meshes, instances): (&mut Vec<Mesh>, &mut Vec<Instance>),
    [hx, hz]: [f32; 2],
    [t, h]: [f32; 2],
    color: [f32; 4],
) {
    let walls = [
        ("wall_north", [-hx - t, hz], [hx + t, hz + t]),
        ("wall_south", [-hx - t, -hz - t], [hx + t, -hz]),
        ("wall_east", [hx, -hz], [hx + t, hz]),
        ("wall_west", [-hx - t, -hz], [-hx, hz]),
    ];
    for (wall, [x0, z0], [x1, z1]) in walls {
        let mesh = meshes.len() as u32;
        meshes.push(closed_box(
            wall,
            Vec3::new(x0, 0.0, z0),
            Vec3::new(x1, h, z1),
        ));
        instances.push(
            Instance::new(wall, mesh, &meshes[mesh as usize], Mat4::IDENTITY).with_color(color),
        );
    }
}

/// A closed 1 m cube standing on the origin: x and z in `[-0.5, 0.5]`, y in `[0, 1]`.
pub(super) fn unit_box(name: &str) -> Mesh {
    let mut builder = MeshBuilder::default();
    builder.cuboid(Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 1.0, 0.5), true);
    builder.build(name)
}

/// Corners of a square cross-section with half width 1, in order, for [`MeshBuilder::lathe`].
pub(super) const SQUARE_RING: [Vec2; 4] = [
    Vec2::new(1.0, 1.0),
    Vec2::new(-1.0, 1.0),
    Vec2::new(-1.0, -1.0),
    Vec2::new(1.0, -1.0),
];

/// A regular polygon of radius 1 with `sides` corners, for [`MeshBuilder::lathe`].
pub(super) fn circle_ring(sides: u32) -> Vec<Vec2> {
    (0..sides)
        .map(|k| Vec2::from_angle(TAU * k as f32 / sides as f32))
        .collect()
}

/// Collects flat-shaded faces into a mesh.
#[derive(Debug, Default)]
pub(super) struct MeshBuilder {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    indices: Vec<u32>,
}

impl MeshBuilder {
    /// A convex planar polygon whose front faces the side `outward` points to, whatever order
    /// the corners come in. Repeated corners are dropped; a degenerate polygon adds nothing.
    pub(super) fn polygon(&mut self, corners: &[Vec3], outward: Vec3) {
        let mut ring: Vec<Vec3> = Vec::with_capacity(corners.len());
        for &corner in corners {
            if ring.last() != Some(&corner) {
                ring.push(corner);
            }
        }
        while ring.len() > 1 && ring.first() == ring.last() {
            ring.pop();
        }
        if ring.len() < 3 {
            return;
        }
        // Newell's method: robust for any planar polygon, points where counter-clockwise does.
        let newell = ring
            .iter()
            .zip(ring.iter().cycle().skip(1))
            .fold(Vec3::ZERO, |acc, (a, b)| acc + a.cross(*b));
        let Some(mut normal) = newell.try_normalize() else {
            return;
        };
        if normal.dot(outward) < 0.0 {
            ring.reverse();
            normal = -normal;
        }
        let base = self.positions.len() as u32;
        self.normals.extend(std::iter::repeat_n(normal, ring.len()));
        self.positions.extend(&ring);
        for k in 1..ring.len() as u32 - 1 {
            self.indices.extend([base, base + k, base + k + 1]);
        }
    }

    /// A solid around the vertical axis through `center`: the cross-section `ring` (corners in
    /// the XZ plane, in order) scaled to each `[radius, y]` of `profile`. The profile is walked
    /// from the bottom with the solid on its inner side, and may step in, up, down or out.
    /// `top_cap` closes the top at the last radius; the bottom stays open.
    pub(super) fn lathe(
        &mut self,
        center: Vec3,
        ring: &[Vec2],
        profile: &[[f32; 2]],
        top_cap: bool,
    ) {
        let at = |k: usize, [radius, y]: [f32; 2]| {
            center + Vec3::new(ring[k].x * radius, y, ring[k].y * radius)
        };
        for pair in profile.windows(2) {
            let ([r0, y0], [r1, y1]) = (pair[0], pair[1]);
            // The solid lies on the inner side, so the outward normal is the walking direction
            // turned clockwise in the (radius, y) plane.
            let (normal_r, normal_y) = (y1 - y0, r0 - r1);
            for k in 0..ring.len() {
                let next = (k + 1) % ring.len();
                let side = (ring[k] + ring[next]).normalize_or_zero();
                let outward = Vec3::new(side.x * normal_r, normal_y, side.y * normal_r);
                self.polygon(
                    &[
                        at(k, pair[0]),
                        at(next, pair[0]),
                        at(next, pair[1]),
                        at(k, pair[1]),
                    ],
                    outward,
                );
            }
        }
        if let (true, Some(&last)) = (top_cap, profile.last()) {
            let cap: Vec<Vec3> = (0..ring.len()).map(|k| at(k, last)).collect();
            self.polygon(&cap, Vec3::Y);
        }
    }

    /// A convex solid between two horizontal quads whose corners correspond, e.g. a car cabin.
    /// `bottom_cap` closes the lower quad.
    pub(super) fn loft(&mut self, bottom: [Vec3; 4], top: [Vec3; 4], bottom_cap: bool) {
        let center = (bottom.iter().sum::<Vec3>() + top.iter().sum::<Vec3>()) / 8.0;
        let outward_of = |face: &[Vec3]| face.iter().sum::<Vec3>() / face.len() as f32 - center;
        for k in 0..4 {
            let next = (k + 1) % 4;
            let face = [bottom[k], bottom[next], top[next], top[k]];
            self.polygon(&face, outward_of(&face));
        }
        self.polygon(&top, outward_of(&top));
        if bottom_cap {
            self.polygon(&bottom, outward_of(&bottom));
        }
    }

    /// An axis-aligned box; `bottom_cap: false` leaves out the face at `min.y`.
    pub(super) fn cuboid(&mut self, min: Vec3, max: Vec3, bottom_cap: bool) {
        let rect = |y| {
            [
                Vec3::new(min.x, y, min.z),
                Vec3::new(max.x, y, min.z),
                Vec3::new(max.x, y, max.z),
                Vec3::new(min.x, y, max.z),
            ]
        };
        self.loft(rect(min.y), rect(max.y), bottom_cap);
    }

    /// A closed prism with `sides` flat sides around `axis` (its length is the height) from
    /// `base_center`: a low-poly cylinder such as a wheel.
    pub(super) fn cylinder(&mut self, base_center: Vec3, axis: Vec3, radius: f32, sides: u32) {
        let Some(direction) = axis.try_normalize() else {
            return;
        };
        let u = direction.any_orthonormal_vector();
        let v = direction.cross(u);
        let spokes: Vec<Vec3> = circle_ring(sides)
            .iter()
            .map(|p| (u * p.x + v * p.y) * radius)
            .collect();
        for k in 0..spokes.len() {
            let next = (k + 1) % spokes.len();
            let (a, b) = (base_center + spokes[k], base_center + spokes[next]);
            self.polygon(&[a, b, b + axis, a + axis], spokes[k] + spokes[next]);
        }
        let bottom: Vec<Vec3> = spokes.iter().map(|s| base_center + *s).collect();
        let top: Vec<Vec3> = bottom.iter().map(|p| *p + axis).collect();
        self.polygon(&bottom, -direction);
        self.polygon(&top, direction);
    }

    pub(super) fn build(self, name: &str) -> Mesh {
        Mesh::new(name, self.positions, Some(self.normals), self.indices)
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// Each triangle's winding agrees with its stored normals (flat shading: all three equal).
    pub(in crate::scene) fn assert_winding_matches_normals(mesh: &Mesh) {
        for tri in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| mesh.positions[i as usize]);
            let face = (b - a).cross(c - a).normalize();
            for &i in tri {
                let normal = mesh.normals[i as usize];
                assert!(
                    (normal.length() - 1.0).abs() < 1e-5,
                    "{}: normal not unit",
                    mesh.name
                );
                assert!(
                    face.dot(normal) > 0.999,
                    "{}: winding disagrees with normal",
                    mesh.name
                );
            }
        }
    }

    /// For a convex mesh: every face normal points away from the vertex centroid.
    fn assert_convex_faces_point_outward(mesh: &Mesh) {
        let center = mesh.positions.iter().sum::<Vec3>() / mesh.positions.len() as f32;
        for tri in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| mesh.positions[i as usize]);
            let centroid = (a + b + c) / 3.0;
            assert!(
                mesh.normals[tri[0] as usize].dot(centroid - center) > 0.0,
                "{}: inward face",
                mesh.name
            );
        }
    }

    #[test]
    fn every_builtin_name_loads_and_unknown_gives_none() {
        for builtin in BUILTIN_SCENES {
            let scene = load_builtin(builtin.name, 1).expect("a listed scene loads");
            assert_eq!(scene.name, format!("builtin:{}", builtin.name));
            assert!(!scene.instances.is_empty() && !builtin.description.is_empty());
        }
        assert!(load_builtin("no-such-scene", 1).is_none());
        assert!(load_builtin("", 1).is_none());
    }

    #[test]
    fn boxes_scene_has_its_known_layout() {
        let scene = load_builtin("boxes", 0).expect("boxes loads");
        assert_eq!(scene.instances.len(), 1 + BOXES_M.len());
        assert_eq!(scene.triangle_count(), 2 + 12 * BOXES_M.len());
        let ground = &scene.instances[0];
        assert_eq!(ground.name, "ground");
        assert_eq!(ground.aabb_in_world.min, Vec3::new(-20.0, 0.0, -20.0));
        assert_eq!(ground.aabb_in_world.max, Vec3::new(20.0, 0.0, 20.0));
        for (k, (instance, [x, z, size_x, height, size_z])) in
            scene.instances[1..].iter().zip(BOXES_M).enumerate()
        {
            assert_eq!(instance.name, format!("box_{k}"));
            let aabb = instance.aabb_in_world;
            let expected_min = Vec3::new(x - size_x / 2.0, 0.0, z - size_z / 2.0);
            assert!((aabb.min - expected_min).abs().max_element() < 1e-5);
            assert!(
                (aabb.extent() - Vec3::new(size_x, height, size_z))
                    .abs()
                    .max_element()
                    < 1e-5
            );
            assert!(instance.casts_shadow && instance.receives_shadow);
        }
        let other_seed = load_builtin("boxes", 99).expect("boxes loads");
        assert_eq!(other_seed.bounds(), scene.bounds());
    }

    #[test]
    fn box_faces_point_outward_and_wind_counter_clockwise() {
        let mesh = unit_box("box");
        assert_eq!(mesh.triangle_count(), 12);
        assert_convex_faces_point_outward(&mesh);
        assert_winding_matches_normals(&mesh);
        let quad = unit_ground_quad("quad");
        assert_winding_matches_normals(&quad);
        assert!(quad.normals.iter().all(|n| *n == Vec3::Y));
    }

    #[test]
    fn primitives_face_outward() {
        let mut parts = Vec::new();
        let mut builder = MeshBuilder::default();
        builder.cuboid(Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 3.0, 3.5), false);
        parts.push(builder.build("cuboid"));
        for axis in [Vec3::X, Vec3::Y, Vec3::new(0.2, -0.3, 1.5)] {
            let mut builder = MeshBuilder::default();
            builder.cylinder(Vec3::new(0.5, -1.0, 2.0), axis, 0.4, 8);
            parts.push(builder.build("cylinder"));
        }
        let mut builder = MeshBuilder::default();
        let rect = |x0: f32, x1: f32, half_z: f32, y: f32| {
            [
                Vec3::new(x0, y, -half_z),
                Vec3::new(x1, y, -half_z),
                Vec3::new(x1, y, half_z),
                Vec3::new(x0, y, half_z),
            ]
        };
        builder.loft(rect(-1.3, 1.0, 0.85, 0.9), rect(-1.0, 0.3, 0.7, 1.4), true);
        parts.push(builder.build("loft"));
        let mut builder = MeshBuilder::default();
        builder.lathe(
            Vec3::new(3.0, 0.0, 1.0),
            &circle_ring(7),
            &[[0.0, 0.0], [1.0, 0.5], [0.8, 2.0], [0.0, 2.5]],
            false,
        );
        parts.push(builder.build("lathe"));
        let mut builder = MeshBuilder::default();
        builder.lathe(
            Vec3::ZERO,
            &SQUARE_RING,
            &[[0.5, 0.0], [0.5, 1.0], [0.3, 1.2]],
            true,
        );
        parts.push(builder.build("square lathe"));
        for mesh in &parts {
            assert!(mesh.triangle_count() > 0);
            assert_convex_faces_point_outward(mesh);
            assert_winding_matches_normals(mesh);
        }
        assert_eq!(parts[1].triangle_count(), 8 * 2 + 2 * 6);
    }

    #[test]
    fn degenerate_polygons_add_nothing() {
        let mut builder = MeshBuilder::default();
        builder.polygon(&[Vec3::ZERO, Vec3::ZERO, Vec3::X], Vec3::Y);
        builder.polygon(&[Vec3::ZERO, Vec3::X, Vec3::X * 2.0], Vec3::Y);
        builder.cylinder(Vec3::ZERO, Vec3::ZERO, 1.0, 6);
        assert_eq!(builder.build("nothing").triangle_count(), 0);
    }
}
