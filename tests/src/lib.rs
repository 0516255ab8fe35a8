//! Helpers for shadowlab's headless GPU tests: a shared adapter, small known-answer scenes,
//! and world positions of captured pixels.

mod packed;
pub mod virtual_pages;

use std::sync::OnceLock;

use glam::{Mat4, Vec3, Vec4};
use render_core::frame::{
    FrameCapture, FrameInput, FrameRenderer, FrameReport, FrameSettings, Method, SceneGpu,
};
use render_core::geom::Camera;
use render_core::gpu::GpuContext;
use render_core::metrics::ShadowError;
use render_core::scene::{Instance, Mesh, Scene, Sun};
use render_core::truth::{SurfacePoint, TruthCache};

pub use packed::{glb_bytes, packed_glb, packed_gltf};

/// One GPU context for every test in a binary (device creation on lavapipe is slow).
/// In CI (`CI=true`) a missing adapter fails the test instead of being reported as skipped.
pub fn gpu() -> &'static GpuContext {
    static GPU: OnceLock<GpuContext> = OnceLock::new();
    GPU.get_or_init(|| match GpuContext::headless() {
        Ok(ctx) => {
            eprintln!("GPU tests run on {}", ctx.adapter_description());
            ctx
        }
        Err(e) => panic!("GPU tests need an adapter: {e}"),
    })
}

/// A scene of one instance per mesh, each moved by its offset and named after its mesh.
pub fn scene_of(name: &str, sun: Sun, parts: Vec<(Mesh, Vec3)>) -> Scene {
    let instances = (0..)
        .zip(&parts)
        .map(|(i, (mesh, at))| {
            Instance::new(mesh.name.clone(), i, mesh, Mat4::from_translation(*at))
        })
        .collect();
    let meshes = parts.into_iter().map(|(mesh, _)| mesh).collect();
    Scene::new(name, meshes, instances, sun)
}

/// A point or spot light of the tests' scenes: white, 2,000,000 cd, 40 m of range.
pub fn punctual_light(
    name: &str,
    position: Vec3,
    kind: render_core::scene::LightKind,
) -> render_core::scene::PunctualLight {
    render_core::scene::PunctualLight {
        name: name.into(),
        position,
        kind,
        color: [1.0, 1.0, 1.0],
        intensity: 2.0e6,
        range: Some(40.0),
    }
}

/// An axis-aligned box mesh with outward faces, counter-clockwise seen from outside.
pub fn box_mesh(name: &str, half_extent: Vec3) -> Mesh {
    let h = half_extent;
    let faces: [(Vec3, Vec3, Vec3); 6] = [
        (Vec3::X, Vec3::Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Y, Vec3::Z),
        (Vec3::Y, Vec3::Z, Vec3::X),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::Y, Vec3::X),
        (Vec3::NEG_Z, Vec3::X, Vec3::Y),
    ];
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut indices = Vec::new();
    for (n, a, b) in faces {
        // `a x b` points along `n` so the quad winds counter-clockwise seen from outside.
        let (a, b) = if a.cross(b).dot(n) > 0.0 {
            (a, b)
        } else {
            (b, a)
        };
        let base = positions.len() as u32;
        for (sa, sb) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            positions.push((n + a * sa + b * sb) * h);
            normals.push(n);
        }
        indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    Mesh::new(name, positions, Some(normals), indices)
}

/// A ground box of `ground_half_m` (top face at y = 0) and one box of `box_size` whose bottom
/// is `lift_m` above the ground (0: standing on it).
pub fn box_on_plane(ground_half_m: f32, box_size: Vec3, lift_m: f32, sun: Sun) -> Scene {
    let ground = box_mesh("ground", Vec3::new(ground_half_m, 0.5, ground_half_m));
    let cube = box_mesh("box", box_size * 0.5);
    let instances = vec![
        Instance::new(
            "ground",
            0,
            &ground,
            Mat4::from_translation(Vec3::new(0.0, -0.5, 0.0)),
        ),
        Instance::new(
            "box",
            1,
            &cube,
            Mat4::from_translation(Vec3::new(0.0, lift_m + box_size.y * 0.5, 0.0)),
        ),
    ];
    Scene::new("test:box-on-plane", vec![ground, cube], instances, sun)
}

