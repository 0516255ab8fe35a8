//! `robots`: a walled hall of walking robots under a low sun, like the robot scene of Lloyd et
//! al.'s CC shadow volumes (their Figure 6: about 96K polygons, "a crowd of moving robots which
//! creates a high degree of occlusion"): 384 robots in 16 rows 2.4 m apart, each of six parts
//! that are shadow casters of their own (legs, body, arms, head). The walls and the
//! crowd hide 44% of the robots wholly from the sun and, from the walk's start, 77% from the
//! camera, so many volumes are culled and most of the rest cross space no visible receiver
//! occupies. Deterministic from the seed: the robots' colours and where along its row each
//! one starts.

use glam::{Mat4, Vec3};

use super::builtin::{MeshBuilder, unit_ground_quad, walls_around};
use super::city::SplitMix64;
use super::{CameraPath, Instance, Mesh, Mobility, Motion, PathKey, Scene, Sun};

/// The hall's floor, metres: x from `-HALL_X` to `HALL_X`, z from `-HALL_Z` to `HALL_Z`.
const HALL_X: f32 = 30.0;
const HALL_Z: f32 = 20.0;
const WALL_HEIGHT_M: f32 = 7.0;
const WALL_THICKNESS_M: f32 = 0.6;
/// Rows of robots along x, and robots per row.
const ROWS: u32 = 16;
const PER_ROW: u32 = 24;
/// A robot's parts, each its own mesh and instance (`robot_parts`).
const PARTS: usize = 6;
/// Sides of the robots' limbs and heads.
const SIDES: u32 = 12;
const WALK_M_PER_S: f32 = 1.2;

const ROBOT_PAINT: [[f32; 4]; 4] = [
    [0.75, 0.72, 0.68, 1.0],
    [0.80, 0.55, 0.20, 1.0],
    [0.35, 0.45, 0.60, 1.0],
    [0.55, 0.58, 0.55, 1.0],
];

/// One robot's parts, about 1.9 m tall together, facing +x, standing on the origin: legs,
/// body, arms, and head with its antenna, each a closed solid and a mesh of its own. Each part
/// is an instance, so each is a shadow caster of its own: Lloyd et al. clamp each caster's
/// volume to the depths its receivers occupy, and say that "a coarser object subdivision ...
/// leads to less fill savings" (their 5; in their 3.3 casters are sub-objects of one parent
/// object). A leg's volume then reaches only the depths where the leg's own shadow falls.
fn robot_parts() -> [Mesh; PARTS] {
    let part = |name: &str, add: &dyn Fn(&mut MeshBuilder)| {
        let mut b = MeshBuilder::default();
        add(&mut b);
        b.build(name)
    };
    let leg = |z: f32| {
        move |b: &mut MeshBuilder| b.cylinder(Vec3::new(0.0, 0.0, z), Vec3::Y * 0.85, 0.11, SIDES)
    };
    let arm = |z: f32| {
        move |b: &mut MeshBuilder| b.cylinder(Vec3::new(0.05, 0.75, z), Vec3::Y * 0.7, 0.08, SIDES)
    };
    [
        part("left_leg", &leg(-0.18)),
        part("right_leg", &leg(0.18)),
        part("body", &|b| {
            b.cuboid(
                Vec3::new(-0.2, 0.85, -0.32),
                Vec3::new(0.2, 1.5, 0.32),
                true,
            );
        }),
        part("left_arm", &arm(-0.42)),
        part("right_arm", &arm(0.42)),
        part("head", &|b| {
            b.cylinder(Vec3::new(0.0, 1.5, 0.0), Vec3::Y * 0.3, 0.17, SIDES);
            b.cylinder(Vec3::new(0.0, 1.8, 0.0), Vec3::Y * 0.12, 0.02, SIDES);
        }),
    ]
}

