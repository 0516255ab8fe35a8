//! `corridor`: a long walled corridor under dense roof trusses, lit by a point light hung among
//! the trusses and by a low sun through the open roof, like the "trusses" scene of Lloyd et
//! al.'s CC shadow volumes (about 100K polygons). Every truss is a lattice of thin struts, so
//! its shadow volumes are long, thin and mostly cross empty air before they reach the floor or
//! a wall: the case where culling and clamping shadow volumes pays. Deterministic from the seed:
//! only the crates along the walls (where, how big, what colour).

use glam::{Mat4, Vec3};

use super::builtin::{MeshBuilder, closed_box, unit_box, walls_around};
use super::city::SplitMix64;
use super::{CameraPath, Instance, LightKind, Mesh, PathKey, PunctualLight, Scene, Sun};

/// The corridor's floor inside the walls, metres: x from `-HALF_LENGTH_M` to `HALF_LENGTH_M`,
/// z from `-HALF_WIDTH_M` to `HALF_WIDTH_M`.
const HALF_LENGTH_M: f32 = 40.0;
const HALF_WIDTH_M: f32 = 5.0;
const WALL_HEIGHT_M: f32 = 6.0;
const WALL_THICKNESS_M: f32 = 0.5;
const FLOOR_THICKNESS_M: f32 = 0.3;
/// A truss every `TRUSS_SPACING_M` along x, the first half a spacing from the west wall.
const TRUSS_SPACING_M: f32 = 2.0;
const TRUSSES: u32 = (2.0 * HALF_LENGTH_M / TRUSS_SPACING_M) as u32;
/// Panels of each truss across the corridor (even, so a node sits under the ridge).
const PANELS: u32 = 18;
/// Height of the bottom chord's axis, of the top chord's axis at the walls (the heel) and at
/// the ridge, metres.
const BOTTOM_CHORD_Y_M: f32 = 4.8;
const HEEL_Y_M: f32 = 5.2;
const RIDGE_Y_M: f32 = 6.4;
/// Strut radii, metres: chords, verticals, diagonals, purlins.
const CHORD_RADIUS_M: f32 = 0.07;
const VERTICAL_RADIUS_M: f32 = 0.04;
const DIAGONAL_RADIUS_M: f32 = 0.035;
const PURLIN_RADIUS_M: f32 = 0.08;
/// Where the purlins run along the corridor on top of the top chords, metres of z.
const PURLIN_Z_M: [f32; 5] = [-4.0, -2.0, 0.0, 2.0, 4.0];
/// Flat sides of every strut.
const STRUT_SIDES: u32 = 12;
const CRATES: u32 = 12;

/// The point light: between two trusses in the west third of the corridor, above the bottom
/// chords and below the ridge, so the trusses on either side cast long shadows down the floor
/// and the walls.
const LIGHT_POSITION_M: Vec3 = Vec3::new(-14.0, 5.3, 0.0);
/// A point light gives `intensity / distance²` lux: this one matches the sun
/// ([`Sun::ILLUMINANCE_LX`]) on a floor point `LIGHT_REFERENCE_DISTANCE_M` away (225 000 lx
/// at 5 m, 56 000 lx at 10 m).
const LIGHT_REFERENCE_DISTANCE_M: f32 = 7.5;
const LIGHT_INTENSITY_CD: f32 =
    Sun::ILLUMINANCE_LX * LIGHT_REFERENCE_DISTANCE_M * LIGHT_REFERENCE_DISTANCE_M;

const CRATE_PAINT: [[f32; 4]; 3] = [
    [0.55, 0.40, 0.22, 1.0],
    [0.45, 0.47, 0.40, 1.0],
    [0.62, 0.30, 0.18, 1.0],
];

/// The top chord's axis height at `z`: a pitched roof from the heels up to the ridge.
fn top_chord_y(z: f32) -> f32 {
    HEEL_Y_M + (RIDGE_Y_M - HEEL_Y_M) * (1.0 - z.abs() / HALF_WIDTH_M)
}

/// A closed strut of `radius` from `from` to `to`.
fn strut(b: &mut MeshBuilder, from: Vec3, to: Vec3, radius: f32) {
    b.cylinder(from, to - from, radius, STRUT_SIDES);
}

/// One pitched roof truss in the plane x = 0 spanning the corridor: a bottom chord, two top
/// chords meeting at the ridge, a vertical at every node and crossed diagonals in every panel,
/// each a closed prism.
fn truss_mesh() -> Mesh {
    let mut b = MeshBuilder::default();
    let w = HALF_WIDTH_M;
    let bottom = |z: f32| Vec3::new(0.0, BOTTOM_CHORD_Y_M, z);
    let top = |z: f32| Vec3::new(0.0, top_chord_y(z), z);
    strut(&mut b, bottom(-w), bottom(w), CHORD_RADIUS_M);
    strut(&mut b, top(-w), top(0.0), CHORD_RADIUS_M);
    strut(&mut b, top(0.0), top(w), CHORD_RADIUS_M);
    let node_z = |k: u32| -w + 2.0 * w * k as f32 / PANELS as f32;
    for k in 0..=PANELS {
        strut(&mut b, bottom(node_z(k)), top(node_z(k)), VERTICAL_RADIUS_M);
    }
    for k in 0..PANELS {
        let (z0, z1) = (node_z(k), node_z(k + 1));
        strut(&mut b, bottom(z0), top(z1), DIAGONAL_RADIUS_M);
        strut(&mut b, bottom(z1), top(z0), DIAGONAL_RADIUS_M);
    }
    b.build("truss")
}

