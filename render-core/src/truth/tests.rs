//! The exact shadow's known answers on the CPU: lit faces near a coordinate plane seen from
//! afar, and the edge rule (which never asks which object a pixel shows).

use glam::{Mat4, Vec3};

use super::{ExactShadow, PixelTruth, SceneRays, ViewKey};
use crate::geom::Camera;
use crate::scene::{
    ChunkSettings, Instance, Mesh, Scene, ShadowLight, Sun, closed_box, split_large_instances,
};

/// A scene of closed boxes, `(min, max)` each, every one an instance moved by `offset`.
fn boxes(name: &str, parts: &[(Vec3, Vec3)], offset: Vec3) -> Scene {
    let meshes: Vec<Mesh> = (0..)
        .zip(parts)
        .map(|(i, &(min, max))| closed_box(&format!("part{i}"), min, max))
        .collect();
    let instances = (0..)
        .zip(&meshes)
        .map(|(i, mesh)| Instance::new(mesh.name.clone(), i, mesh, Mat4::from_translation(offset)))
        .collect();
    Scene::new(name, meshes, instances, Sun::default())
}

fn cast(scene: &Scene, camera: Camera, size: (u32, u32), light: ShadowLight) -> ExactShadow {
    let rays = SceneRays::new(scene);
    let key = ViewKey {
        camera,
        width: size.0,
        height: size.1,
        light,
        poses: rays.version,
    };
    ExactShadow::cast(&rays, key)
}

