//! Bittner et al. 2011, Figure 3, in 3D: a receiver partly hidden from the camera by a wall,
//! and four casters. A shadows the visible part; B shadows only the hidden part; C lies in B's
//! shadow from the light; D's shadow falls just outside the receiver, `gap` texels beyond its
//! box. "Object A is always rendered as it intersects all masks, object B is culled only by
//! the FRAG mask, C is culled by depth test (occluded by B) and by the FRAG and GEOM masks,
//! and finally D is culled by all types of masks." The footprint test (casters' boxes
//! rasterised against the map and the mask) gives exactly these answers; BVOL and GEOM widen
//! their masks by the filter's reach (PCF radius, normal offset, a texel), so they keep a D
//! that close. FRAG's mask holds the texels that the visible pixels' footprints read: it culls
//! B, and D once D's shadow lies beyond the footprint of the receiver's last pixels.

use glam::{Mat4, Vec3};
use render_core::frame::{CasterOutcome, FrameReport, Method};
use render_core::geom::Camera;
use render_core::scene::{Instance, Mesh, Scene, Sun};
use shadowlab_tests::{box_mesh, measured_frames};

const A: u32 = 1;
const B: u32 = 2;
const C: u32 = 3;
const D: u32 = 4;

/// The scene with D's shadow `gap_m` metres (across the light) beyond the receiver's box.
fn figure_3(gap_m: f32) -> (Scene, Camera) {
    // The light travels along (-1, -1, 0): shadows fall towards -x, 45 degrees down.
    // Across the light, x - y measures the receiver box's far edge at x - y = -20 (its top
    // corner at x = -20, y = 0); D (x - y from its own -1 to +1 around the centre) sits above
    // the receiver so the scene's bounds do not depend on the gap.
    let d_x = 3.0 - 20.0 - 1.0 - gap_m * std::f32::consts::SQRT_2;
    figure_3_of(glam::Quat::IDENTITY, Vec3::new(d_x, 3.0, -10.0))
}

/// Figure 3 under the sun (1, 1, 0) turned by `turn` about the vertical, with everything
/// but the receiver and D turned alike: the receiver (a box 40 m square) stays square to the
/// world, D stands at `d_at`.
fn figure_3_of(turn: glam::Quat, d_at: Vec3) -> (Scene, Camera) {
    let receiver = box_mesh("receiver", Vec3::new(20.0, 0.25, 20.0));
    let wall = box_mesh("wall", Vec3::new(25.0, 4.0, 0.5));
    let unit = box_mesh("caster", Vec3::splat(0.5));
    let small = box_mesh("small caster", Vec3::splat(0.25));
    let turned = |x, y, z| Mat4::from_rotation_translation(turn, turn * Vec3::new(x, y, z));
    let mut instances = vec![
        Instance::new(
            "receiver",
            0,
            &receiver,
            Mat4::from_translation(Vec3::new(0.0, -0.25, 0.0)),
        ),
        Instance::new("A", 2, &unit, turned(0.0, 2.0, -10.0)),
        Instance::new("B", 2, &unit, turned(0.0, 2.0, 12.0)),
        // In B's shadow: 1 m further along the light, well inside B's silhouette.
        Instance::new("C", 3, &small, turned(-0.7, 1.3, 12.0)),
        Instance::new("D", 2, &unit, Mat4::from_translation(d_at)),
        Instance::new("wall", 1, &wall, turned(0.0, 4.0, 4.5)),
    ];
    // Only the receiver receives; the wall only hides the receiver's far part from the camera.
    for inst in &mut instances[1..] {
        inst.receives_shadow = false;
    }
    instances[5].casts_shadow = false;
    let scene = Scene::new(
        "test:figure-3",
        vec![receiver, wall, unit, small],
        instances,
        Sun::from_direction(turn * Vec3::new(1.0, 1.0, 0.0)),
    );
    let camera = Camera::look_at(
        turn * Vec3::new(0.0, 6.0, -40.0),
        Vec3::ZERO,
        60f32.to_radians(),
        0.1,
        300.0,
    );
    (scene, camera)
}