/// `scene` with every instance moved by `offset` (hard cases far from the origin).
pub fn translated(scene: &Scene, offset: Vec3) -> Scene {
    let mut instances = scene.instances.clone();
    for inst in &mut instances {
        inst.world_from_local = Mat4::from_translation(offset) * inst.world_from_local;
        inst.aabb_in_world = scene.meshes[inst.mesh as usize]
            .aabb_in_local
            .transformed(&inst.world_from_local);
    }
    Scene::new("test:far-away", scene.meshes.clone(), instances, scene.sun)
}

/// Where the point-light tests put their light: beside and above the box of
/// [`box_on_plane`]`(20.0, (2, 3, 1.5), 1.0)` (1 m above the ground at the origin).
pub const LIGHT_BESIDE_THE_BOX: Vec3 = Vec3::new(3.0, 6.0, 0.5);

/// Above and beside that box, [`LIGHT_BESIDE_THE_BOX`] in the picture.
pub fn overlooking_the_box() -> Camera {
    Camera::look_at(
        Vec3::new(-10.0, 7.0, 10.0),
        Vec3::new(0.0, 2.0, 0.0),
        60f32.to_radians(),
        0.1,
        200.0,
    )
}

/// A point of the ground (y 0, facing up) at `x`, `z`.
pub fn ground_point(x: f32, z: f32) -> SurfacePoint {
    SurfacePoint {
        position: [x, 0.0, z, 1.0],
        normal: [0.0, 1.0, 0.0, 0.0],
    }
}

/// Street level in city-small, looking east down a street: the view the culling tests share.
pub fn city_small_street_camera() -> Camera {
    Camera::look_at(
        Vec3::new(-40.0, 3.5, 2.0),
        Vec3::new(60.0, 8.0, 2.0),
        60f32.to_radians(),
        0.1,
        2000.0,
    )
}

/// The caster taller than 8 m with the largest box: the biggest building of a city.
pub fn biggest_building(scene: &Scene) -> Option<&Instance> {
    let volume = |i: &Instance| {
        let s = i.aabb_in_world.max - i.aabb_in_world.min;
        s.x * s.y * s.z
    };
    scene
        .instances
        .iter()
        .filter(|i| i.casts_shadow && i.aabb_in_world.max.y - i.aabb_in_world.min.y > 8.0)
        .max_by(|a, b| volume(a).total_cmp(&volume(b)))
}

/// `frames` measured frames of `method` under `sun` at 256x192, by a renderer that `setup`
/// prepares first: the renderer and the scene's buffers (for what the tests read afterwards)
/// and every frame's report.
pub fn measured_frames(
    (scene, camera): (&Scene, &Camera),
    (method, sun): (Method, Sun),
    frames: usize,
    setup: impl FnOnce(&mut FrameRenderer),
) -> (FrameRenderer, SceneGpu, Vec<FrameReport>) {
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, scene);
    let mut renderer = FrameRenderer::new(ctx);
    setup(&mut renderer);
    let settings = FrameSettings {
        sun,
        method,
        measure: true,
        ..FrameSettings::default()
    };
    let input = FrameInput {
        camera,
        width: 256,
        height: 192,
        settings: &settings,
    };
    let reports = (0..frames)
        .map(|_| {
            renderer
                .render_and_wait(ctx, scene, &scene_gpu, &input)
                .expect("frame")
        })
        .collect();
    (renderer, scene_gpu, reports)
}

/// `frames` frames of `input` by `renderer` (one that settles on its visible set), the last
/// one's report.
pub fn last_of_frames(
    renderer: &mut FrameRenderer,
    (scene, scene_gpu): (&Scene, &SceneGpu),
    input: &FrameInput<'_>,
    frames: usize,
) -> FrameReport {
    let ctx = gpu();
    let mut report = None;
    for _ in 0..frames.max(1) {
        report = Some(
            renderer
                .render_and_wait(ctx, scene, scene_gpu, input)
                .expect("frame"),
        );
    }
    report.expect("at least one frame")
}