/// A purlin: a closed strut along the whole corridor through the origin, resting on the top
/// chords once lifted to them.
fn purlin_mesh() -> Mesh {
    let mut b = MeshBuilder::default();
    let x = HALF_LENGTH_M;
    strut(&mut b, Vec3::NEG_X * x, Vec3::X * x, PURLIN_RADIUS_M);
    b.build("purlin")
}

/// The x of truss `k`.
fn truss_x(k: u32) -> f32 {
    -HALF_LENGTH_M + TRUSS_SPACING_M * (k as f32 + 0.5)
}

/// The trussed corridor from `seed`.
pub(super) fn corridor_scene(name: String, seed: u64) -> Scene {
    let mut rng = SplitMix64::new(seed);
    let (hx, hz, t, h) = (HALF_LENGTH_M, HALF_WIDTH_M, WALL_THICKNESS_M, WALL_HEIGHT_M);
    let floor_min = Vec3::new(-hx - t, -FLOOR_THICKNESS_M, -hz - t);
    let mut meshes = vec![
        closed_box("floor", floor_min, Vec3::new(hx + t, 0.0, hz + t)),
        truss_mesh(),
        purlin_mesh(),
        unit_box("crate"),
    ];
    let mut instances = vec![
        Instance::new("floor", 0, &meshes[0], Mat4::IDENTITY).with_color([0.50, 0.50, 0.48, 1.0]),
    ];
    walls_around(
        (&mut meshes, &mut instances),
        [hx, hz],
        [t, h],
        [0.66, 0.62, 0.56, 1.0],
    );
    for k in 0..TRUSSES {
        let world_from_local = Mat4::from_translation(Vec3::new(truss_x(k), 0.0, 0.0));
        instances.push(
            Instance::new(format!("truss_{k}"), 1, &meshes[1], world_from_local)
                .with_color([0.30, 0.32, 0.36, 1.0]),
        );
    }
    for (k, z) in PURLIN_Z_M.into_iter().enumerate() {
        let y = top_chord_y(z) + CHORD_RADIUS_M + PURLIN_RADIUS_M;
        let world_from_local = Mat4::from_translation(Vec3::new(0.0, y, z));
        instances.push(
            Instance::new(format!("purlin_{k}"), 2, &meshes[2], world_from_local)
                .with_color([0.35, 0.30, 0.28, 1.0]),
        );
    }
    // Crates stand against the walls, leaving the middle 6 m free for the walk.
    for k in 0..CRATES {
        let size = Vec3::new(
            rng.range_f32(0.6, 1.6),
            rng.range_f32(0.5, 1.5),
            rng.range_f32(0.6, 1.6),
        );
        let side = if k % 2 == 0 { 1.0 } else { -1.0 };
        let x = rng.range_f32(-hx + 1.0, hx - 1.0);
        let z = side * (hz - 0.1 - size.z / 2.0);
        let world_from_local =
            Mat4::from_translation(Vec3::new(x, 0.0, z)) * Mat4::from_scale(size);
        let paint = CRATE_PAINT[rng.below(CRATE_PAINT.len())];
        instances.push(
            Instance::new(format!("crate_{k}"), 3, &meshes[3], world_from_local).with_color(paint),
        );
    }
    let mut scene = Scene::new(
        name,
        meshes,
        instances,
        Sun::from_azimuth_elevation_deg(30.0, 35.0),
    );
    scene.lights.push(PunctualLight {
        name: "truss_lamp".into(),
        position: LIGHT_POSITION_M,
        kind: LightKind::Point,
        color: [1.0, 0.92, 0.80],
        intensity: LIGHT_INTENSITY_CD,
        range: None,
    });
    scene
}