/// The drawn casters after a few measured frames (every frame without error), and the
/// report of the last frame.
fn settled(scene: &Scene, camera: &Camera, method: Method) -> (FrameReport, Vec<u32>) {
    let (report, outcomes) = settled_outcomes(scene, camera, method);
    let drawn = (0..)
        .zip(&outcomes)
        .filter(|(_, o)| **o == CasterOutcome::Rendered)
        .map(|(i, _)| i)
        .collect();
    (report, drawn)
}

/// What happened to each instance in the last of a few measured frames without error.
fn settled_outcomes(
    scene: &Scene,
    camera: &Camera,
    method: Method,
) -> (FrameReport, Vec<CasterOutcome>) {
    let (renderer, _, reports) = measured_frames((scene, camera), (method, scene.sun), 3, |_| {});
    for (frame, report) in reports.iter().enumerate() {
        if !method.may_err() {
            assert_no_culling_error(report, method, frame);
        }
    }
    let report = reports.last().expect("three frames").clone();
    (report, renderer.caster_outcomes())
}

/// Frame `frame` of `method` differs nowhere from the reference maps of every caster.
fn assert_no_culling_error(report: &FrameReport, method: Method, frame: usize) {
    let e = report.error.expect("measured");
    assert_eq!(
        (e.missing_shadow_px, e.extra_shadow_px),
        (0, 0),
        "{} frame {frame}: no error",
        method.name()
    );
}

#[test]
fn each_method_culls_what_bittners_figure_3_says() {
    // The texel size across the light, from the fitted map (the gap does not change it).
    let (probe, camera) = figure_3(0.0);
    let (report, _) = settled(&probe, &camera, Method::None);
    let texel_m = report.light.texel_size_m[1];
    assert!(texel_m > 0.005 && texel_m < 0.05, "texel {texel_m} m");

    for gap_texels in [2.0, 8.0, 32.0] {
        let (scene, camera) = figure_3(gap_texels * texel_m);
        let drawn = |m: Method| settled(&scene, &camera, m).1;
        let oracle = drawn(Method::Oracle);
        assert!(oracle.contains(&A), "A shadows visible ground: {oracle:?}");
        for culled in [B, C] {
            assert!(!oracle.contains(&culled), "{culled}: {oracle:?}");
        }
        let within_reach = gap_texels < 5.0;
        let d_if = |kept: bool| if kept { vec![D] } else { vec![] };
        let expected: Vec<(Method, Vec<u32>)> = vec![
            (Method::None, vec![0, A, B, C, D]),
            (Method::Vfc, vec![0, A, B, C, D]),
            // Depth culls C (in B's shadow from the light).
            (Method::Ref, vec![0, A, B, D]),
            // FOCUS fits the light's frustum to the visible receiver, which leaves D out.
            (Method::Focus, vec![0, A, B]),
            // The masks cull D beyond their reach.
            (Method::Bvol, [vec![0, A, B], d_if(within_reach)].concat()),
            (Method::Geom, [vec![0, A, B], d_if(within_reach)].concat()),
            (
                Method::GeomBvol,
                [vec![0, A, B], d_if(within_reach)].concat(),
            ),
            // FRAG culls B too: its shadow falls where no visible pixel looks. Its mask holds
            // what each pixel's footprint reads (here about 0.2 m of the receiver, capped at 8
            // texels around the pixel's point): D 2 texels out lies within the footprint of
            // the receiver's last pixels, as a camera a pixel to the side would see it, and
            // 8 texels out beyond it.
            (Method::Frag, [vec![A], d_if(within_reach)].concat()),
        ];
        for (method, mut want) in expected {
            want.sort_unstable();
            assert_eq!(
                drawn(method),
                want,
                "{} with D's shadow {gap_texels} texels outside the receiver",
                method.name()
            );
        }
        if gap_texels >= 8.0 {
            assert!(!oracle.contains(&D), "D is out of every tap's reach");
        }
    }
}