/// The robot hall from `seed`.
pub(super) fn robots_scene(name: String, seed: u64) -> Scene {
    let mut rng = SplitMix64::new(seed);
    let (hx, hz, t, h) = (HALL_X, HALL_Z, WALL_THICKNESS_M, WALL_HEIGHT_M);
    let mut meshes = vec![unit_ground_quad("floor")];
    let floor_size = Vec3::new(2.0 * (hx + t), 1.0, 2.0 * (hz + t));
    let mut instances = vec![
        Instance::new("floor", 0, &meshes[0], Mat4::from_scale(floor_size))
            .with_color([0.50, 0.50, 0.48, 1.0]),
    ];
    walls_around(
        (&mut meshes, &mut instances),
        [hx, hz],
        [t, h],
        [0.62, 0.58, 0.52, 1.0],
    );
    let first_part = meshes.len();
    meshes.extend(robot_parts());
    let mut motions = Vec::new();
    let row_gap = 2.0 * hz / (ROWS + 1) as f32;
    let length = 2.0 * hx - 2.0;
    for row in 0..ROWS {
        let z = -hz + row_gap * (row + 1) as f32;
        // Rows walk in turn east and west.
        let (start, direction) = if row % 2 == 0 {
            (Vec3::new(-hx + 1.0, 0.0, z), Vec3::X)
        } else {
            (Vec3::new(hx - 1.0, 0.0, z), Vec3::NEG_X)
        };
        let jitter = rng.range_f32(0.0, length / PER_ROW as f32);
        for k in 0..PER_ROW {
            let paint = ROBOT_PAINT[rng.below(ROBOT_PAINT.len())];
            // The parts walk together: each instance's motion is the robot's path.
            let motion_of = |instance: usize| Motion {
                instance: instance as u32,
                start,
                direction,
                length_m: length,
                offset_m: (jitter + length * k as f32 / PER_ROW as f32) % length,
                speed_m_per_s: WALK_M_PER_S,
            };
            for (part, mesh) in meshes.iter().enumerate().skip(first_part) {
                let motion = motion_of(instances.len());
                instances.push(
                    Instance::new(
                        format!("robot_{row}_{k}_{}", mesh.name),
                        part as u32,
                        mesh,
                        motion.world_from_local(0.0),
                    )
                    .with_color(paint)
                    .with_mobility(Mobility::Dynamic),
                );
                motions.push(motion);
            }
        }
    }
    let mut scene = Scene::new(
        name,
        meshes,
        instances,
        Sun::from_azimuth_elevation_deg(25.0, 14.0),
    );
    scene.motions = motions;
    scene
}

/// A walk through the hall at eye height between the rows, then along the sunny wall.
pub(super) fn robots_walk() -> CameraPath {
    let at = |x: f32, z: f32| Vec3::new(x, 1.7, z);
    let gap = 2.0 * HALL_Z / (ROWS + 1) as f32;
    let aisle = -HALL_Z + gap * 5.5;
    let keys = vec![
        PathKey {
            eye: at(-HALL_X + 2.0, aisle),
            target: at(0.0, aisle - 3.0),
        },
        PathKey {
            eye: at(-8.0, aisle),
            target: at(10.0, aisle + 4.0),
        },
        PathKey {
            eye: at(8.0, aisle - gap * 2.0),
            target: at(HALL_X, aisle - gap * 5.0),
        },
        PathKey {
            eye: Vec3::new(HALL_X - 3.0, 5.0, -HALL_Z + 3.0),
            target: at(-10.0, 5.0),
        },
    ];
    CameraPath::new("robots walk", keys).expect("four keys")
}

#[cfg(test)]
mod tests {
    use super::super::builtin::tests::assert_winding_matches_normals;
    use super::*;
    use crate::truth::SceneRays;

