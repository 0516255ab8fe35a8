//! `hall`: a low-walled hall with a dense, bumpy statue on a plinth at its centre, ringed by
//! columns and lit by 32 shadow-casting spot and point lights, like the test scene of Rákos's
//! "Massive number of shadow-casting lights with layered rendering" (GPU Pro 4: a dense
//! Stanford-dragon-like mesh under many lights). The statue (about 49K triangles) is a knotted
//! tube with bumps, so it shadows itself from every side; the columns throw long shadows of
//! every light across the floor and onto the walls. Deterministic from the seed: only the
//! lights (where on their ring, how high, colour, where each spot aims and how wide).

use std::f32::consts::TAU;

use glam::{Mat4, Vec3};

use super::builtin::{closed_box, unit_box, walls_around};
use super::city::SplitMix64;
use super::{CameraPath, Instance, LightKind, Mesh, PathKey, PunctualLight, Scene, Sun};

/// The hall's floor inside the walls, metres: x and z from `-HALF_SIZE_M` to `HALF_SIZE_M`.
const HALF_SIZE_M: f32 = 15.0;
const WALL_HEIGHT_M: f32 = 3.0;
const WALL_THICKNESS_M: f32 = 0.5;
const FLOOR_THICKNESS_M: f32 = 0.3;
/// Columns on a ring round the statue, the first at half a step from +x (so the walk's keys
/// look between them).
const COLUMNS: u32 = 8;
const COLUMN_RING_RADIUS_M: f32 = 6.0;
const COLUMN_WIDTH_M: f32 = 0.6;
const COLUMN_HEIGHT_M: f32 = 5.0;
/// The plinth: a box centred on the origin.
const PLINTH_WIDTH_M: f32 = 2.0;
const PLINTH_HEIGHT_M: f32 = 0.8;
/// How far the statue's lowest point sinks into the plinth, so it stands on a small patch.
const STATUE_SINK_M: f32 = 0.04;
/// About the statue's middle: where the walk looks.
const STATUE_MIDDLE_M: Vec3 = Vec3::new(0.0, PLINTH_HEIGHT_M + 1.5, 0.0);

/// The statue's centre line: a (`KNOT_P`, `KNOT_Q`) torus knot (a trefoil) standing in the
/// xy plane, on a torus of ring radius `KNOT_RING_M` and tube radius `KNOT_SWING_M`, squeezed
/// along x by `KNOT_SQUEEZE_X` to stand on the plinth. Its tube is `TUBE_RADIUS_M` thick.
const KNOT_P: f32 = 2.0;
const KNOT_Q: f32 = 3.0;
const KNOT_RING_M: f32 = 0.9;
const KNOT_SWING_M: f32 = 0.42;
const KNOT_SQUEEZE_X: f32 = 0.75;
const TUBE_RADIUS_M: f32 = 0.18;
/// Rings along the knot and vertices round each ring: 2 × 512 × 48 = 49,152 triangles.
const KNOT_SEGMENTS: u32 = 512;
const TUBE_SIDES: u32 = 48;
/// The bumps: a sum of sines of position, each a wave vector (radians per metre) and an
/// amplitude (metres), pushing the tube's surface in and out.
const BUMPS: [([f32; 3], f32); 3] = [
    ([5.0, 3.0, 4.0], 0.03),
    ([-7.0, 9.0, 6.0], 0.02),
    ([13.0, -11.0, 12.0], 0.01),
];