#[test]
fn the_footprint_stage_says_what_it_culled() {
    let (scene, camera) = figure_3(0.5);
    let (report, drawn) = settled(&scene, &camera, Method::Ref);
    let names: Vec<&str> = report.stages.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "scene casters",
            "light frustum",
            "light occlusion",
            "footprint (texel-exact)"
        ]
    );
    let last = report.stages.last().map(|s| s.remaining);
    assert_eq!(
        last,
        Some(drawn.len() as u32),
        "the last stage is what is drawn"
    );
    assert!(!drawn.contains(&C), "C is hidden by B: {drawn:?}");
}

const CUBE: u32 = 1;
const DUMBBELL: u32 = 2;
const BLOCK: u32 = 2;

/// Two cubes 12 m apart as one mesh: its box spans the gap, its shadow does not.
fn dumbbell() -> Mesh {
    let cube = box_mesh("cube", Vec3::splat(0.5));
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for x in [-6.0, 6.0] {
        let base = positions.len() as u32;
        positions.extend(cube.positions.iter().map(|p| *p + Vec3::new(x, 0.0, 0.0)));
        indices.extend(cube.indices.iter().map(|i| base + i));
    }
    let normals = [cube.normals.clone(), cube.normals].concat();
    Mesh::new("dumbbell", positions, Some(normals), indices)
}

#[test]
fn frags_footprint_is_the_casters_geometry() {
    // A small receiving slab under the dumbbell's gap, a cube above it; the sun nearly overhead.
    let sun = Sun::from_direction(Vec3::new(0.2, 1.0, 0.1));
    let slab = box_mesh("slab", Vec3::new(1.0, 0.1, 1.0));
    let cube = box_mesh("cube", Vec3::splat(0.5));
    let bar = dumbbell();
    let at = |x, y, z| Mat4::from_translation(Vec3::new(x, y, z));
    let mut instances = vec![
        Instance::new("slab", 0, &slab, at(0.0, 0.0, 0.0)),
        Instance::new("cube", 1, &cube, at(0.0, 3.0, 0.0)),
        Instance::new("dumbbell", 2, &bar, at(0.0, 3.0, 0.0)),
    ];
    for inst in &mut instances[1..] {
        inst.receives_shadow = false;
    }
    let scene = Scene::new("test:dumbbell", vec![slab, cube, bar], instances, sun);
    let camera = Camera::look_at(
        Vec3::new(0.0, 8.0, -12.0),
        Vec3::ZERO,
        50f32.to_radians(),
        0.1,
        100.0,
    );
    let (_, oracle) = settled(&scene, &camera, Method::Oracle);
    assert!(
        oracle.contains(&CUBE) && !oracle.contains(&DUMBBELL),
        "{oracle:?}"
    );
    // REF, BVOL and GEOM test boxes, as Bittner's occlusion queries do: the dumbbell's spans
    // the slab. FRAG, whose mask leaves few candidates, tests their triangles.
    for method in [Method::Ref, Method::Bvol, Method::Geom, Method::GeomBvol] {
        let drawn = settled(&scene, &camera, method).1;
        assert!(drawn.contains(&DUMBBELL), "{}: {drawn:?}", method.name());
    }
    let (report, outcomes) = settled_outcomes(&scene, &camera, Method::Frag);
    let stage = match outcomes[DUMBBELL as usize] {
        CasterOutcome::Culled { stage } => report.stages[stage].name.clone(),
        other => panic!("frag: the dumbbell is {other:?}"),
    };
    assert_eq!(stage, "footprint (texel-exact)");
    assert_eq!(outcomes[CUBE as usize], CasterOutcome::Rendered);
}