/// Issue 47's wall, turned so its lit face is the plane `axis` = `face_at` (x, y or z), a box
/// 0.3 m thick behind it and 8 m wide, on a ground slab under it (below it for y), the whole
/// moved by `offset`; seen from `distance` m off the face, with the sun before it. Every
/// pixel showing the face must be lit: nothing stands between it and the sun. Returns the
/// face's pixels.
fn face_pixels_all_lit(axis: usize, face_at: f32, distance: f32, offset: Vec3) -> u32 {
    // The face's own frame: `a` across it, `u` and `v` along it.
    let a = Vec3::AXES[axis];
    let (u, v) = (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
    let wall = (
        a * (face_at - 0.3) - (u + v) * 4.0,
        a * face_at + (u + v) * 4.0,
    );
    // The ground lies behind the face: it cannot shadow it.
    let ground = (
        a * (face_at - 2.1) - (u + v) * 10.0,
        a * (face_at - 2.0) + (u + v) * 10.0,
    );
    let scene = boxes("test:wall", &[ground, wall], offset);
    let centre = offset + a * face_at;
    let towards_eye = (a + u * 0.05 + v * 0.08).normalize();
    let fov = 2.0 * (5.0 / distance).atan();
    let camera = Camera::look_at(centre + towards_eye * distance, centre, fov, 0.05, 500.0);
    let up = if axis == 1 { Vec3::Z } else { Vec3::Y };
    let camera = camera.with_up(up);
    let sun = (a * 0.8 + u * 0.5 + v * 0.3).normalize();
    let exact = cast(&scene, camera, (320, 180), ShadowLight::Sun(sun));
    let mut face = 0;
    for (i, point) in exact.points.iter().enumerate() {
        let p = Vec3::from_slice(&point.position[..3]) - offset;
        let n = Vec3::from_slice(&point.normal[..3]);
        if (p[axis] - face_at).abs() > 1e-3 || n.dot(a) < 0.99 {
            continue;
        }
        face += 1;
        let pixel = exact.point_pixels[i];
        assert_eq!(
            exact.pixels[pixel as usize],
            PixelTruth::Lit,
            "the face at {face_at} m along axis {axis} seen from {distance} m (scene moved by \
             {offset}): pixel {pixel} at {p} is shadowed"
        );
    }
    face
}

#[test]
fn a_face_near_a_coordinate_plane_is_lit_from_near_and_far() {
    for axis in 0..3 {
        for face_at in [0.003, 0.02, 0.14, 0.6, -0.07] {
            for distance in [10.0, 60.0, 150.0] {
                let face = face_pixels_all_lit(axis, face_at, distance, Vec3::ZERO);
                assert!(face > 10_000, "the face fills the view: {face} pixels");
            }
        }
    }
}

#[test]
fn a_face_far_from_the_origin_is_lit() {
    for offset in [
        Vec3::new(100_000.0, 0.0, 100_000.0),
        Vec3::new(-3_000.0, 250.0, 7_000.0),
    ] {
        for axis in 0..3 {
            for distance in [10.0, 60.0, 150.0] {
                let face = face_pixels_all_lit(axis, 0.14, distance, offset);
                assert!(face > 10_000, "the face fills the view: {face} pixels");
            }
        }
    }
}

/// A ground of 20 x 20 quads and three boxes on it, under a low sun: shadows, outlines
/// against the ground and against the sky.
fn yard() -> Scene {
    let quads = 20;
    let mut positions = Vec::new();
    for j in 0..=quads {
        for i in 0..=quads {
            positions.push(Vec3::new(i as f32 - 10.0, 0.0, j as f32 - 10.0));
        }
    }
    let mut indices = Vec::new();
    for j in 0..quads {
        for i in 0..quads {
            let a = j * (quads + 1) + i;
            let (b, c, d) = (a + 1, a + quads + 1, a + quads + 2);
            indices.extend([a, c, b, b, c, d]);
        }
    }
    let ground = Mesh::new("ground", positions, None, indices);
    let mut meshes = vec![ground];
    let mut instances = vec![Instance::new("ground", 0, &meshes[0], Mat4::IDENTITY)];
    for (k, (min, max)) in [
        (Vec3::new(-3.0, 0.0, -2.0), Vec3::new(-1.0, 3.0, 0.0)),
        (Vec3::new(2.0, 0.0, 1.0), Vec3::new(3.0, 1.5, 4.0)),
        (Vec3::new(-1.0, 0.0, 3.0), Vec3::new(1.5, 0.7, 3.5)),
    ]
    .into_iter()
    .enumerate()
    {
        meshes.push(closed_box(&format!("box{k}"), min, max));
        let mesh = meshes.len() as u32 - 1;
        instances.push(Instance::new(
            format!("box{k}"),
            mesh,
            &meshes[mesh as usize],
            Mat4::IDENTITY,
        ));
    }
    Scene::new("test:yard", meshes, instances, Sun::default())
}

#[test]
fn a_mesh_cut_into_chunks_has_the_same_edges_as_the_whole_mesh() {
    let whole = yard();
    let mut meshes = whole.meshes.clone();
    let instances = split_large_instances(
        &mut meshes,
        whole.instances.clone(),
        &ChunkSettings {
            max_extent_fraction: 0.2,
        },
    );
    assert!(
        instances.len() > 10,
        "the ground is cut: {} objects",
        instances.len()
    );
    let chunked = Scene::new("test:yard-chunked", meshes, instances, whole.sun);
    let camera = Camera::look_at(
        Vec3::new(-9.0, 6.0, 11.0),
        Vec3::new(0.5, 0.0, 0.0),
        60f32.to_radians(),
        0.1,
        100.0,
    );
    let sun = ShadowLight::Sun(Vec3::new(0.6, 0.5, -0.4).normalize());
    let a = cast(&whole, camera, (240, 160), sun);
    let b = cast(&chunked, camera, (240, 160), sun);
    assert_eq!(a.pixels, b.pixels, "the same truth");
    let edges = a.on_edge.iter().filter(|&&e| e).count();
    assert!(
        edges > 1_000 && edges < a.points.len() / 4,
        "{edges} of {} pixels on edges",
        a.points.len()
    );
    let differ: Vec<u32> = (0..a.points.len())
        .filter(|&i| a.on_edge[i] != b.on_edge[i])
        .map(|i| a.point_pixels[i])
        .collect();
    assert!(
        differ.is_empty(),
        "pixels on an edge in one only: {differ:?}"
    );
}

#[test]
fn edges_are_the_shadows_outlines_and_the_depth_jumps_only() {
    // One box on the ground before a far wall, the camera below its top: its top edge
    // against the wall jumps in depth, its foot on the ground does not.
    let scene = boxes(
        "test:box",
        &[
            (Vec3::new(-30.0, -0.1, -30.0), Vec3::new(30.0, 0.0, 30.0)),
            (Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0)),
            (Vec3::new(-30.0, 0.0, -12.0), Vec3::new(30.0, 10.0, -11.0)),
        ],
        Vec3::ZERO,
    );
    let camera = Camera::look_at(
        Vec3::new(0.3, 1.5, 8.0),
        Vec3::new(0.0, 1.0, 0.0),
        50f32.to_radians(),
        0.1,
        100.0,
    );
    // The sun behind the camera: the box's shadow falls behind it, out of sight.
    let exact = cast(
        &scene,
        camera,
        (200, 150),
        ShadowLight::Sun(Vec3::new(0.1, 1.0, 1.2).normalize()),
    );
    let (mut foot, mut outline) = (0, 0);
    for i in 0..exact.points.len() {
        let p = Vec3::from_slice(&exact.points[i].position[..3]);
        let on_front = (p.z - 1.0).abs() < 1e-4 && p.x.abs() < 0.9;
        // The front face's foot: the ground meets it in a crease, no jump.
        if on_front && p.y < 0.05 {
            foot += 1;
            assert!(!exact.on_edge[i], "the box's foot at {p} is not an edge");
        }
        // The front face's top edge, against the ground far behind: a jump.
        if on_front && p.y > 1.97 {
            outline += 1;
            assert!(exact.on_edge[i], "the box's outline at {p} is an edge");
        }
    }
    assert!(
        foot > 20 && outline > 20,
        "{foot} foot and {outline} outline pixels"
    );
}