/// The lights: `LIGHTS` round a ring about the statue, a slot each in order of angle, every
/// `POINT_EVERY`th a point light and the others spot lights aimed at the statue.
const LIGHTS: u32 = 32;
const POINT_EVERY: u32 = 4;
/// How far a light strays from its slot's middle, in slots (under a half keeps the order).
const SLOT_JITTER: f32 = 0.35;
const LIGHT_RING_RADIUS_M: (f32, f32) = (9.0, 11.0);
const LIGHT_HEIGHT_M: (f32, f32) = (3.0, 6.0);
/// How far a spot light's aim strays from the statue's centre, metres along each axis.
const AIM_JITTER_M: f32 = 0.4;
const OUTER_CONE_DEG: (f32, f32) = (30.0, 40.0);
const INNER_CONE_FRACTION: f32 = 0.8;
const LIGHT_RANGE_M: f32 = 25.0;
/// A light gives `intensity / distance²` lux. The corridor's lamp matches the sun
/// ([`Sun::ILLUMINANCE_LX`]) on its floor; here `LIGHTS_SUMMED` lights add up on any side of
/// the statue, so each gives it a `LIGHTS_SUMMED`th of that from `LIGHT_REFERENCE_DISTANCE_M`
/// (about the ring's distance to the statue's centre).
const LIGHTS_SUMMED: f32 = 12.0;
const LIGHT_REFERENCE_DISTANCE_M: f32 = 10.0;
const LIGHT_INTENSITY_CD: f32 =
    Sun::ILLUMINANCE_LX / LIGHTS_SUMMED * LIGHT_REFERENCE_DISTANCE_M * LIGHT_REFERENCE_DISTANCE_M;
/// Linear RGB, two warm and two cool.
const LIGHT_COLORS: [[f32; 3]; 4] = [
    [1.0, 0.84, 0.66],
    [1.0, 0.93, 0.80],
    [0.80, 0.89, 1.0],
    [0.70, 0.80, 1.0],
];

/// The walk: keys round the statue at eye height, `WALK_RADIUS_M` out (clear of the columns
/// on the chords between keys too).
const WALK_KEYS: u32 = 8;
const WALK_RADIUS_M: f32 = 7.5;
const EYE_HEIGHT_M: f32 = 1.7;

/// The knot's centre line at `t` in `[0, TAU)`, and the outward normal of the torus it lies on
/// there (perpendicular to the line before the squeeze).
fn knot_at(t: f32) -> (Vec3, Vec3) {
    let ((sin_phi, cos_phi), (sin_theta, cos_theta)) =
        ((KNOT_P * t).sin_cos(), (KNOT_Q * t).sin_cos());
    let rho = KNOT_RING_M + KNOT_SWING_M * cos_theta;
    let point = Vec3::new(
        KNOT_SQUEEZE_X * rho * cos_phi,
        rho * sin_phi,
        KNOT_SWING_M * sin_theta,
    );
    (
        point,
        Vec3::new(cos_theta * cos_phi, cos_theta * sin_phi, sin_theta),
    )
}

/// The knot's centre line, `KNOT_SEGMENTS` points.
fn knot_centre_line() -> Vec<Vec3> {
    (0..KNOT_SEGMENTS)
        .map(|i| knot_at(TAU * i as f32 / KNOT_SEGMENTS as f32).0)
        .collect()
}

/// How far the bumps push the surface out at `p`, metres (in at most the amplitudes' sum).
fn bump_m(p: Vec3) -> f32 {
    BUMPS
        .iter()
        .map(|&(wave, amplitude)| amplitude * Vec3::from_array(wave).dot(p).sin())
        .sum()
}

/// The statue in its own space: a bumpy tube round the knot, one closed surface of shared
/// vertices with smooth normals, wound counter-clockwise seen from outside.
fn statue_mesh() -> Mesh {
    let line = knot_centre_line();
    let (n, sides) = (KNOT_SEGMENTS as usize, TUBE_SIDES as usize);
    let mut positions = Vec::with_capacity(n * sides);
    for i in 0..n {
        let tangent = (line[(i + 1) % n] - line[(i + n - 1) % n]).normalize();
        let torus_normal = knot_at(TAU * i as f32 / n as f32).1;
        // A frame round the line that closes on itself: the torus's normal made perpendicular
        // to the tangent, and the binormal.
        let normal = (torus_normal - torus_normal.dot(tangent) * tangent).normalize();
        let binormal = tangent.cross(normal);
        for j in 0..sides {
            let angle = TAU * j as f32 / sides as f32;
            let outward = normal * angle.cos() + binormal * angle.sin();
            let surface = line[i] + outward * TUBE_RADIUS_M;
            positions.push(surface + outward * bump_m(surface));
        }
    }
    let at = |i: usize, j: usize| ((i % n) * sides + j % sides) as u32;
    let mut indices = Vec::with_capacity(6 * n * sides);
    for i in 0..n {
        for j in 0..sides {
            // Along the line × round the tube points inwards, so each quad goes round first.
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            indices.extend([a, b, c, a, c, d]);
        }
    }
    Mesh::new("statue", positions, None, indices)
}

