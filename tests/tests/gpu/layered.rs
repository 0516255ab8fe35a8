//! Many lights (`--shadow lights`, `layered/`): spot and point lights around a lifted box, their
//! maps rendered by each path (a pass per map, multiview groups, an instanced atlas) must be
//! the same maps; the shadows they cast are the ones the geometry says; a light whose views
//! see nothing and a light inside the box behave.

use glam::{Vec3, Vec3Swizzles};
use render_core::frame::{
    FrameInput, FrameRenderer, FrameReport, FrameSettings, Method, ShadowSetup,
};
use render_core::geom::Camera;
use render_core::gpu::read_texture_layer;
use render_core::layered::multiview_reaches_every_layer;
use render_core::scene::{LightKind, PunctualLight, Scene, Sun};
use render_core::scene_gpu::SceneGpu;
use render_core::shadow_view::{LayerCulling, LayeredPath, ShadowView};
use shadowlab_tests::{box_on_plane, gpu, pixels_of, punctual_light as light, render};

const SIZE: (u32, u32) = (256, 192);
const MAP: u32 = 256;
/// The lifted box: 2 x 3 x 1.5 m, its bottom 1 m above the ground, centred on the origin.
const BOX_MIN: Vec3 = Vec3::new(-1.0, 1.0, -0.75);
const BOX_MAX: Vec3 = Vec3::new(1.0, 4.0, 0.75);

fn spot(direction: Vec3, outer_deg: f32) -> LightKind {
    LightKind::Spot {
        direction: direction.normalize(),
        inner_cone_rad: (0.8 * outer_deg).to_radians(),
        outer_cone_rad: outer_deg.to_radians(),
    }
}

/// The lifted box on a 40 m ground with `lights`.
fn scene(lights: Vec<PunctualLight>) -> Scene {
    let mut scene = box_on_plane(20.0, BOX_MAX - BOX_MIN, 1.0, Sun::default());
    scene.lights = lights;
    scene
}

/// A spot straight above the box, a point light beside it, a spot that looks at the sky
/// (its view sees nothing) and a second point light.
fn four_lights() -> Vec<PunctualLight> {
    vec![
        light("above", Vec3::new(0.0, 10.0, 0.0), spot(Vec3::NEG_Y, 40.0)),
        light("beside", Vec3::new(4.0, 5.0, 1.0), LightKind::Point),
        light("sky", Vec3::new(-6.0, 3.0, 6.0), spot(Vec3::Y, 30.0)),
        light("far", Vec3::new(-5.0, 6.0, -4.0), LightKind::Point),
    ]
}

fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(-9.0, 9.0, 11.0),
        Vec3::new(0.0, 1.0, 0.0),
        60f32.to_radians(),
        0.1,
        200.0,
    )
}

fn with_culling(path: LayeredPath, culling: LayerCulling) -> FrameSettings {
    let mut settings = lights(path);
    settings.layered.culling = culling;
    settings
}

fn lights(path: LayeredPath) -> FrameSettings {
    let mut settings = FrameSettings {
        setup: ShadowSetup::Lights,
        method: Method::Vfc,
        ..FrameSettings::default()
    };
    settings.shadow.resolution = MAP;
    settings.layered.path = path;
    settings
}

/// One frame: the report, every view's map (its square, row by row), the picture's light per
/// pixel, and the triangles each slot kept (where culling ran).
fn frame(
    scene: &Scene,
    settings: &FrameSettings,
) -> (FrameReport, Vec<Vec<f32>>, Vec<u8>, Vec<u32>) {
    let ctx = gpu();
    let scene_gpu = SceneGpu::new(ctx, scene);
    let mut renderer = FrameRenderer::new(ctx);
    let camera = camera();
    let input = FrameInput {
        camera: &camera,
        width: SIZE.0,
        height: SIZE.1,
        settings,
    };
    let report = renderer
        .render_and_wait(ctx, scene, &scene_gpu, &input)
        .expect("frame renders");
    let views = renderer.last_views().to_vec();
    let texture = if settings.setup == ShadowSetup::Lights {
        renderer
            .lights_depth_texture()
            .expect("the frame drew the lights' maps")
    } else {
        renderer.shadow_depth_texture()
    };
    let maps = views.iter().map(|v| view_map(texture, v)).collect();
    let capture =
        render_core::frame::FrameCapture::read(ctx, renderer.targets().unwrap()).expect("readback");
    let kept = if settings.layered.culling == LayerCulling::None {
        Vec::new()
    } else {
        renderer.lights_kept_triangles(ctx).expect("reads back")
    };
    (report, maps, capture.shadow, kept)
}

