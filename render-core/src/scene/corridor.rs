//! `corridor`: a long walled corridor under dense roof trusses, lit by a point light hung among
//! the trusses and by a low sun through the open roof, like the "trusses" scene of Lloyd et
//! al.'s CC shadow volumes (about 100K polygons). Every truss is a lattice of thin struts,
//! each strut an object (one mesh, placed 3,840 times), so their shadow volumes are long, thin
//! and mostly cross empty air before they reach the floor or a wall: the case where culling
//! and clamping shadow volumes pays. Deterministic from the seed:
//! only the crates along the walls (where, how big, what colour).

use glam::{Mat4, Quat, Vec3};

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
const STRUT_SIDES: u32 = 8;
const CRATES: u32 = 12;

/// The point light: hung over the open roof of the west third of the corridor, above every
/// truss and between two trusses and two purlins, so every strut's shadow volume runs down
/// through the empty air under the trusses to the floor and the walls (Lloyd's "trusses
/// overhead which cast shadows on the floor and walls below").
const LIGHT_POSITION_M: Vec3 = Vec3::new(-14.0, 9.0, 1.0);
/// A point light gives `intensity / distance²` lux: this one matches the sun
/// ([`Sun::ILLUMINANCE_LX`]) on a floor point `LIGHT_REFERENCE_DISTANCE_M` away (225 000 lx
/// at 5 m, 56 000 lx at 10 m).
const LIGHT_REFERENCE_DISTANCE_M: f32 = 7.5;
const LIGHT_INTENSITY_CD: f32 =
    Sun::ILLUMINANCE_LX * LIGHT_REFERENCE_DISTANCE_M * LIGHT_REFERENCE_DISTANCE_M;

const TRUSS_PAINT: [f32; 4] = [0.30, 0.32, 0.36, 1.0];
const PURLIN_PAINT: [f32; 4] = [0.35, 0.30, 0.28, 1.0];
const CRATE_PAINT: [[f32; 4]; 3] = [
    [0.55, 0.40, 0.22, 1.0],
    [0.45, 0.47, 0.40, 1.0],
    [0.62, 0.30, 0.18, 1.0],
];

/// The top chord's axis height at `z`: a pitched roof from the heels up to the ridge.
fn top_chord_y(z: f32) -> f32 {
    HEEL_Y_M + (RIDGE_Y_M - HEEL_Y_M) * (1.0 - z.abs() / HALF_WIDTH_M)
}

/// A strut: the unit strut mesh (a prism of radius 1 along +y from 0 to 1) placed from `from`
/// to `to` with `radius`.
fn strut_from_unit(from: Vec3, to: Vec3, radius: f32) -> Mat4 {
    let axis = to - from;
    Mat4::from_translation(from)
        * Mat4::from_quat(Quat::from_rotation_arc(Vec3::Y, axis.normalize()))
        * Mat4::from_scale(Vec3::new(radius, axis.length(), radius))
}

/// The unit strut: a closed prism of radius 1 along +y from 0 to 1.
fn unit_strut() -> Mesh {
    let mut b = MeshBuilder::default();
    b.cylinder(Vec3::ZERO, Vec3::Y, 1.0, STRUT_SIDES);
    b.build("strut")
}

