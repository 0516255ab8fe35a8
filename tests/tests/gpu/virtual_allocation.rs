//! Where pages land in the physical atlas (`virtual_maps/allocate.wgsl`). The rasteriser's
//! depths depend, in their last bit, on where in the atlas a page is drawn, and a tap whose
//! depth test is decided that close (at a shadow's edge on a curved or grazing receiver) reads
//! lit at one place and shadowed at another. So allocation is ordered, the same frame giving
//! every page the same physical page on every run (the same atlas and picture, bit for bit),
//! and a page drawn again because it went invalid, or because everything did, is drawn in
//! the physical page it holds: a frame with the cache off is the exact reference of a cached
//! one.

use glam::Vec3;
use render_core::frame::FrameSettings;
use render_core::geom::Camera;
use render_core::scene::{PointShadow, Scene, Sun};
use render_core::shadow_view::VirtualSettings;
use shadowlab_tests::gpu;
use shadowlab_tests::virtual_pages::{
    Frame, Frames, MARKED, RENDERED, RESIDENT, camera, entries_with, scene, settings,
};

/// The camera of [`camera`] turned 12 degrees left about its eye: it reads pages the first
/// did not, and the clipmap's squares, centred on the eye, stay where they were.
fn turned() -> Camera {
    let c = camera();
    let forward = glam::Quat::from_rotation_y(12f32.to_radians()) * c.forward;
    Camera::look_at(c.eye, c.eye + forward, c.fov_y_rad, c.near_m, c.far_m)
}

/// The physical page of each entry and the atlas's texels after the renderer's last frame.
fn slots_and_atlas(frames: &Frames) -> (Vec<u32>, Vec<u8>) {
    let slots = frames
        .renderer
        .virtual_page_slots(gpu())
        .expect("reads back");
    let atlas = frames.renderer.virtual_atlas().expect("an atlas");
    let texels = render_core::gpu::read_texture(gpu(), atlas, wgpu::TextureAspect::DepthOnly)
        .expect("reads back");
    (slots, texels.bytes)
}

/// Two frames, the camera turning between them, and what they left: their frames, the
/// physical pages and the atlas.
struct Run {
    first: Frame,
    second: Frame,
    slots: [Vec<u32>; 2],
    atlas: Vec<u8>,
}

fn run(scene: &Scene, settings: &FrameSettings) -> (Frames, Run) {
    let mut frames = Frames::new(scene);
    let first = frames.frame(scene, &camera(), settings);
    let (first_slots, _) = slots_and_atlas(&frames);
    let second = frames.frame(scene, &turned(), settings);
    let (second_slots, atlas) = slots_and_atlas(&frames);
    let run = Run {
        first,
        second,
        slots: [first_slots, second_slots],
        atlas,
    };
    (frames, run)
}

/// The known answer of ordered allocation: a first frame's pages take physical pages 0, 1,
/// 2, ... in the order of their entries; in the second, the pages kept stay where they were,
/// and the new ones take the free physical pages in order.
fn assert_ordered(run: &Run, pool: u32) {
    let resident = entries_with(&run.first.flags, RESIDENT);
    let first: Vec<u32> = resident.iter().map(|&e| run.slots[0][e]).collect();
    assert_eq!(first, (0..resident.len() as u32).collect::<Vec<_>>());
    let now = entries_with(&run.second.flags, RESIDENT);
    let (kept, new): (Vec<usize>, Vec<usize>) =
        now.iter().partition(|e| resident.binary_search(e).is_ok());
    assert!(
        !new.is_empty() && !kept.is_empty(),
        "{} kept, {} new",
        kept.len(),
        new.len()
    );
    for &e in &kept {
        assert_eq!(run.slots[1][e], run.slots[0][e], "entry {e} stays");
    }
    let held: Vec<u32> = kept.iter().map(|&e| run.slots[1][e]).collect();
    let free: Vec<u32> = (0..pool).filter(|s| !held.contains(s)).collect();
    let taken: Vec<u32> = new.iter().map(|&e| run.slots[1][e]).collect();
    assert_eq!(taken, free[..new.len()]);
}

#[test]
fn pages_take_the_free_physical_pages_in_order_and_every_run_draws_the_same_atlas() {
    let scene = scene(Sun::default());
    let sun = settings(VirtualSettings::default());
    let point = FrameSettings {
        point_light: Some(PointShadow::omni(Vec3::new(3.0, 6.0, 2.0), 2.0e6)),
        ..settings(VirtualSettings {
            separate_static: true,
            ..VirtualSettings::default()
        })
    };
    for settings in [sun, point] {
        let pool = settings.virtual_maps.pages;
        let (_, a) = run(&scene, &settings);
        assert_ordered(&a, pool);
        let (_, b) = run(&scene, &settings);
        assert_eq!(a.slots, b.slots);
        assert!(a.atlas == b.atlas, "the atlas differs between two runs");
        assert_eq!(a.second.capture.shadow, b.second.capture.shadow);
    }
}

#[test]
fn a_frame_with_the_cache_off_draws_every_page_again_where_it_is() {
    let scene = scene(Sun::default());
    let settings = settings(VirtualSettings::default());
    let (mut frames, cached) = run(&scene, &settings);
    let redrawn = frames.redrawn(&scene, &turned(), &settings);
    let (slots, _) = slots_and_atlas(&frames);
    let marked = entries_with(&redrawn.flags, MARKED);
    assert_eq!(entries_with(&redrawn.flags, RENDERED), marked);
    assert_eq!(entries_with(&redrawn.flags, RESIDENT), marked);
    for &e in &marked {
        assert_eq!(slots[e], cached.slots[1][e], "entry {e} stays");
    }
    assert!(redrawn.pages.all_invalidated);
    assert_eq!(redrawn.capture.shadow, cached.second.capture.shadow);
}