/// View `view`'s square of the depth array.
fn view_map(texture: &wgpu::Texture, view: &ShadowView) -> Vec<f32> {
    let t = view.target;
    let layer = read_texture_layer(gpu(), texture, wgpu::TextureAspect::DepthOnly, t.layer)
        .expect("reads back");
    let depths: Vec<f32> = layer
        .bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    (0..t.size)
        .flat_map(|y| (0..t.size).map(move |x| (x, y)))
        .map(|(x, y)| depths[((t.origin[1] + y) * layer.width + t.origin[0] + x) as usize])
        .collect()
}

#[test]
fn every_path_and_culling_renders_the_same_maps_and_shadows_as_a_pass_per_map() {
    let scene = scene(four_lights());
    let unculled = with_culling(LayeredPath::Traditional, LayerCulling::None);
    let (report, traditional, light, _) = frame(&scene, &unculled);
    // A spot is one view, a point light six: 14 maps, a pass each.
    assert_eq!(traditional.len(), 14);
    let facts = report.layered.expect("the technique reports its path");
    assert_eq!(
        (facts.path, facts.maps, facts.passes),
        (LayeredPath::Traditional, 14, 14)
    );
    // The spot that looks at the sky sees nothing: its map is clear, and vfc drew nothing.
    assert!(traditional[7].iter().all(|&d| d >= 1.0));
    assert_eq!(report.views[7].name, "spot 2");
    assert_eq!(report.views[7].casters_rendered, 0);
    for culling in LayerCulling::ALL {
        for path in LayeredPath::ALL {
            if (path, culling) == (LayeredPath::Traditional, LayerCulling::None) {
                continue;
            }
            let (report, maps, other_light, kept) = frame(&scene, &with_culling(path, culling));
            let facts = report.layered.expect("the technique reports its path");
            assert_eq!(facts.culling, culling);
            let case = format!("{path}, culling {culling}");
            if path == LayeredPath::Multiview && !multiview_reaches_every_layer(gpu()) {
                // Lavapipe in Mesa 22.3 exposes multiview but draws only a pass's first
                // view: the path falls back to a pass per map, and says so.
                assert_eq!(facts.path, LayeredPath::Traditional);
                let note = "only the first view";
                assert!(report.notes.iter().any(|n| n.contains(note)));
            } else {
                assert_eq!(facts.path, path, "lavapipe has clip distances");
            }
            same_maps(&traditional, &maps, &case);
            same_shadows(&light, &other_light, &case);
            if culling != LayerCulling::None {
                // Every slot's kept triangles are among those it tested, and culling kept
                // fewer than it tested.
                let kept: u64 = kept.iter().map(|&k| u64::from(k)).sum();
                assert!(kept > 0 && kept < facts.triangles_tested, "{case}: {kept}");
            }
            match (facts.path, culling) {
                (LayeredPath::Multiview, _) => {
                    let group = facts.multiview_group;
                    let limit = gpu().device.limits().max_multiview_view_count;
                    assert!(group >= 2 && group <= limit, "{group} within {limit}");
                    assert_eq!(facts.passes, 14u32.div_ceil(group));
                }
                // 14 maps of 256 fit one page of 4 x 4 tiles: one pass; a draw per mesh, or
                // with culling one multi-draw of each view's kept triangles.
                (LayeredPath::Atlas, LayerCulling::None) => {
                    assert_eq!((facts.passes, facts.draws), (1, 2));
                }
                (LayeredPath::Atlas, _) => assert_eq!((facts.passes, facts.draws), (1, 14)),
                (LayeredPath::Traditional, _) => assert_eq!(facts.passes, 14),
            }
        }
    }
}