#[test]
fn frag_leaves_a_visible_receiver_the_light_does_not_see_to_the_depth_test() {
    // A block standing on the ground under a wide roof: its shadow falls where the roof's
    // already is, so the oracle does without it. GEOM draws every visible receiver into the
    // map first (Bittner 4.2); FRAG, once it knows last frame's light-visible casters, tests
    // the others against the map, which culls the block.
    let sun = Sun::from_direction(Vec3::new(0.2, 1.0, 0.1));
    let ground = box_mesh("ground", Vec3::new(20.0, 0.5, 20.0));
    let roof = box_mesh("roof", Vec3::new(6.0, 0.2, 6.0));
    let block = box_mesh("block", Vec3::splat(0.5));
    let at = |x, y, z| Mat4::from_translation(Vec3::new(x, y, z));
    let mut instances = vec![
        Instance::new("ground", 0, &ground, at(0.0, -0.5, 0.0)),
        Instance::new("roof", 1, &roof, at(0.0, 8.0, 0.0)),
        Instance::new("block", 2, &block, at(0.0, 0.5, 0.0)),
    ];
    instances[1].receives_shadow = false;
    let scene = Scene::new("test:roof", vec![ground, roof, block], instances, sun);
    // Under the roof's edge, looking at the block and the shadowed ground around it.
    let camera = Camera::look_at(
        Vec3::new(0.0, 2.5, -14.0),
        Vec3::new(0.0, 0.5, 0.0),
        60f32.to_radians(),
        0.1,
        100.0,
    );
    let (_, oracle) = settled(&scene, &camera, Method::Oracle);
    assert!(
        !oracle.contains(&BLOCK),
        "the roof hides the block's shadow: {oracle:?}"
    );
    let (_, geom) = settled(&scene, &camera, Method::Geom);
    assert!(
        geom.contains(&BLOCK),
        "GEOM draws the visible receivers: {geom:?}"
    );
    let (_, frag) = settled(&scene, &camera, Method::Frag);
    assert_eq!(frag, oracle, "FRAG draws the oracle's casters");
}

/// Figure 3 with the sun turned `azimuth_deg` about the vertical, and everything but the
/// receiver turned with it (so A, B and C keep their parts), the receiver's box staying
/// square to the world: the light's axes are then turned against the box. D hangs where its
/// shadow falls `gap_m` (across the light) beyond the receiver's outline, past the middle
/// of the edge that the light, travelling from the middle of the receiver, leaves it by.
/// There the box's light-space rectangle reaches far past its outline once the box is
/// turned against the light.
fn figure_3_turned(azimuth_deg: f32, gap_m: f32) -> (Scene, Camera) {
    let turn = glam::Quat::from_rotation_y(azimuth_deg.to_radians());
    let sun = turn * Vec3::new(1.0, 1.0, 0.0).normalize();

    // The light's view: across it, `right` and `up` (the renderer's basis).
    let (right, up) = render_core::geom::basis_for_direction(-sun.as_dvec3());
    let (right, up) = (right.as_vec3(), up.as_vec3());
    let across = |p: Vec3| glam::Vec2::new(right.dot(p), up.dot(p));
    // Where the light's horizontal travel leaves the receiver's top (the square of side 40).
    let travel = turn * Vec3::NEG_X;
    let to_edge = |d: f32| {
        if d.abs() < 1e-6 {
            f32::INFINITY
        } else {
            20.0 / d.abs()
        }
    };
    let exit = travel * to_edge(travel.x).min(to_edge(travel.z));
    let along_edge = if (exit.x.abs() - 20.0).abs() < 1e-3 {
        Vec3::Z
    } else {
        Vec3::X
    };
    let edge = across(along_edge);
    let mut normal = glam::Vec2::new(edge.y, -edge.x).normalize();
    if normal.dot(across(exit)) < 0.0 {
        normal = -normal;
    }
    // The receiver's reach along the normal, and D's (a unit cube) back towards it.
    let receiver_reach = (0..8)
        .map(|k| {
            let corner = Vec3::new(
                if k & 1 == 0 { -20.0 } else { 20.0 },
                if k & 2 == 0 { -0.5 } else { 0.0 },
                if k & 4 == 0 { -20.0 } else { 20.0 },
            );
            normal.dot(across(corner))
        })
        .fold(f32::MIN, f32::max);
    let normal_3d = right * normal.x + up * normal.y;
    let d_reach = 0.5 * normal_3d.abs().element_sum();
    let centre =
        across(exit) + normal * (receiver_reach - normal.dot(across(exit)) + gap_m + d_reach);
    // D's centre: that point across the light, 3 m above the ground.
    let on_plane = right * centre.x + up * centre.y;
    let d_at = on_plane + sun * ((3.0 - on_plane.y) / sun.y);

    figure_3_of(turn, d_at)
}