    #[test]
    fn the_hall_holds_its_robots_walking_and_about_lloyds_polygons() {
        let scene = robots_scene("builtin:robots".into(), 7);
        let parts = (ROWS * PER_ROW) as usize * PARTS;
        assert_eq!(scene.motions.len(), parts);
        assert_eq!(scene.instances.len(), 5 + parts);
        // A robot's parts are its six solids, and they walk together.
        let robot = &scene.instances[5..5 + PARTS];
        let names: Vec<&str> = robot.iter().map(|i| i.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "robot_0_0_left_leg",
                "robot_0_0_right_leg",
                "robot_0_0_body",
                "robot_0_0_left_arm",
                "robot_0_0_right_arm",
                "robot_0_0_head"
            ]
        );
        let mut walked = scene.clone();
        walked.animate(9.0);
        for i in 5..5 + PARTS {
            assert_eq!(
                walked.instances[i].world_from_local,
                walked.instances[5].world_from_local
            );
        }
        let triangles: usize = scene
            .instances
            .iter()
            .map(|i| scene.meshes[i.mesh as usize].indices.len() / 3)
            .sum();
        assert!(
            (50_000..150_000).contains(&triangles),
            "{triangles} triangles"
        );
        for mesh in &scene.meshes {
            assert_winding_matches_normals(mesh);
        }
        // Every robot stays inside the walls as it walks.
        let mut moved = scene.clone();
        for time in [0.0, 7.5, 31.0] {
            moved.animate(time);
            for i in &moved.instances[5..] {
                let b = i.aabb_in_world;
                assert!(
                    b.min.x > -HALL_X && b.max.x < HALL_X && b.min.z > -HALL_Z && b.max.z < HALL_Z,
                    "{} at {time} s: {b:?}",
                    i.name
                );
            }
        }
        let again = robots_scene("builtin:robots".into(), 7);
        assert_eq!(
            again.instances[9].world_from_local,
            scene.instances[9].world_from_local
        );
    }

    /// The share of robots that every sample point of which `hidden` says is hidden by an
    /// instance other than the robot's own parts (given as their first instance), through
    /// the scene's rays.
    fn share_hidden(scene: &Scene, hidden: impl Fn(&SceneRays, u32, Vec3) -> bool) -> f32 {
        let rays = SceneRays::new(scene);
        let robots: Vec<&Instance> = scene.instances[5..].iter().step_by(PARTS).collect();
        let samples = [
            Vec3::new(0.0, 1.65, 0.0),
            Vec3::new(0.0, 1.2, 0.0),
            Vec3::new(0.0, 0.4, -0.18),
            Vec3::new(0.0, 0.4, 0.18),
        ];
        let count = robots
            .iter()
            .enumerate()
            .filter(|(k, robot)| {
                let instance = (5 + k * PARTS) as u32;
                samples
                    .iter()
                    .all(|&s| hidden(&rays, instance, robot.world_from_local.transform_point3(s)))
            })
            .count();
        count as f32 / robots.len() as f32
    }

    /// Whether an instance other than the parts of the robot whose first part is `own` lies
    /// between `point` and `point + to`.
    fn blocked_by_another(rays: &SceneRays, own: u32, point: Vec3, to: Vec3) -> bool {
        let mut other = false;
        let parts = own..own + PARTS as u32;
        rays.blockers(point.as_dvec3(), to, (0.0, 1.0), |i| {
            other |= !parts.contains(&i);
        });
        other
    }

    /// Lloyd's robot room is a crowd "which creates a high degree of occlusion": with the
    /// light low, culling removes many casters. Many robots stand wholly in the shadow of the
    /// walls or of other robots (their volumes are culled), and from the walk's first key the
    /// crowd hides most robots from the eye (their shadows fall where nobody looks).
    #[test]
    fn the_crowd_hides_most_robots_from_the_sun_and_from_the_walk() {
        let scene = robots_scene("builtin:robots".into(), 0);
        let to_sun = scene.sun.direction_to_sun * 200.0;
        let from_sun = share_hidden(&scene, |rays, own, p| {
            blocked_by_another(rays, own, p, to_sun)
        });
        let eye = robots_walk().keys()[0].eye;
        let from_eye = share_hidden(&scene, |rays, own, p| {
            blocked_by_another(rays, own, p, eye - p)
        });
        // 44% and 77% at seed 0; the hall of 120 robots 4.8 m apart that this crowd
        // replaced hid 45% and 27%.
        assert!(
            from_sun > 0.4 && from_eye > 0.7,
            "hidden from the sun {from_sun}, from the walk's start {from_eye}"
        );
    }

    #[test]
    fn the_walk_stays_inside_the_hall() {
        for key in robots_walk().keys() {
            assert!(
                key.eye.x.abs() < HALL_X && key.eye.z.abs() < HALL_Z,
                "{key:?}"
            );
        }
    }
}