/// A walk down the corridor at eye height, looking along it, with a look up at the trusses
/// and the lamp among them, then back from the far end.
pub(super) fn corridor_walk() -> CameraPath {
    let at = |x: f32, z: f32| Vec3::new(x, 1.7, z);
    let keys = vec![
        PathKey {
            eye: at(-HALF_LENGTH_M + 2.0, -1.5),
            target: at(0.0, 0.0),
        },
        PathKey {
            eye: at(-20.0, -1.0),
            target: LIGHT_POSITION_M,
        },
        PathKey {
            eye: at(-4.0, 1.5),
            target: at(20.0, 0.0),
        },
        PathKey {
            eye: at(20.0, -2.0),
            target: at(HALF_LENGTH_M, 1.0),
        },
        PathKey {
            eye: at(HALF_LENGTH_M - 2.0, 0.0),
            target: Vec3::new(0.0, 4.0, 0.0),
        },
    ];
    CameraPath::new("corridor walk", keys).expect("five keys")
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::super::builtin::tests::assert_winding_matches_normals;
    use super::*;
    use crate::geom::Aabb;

    fn corridor() -> Scene {
        corridor_scene("builtin:corridor".into(), 7)
    }

    /// Whether the segment from `a` to `b` meets `aabb` (slab test).
    fn segment_hits(a: Vec3, b: Vec3, aabb: &Aabb) -> bool {
        let (mut t0, mut t1) = (0.0_f32, 1.0_f32);
        let d = b - a;
        for axis in 0..3 {
            let (lo, hi) = (aabb.min[axis], aabb.max[axis]);
            if d[axis].abs() < 1e-9 {
                if a[axis] < lo || a[axis] > hi {
                    return false;
                }
                continue;
            }
            let (s0, s1) = ((lo - a[axis]) / d[axis], (hi - a[axis]) / d[axis]);
            t0 = t0.max(s0.min(s1));
            t1 = t1.min(s0.max(s1));
        }
        t0 <= t1
    }

    /// Every directed edge, compared by position to 0.1 mm, appears once and its reverse once:
    /// the mesh is closed and consistently wound.
    fn assert_closed(mesh: &Mesh) {
        let key = |i: u32| {
            (mesh.positions[i as usize] * 1e4)
                .round()
                .as_ivec3()
                .to_array()
        };
        let mut edges: HashMap<_, u32> = HashMap::new();
        for tri in mesh.indices.chunks_exact(3) {
            for (a, b) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
                *edges.entry((key(a), key(b))).or_default() += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(
                count, 1,
                "{}: edge {a:?}-{b:?} used {count} times",
                mesh.name
            );
            assert_eq!(
                edges.get(&(b, a)),
                Some(&1),
                "{}: edge {a:?}-{b:?} open",
                mesh.name
            );
        }
    }

    #[test]
    fn the_corridor_has_about_lloyds_polygons_in_closed_outward_meshes() {
        let scene = corridor();
        let triangles = scene.triangle_count();
        assert!(
            (80_000..130_000).contains(&triangles),
            "{triangles} triangles"
        );
        let instances = scene.instances.len();
        assert!((40..=120).contains(&instances), "{instances} instances");
        assert_eq!(
            scene.instances.iter().filter(|i| i.mesh == 1).count(),
            TRUSSES as usize
        );
        for mesh in &scene.meshes {
            assert_winding_matches_normals(mesh);
            assert_closed(mesh);
        }
        let again = corridor();
        let last = instances - 1;
        assert_eq!(
            again.instances[last].world_from_local,
            scene.instances[last].world_from_local
        );
    }

    #[test]
    fn one_point_light_hangs_among_the_trusses_inside_the_corridor() {
        let scene = corridor();
        assert_eq!(scene.lights.len(), 1);
        let light = &scene.lights[0];
        assert_eq!(light.kind, LightKind::Point);
        let p = light.position;
        assert!(p.x.abs() < HALF_LENGTH_M && p.z.abs() < HALF_WIDTH_M, "{p}");
        assert!(p.y > 0.0 && p.y < WALL_HEIGHT_M, "{p}");
        // Inside no solid.
        for i in &scene.instances {
            assert!(
                !i.aabb_in_world.contains_point(p),
                "light inside {}",
                i.name
            );
        }
        let trusses: Vec<&Instance> = scene.instances.iter().filter(|i| i.mesh == 1).collect();
        // Above the bottom chords, below the ridge.
        let truss_box = trusses[0].aabb_in_world;
        assert!(p.y > BOTTOM_CHORD_Y_M + CHORD_RADIUS_M && p.y < truss_box.max.y);
        // Straight down it lights the floor between two trusses...
        let below = Vec3::new(p.x, 0.0, p.z);
        assert!(
            trusses
                .iter()
                .all(|i| !segment_hits(p, below, &i.aabb_in_world))
        );
        // ...but the floor 20 m along the corridor either way lies behind the lattice of the
        // neighbouring truss on that side, and only of that one: the next truss down the ray
        // is already below its bottom chord.
        for direction in [1.0, -1.0] {
            let far = Vec3::new(p.x + 20.0 * direction, 0.0, p.z);
            let crossed: Vec<f32> = trusses
                .iter()
                .filter(|i| segment_hits(p, far, &i.aabb_in_world))
                .map(|i| i.aabb_in_world.center().x)
                .collect();
            assert_eq!(crossed.len(), 1, "{crossed:?}");
            let gap = (crossed[0] - p.x) * direction;
            assert!(gap > 0.0 && gap < TRUSS_SPACING_M, "{crossed:?}");
        }
    }

    #[test]
    fn the_walk_stays_inside_the_corridor() {
        let scene = corridor();
        for key in corridor_walk().keys() {
            let e = key.eye;
            assert!(
                e.x.abs() < HALF_LENGTH_M && e.z.abs() < HALF_WIDTH_M,
                "{key:?}"
            );
            assert!(e.y > 0.0 && e.y < WALL_HEIGHT_M, "{key:?}");
            for i in &scene.instances {
                assert!(!i.aabb_in_world.contains_point(e), "{key:?} in {}", i.name);
            }
        }
    }
}