/// Renders one frame headless and reads every target back.
pub fn render(
    scene: &Scene,
    camera: &Camera,
    settings: &FrameSettings,
    width: u32,
    height: u32,
) -> (FrameReport, FrameCapture) {
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, scene);
    let mut renderer = FrameRenderer::new(ctx);
    let input = FrameInput {
        camera,
        width,
        height,
        settings,
    };
    let report = renderer
        .render_and_wait(ctx, scene, &scene_gpu, &input)
        .expect("frame renders");
    let capture = FrameCapture::read(
        ctx,
        renderer.targets().expect("targets exist after a frame"),
    )
    .expect("readback");
    (report, capture)
}

/// One frame of `settings` at `size`, its error against the exact shadow of the frame's light
/// (the sun or its point light), how many exact points are shadowed, the renderer (to read
/// the light at points) and its report.
pub fn against_truth(
    scene: &Scene,
    camera: &Camera,
    settings: &FrameSettings,
    (width, height): (u32, u32),
) -> (ShadowError, u32, FrameRenderer, FrameReport) {
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, scene);
    let mut renderer = FrameRenderer::new(ctx);
    let input = FrameInput {
        camera,
        width,
        height,
        settings,
    };
    let report = renderer
        .render_and_wait(ctx, scene, &scene_gpu, &input)
        .expect("frame renders");
    let mut truth = TruthCache::default();
    let (exact, rays) =
        truth.exact_and_rays(scene, camera, (width, height), settings.shadow_light());
    let shadowed = (0..exact.points.len())
        .filter(|&i| exact.shadowed(i))
        .count() as u32;
    let error = renderer.exact_error(ctx, (exact, rays)).expect("read back");
    (error, shadowed, renderer, report)
}

/// World position of pixel `(x, y)` from the captured reversed depth, or `None` for sky.
pub fn world_position(capture: &FrameCapture, camera: &Camera, x: u32, y: u32) -> Option<Vec3> {
    let i = (y * capture.width + x) as usize;
    let depth = capture.depth[i];
    if depth <= 0.0 {
        return None;
    }
    let aspect = capture.width as f32 / capture.height as f32;
    let ndc = Vec4::new(
        (x as f32 + 0.5) / capture.width as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / capture.height as f32 * 2.0,
        depth,
        1.0,
    );
    let world = camera.clip_from_world(aspect).inverse() * ndc;
    Some(world.truncate() / world.w)
}

/// Whether the ray from `p` towards the sun hits the axis-aligned box `[min, max]` (slab test).
pub fn ray_hits_box(p: Vec3, direction_to_sun: Vec3, min: Vec3, max: Vec3) -> bool {
    let inv = direction_to_sun.recip();
    let t0 = (min - p) * inv;
    let t1 = (max - p) * inv;
    let t_near = t0.min(t1).max_element();
    let t_far = t0.max(t1).min_element();
    t_far >= t_near.max(0.0)
}

/// Whether ground point `p` is in the shadow of the box `[min, max]`, or `None` when it lies in
/// the band where the answer changes if the box grows or shrinks by `margin_m` (the PCF border).
pub fn expected_shadow(
    p: Vec3,
    direction_to_sun: Vec3,
    min: Vec3,
    max: Vec3,
    margin_m: f32,
) -> Option<bool> {
    let origin = p + Vec3::Y * 1e-3;
    let margin = Vec3::splat(margin_m);
    let grown = ray_hits_box(origin, direction_to_sun, min - margin, max + margin);
    let shrunk = ray_hits_box(origin, direction_to_sun, min + margin, max - margin);
    (grown == shrunk).then_some(grown)
}

/// The pixels that show object `id` (instance index + 1), as `(pixel index, world position)`.
pub fn pixels_of<'a>(
    capture: &'a FrameCapture,
    camera: &'a Camera,
    id: u32,
) -> impl Iterator<Item = (usize, Vec3)> + 'a {
    (0..capture.height)
        .flat_map(move |y| (0..capture.width).map(move |x| (x, y)))
        .filter_map(move |(x, y)| {
            let i = (y * capture.width + x) as usize;
            if capture.ids[i] == id {
                world_position(capture, camera, x, y).map(|p| (i, p))
            } else {
                None
            }
        })
}