/// One pitched roof truss in the plane x = 0 spanning the corridor, as its struts (name,
/// ends, radius): a bottom chord and two top chords meeting at the ridge, each a strut per
/// panel, a vertical at every node and crossed diagonals in every panel. Each strut is an
/// object of its own, as the trusses of Lloyd et al.'s corridor are many objects: a volume
/// is culled and clamped by what lies under its own strut.
fn truss_struts() -> Vec<(String, Vec3, Vec3, f32)> {
    let w = HALF_WIDTH_M;
    let bottom = |z: f32| Vec3::new(0.0, BOTTOM_CHORD_Y_M, z);
    let top = |z: f32| Vec3::new(0.0, top_chord_y(z), z);
    let node_z = |k: u32| -w + 2.0 * w * k as f32 / PANELS as f32;
    let mut struts = Vec::new();
    for k in 0..=PANELS {
        let z = node_z(k);
        struts.push((
            format!("vertical_{k}"),
            bottom(z),
            top(z),
            VERTICAL_RADIUS_M,
        ));
    }
    for k in 0..PANELS {
        let (z0, z1) = (node_z(k), node_z(k + 1));
        struts.push((
            format!("bottom_{k}"),
            bottom(z0),
            bottom(z1),
            CHORD_RADIUS_M,
        ));
        struts.push((format!("top_{k}"), top(z0), top(z1), CHORD_RADIUS_M));
        struts.push((
            format!("rising_{k}"),
            bottom(z0),
            top(z1),
            DIAGONAL_RADIUS_M,
        ));
        struts.push((
            format!("falling_{k}"),
            bottom(z1),
            top(z0),
            DIAGONAL_RADIUS_M,
        ));
    }
    struts
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
        unit_strut(),
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
    let strut = |name: String, from: Vec3, to: Vec3, radius: f32, color: [f32; 4]| {
        Instance::new(name, 1, &meshes[1], strut_from_unit(from, to, radius)).with_color(color)
    };
    let mut struts = Vec::new();
    for k in 0..TRUSSES {
        let at = Vec3::X * truss_x(k);
        for (part, from, to, radius) in truss_struts() {
            let name = format!("truss_{k}_{part}");
            struts.push(strut(name, at + from, at + to, radius, TRUSS_PAINT));
        }
    }
    // Purlins run along the corridor on top of the top chords, a strut per bay.
    for (k, z) in PURLIN_Z_M.into_iter().enumerate() {
        let y = top_chord_y(z) + CHORD_RADIUS_M + PURLIN_RADIUS_M;
        for bay in 0..TRUSSES {
            let x0 = -hx + TRUSS_SPACING_M * bay as f32;
            let (from, to) = (Vec3::new(x0, y, z), Vec3::new(x0 + TRUSS_SPACING_M, y, z));
            let name = format!("purlin_{k}_{bay}");
            struts.push(strut(name, from, to, PURLIN_RADIUS_M, PURLIN_PAINT));
        }
    }
    instances.extend(struts);
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
            Instance::new(format!("crate_{k}"), 2, &meshes[2], world_from_local).with_color(paint),
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
/// and the lamp over them, then back from the far end.
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

    /// Each truss's box: the union of its struts'.
    fn truss_boxes(scene: &Scene) -> Vec<Aabb> {
        (0..TRUSSES)
            .map(|k| {
                let prefix = format!("truss_{k}_");
                scene
                    .instances
                    .iter()
                    .filter(|i| i.name.starts_with(&prefix))
                    .map(|i| i.aabb_in_world)
                    .reduce(Aabb::union)
                    .expect("a truss has struts")
            })
            .collect()
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
        let struts = scene.instances.iter().filter(|i| i.mesh == 1).count();
        let per_truss = truss_struts().len();
        assert_eq!(per_truss, 5 * PANELS as usize + 1);
        assert_eq!(
            struts,
            TRUSSES as usize * (per_truss + PURLIN_Z_M.len()),
            "every strut an object"
        );
        assert_eq!(instances, 1 + 4 + struts + CRATES as usize);
        // Each strut joins its truss's neighbours: its ends are nodes of the truss.
        for i in scene.instances.iter().filter(|i| i.mesh == 1) {
            let size = i.aabb_in_world.max - i.aabb_in_world.min;
            assert!(
                size.max_element() <= TRUSS_SPACING_M + 2.0 * PURLIN_RADIUS_M + 1e-3,
                "{}: {size}",
                i.name
            );
        }
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
    fn one_point_light_hangs_over_the_trusses_above_the_corridor() {
        let scene = corridor();
        assert_eq!(scene.lights.len(), 1);
        let light = &scene.lights[0];
        assert_eq!(light.kind, LightKind::Point);
        let p = light.position;
        assert!(p.x.abs() < HALF_LENGTH_M && p.z.abs() < HALF_WIDTH_M, "{p}");
        // Above every strut and wall, inside no solid.
        for i in &scene.instances {
            assert!(i.aabb_in_world.max.y < p.y, "light below {}", i.name);
        }
        let trusses = truss_boxes(&scene);
        let struts: Vec<Aabb> = scene
            .instances
            .iter()
            .filter(|i| i.mesh == 1)
            .map(|i| i.aabb_in_world)
            .collect();
        // Straight down it lights the floor between two trusses and two purlins...
        let below = Vec3::new(p.x, 0.0, p.z);
        assert!(struts.iter().all(|b| !segment_hits(p, below, b)));
        // ...but the floor 10 m along the corridor either way lies behind the lattice of a
        // truss on that side.
        for direction in [1.0, -1.0] {
            let far = Vec3::new(p.x + 10.0 * direction, 0.0, p.z);
            let crossed = trusses.iter().filter(|b| segment_hits(p, far, b)).count();
            assert!(crossed >= 1, "{direction}: {crossed} trusses");
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
