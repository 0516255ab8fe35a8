//! A virtual level and a single map on the same texel grid cast the same shadow: the level's
//! pages, drawn one by one into the physical atlas and read through the page table, hold the
//! depths the single map holds for its texels, pixel for pixel.

use glam::Vec3;
use render_core::frame::{FrameCapture, FrameInput, FrameRenderer, FrameSettings, ShadowSetup};
use render_core::scene::{Scene, Sun};
use render_core::scene_gpu::SceneGpu;
use render_core::shadow_view::{LEVEL_PAGES, PAGE_TEXELS, VirtualSettings};
use shadowlab_tests::virtual_pages::{SIZE, camera};
use shadowlab_tests::{box_on_plane, gpu};

fn render(
    renderer: &mut FrameRenderer,
    scene: &Scene,
    settings: &FrameSettings,
) -> (FrameCapture, Option<render_core::technique::VirtualPages>) {
    let ctx = gpu();
    let camera = camera();
    let input = FrameInput {
        camera: &camera,
        width: SIZE.0,
        height: SIZE.1,
        settings,
    };
    let report = renderer
        .render_and_wait(ctx, scene, &SceneGpu::new(ctx, scene), &input)
        .expect("frame renders");
    assert_eq!(report.shadow_failure, None);
    let capture = FrameCapture::read(ctx, renderer.targets().expect("targets")).expect("readback");
    (capture, report.virtual_pages)
}

/// One level of 2 cm texels (an 82 m square around the camera) holds every visible point of
/// a 40 m ground, so every pixel is shaded from it; the single map renders that level's view
/// (the same light-space texel grid, 4096 texels square, the same depth range).
#[test]
fn a_virtual_level_and_a_single_map_on_its_texel_grid_cast_identical_shadows() {
    let scene = box_on_plane(20.0, Vec3::new(2.0, 3.0, 1.5), 1.0, Sun::default());
    let mut virtual_renderer = FrameRenderer::new(gpu());
    let settings = FrameSettings {
        setup: ShadowSetup::Virtual,
        virtual_maps: VirtualSettings {
            levels: 1,
            finest_texel_m: 0.02,
            ..VirtualSettings::default()
        },
        ..FrameSettings::default()
    };
    let (pages, page_stats) = render(&mut virtual_renderer, &scene, &settings);
    let stats = page_stats.expect("the virtual maps report their pages");
    assert_eq!(stats.pages_refused, 0, "{stats:?}");
    assert!(stats.pages_rendered > 0, "{stats:?}");
    let views = virtual_renderer.last_views().to_vec();
    assert_eq!(views.len(), 1);
    let side = LEVEL_PAGES * PAGE_TEXELS;
    let texel = views[0].light.texel_size_m;
    assert!(texel.iter().all(|t| (t - 0.02).abs() < 1e-6), "{texel:?}");

    let mut map_renderer = FrameRenderer::new(gpu());
    map_renderer.set_single_map_views(views.clone());
    let mut single = FrameSettings {
        setup: ShadowSetup::Single,
        ..settings
    };
    single.shadow.resolution = side;
    let (map, _) = render(&mut map_renderer, &scene, &single);
    assert_eq!(map_renderer.last_views(), views.as_slice());

    // Not a trivial picture: the box's shadow and lit ground are both in view.
    assert!(pages.shadow.contains(&0));
    assert!(pages.shadow.contains(&255));
    let differing: Vec<usize> = (0..map.shadow.len())
        .filter(|&i| map.shadow[i] != pages.shadow[i])
        .collect();
    assert!(
        differing.is_empty(),
        "{} pixels differ, first {:?}",
        differing.len(),
        &differing[..differing.len().min(8)]
    );
}