#[test]
fn the_suns_cascades_through_every_path_are_the_cascades_techniques_maps_and_shadows() {
    // The sun over the box and the four lights: three cascades of the sun rendered by the
    // cascades technique, then by each path with the lights' fourteen maps.
    let scene = scene(four_lights());
    let mut alone = FrameSettings {
        setup: ShadowSetup::Cascades,
        method: Method::Vfc,
        ..FrameSettings::default()
    };
    // The sun's maps are 512 texels at least.
    alone.shadow.resolution = 512;
    alone.cascades.count = 3;
    let (expected_report, expected, sun, _) = frame(&scene, &alone);
    assert_eq!(expected.len(), 3);
    let shadowed = sun.iter().filter(|&&s| s < 128).count();
    assert!(
        shadowed > 100,
        "the box shadows the ground: {shadowed} pixels"
    );
    for path in LayeredPath::ALL {
        for culling in [LayerCulling::None, LayerCulling::Both] {
            let mut settings = with_culling(path, culling);
            settings.layered.sun = true;
            settings.cascades = alone.cascades;
            settings.shadow.resolution = alone.shadow.resolution;
            let case = format!("{path}, culling {culling}, with the sun");
            let (report, maps, light, _) = frame(&scene, &settings);
            assert_eq!(maps.len(), 3 + 14, "{case}");
            for (v, (a, b)) in expected_report.views.iter().zip(&report.views).enumerate() {
                assert_eq!(a.name, format!("cascade {v}"));
                assert_eq!(
                    (&a.name, a.texel_size_m, a.depth_range_m),
                    (&b.name, b.texel_size_m, b.depth_range_m),
                    "{case}"
                );
            }
            assert_eq!(report.views[3].name, "spot 0", "{case}: the lights follow");
            same_maps(&expected, &maps[..3], &case);
            // With the sun, the light term's visibility is the sun's, as the cascades shade it.
            same_shadows(&sun, &light, &case);
            let facts = report.layered.expect("the technique reports its path");
            assert_eq!(facts.maps, 17, "{case}");
        }
    }
}

/// The pictures' light agrees: no more than two pixels (an edge's rounding) shadowed in one
/// and lit in the other.
fn same_shadows(expected: &[u8], light: &[u8], case: &str) {
    let differ = expected
        .iter()
        .zip(light)
        .filter(|(a, b)| (**a < 128) != (**b < 128))
        .count();
    assert!(differ <= 2, "{case}: {differ} pixels shadowed differently");
}

/// The maps agree texel by texel: the same texels covered (but for one in 10,000, the
/// rasteriser's rounding on a triangle's edge) and their depths within 1e-5.
fn same_maps(expected: &[Vec<f32>], maps: &[Vec<f32>], case: &str) {
    let mut covered_differently = 0;
    let mut worst = 0.0f32;
    for (a, b) in expected.iter().zip(maps) {
        for (&x, &y) in a.iter().zip(b) {
            if (x < 1.0) == (y < 1.0) {
                worst = worst.max((x - y).abs());
            } else {
                covered_differently += 1;
            }
        }
    }
    let texels: usize = expected.iter().map(Vec::len).sum();
    assert!(
        covered_differently * 10_000 <= texels,
        "{case}: {covered_differently} of {texels} texels covered differently"
    );
    assert!(worst < 1e-5, "{case}: depths differ by {worst}");
}

#[test]
fn the_spot_over_the_box_shadows_the_ground_under_it_and_lights_the_ground_beside_it() {
    let above = vec![light(
        "above",
        Vec3::new(0.0, 10.0, 0.0),
        spot(Vec3::NEG_Y, 40.0),
    )];
    let scene = scene(above);
    let camera = camera();
    let (_, capture) = render(&scene, &camera, &lights(LayeredPath::Atlas), SIZE.0, SIZE.1);
    let ground = 1; // box_on_plane: the ground is the first instance.
    let (mut under, mut beside) = (0, 0);
    for (i, p) in pixels_of(&capture, &camera, ground) {
        // The box's shadow from the light straight above, by similar triangles: its top face
        // casts the outline (the bottom's lies inside it); away from the edges by the PCF's
        // reach; and the cone's inside, away from the shadow.
        let scale = 10.0 / (10.0 - BOX_MAX.y);
        let (hx, hz) = (BOX_MAX.x * scale, BOX_MAX.z * scale);
        if p.x.abs() < hx - 0.2 && p.z.abs() < hz - 0.2 {
            assert!(capture.shadow[i] < 10, "{p} under the box is lit");
            under += 1;
        } else if (p.x.abs() > hx + 0.3 || p.z.abs() > hz + 0.3) && p.xz().length() < 6.0 {
            assert!(capture.shadow[i] > 245, "{p} beside the box is shadowed");
            beside += 1;
        }
    }
    assert!(under > 50 && beside > 500, "{under} under, {beside} beside");
}