/// The hall from `seed`.
pub(super) fn hall_scene(name: String, seed: u64) -> Scene {
    let mut rng = SplitMix64::new(seed);
    let (hs, t, h) = (HALF_SIZE_M, WALL_THICKNESS_M, WALL_HEIGHT_M);
    let floor_min = Vec3::new(-hs - t, -FLOOR_THICKNESS_M, -hs - t);
    let mut meshes = vec![
        closed_box("floor", floor_min, Vec3::new(hs + t, 0.0, hs + t)),
        unit_box("box"),
        statue_mesh(),
    ];
    let plinth = Vec3::new(PLINTH_WIDTH_M, PLINTH_HEIGHT_M, PLINTH_WIDTH_M);
    let mut instances = vec![
        Instance::new("floor", 0, &meshes[0], Mat4::IDENTITY).with_color([0.50, 0.50, 0.48, 1.0]),
        Instance::new("plinth", 1, &meshes[1], Mat4::from_scale(plinth))
            .with_color([0.30, 0.29, 0.28, 1.0]),
    ];
    // The statue stands centred on the plinth, sunk a little into it.
    let local = meshes[2].aabb_in_local;
    let statue_at = Vec3::new(0.0, PLINTH_HEIGHT_M - STATUE_SINK_M - local.min.y, 0.0)
        - local.center() * Vec3::new(1.0, 0.0, 1.0);
    let statue = Instance::new("statue", 2, &meshes[2], Mat4::from_translation(statue_at))
        .with_color([0.72, 0.62, 0.48, 1.0]);
    let statue_centre = statue.aabb_in_world.center();
    instances.push(statue);
    for k in 0..COLUMNS {
        let angle = TAU * (k as f32 + 0.5) / COLUMNS as f32;
        let (sin, cos) = angle.sin_cos();
        let world_from_local =
            Mat4::from_translation(Vec3::new(cos, 0.0, sin) * COLUMN_RING_RADIUS_M)
                * Mat4::from_scale(Vec3::new(COLUMN_WIDTH_M, COLUMN_HEIGHT_M, COLUMN_WIDTH_M));
        instances.push(
            Instance::new(format!("column_{k}"), 1, &meshes[1], world_from_local)
                .with_color([0.70, 0.68, 0.63, 1.0]),
        );
    }
    let plaster = [0.62, 0.60, 0.56, 1.0];
    walls_around((&mut meshes, &mut instances), [hs, hs], [t, h], plaster);
    let sun = Sun::from_azimuth_elevation_deg(40.0, 50.0);
    let mut scene = Scene::new(name, meshes, instances, sun);
    for k in 0..LIGHTS {
        let slot = k as f32 + 0.5 + rng.range_f32(-SLOT_JITTER, SLOT_JITTER);
        let (sin, cos) = (TAU * slot / LIGHTS as f32).sin_cos();
        let radius = rng.range_f32(LIGHT_RING_RADIUS_M.0, LIGHT_RING_RADIUS_M.1);
        let height = rng.range_f32(LIGHT_HEIGHT_M.0, LIGHT_HEIGHT_M.1);
        let position = Vec3::new(cos * radius, height, sin * radius);
        let color = LIGHT_COLORS[rng.below(LIGHT_COLORS.len())];
        let (name, kind) = if k % POINT_EVERY == POINT_EVERY - 1 {
            (format!("point_{k}"), LightKind::Point)
        } else {
            let mut jitter = || rng.range_f32(-AIM_JITTER_M, AIM_JITTER_M);
            let aim = statue_centre + Vec3::new(jitter(), jitter(), jitter());
            let outer_deg = rng.range_f32(OUTER_CONE_DEG.0, OUTER_CONE_DEG.1);
            let outer = outer_deg.to_radians();
            let kind = LightKind::Spot {
                direction: (aim - position).normalize(),
                inner_cone_rad: INNER_CONE_FRACTION * outer,
                outer_cone_rad: outer,
            };
            (format!("spot_{k}"), kind)
        };
        scene.lights.push(PunctualLight {
            name,
            position,
            kind,
            color,
            intensity: LIGHT_INTENSITY_CD,
            range: Some(LIGHT_RANGE_M),
        });
    }
    scene
}