/// The casters each method draws after its number of frames, one after the other on
/// `renderer` (every frame without culling error), and the texel size across the light.
fn drawn_in_turn(
    renderer: &mut render_core::frame::FrameRenderer,
    scene: &Scene,
    camera: &Camera,
    methods: &[(Method, usize)],
) -> (Vec<Vec<u32>>, f32) {
    let ctx = shadowlab_tests::gpu();
    let scene_gpu = render_core::frame::SceneGpu::new(ctx, scene);
    let mut texel_m = 0.0;
    let drawn = methods
        .iter()
        .map(|&(method, frames)| {
            let settings = render_core::frame::FrameSettings {
                sun: scene.sun,
                method,
                measure: true,
                ..render_core::frame::FrameSettings::default()
            };
            let input = render_core::frame::FrameInput {
                camera,
                width: 256,
                height: 192,
                settings: &settings,
            };
            for frame in 0..frames {
                let report = renderer
                    .render_and_wait(ctx, scene, &scene_gpu, &input)
                    .expect("frame");
                assert_no_culling_error(&report, method, frame);
                texel_m = report.light.texel_size_m[0].max(report.light.texel_size_m[1]);
            }
            (0..)
                .zip(renderer.caster_outcomes())
                .filter(|(_, o)| *o == CasterOutcome::Rendered)
                .map(|(i, _)| i)
                .collect()
        })
        .collect();
    (drawn, texel_m)
}

#[test]
fn bvol_marks_the_receivers_outline_not_its_light_space_rectangle() {
    // One renderer for every scene: building one takes seconds on a CPU adapter.
    let mut renderer = render_core::frame::FrameRenderer::new(shadowlab_tests::gpu());
    for azimuth_deg in [0.0, 30.0, 45.0, 60.0] {
        let (probe, camera) = figure_3_turned(azimuth_deg, 0.0);
        let (_, texel_m) = drawn_in_turn(&mut renderer, &probe, &camera, &[(Method::None, 1)]);
        assert!(texel_m > 0.005 && texel_m < 0.1, "texel {texel_m} m");
        for gap_texels in [8.0, 32.0] {
            let (scene, camera) = figure_3_turned(azimuth_deg, gap_texels * texel_m);
            let case = format!("sun turned {azimuth_deg}°, D's shadow {gap_texels} texels out");
            // Every caster is in the light's frustum; without error (checked every frame)
            // BVOL culls D, and so does GEOM+BVOL, which marks boxes too.
            let methods = [(Method::None, 1), (Method::Bvol, 3), (Method::GeomBvol, 3)];
            let (drawn, _) = drawn_in_turn(&mut renderer, &scene, &camera, &methods);
            assert_eq!(drawn[0], [0, A, B, C, D], "none, {case}");
            assert_eq!(drawn[1], [0, A, B], "bvol, {case}");
            assert_eq!(drawn[2], [0, A, B], "geom-bvol, {case}");
        }
    }
}