#[test]
fn a_point_light_inside_the_box_shadows_everything_outside_it() {
    let inside = vec![light("inside", Vec3::new(0.0, 2.5, 0.0), LightKind::Point)];
    let scene = scene(inside);
    let camera = camera();
    let settings = lights(LayeredPath::Multiview);
    let (report, capture) = render(&scene, &camera, &settings, SIZE.0, SIZE.1);
    assert_eq!(report.views.len(), 6);
    let mut ground = 0;
    for (i, p) in pixels_of(&capture, &camera, 1) {
        if p.xz().length() < 15.0 {
            assert!(capture.shadow[i] < 3, "{p} outside the box is lit");
            ground += 1;
        }
    }
    assert!(ground > 1000, "{ground}");
}

#[test]
fn culling_casters_per_view_by_their_frustum_changes_no_map() {
    // Every light of the hall (72 maps): `vfc` draws each map's casters in its frustum only;
    // `none` draws every caster into every map. The maps must be the same.
    let hall = render_core::scene::load_builtin("hall", 1).expect("the hall");
    let mut settings = with_culling(LayeredPath::Atlas, LayerCulling::None);
    settings.shadow.resolution = 128;
    let (vfc, maps, _, _) = frame(&hall, &settings);
    settings.method = Method::None;
    let (none, every, _, _) = frame(&hall, &settings);
    assert_eq!(maps.len(), 72);
    assert_eq!(
        maps, every,
        "a caster outside a view's frustum drew into it"
    );
    let drawn = |r: &FrameReport| r.views.iter().map(|v| v.casters_rendered).sum::<u32>();
    assert!(
        drawn(&vfc) < drawn(&none),
        "{} against {}",
        drawn(&vfc),
        drawn(&none)
    );
}

#[test]
fn the_geometry_loads_of_the_bench_change_no_map_or_leave_every_map_empty() {
    let scene = scene(four_lights());
    let unloaded = with_culling(LayeredPath::Atlas, LayerCulling::Frustum);
    let (_, maps, _, _) = frame(&scene, &unloaded);
    for path in LayeredPath::ALL {
        // Skinning-like work per vertex (Rákos's Figure 19.6) computes and draws the same.
        let mut heavy = with_culling(path, LayerCulling::Frustum);
        heavy.layered.load.vertex_work = 16;
        let (_, worked, _, _) = frame(&scene, &heavy);
        same_maps(&maps, &worked, &format!("{path} with vertex work"));
        // Without rasterisation (Figure 19.4) the vertices run and no texel is written.
        heavy.layered.load.no_raster = true;
        let (_, empty, _, _) = frame(&scene, &heavy);
        assert!(
            empty.iter().flatten().all(|&d| d >= 1.0),
            "{path} rasterised"
        );
    }
}

#[test]
fn pipeline_statistics_count_the_triangles_each_pass_draws() {
    let ctx = gpu();
    if !ctx
        .features()
        .contains(wgpu::Features::PIPELINE_STATISTICS_QUERY)
    {
        return; // Lavapipe has them; another adapter may not.
    }
    let scene = scene(four_lights());
    let scene_gpu = SceneGpu::new(ctx, &scene);
    let camera = camera();
    for culling in [LayerCulling::None, LayerCulling::Both] {
        let settings = with_culling(LayeredPath::Traditional, culling);
        let mut renderer = FrameRenderer::new(ctx);
        let input = FrameInput {
            camera: &camera,
            width: SIZE.0,
            height: SIZE.1,
            settings: &settings,
        };
        let report = renderer
            .render_and_wait(ctx, &scene, &scene_gpu, &input)
            .expect("frame renders");
        let passes = renderer.lights_pass_statistics(ctx).expect("reads back");
        let facts = report.layered.expect("the technique reports its path");
        // A pass a map, each counted.
        assert_eq!(passes.len(), 14);
        let clipped: u64 = passes.iter().map(|p| p.clipper_invocations).sum();
        let drawn = if culling == LayerCulling::None {
            facts.triangles
        } else {
            let kept = renderer.lights_kept_triangles(ctx).expect("reads back");
            kept.iter().map(|&k| u64::from(k)).sum()
        };
        // Every triangle a pass draws enters its clipper once.
        assert_eq!(clipped, drawn, "culling {culling}");
        // Some are rasterised (clipping at the near plane may split one in two).
        assert!(
            passes
                .iter()
                .any(|p| p.rasterised > 0 && p.vertex_invocations > 0)
        );
    }
}