/// A walk round the statue at eye height, looking at it, between the columns and the lights;
/// the first key looks at it from +x.
pub(super) fn hall_walk() -> CameraPath {
    let keys = (0..WALK_KEYS)
        .map(|k| {
            let (sin, cos) = (TAU * k as f32 / WALK_KEYS as f32).sin_cos();
            PathKey {
                eye: Vec3::new(cos * WALK_RADIUS_M, EYE_HEIGHT_M, sin * WALK_RADIUS_M),
                target: STATUE_MIDDLE_M,
            }
        })
        .collect();
    CameraPath::new("hall walk", keys).expect("eight keys")
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use glam::Vec3Swizzles;

    use super::super::builtin::tests::assert_winding_matches_normals;
    use super::*;
    use crate::geom::Aabb;

    fn hall(seed: u64) -> Scene {
        hall_scene("builtin:hall".into(), seed)
    }

    fn placed(scene: &Scene, name: &str) -> Aabb {
        let found = scene.instances.iter().find(|i| i.name == name);
        found.unwrap_or_else(|| panic!("no {name}")).aabb_in_world
    }

    #[test]
    fn the_statue_is_one_closed_outward_tube_of_40k_to_60k_triangles_on_the_plinth() {
        let mesh = statue_mesh();
        let triangles = mesh.triangle_count();
        assert!((40_000..=60_000).contains(&triangles), "{triangles}");
        // Closed and consistently wound: every directed edge once and its reverse once.
        let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
        for tri in mesh.indices.chunks_exact(3) {
            for (a, b) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
                *edges.entry((a, b)).or_default() += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "edge {a}-{b} used {count} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}-{b} open");
        }
        // Wound counter-clockwise from outside: the enclosed volume is positive, about the
        // tube's cross-section times the line's length.
        let volume: f32 = (mesh.indices.chunks_exact(3))
            .map(|t| [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]))
            .map(|[a, b, c]| a.dot(b.cross(c)) / 6.0)
            .sum();
        let line = knot_centre_line();
        let length: f32 = (line.iter().zip(line.iter().cycle().skip(1)))
            .map(|(a, b)| a.distance(*b))
            .sum();
        let tube = TAU / 2.0 * TUBE_RADIUS_M * TUBE_RADIUS_M * length;
        assert!(volume > 0.8 * tube && volume < 1.2 * tube, "{volume} m³");
        // About 3 m tall, standing on the plinth's top and about as wide as the plinth.
        let b = placed(&hall(7), "statue");
        let size = b.extent();
        assert!((2.7..3.3).contains(&size.y), "{size}");
        assert!((b.min.y - (PLINTH_HEIGHT_M - STATUE_SINK_M)).abs() < 1e-4);
        assert!(size.xz().max_element() < PLINTH_WIDTH_M + 0.3, "{size}");
        // The tube never passes through itself: points an eighth of the loop or more apart
        // along the line are two bumpy tube radii apart and then some.
        let n = line.len();
        let reach = TUBE_RADIUS_M + BUMPS.iter().map(|b| b.1).sum::<f32>();
        for i in 0..n {
            for k in i + n / 8..=i + n - n / 8 {
                let gap = line[i].distance(line[k % n]);
                assert!(gap > 2.0 * reach + 0.1, "{i} and {}: {gap} m", k % n);
            }
        }
    }

    #[test]
    fn the_hall_is_a_floor_four_walls_eight_columns_a_plinth_and_the_statue() {
        let scene = hall(7);
        assert_eq!(scene.instances.len(), 3 + COLUMNS as usize + 4);
        let floor = placed(&scene, "floor");
        assert!(floor.max.y.abs() < 1e-6);
        assert!(floor.extent().xz().min_element() >= 2.0 * HALF_SIZE_M);
        assert!((placed(&scene, "wall_north").max.y - WALL_HEIGHT_M).abs() < 1e-6);
        for k in 0..COLUMNS {
            let b = placed(&scene, &format!("column_{k}"));
            let radius = b.center().xz().length();
            assert!((radius - COLUMN_RING_RADIUS_M).abs() < 1e-3, "{radius}");
            assert!((b.extent().y - COLUMN_HEIGHT_M).abs() < 1e-4);
        }
        for mesh in scene.meshes.iter().filter(|m| m.name != "statue") {
            assert_winding_matches_normals(mesh);
        }
    }

    #[test]
    fn thirty_two_lights_ring_the_statue_every_fourth_a_point_light() {
        let scene = hall(7);
        let centre = placed(&scene, "statue").center();
        assert_eq!(scene.lights.len(), LIGHTS as usize);
        let points = scene.lights.iter().filter(|l| l.kind == LightKind::Point);
        assert_eq!(points.count(), 8);
        let mut last_angle = 0.0;
        for (k, light) in scene.lights.iter().enumerate() {
            let p = light.position;
            let angle = p.z.atan2(p.x).rem_euclid(TAU);
            assert!(angle > last_angle, "{} out of order", light.name);
            last_angle = angle;
            let radius = p.xz().length();
            assert!((9.0..=11.0).contains(&radius), "{p}");
            assert!((3.0..=6.0).contains(&p.y), "{p}");
            assert_eq!(light.range, Some(LIGHT_RANGE_M));
            // A twelfth of the corridor lamp's sun-bright floor, give or take the distance.
            let lux = light.intensity / p.distance_squared(centre);
            let share = Sun::ILLUMINANCE_LX / LIGHTS_SUMMED;
            assert!(lux > 0.7 * share && lux < 1.3 * share, "{lux} lx");
            let LightKind::Spot {
                direction,
                inner_cone_rad: inner,
                outer_cone_rad: outer,
            } = light.kind
            else {
                assert_eq!(light.name, format!("point_{k}"));
                continue;
            };
            assert_eq!(light.name, format!("spot_{k}"));
            assert!((direction.length() - 1.0).abs() < 1e-5);
            let off_aim = direction.angle_between(centre - p);
            assert!(off_aim < outer / 4.0, "{}: {off_aim}", light.name);
            assert!((30.0..=40.0).contains(&outer.to_degrees()), "{outer}");
            assert!((inner / outer - 0.8).abs() < 1e-5);
        }
    }

    #[test]
    fn the_hall_is_the_same_for_a_seed_and_its_lights_move_with_another() {
        let (a, b, other) = (hall(7), hall(7), hall(8));
        assert_eq!(a.lights, b.lights);
        // Only the lights follow the seed.
        for s in [&b, &other] {
            let mut pairs = a.instances.iter().zip(&s.instances);
            assert!(pairs.all(|(x, y)| x.world_from_local == y.world_from_local));
        }
        let moved = a.lights.iter().zip(&other.lights);
        assert!(moved.filter(|(x, y)| x.position != y.position).count() > 16);
    }

    #[test]
    fn the_walk_circles_the_statue_at_eye_height_outside_every_solid() {
        let scene = hall(7);
        let path = hall_walk();
        assert_eq!(path.keys().len(), WALK_KEYS as usize);
        for k in 0..=200 {
            let key = path.sample(k as f32 / 200.0);
            let e = key.eye;
            assert!((e.y - EYE_HEIGHT_M).abs() < 1e-5, "{e}");
            assert!(
                (6.5..WALK_RADIUS_M + 1e-3).contains(&e.xz().length()),
                "{e}"
            );
            assert!(key.target.distance(STATUE_MIDDLE_M) < 1e-4);
            let near = Aabb::new(e - Vec3::splat(0.3), e + Vec3::splat(0.3));
            for i in &scene.instances {
                assert!(!near.overlaps(&i.aabb_in_world), "{e} near {}", i.name);
            }
        }
    }
}
